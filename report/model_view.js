(function () {
  'use strict';
  var box = document.getElementById('model-view');
  var canvas = document.createElement('canvas');
  var gl = canvas.getContext('webgl', {antialias: true}) || canvas.getContext('experimental-webgl');
  if (!gl) {
    box.textContent = 'This browser offers no WebGL: the 3D view is left out (model.glb opens in Blender).';
    box.style.height = 'auto';
    return;
  }
  box.appendChild(canvas);
  var width = box.clientWidth, height = box.clientHeight;
  var renderer = new THREE.WebGLRenderer({canvas: canvas, context: gl, antialias: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(width, height);
  renderer.setClearColor(0xeeeeff);
  // The texture holds encoded (sRGB) colours: encode the output again, or the model looks dark.
  if (Number(THREE.REVISION) >= 112) renderer.outputEncoding = THREE.sRGBEncoding;
  else renderer.gammaOutput = true;
  var scene = new THREE.Scene();
  var camera = new THREE.PerspectiveCamera(40, width / height, 0.01, 1000);
  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  function render() { renderer.render(scene, camera); }
  controls.addEventListener('change', render);
  var text = document.getElementById('model-glb').textContent.trim();
  var raw = atob(text), bytes = new Uint8Array(raw.length);
  for (var i = 0; i < raw.length; ++i) bytes[i] = raw.charCodeAt(i);
  new THREE.GLTFLoader().parse(bytes.buffer, '', function (gltf) {
    scene.add(gltf.scene);
    var bounds = new THREE.Box3().setFromObject(gltf.scene);
    var centre = bounds.getCenter(new THREE.Vector3()), size = bounds.getSize(new THREE.Vector3()).length() || 1;
    camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.45, 0.8).multiplyScalar(size));
    camera.near = size / 1000; camera.far = size * 100; camera.updateProjectionMatrix();
    controls.target.copy(centre);
    controls.update();
    render();
    // Textures decode asynchronously: draw again once they are in.
    setTimeout(render, 300);
  }, function (error) { console.error('model.glb: ' + error); });
})();
