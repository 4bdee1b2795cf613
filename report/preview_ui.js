// preview.html's controls: a slider per parameter (its ends editable for a uniform prior),
// the values as an --at file and as the scene with them as `init`, and the check that the
// JavaScript port agrees with vkrecon. The URL's fragment sets values at load
// (preview.html#w=1.2&yaw=10), through the sliders, as a hand would; a browser test uses it.
(function () {
  'use strict';
  var port = previewPort, data = port.data, params = data.parameters, names = port.names;
  var first = params.map(function (p) { return p.value; }), values = first.slice();
  var sliders = [], numbers = [];
  var canSaveScene = !!(data.scene_json && data.scene_json.parameters);

  // The port against vkrecon at the first values: every expression, and each camera's check
  // points (a vertex's pixel through the lens). A disagreement is a console error.
  function check() {
    var worst = 0, worstPixel = 0, points = 0;
    port.expressions.forEach(function (f, i) {
      var want = data.expressions[i].value, got = f(first);
      worst = Math.max(worst, Math.abs(got - want) / Math.max(1, Math.abs(want)));
      if (!(Math.abs(got - want) <= 1e-9 * Math.max(1, Math.abs(want))))
        console.error('expression "' + data.expressions[i].text + '" (' + data.expressions[i].field + '): vkrecon ' +
                      want + ', the page ' + got);
    });
    var world = port.worldFromNode(first);
    data.cameras.forEach(function (c) {
      var cam = port.camera(c, first);
      c.check.forEach(function (p) {
        var q = port.pixel(cam, port.apply(cam.camFromWorld, port.apply(world[p[0]], data.nodes[p[0]].vertices[p[1]])));
        var error = Math.hypot(q[0] - p[2], q[1] - p[3]);
        worstPixel = Math.max(worstPixel, error);
        ++points;
        if (!(error <= 1e-6)) console.error(c.name + ': node ' + p[0] + ' vertex ' + p[1] + ' at (' + q + '), vkrecon (' +
                                            p[2] + ',' + p[3] + ')');
      });
    });
    document.body.setAttribute('data-preview-check', points + ' points, max ' + worstPixel.toExponential(2) +
                               ' px; expressions max ' + worst.toExponential(2));
  }

  function atJson() {
    var at = {};
    names.forEach(function (name, i) { at[name] = values[i]; });
    return JSON.stringify(at, null, 2) + '\n';
  }
  // The saved files' texts are also in the page (hidden), for a browser test to read.
  function redraw() {
    port.draw(values);
    document.getElementById('at-json').textContent = atJson();
    if (canSaveScene) document.getElementById('scene-json').textContent = sceneJson();
  }
  function set(i, value) {
    values[i] = Math.min(params[i].hi, Math.max(params[i].lo, value));
    sliders[i].value = values[i];
    numbers[i].value = +values[i].toPrecision(6);  // the full value is in the saved files
    redraw();
  }
  function input(type, value, title, onchange) {
    var e = document.createElement('input');
    e.type = type;
    if (type === 'number') e.step = 'any';
    e.value = value;
    e.title = title;
    e.addEventListener(type === 'range' ? 'input' : 'change', onchange);
    return e;
  }
  params.forEach(function (p, i) {
    var row = document.createElement('div'), label = document.createElement('label');
    row.className = 'slider';
    label.textContent = p.name;
    var uniform = p.prior.kind === 'uniform';
    var lo = input('number', p.lo, 'the slider\'s low end' + (uniform ? ' (saved as the prior\'s)' : ''), function () {
      p.lo = Math.min(parseFloat(lo.value), p.hi); sliders[i].min = p.lo; set(i, values[i]);
    });
    var hi = input('number', p.hi, 'the slider\'s high end' + (uniform ? ' (saved as the prior\'s)' : ''), function () {
      p.hi = Math.max(parseFloat(hi.value), p.lo); sliders[i].max = p.hi; set(i, values[i]);
    });
    var slider = input('range', p.value, p.prior.kind + ' prior (' + p.prior.a + ', ' + p.prior.b + ')', function () {
      set(i, parseFloat(slider.value));
    });
    slider.min = p.lo; slider.max = p.hi; slider.step = (p.hi - p.lo) / 1000 || 'any'; slider.value = p.value;
    slider.id = 'slider-' + p.name;
    var number = input('number', p.value, 'the value', function () { set(i, parseFloat(number.value)); });
    number.className = 'value';
    sliders.push(slider); numbers.push(number);
    [label, lo, slider, hi, number].forEach(function (e) { row.appendChild(e); });
    document.getElementById('sliders').appendChild(row);
  });

  function download(name, text) {
    var a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([text], {type: 'application/json'}));
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
  }
  // The scene file with `init` at the values and each uniform prior at its slider's ends.
  function sceneJson() {
    var scene = JSON.parse(JSON.stringify(data.scene_json));
    params.forEach(function (p, i) {
      var entry = scene.parameters && scene.parameters[p.name];
      if (!entry) return;
      entry.init = values[i];
      if (p.prior.kind === 'uniform') entry.prior = {uniform: [p.lo, p.hi]};
    });
    return JSON.stringify(scene, null, 2) + '\n';
  }
  document.getElementById('save-at').addEventListener('click', function () { download('at.json', atJson()); });
  var saveScene = document.getElementById('save-scene');
  if (canSaveScene) {
    saveScene.addEventListener('click', function () { download(data.scene_name, sceneJson()); });
    saveScene.title = 'save it beside ' + data.scene_name + ': its relative paths (images, cameras) are relative to it';
  } else {
    saveScene.disabled = true;
    saveScene.title = 'the scene file is not plain JSON with a "parameters" object';
  }
  document.getElementById('reset').addEventListener('click', function () {
    first.forEach(function (v, i) { set(i, v); });
  });

  check();
  redraw();
  // #name=value&…: as if the sliders were moved (an unknown name is an error).
  location.hash.slice(1).split('&').filter(Boolean).forEach(function (pair) {
    var kv = pair.split('='), i = names.indexOf(decodeURIComponent(kv[0]));
    if (i < 0) { console.error('#' + pair + ': no parameter ' + kv[0]); return; }
    sliders[i].value = parseFloat(kv[1]);
    sliders[i].dispatchEvent(new Event('input'));
  });
  document.body.setAttribute('data-preview', 'drawn');
})();
