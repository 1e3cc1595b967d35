// What the report (viewer.js) and the spec editor (editor.js) share: typed arrays from the
// page's base64, DOM helpers, and the 3D viewport with the part's mesh.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

// ---- typed arrays from base64 -------------------------------------------------------------
export function bytes(b64) {
  const s = atob(b64 || '');
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out;
}
export const f32 = (b64) => new Float32Array(bytes(b64).buffer);
export const u32 = (b64) => new Uint32Array(bytes(b64).buffer);
export const i32 = (b64) => new Int32Array(bytes(b64).buffer);

// ---- small DOM helpers ----------------------------------------------------------------------
export const $ = (id) => document.getElementById(id);
export function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c instanceof Node ? c : document.createTextNode(String(c)));
  return e;
}
export const fmt = (x, digits = 1) => (typeof x === 'number' ? x.toFixed(digits) : String(x ?? ''));
export const pct = (a, b) => (b > 0 ? `${((100 * a) / b).toFixed(1)} %` : '–');
export const rgb = (c) => `rgb(${c[0]},${c[1]},${c[2]})`;

// A table: columns [{title, num}], rows of cells; onPick(rowIndex) makes rows clickable.
export function table(columns, rows, onPick) {
  const head = el('tr', {}, ...columns.map((c) => el('th', c.num ? { class: 'num' } : {}, c.title)));
  const body = rows.map((cells, i) => el('tr', onPick ? { class: 'pick', onclick: () => onPick(i) } : {},
    ...cells.map((cell, k) => el('td', columns[k].num ? { class: 'num' } : {}, cell))));
  return el('table', {}, el('thead', {}, head), el('tbody', {}, ...body));
}

// The centre and radius of a box {min, max}, for framing the camera.
export function box(b) {
  const min = new THREE.Vector3(...b.min), max = new THREE.Vector3(...b.max);
  return { centre: min.clone().add(max).multiplyScalar(0.5), radius: Math.max(min.distanceTo(max) / 2, 1) };
}

// The 3D viewport in the element `viewport`: renderer, camera orbiting a scene of `radius`
// (mm), lights, and frameOn({centre, radius}). `render()` is called after each drawing;
// redraw() asks for one where the scene changes without input.
export function createViewport(viewport, radius, render = () => {}) {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setClearColor(0xeef1f4);
  viewport.append(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, 1, radius / 1000, radius * 100);
  camera.up.set(0, 0, 1);
  const controls = new OrbitControls(camera, renderer.domElement);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
  const headlight = new THREE.DirectionalLight(0xffffff, 1.4);
  camera.add(headlight);
  scene.add(camera);
  // Drawn on demand: when the camera moves, the viewport is resized, or after any input on
  // the page (every change to the scene follows one), so that an idle page costs nothing.
  let stale = true;
  const redraw = () => { stale = true; };
  function frameOn({ centre, radius: r }) {
    camera.position.copy(centre).add(new THREE.Vector3(0.9, -1.2, 0.9).normalize().multiplyScalar(r * 3));
    controls.target.copy(centre);
    stale = true;
  }
  controls.addEventListener('change', redraw);
  for (const type of ['pointerdown', 'pointerup', 'click', 'change', 'input', 'keydown', 'keyup', 'wheel'])
    window.addEventListener(type, redraw, true);
  const resizers = [];
  function resize() {
    const w = viewport.clientWidth, h = viewport.clientHeight;
    renderer.setSize(w, h);
    for (const r of resizers) r(w, h);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
    redraw();
  }
  window.addEventListener('resize', resize);
  function start() {
    resize();
    const frame = () => {
      if (stale) {
        stale = false;
        controls.update();
        renderer.render(scene, camera);
        render();
      }
      requestAnimationFrame(frame);
    };
    frame();
  }
  // The pointer's place in normalised device coordinates, for a raycaster.
  function ndc(e) {
    const r = renderer.domElement.getBoundingClientRect();
    return new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  }
  // Calls onClick(event) for a press and release without a drag in between.
  function onClick(handler) {
    let down = null;
    renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
    renderer.domElement.addEventListener('pointerup', (e) => {
      if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) <= 4) handler(e);
    });
  }
  return { renderer, scene, camera, controls, frameOn, resizers, start, ndc, onClick, redraw };
}

// The part's mesh as the page carries it ({positions, indices, faces} in base64): a mesh
// with a colour per vertex, and paint(colourOfFace) colouring every triangle by the face
// id it belongs to (colourOfFace(id) gives [r, g, b] in 0..255).
export function partMesh(mesh) {
  const positions = f32(mesh.positions), indices = u32(mesh.indices), triangleFaces = i32(mesh.faces);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  const colours = new Float32Array(positions.length);
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  function paint(colourOfFace) {
    for (let t = 0; t < triangleFaces.length; ++t) {
      const c = colourOfFace(triangleFaces[t]);
      for (let k = 0; k < 3; ++k) colours.set([c[0] / 255, c[1] / 255, c[2] / 255], 3 * indices[3 * t + k]);
    }
    geometry.attributes.color.needsUpdate = true;
  }
  geometry.computeVertexNormals();
  const object = new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({
    vertexColors: true, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  }));
  // The box of the faces `ids` (a Set), for flying the camera to them.
  function facesBox(ids, least = 1) {
    const min = new THREE.Vector3(Infinity, Infinity, Infinity), max = min.clone().negate(), p = new THREE.Vector3();
    for (let t = 0; t < triangleFaces.length; ++t) {
      if (!ids.has(triangleFaces[t])) continue;
      for (let k = 0; k < 3; ++k) {
        p.fromArray(positions, 3 * indices[3 * t + k]);
        min.min(p); max.max(p);
      }
    }
    return { centre: min.clone().add(max).multiplyScalar(0.5), radius: Math.max(min.distanceTo(max) / 2, least) };
  }
  return { object, geometry, positions, indices, triangleFaces, paint, facesBox };
}

// The working plane (z = 0) under a part of `partBox`: a translucent square with a grid.
export function workingPlane(partBox) {
  const size = 3 * partBox.radius;
  const group = new THREE.Group();
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(size, size), new THREE.MeshBasicMaterial({
    color: 0x8a96a8, transparent: true, opacity: 0.25, side: THREE.DoubleSide, depthWrite: false,
  }));
  const grid = new THREE.GridHelper(size, 12, 0x8a96a8, 0xb4bcc8);
  grid.rotation.x = Math.PI / 2;
  group.add(plane, grid);
  group.position.set(partBox.centre.x, partBox.centre.y, 0);
  return group;
}
