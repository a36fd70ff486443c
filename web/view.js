// What the web views share (report_viewer.js, tileset_viewer.js): a canvas
// with a z-up camera, lights and orbit controls drawn on demand, framing,
// click picking, the pick panel and number format. esbuild bundles it into
// each view's script.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

// Drawn unlit (each pixel its element's colour), for tests that count colours.
export const unlit = () => /(^|[#&])unlit\b/.test(location.hash);

export function webglAvailable() {
  try {
    const c = document.createElement('canvas');
    return !!(c.getContext('webgl2') || c.getContext('webgl'));
  } catch (e) {
    return false;
  }
}

export function say(div, text) {
  const p = document.createElement('p');
  p.className = 'view3d-note';
  p.textContent = text;
  div.appendChild(p);
  div.dataset.state = 'unavailable';
}

export function material(colour, vertexColours) {
  const options = { side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 };
  if (vertexColours) options.vertexColors = true;
  else options.color = new THREE.Color(colour);
  return unlit() ? new THREE.MeshBasicMaterial(options) : new THREE.MeshLambertMaterial(options);
}

// The canvas, camera (z up, as the model), lights and orbit controls; the
// scene is drawn when something changes, not in a loop.
export function makeView(div) {
  const holder = document.createElement('div');
  holder.className = 'view3d-canvas';
  div.appendChild(holder);
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  holder.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color('#f4f4ef');
  const camera = new THREE.PerspectiveCamera(35, 1, 0.5, 50000);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.HemisphereLight('#ffffff', '#8a8678', 2.0));
  const sun = new THREE.DirectionalLight('#ffffff', 1.6);
  sun.position.set(-0.5, -0.8, 1.2);  // from the south-west, high
  scene.add(sun);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.screenSpacePanning = false;  // pan over the ground
  controls.maxPolarAngle = Math.PI * 0.495;  // stay above it
  // before: called ahead of each frame; listeners: after each; drawn: once, after the next.
  const view = { div, renderer, scene, camera, controls, before: [], listeners: [], drawn: [] };
  let queued = false;
  view.render = () => {
    if (queued) return;
    queued = true;
    requestAnimationFrame(() => {
      queued = false;
      for (const f of view.before) f();
      renderer.render(scene, camera);
      for (const f of view.listeners) f();
      for (const f of view.drawn.splice(0)) f();
    });
  };
  // Resolves once what the scene holds now is on the canvas.
  view.frame = () => new Promise((ok) => { view.drawn.push(ok); view.render(); });
  const resize = () => {
    const w = holder.clientWidth || 600, h = holder.clientHeight || 420;
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    view.render();
  };
  new ResizeObserver(resize).observe(holder);
  resize();
  controls.addEventListener('change', view.render);
  return view;
}

// Looks at box from the south-west, 35 degrees up, as close as keeps each of
// its corners in view.
export function frame(view, box) {
  const centre = box.getCenter(new THREE.Vector3());
  const up = THREE.MathUtils.degToRad(35), az = THREE.MathUtils.degToRad(225);
  const back = new THREE.Vector3(Math.cos(up) * Math.sin(az), Math.cos(up) * Math.cos(az), Math.sin(up));
  const right = new THREE.Vector3(0, 0, 1).cross(back).normalize(), top = back.clone().cross(right);
  const tanV = Math.tan(THREE.MathUtils.degToRad(view.camera.fov) / 2), tanH = tanV * view.camera.aspect;
  let d = 5;
  for (let k = 0; k < 8; ++k) {
    const c = new THREE.Vector3(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                                k & 4 ? box.max.z : box.min.z).sub(centre);
    const z = c.dot(back);
    d = Math.max(d, z + Math.abs(c.dot(right)) / tanH * 1.05, z + Math.abs(c.dot(top)) / tanV * 1.05);
  }
  view.camera.position.copy(centre).addScaledVector(back, d);
  view.camera.near = Math.max(0.1, d / 1000);
  view.camera.far = d * 20;
  view.camera.updateProjectionMatrix();
  view.controls.target.copy(centre);
  view.controls.update();
  view.render();
}

// Calls pick(hit) for a click (not a drag) on one of objects, hit null off them.
export function onClick(view, objects, pick) {
  const canvas = view.renderer.domElement;
  let down = null;
  canvas.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const r = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, view.camera);
    const hits = ray.intersectObjects(objects(), false);
    pick(hits.length ? hits[0] : null);
  });
}

// Where a point of the scene is drawn, in page pixels (tests click there).
export function onScreen(view, p) {
  const v = p.clone().project(view.camera);
  const r = view.renderer.domElement.getBoundingClientRect();
  return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height, depth: v.z };
}

export function panel(div) {
  const p = document.createElement('div');
  p.className = 'view3d-pick';
  p.textContent = 'Click an element for its figures. Drag to turn, right-drag to pan, wheel to zoom.';
  div.appendChild(p);
  return p;
}

export const num = (v, d) => (v == null || v < 0 || !isFinite(v) ? '\u2014' : v.toLocaleString('en-US', { minimumFractionDigits: d, maximumFractionDigits: d }));
