// preview.html's port of the scene: recomputed from the transform graph in #preview-data at
// any values and drawn as pipelines/rendering/WireframeOverlay.cpp draws it (same edges, lens
// and near clip), as SVG paths in the photograph's pixels. Matrices are row-major arrays of 16.
// preview_ui.js wires the sliders to it and checks it against vkrecon's numbers.
var previewPort = (function () {
  'use strict';
  var data = JSON.parse(document.getElementById('preview-data').textContent);
  var params = data.parameters, names = params.map(function (p) { return p.name; });
  var expressions = data.expressions.map(function (e) { return compileExpression(e.text, names); });
  var kNear = 1e-3, kCreaseCos = Math.cos(data.crease_degrees * Math.PI / 180);

  function scalar(s, v) { return typeof s === 'number' ? s : expressions[s.expr](v); }
  function multiply(a, b) {
    var out = new Array(16).fill(0);
    for (var r = 0; r < 4; ++r)
      for (var c = 0; c < 4; ++c)
        for (var k = 0; k < 4; ++k) out[r * 4 + c] += a[r * 4 + k] * b[k * 4 + c];
    return out;
  }
  function identity() { return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]; }
  // rotate [rx, ry, rz] in degrees: Rz·Ry·Rx, x first (engine/scene/Scene.cpp, RotationZYX).
  function rotation(rx, ry, rz) {
    var d = Math.PI / 180, cx = Math.cos(rx * d), sx = Math.sin(rx * d), cy = Math.cos(ry * d), sy = Math.sin(ry * d),
        cz = Math.cos(rz * d), sz = Math.sin(rz * d);
    var x = [1, 0, 0, 0, 0, cx, -sx, 0, 0, sx, cx, 0, 0, 0, 0, 1];
    var y = [cy, 0, sy, 0, 0, 1, 0, 0, -sy, 0, cy, 0, 0, 0, 0, 1];
    var z = [cz, -sz, 0, 0, sz, cz, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
    return multiply(z, multiply(y, x));
  }
  // m · T1 · T2 · … (Scene.cpp, ApplyTransforms).
  function compose(chain, v, m) {
    chain.forEach(function (t) {
      var x = scalar(t.value[0], v), y = scalar(t.value[1], v), z = scalar(t.value[2], v);
      if (t.kind === 'translate') m = multiply(m, [1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1]);
      else if (t.kind === 'rotate') m = multiply(m, rotation(x, y, z));
      else m = multiply(m, [x, 0, 0, 0, 0, y, 0, 0, 0, 0, z, 0, 0, 0, 0, 1]);
    });
    return m;
  }
  function worldFromNode(v) {
    var world = [];
    data.nodes.forEach(function (node, i) {
      world.push(compose(node.transforms, v, node.parent >= 0 ? world[node.parent] : identity()));
    });
    return world;
  }
  function apply(m, p) {
    return [0, 1, 2].map(function (r) { return m[r * 4] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3]; });
  }
  // The camera at v: K, and cam_from_world = [R t] · pose⁻¹ (a pose is rigid).
  function camera(c, v) {
    // A photograph shrunk by the scene's max_side has K's first two rows divided (Scene::Cameras).
    var K = c.K.map(function (s, i) { return i < 6 ? scalar(s, v) / c.shrink : scalar(s, v); });
    var m = [c.R[0], c.R[1], c.R[2], c.t[0], c.R[3], c.R[4], c.R[5], c.t[1], c.R[6], c.R[7], c.R[8], c.t[2], 0, 0, 0, 1];
    if (c.pose.length) {
      var p = compose(c.pose, v, identity()), inverse = identity();
      for (var r = 0; r < 3; ++r) {
        for (var k = 0; k < 3; ++k) inverse[r * 4 + k] = p[k * 4 + r];
        inverse[r * 4 + 3] = -(p[r] * p[3] + p[4 + r] * p[7] + p[8 + r] * p[11]);
      }
      m = multiply(m, inverse);
    }
    var centre = [0, 1, 2].map(function (k) { return -(m[k] * m[3] + m[4 + k] * m[7] + m[8 + k] * m[11]); });
    return {K: K, camFromWorld: m, centre: centre, lens: c.lens};
  }
  // LensDistortion::Distort with the FULL_OPENCV coefficients k1 k2 p1 p2 k3 k4 k5 k6.
  function distort(lens, x, y) {
    var k1 = lens[0], k2 = lens[1], p1 = lens[2], p2 = lens[3], k3 = lens[4], k4 = lens[5], k5 = lens[6], k6 = lens[7];
    var r2 = x * x + y * y;
    var radial = (1 + r2 * (k1 + r2 * (k2 + r2 * k3))) / (1 + r2 * (k4 + r2 * (k5 + r2 * k6)));
    return [x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x), y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y];
  }
  // WireframeOverlay.cpp's LensPixel: a camera-frame point to the photograph's pixels.
  function pixel(cam, xc) {
    var n = [xc[0] / xc[2], xc[1] / xc[2]];
    if (cam.lens) n = distort(cam.lens, n[0], n[1]);
    var K = cam.K, w = K[6] * n[0] + K[7] * n[1] + K[8];
    return [(K[0] * n[0] + K[1] * n[1] + K[2]) / w, (K[3] * n[0] + K[4] * n[1] + K[5]) / w];
  }
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }

  // SceneEdges: every edge in the world with the unit normals of its uncollapsed triangles.
  function sceneEdges(v) {
    var world = worldFromNode(v), edges = [];
    data.nodes.forEach(function (node, i) {
      var points = node.vertices.map(function (p) { return apply(world[i], p); });
      var normals = node.triangles.map(function (t) {
        var n = cross(sub(points[t[1]], points[t[0]]), sub(points[t[2]], points[t[0]])), l = Math.sqrt(dot(n, n));
        return l > 0 ? [n[0] / l, n[1] / l, n[2] / l] : null;
      });
      node.edges.forEach(function (e) {
        var ns = e.triangles.map(function (t) { return normals[t]; }).filter(function (n) { return n; });
        if (ns.length) edges.push({a: points[e.a], b: points[e.b], normals: ns});
      });
    });
    return edges;
  }
  // IsDrawnEdge: a boundary, a crease, or on the silhouette seen from `centre`.
  function drawn(edge, centre) {
    if (edge.normals.length !== 2) return true;
    var n0 = edge.normals[0], n1 = edge.normals[1];
    if (dot(n0, n1) < kCreaseCos) return true;
    var mid = [0, 1, 2].map(function (k) { return centre[k] - 0.5 * (edge.a[k] + edge.b[k]); });
    return (dot(n0, mid) > 0) !== (dot(n1, mid) > 0);
  }
  // DrawWireframe's lines as an SVG path: clipped at the near plane, in 32 pieces through a lens.
  function path(cam, edges) {
    var d = [], pieces = cam.lens ? 32 : 1, m = cam.camFromWorld;
    edges.forEach(function (edge) {
      if (!drawn(edge, cam.centre)) return;
      var a = apply(m, edge.a), b = apply(m, edge.b);
      if (a[2] < kNear && b[2] < kNear) return;
      if (a[2] < kNear) a = b.map(function (bk, k) { return bk + (a[k] - bk) * ((b[2] - kNear) / (b[2] - a[2])); });
      if (b[2] < kNear) b = a.map(function (ak, k) { return ak + (b[k] - ak) * ((a[2] - kNear) / (a[2] - b[2])); });
      for (var k = 0; k <= pieces; ++k) {
        var s = k / pieces, p = pixel(cam, [0, 1, 2].map(function (j) { return a[j] + (b[j] - a[j]) * s; }));
        if (isFinite(p[0]) && isFinite(p[1])) d.push((k ? 'L' : 'M') + p[0].toFixed(2) + ' ' + p[1].toFixed(2));
      }
    });
    return d.join('');
  }

  // Each parameter at either end of its range, the others at `v` (the faint lines).
  function extremes(v) {
    var out = [];
    params.forEach(function (p, i) {
      [p.lo, p.hi].forEach(function (end) {
        if (end === v[i]) return;
        var moved = v.slice();
        moved[i] = end;
        out = out.concat(sceneEdges(moved));
      });
    });
    return out;
  }
  // Every camera's two paths at `v`: the wireframe and, faint, the extremes.
  function draw(v) {
    var edges = sceneEdges(v), faint = extremes(v);
    data.cameras.forEach(function (c, i) {
      var svg = document.getElementById('camera-' + i), cam = camera(c, v);
      svg.querySelector('path.current').setAttribute('d', path(cam, edges));
      svg.querySelector('path.extreme').setAttribute('d', path(cam, faint));
    });
  }
  return {data: data, names: names, expressions: expressions, camera: camera, pixel: pixel,
          worldFromNode: worldFromNode, apply: apply, draw: draw};
})();
