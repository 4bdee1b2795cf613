(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('report-data').textContent);
  var chains = data.chain.chains, names = data.chain.names, burn = data.burn_in;
  var colours = ['#1f77b4', '#ff7f0e', '#2ca02c', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f', '#bcbd22', '#17becf'];
  Chart.defaults.animation = false;
  Chart.defaults.font.size = 11;
  Chart.defaults.maintainAspectRatio = false;
  Chart.defaults.elements.point.radius = 0;
  Chart.defaults.elements.line.borderWidth = 1;

  function points(xs, ys) {
    var out = [];
    for (var i = 0; i < xs.length; ++i) if (ys[i] !== null && isFinite(ys[i])) out.push({x: xs[i], y: ys[i]});
    return out;
  }
  function finite(values) { return values.filter(function (v) { return v !== null && isFinite(v); }); }
  function quantile(values, q) {
    var s = finite(values).slice().sort(function (a, b) { return a - b; });
    return s.length ? s[Math.min(s.length - 1, Math.floor(q * s.length))] : 0;
  }
  function smooth(values, span) {
    var out = [];
    for (var i = 0; i < values.length; ++i) {
      var sum = 0, n = 0;
      for (var j = Math.max(0, i - span); j <= Math.min(values.length - 1, i + span); ++j)
        if (values[j] !== null) { sum += values[j]; ++n; }
      out.push(n ? sum / n : null);
    }
    return out;
  }
  function vertical(x, lo, hi, colour, label, dash) {
    return {label: label, data: [{x: x, y: lo}, {x: x, y: hi}], borderColor: colour, borderDash: dash || [],
            borderWidth: 1.5, pointRadius: 0};
  }
  function lineChart(canvas, datasets, title, yOptions, xTitle) {
    return new Chart(canvas, {type: 'line', data: {datasets: datasets},
      options: {parsing: true, plugins: {title: {display: true, text: title}, legend: {labels: {boxWidth: 10}}},
                scales: {x: xTitle === 'iteration' ? {type: 'linear', min: first, max: last, title: {display: true, text: xTitle}}
                                                   : {type: 'linear', title: {display: !!xTitle, text: xTitle || ''}},
                         y: yOptions || {}}}});
  }
  // Every iteration plot spans the whole run, whatever part of it its y range shows.
  var first = Infinity, last = -Infinity;
  chains.forEach(function (c) {
    if (c.iteration.length) { first = Math.min(first, c.iteration[0]); last = Math.max(last, c.iteration[c.iteration.length - 1]); }
  });
  if (!isFinite(first)) { first = 0; last = 1; }
  function perChain(key) {
    return chains.map(function (c, i) {
      return {label: 'chain ' + i, data: points(c.iteration, c[key]), borderColor: colours[i % colours.length]};
    });
  }
  // Post burn-in draws of parameter p over all chains (all draws when the run kept none).
  function draws(p) {
    var out = [], all = [];
    chains.forEach(function (c) {
      c.values[p].forEach(function (v, i) { if (v === null) return; all.push(v); if (c.iteration[i] >= burn) out.push(v); });
    });
    return out.length > 1 ? out : all;
  }

  // Log posterior: the y range fits the finest level's values from their 5 % quantile up (the
  // coarse levels' are on other scales, the first iterations' far below: they would flatten the rest).
  var lp = [];
  chains.forEach(function (c) {
    c.log_posterior.forEach(function (v, i) { if (c.level[i] === 0) lp.push(v); });
  });
  if (!finite(lp).length) chains.forEach(function (c) { lp = lp.concat(c.log_posterior); });
  var lpLo = quantile(lp, 0.05), lpHi = Math.max.apply(null, finite(lp).concat([lpLo + 1]));
  var pad = 0.05 * (lpHi - lpLo) || 1;
  lineChart(document.getElementById('chart-logpost'),
            perChain('log_posterior').concat([vertical(burn, lpLo - pad, lpHi + pad, '#888', 'burn-in', [4, 4])]),
            'log posterior (coldest replica; y fits level 0)', {min: lpLo - pad, max: lpHi + pad}, 'iteration');

  // Acceptance and swap rates, mean over chains, smoothed.
  function meanOverChains(key) {
    var n = Math.max.apply(null, chains.map(function (c) { return c[key].length; }));
    var out = [];
    for (var i = 0; i < n; ++i) {
      var v = finite(chains.map(function (c) { return i < c[key].length ? c[key][i] : null; }));
      out.push(v.length ? v.reduce(function (a, b) { return a + b; }, 0) / v.length : null);
    }
    return out;
  }
  var its = chains.length ? chains[0].iteration : [];
  var span = Math.max(2, Math.round(its.length / 40));
  lineChart(document.getElementById('chart-rates'), [
    {label: 'acceptance', data: points(its, smooth(meanOverChains('accepted'), span)), borderColor: colours[0]},
    {label: 'swaps', data: points(its, smooth(meanOverChains('swapped'), span)), borderColor: colours[1]},
    vertical(burn, 0, 1, '#888', 'burn-in', [4, 4])], 'acceptance and swap rates (mean over chains)',
    {min: 0, max: 1}, 'iteration');

  // The annealing: the coldest replica's temperature, and the likelihood level it was scored at.
  var temperature = perChain('temperature');
  temperature.push({label: 'level', data: points(its, chains.length ? chains[0].level : []), borderColor: '#aaa',
                    stepped: true, yAxisID: 'level'});
  new Chart(document.getElementById('chart-temperature'), {type: 'line', data: {datasets: temperature},
    options: {plugins: {title: {display: true, text: 'temperature of the coldest replica, and level'},
                        legend: {labels: {boxWidth: 10}}},
              scales: {x: {type: 'linear', min: first, max: last, title: {display: true, text: 'iteration'}},
                       y: {type: 'logarithmic'},
                       level: {position: 'right', min: 0, ticks: {stepSize: 1}, grid: {drawOnChartArea: false}}}}});

  // The temperature ladder: each rung's acceptance, and the swap rate between neighbouring rungs.
  var rungs = 0;
  data.ladder.forEach(function (c) { rungs = Math.max(rungs, (c.replica_acceptance || []).length); });
  var labels = [], accept = [], swap = [];
  for (var k = 0; k < rungs; ++k) {
    labels.push('rung ' + k + (k === 0 ? ' (coldest)' : ''));
    var a = finite(data.ladder.map(function (c) { return (c.replica_acceptance || [])[k]; }));
    var s = finite(data.ladder.map(function (c) { return (c.swap_acceptance || [])[k]; }));
    accept.push(a.length ? a.reduce(function (x, y) { return x + y; }, 0) / a.length : null);
    swap.push(s.length ? s.reduce(function (x, y) { return x + y; }, 0) / s.length : null);
  }
  new Chart(document.getElementById('chart-ladder'), {type: 'bar',
    data: {labels: labels, datasets: [{label: 'acceptance', data: accept, backgroundColor: colours[0]},
                                      {label: 'swap with the next rung', data: swap, backgroundColor: colours[1]}]},
    options: {plugins: {title: {display: true, text: 'temperature ladder (mean over chains, map.json)'}},
              scales: {y: {min: 0, max: 1}}}});

  // Per parameter: trace and marginal.
  var container = document.getElementById('per-parameter');
  names.forEach(function (name, p) {
    var info = data.parameters.filter(function (q) { return q.name === name; })[0] || {};
    var row = document.createElement('div');
    row.className = 'param-row';
    var left = document.createElement('div'), right = document.createElement('div');
    left.className = right.className = 'chart';
    var trace = document.createElement('canvas'), hist = document.createElement('canvas');
    left.appendChild(trace); right.appendChild(hist); row.appendChild(left); row.appendChild(right);
    container.appendChild(row);

    var all = [];
    chains.forEach(function (c) { all = all.concat(finite(c.values[p])); });
    var lo = Math.min.apply(null, all), hi = Math.max.apply(null, all);
    var traces = chains.map(function (c, i) {
      return {label: 'chain ' + i, data: points(c.iteration, c.values[p]), borderColor: colours[i % colours.length]};
    });
    traces.push(vertical(burn, lo, hi, '#888', 'burn-in', [4, 4]));
    lineChart(trace, traces, name + ': trace', {}, 'iteration');

    // The draws as map.json's interval describes them: moved with a MAP polished beyond the
    // chains' likelihood (interval_shift; the trace shows them as sampled).
    var shift = typeof info.shift === 'number' ? info.shift : 0;
    var d = draws(p).map(function (v) { return v + shift; });
    var dlo = Math.min.apply(null, d), dhi = Math.max.apply(null, d);
    [info.map, info.truth, info.q025, info.q975].forEach(function (v) {
      if (typeof v === 'number') { dlo = Math.min(dlo, v); dhi = Math.max(dhi, v); }
    });
    if (!(dhi > dlo)) { dlo -= 0.5; dhi += 0.5; }
    var margin = 0.05 * (dhi - dlo);
    dlo -= margin; dhi += margin;
    var bins = 30, width = (dhi - dlo) / bins, counts = [];
    for (var b = 0; b < bins; ++b) counts.push(0);
    d.forEach(function (v) { counts[Math.min(bins - 1, Math.max(0, Math.floor((v - dlo) / width)))] += 1; });
    var histogram = [], peak = 0;
    for (b = 0; b < bins; ++b) {
      var density = counts[b] / (d.length * width);
      peak = Math.max(peak, density);
      histogram.push({x: dlo + b * width, y: density});
    }
    histogram.push({x: dhi, y: histogram[bins - 1].y});
    var sets = [{label: shift ? 'posterior draws, moved with the MAP' : 'posterior draws', data: histogram,
                 stepped: 'before', borderColor: colours[0],
                 backgroundColor: 'rgba(31,119,180,0.25)', fill: 'origin'}];
    if (info.prior) {
      var prior = [];
      for (var i = 0; i <= 100; ++i) {
        var x = dlo + (dhi - dlo) * i / 100, y;
        if (info.prior.kind === 'uniform') y = (x >= info.prior.a && x <= info.prior.b) ? 1 / (info.prior.b - info.prior.a) : 0;
        else y = Math.exp(-0.5 * Math.pow((x - info.prior.a) / info.prior.b, 2)) / (info.prior.b * Math.sqrt(2 * Math.PI));
        prior.push({x: x, y: y});
        peak = Math.max(peak, y);
      }
      sets.push({label: 'prior', data: prior, borderColor: '#444', borderDash: [5, 3]});
    }
    if (typeof info.map === 'number') sets.push(vertical(info.map, 0, peak, '#d62728', 'MAP'));
    if (typeof info.truth === 'number') sets.push(vertical(info.truth, 0, peak, '#2ca02c', 'truth'));
    lineChart(hist, sets, name + ': marginal (' + d.length + ' draws)', {min: 0}, name);
  });

  // The most correlated pairs of parameters (Pearson's r over the draws after burn-in).
  var columns = names.map(function (_, p) { return draws(p); });
  var pairs = [];
  for (var a = 0; a < names.length; ++a)
    for (var b2 = a + 1; b2 < names.length; ++b2) {
      var x = columns[a], y = columns[b2], n = Math.min(x.length, y.length);
      if (n < 3) continue;
      var mx = 0, my = 0;
      for (var i2 = 0; i2 < n; ++i2) { mx += x[i2] / n; my += y[i2] / n; }
      var sxy = 0, sxx = 0, syy = 0;
      for (i2 = 0; i2 < n; ++i2) {
        sxy += (x[i2] - mx) * (y[i2] - my); sxx += (x[i2] - mx) * (x[i2] - mx); syy += (y[i2] - my) * (y[i2] - my);
      }
      if (sxx > 0 && syy > 0) pairs.push({a: a, b: b2, r: sxy / Math.sqrt(sxx * syy)});
    }
  pairs.sort(function (p, q) { return Math.abs(q.r) - Math.abs(p.r); });
  var pairBox = document.getElementById('pairs');
  pairs.slice(0, 2).forEach(function (pair) {
    var box = document.createElement('div'), canvas = document.createElement('canvas');
    box.className = 'chart';
    box.appendChild(canvas);
    pairBox.appendChild(box);
    var sets = chains.map(function (c, i) {
      var pts = [];
      for (var j = 0; j < c.iteration.length; ++j)
        if (c.iteration[j] >= burn && c.values[pair.a][j] !== null && c.values[pair.b][j] !== null)
          pts.push({x: c.values[pair.a][j], y: c.values[pair.b][j]});
      return {label: 'chain ' + i, data: pts, backgroundColor: colours[i % colours.length], pointRadius: 2};
    });
    new Chart(canvas, {type: 'scatter', data: {datasets: sets},
      options: {plugins: {title: {display: true, text: names[pair.a] + ' and ' + names[pair.b] + ': r = ' + pair.r.toFixed(2)}},
                scales: {x: {title: {display: true, text: names[pair.a]}}, y: {title: {display: true, text: names[pair.b]}}}}});
  });
  if (!pairs.length) pairBox.textContent = 'Fewer than two parameters with spread draws: no pair to show.';
  document.body.setAttribute('data-report-charts', 'drawn');  // for scripts/report_screenshot.sh
})();
