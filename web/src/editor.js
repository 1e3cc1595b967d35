// The inspection-spec editor's page: the part from the page's data, faces picked into tasks
// and roles, control points clicked onto the exact faces, settings, and spec.yaml and
// points.csv written as the command line reads them. Bundled with three.js by esbuild
// (src/CMakeLists.txt).

import * as THREE from 'three';
import { $, box, createViewport, el, fmt, partMesh, rgb, table, workingPlane } from './common.js';
import { snapToSurface } from './snap.js';
import { specYaml, pointsCsv } from './spec_yaml.js';

const data = JSON.parse(document.getElementById('scanplan-data').textContent);
const faceOf = (id) => data.faces[id - 1];
const FACE_TASKS = ['gdt', 'trim', 'surface'];
const TASK_TYPES = [...FACE_TASKS, 'global', 'points'];
const ROLES = ['priority', 'fixture', 'specular'];
const palette = {
  selected: [255, 170, 0], gdt: [200, 60, 160], trim: [40, 140, 220], surface: [60, 170, 90],
  priority: [235, 125, 40], fixture: [95, 100, 110], specular: [150, 215, 245], none: [205, 210, 216],
};

// ---- the spec being edited --------------------------------------------------------------------
// `document` is the spec as read: the settings write into it, and what the editor does not
// show (registration, cell, planner, a scanner of its own, ...) is written back unchanged.
const loaded = data.spec;
const state = {
  document: loaded ? structuredClone(loaded.document || {}) : {},
  tasks: [],   // {type, faces: Set of ids}
  roles: Object.fromEntries(ROLES.map((r) => [r, new Set(loaded ? loaded[r] : [])])),
  points: [],  // {position, normal, face, exact}
  selection: new Set(),
};
if (loaded) {
  for (const t of loaded.tasks) {
    if (t.type === 'points' && state.tasks.some((u) => u.type === 'points')) continue;  // one points list
    state.tasks.push({ type: t.type, faces: new Set(t.faces) });
  }
  state.points = loaded.points.map((p) => ({ ...p, exact: false }));
}

// ---- header and legend ----------------------------------------------------------------------------
document.title = `scanplan spec editor – ${data.title}`;
$('title').textContent = `scanplan spec editor – ${data.title}`;
$('editor-header').textContent = [`part ${data.title}`, `${data.faces.length} faces`,
  `${data.characteristics.length} characteristics`, loaded ? `starting from ${loaded.file}` : 'a new spec', `scanplan ${data.header.version}`, data.header.date].join(' · ');
for (const [name, title] of [['selected', 'selected'], ['gdt', 'gdt task'], ['trim', 'trim task'], ['surface', 'surface task'],
  ['priority', 'priority'], ['fixture', 'fixture'], ['specular', 'specular'], ['none', 'not assigned']]) {
  $('legend').append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(palette[name])}` }), title));
}
$('legend').append(el('div', {}, el('span', { class: 'sw', style: 'background:#e0115f' }), 'control point'));

// ---- 3D scene -----------------------------------------------------------------------------------------
const viewport = $('viewport');
const partBounds = box(data.bounds);
const { renderer, scene, camera, controls, frameOn, start, ndc, onClick } = createViewport(viewport, partBounds.radius);
const mesh = partMesh(data.mesh);
const partFrame = new THREE.Group();  // the part placed in its rest orientation
partFrame.matrixAutoUpdate = false;
partFrame.add(mesh.object);
scene.add(partFrame);
const pointGeometry = new THREE.BufferGeometry();
const pointCloud = new THREE.Points(pointGeometry, new THREE.PointsMaterial({ color: 0xe0115f, size: 12, sizeAttenuation: false, depthTest: false }));
partFrame.add(pointCloud);
let plane = null;

// The faces a task of type gdt targets beyond those it lists: the file's GD&T faces.
function gdtFileFaces() {
  const gdt = state.document.gdt;
  return gdt === 'all' ? data.gdt_all_faces : gdt === 'from-file' ? data.gdt_faces : [];
}
function colourOf(id) {
  if (state.selection.has(id)) return palette.selected;
  if (state.roles.fixture.has(id)) return palette.fixture;
  for (const t of state.tasks) {
    if (t.faces.has(id) || (t.type === 'gdt' && gdtFileFaces().includes(id))) return palette[t.type];
  }
  if (state.roles.priority.has(id)) return palette.priority;
  if (state.roles.specular.has(id)) return palette.specular;
  return palette.none;
}

// ---- rest orientation ----------------------------------------------------------------------------------
// part.rest as the spec gives it: absent (as modelled), auto, all, a face id or a matrix.
function restMatrix(rest) {
  const m = new THREE.Matrix4();
  const byFace = typeof rest === 'number' ? data.rests.find((r) => r.face === rest) : null;
  const rows = Array.isArray(rest) ? rest : rest === 'auto' || rest === 'all' ? data.rests[0]?.part_to_world : byFace?.part_to_world;
  if (rows) {
    m.set(...rows.flat());
  } else {  // as modelled, lifted onto the plane
    m.makeTranslation(0, 0, -data.bounds.min[2]);
  }
  return m;
}
let placedBox = partBounds;  // the part's box where it rests
function placePart() {
  partFrame.matrix.copy(restMatrix(state.document.part?.rest));
  partFrame.updateMatrixWorld(true);
  const placed = new THREE.Box3().setFromObject(mesh.object);
  const b = box({ min: placed.min.toArray(), max: placed.max.toArray() });
  if (plane) scene.remove(plane);
  plane = workingPlane(b);
  scene.add(plane);
  placedBox = b;
  frameOn(b);
}
$('frame').addEventListener('click', () => frameOn(placedBox));

// ---- painting and the side panel ---------------------------------------------------------------------
function faceLabel(id) {
  const f = faceOf(id);
  return `face ${id} · ${f.type}${f.name ? ` · ${f.name}` : ''}`;
}
function assignments(id) {
  const tasks = state.tasks.map((t, k) => (t.faces.has(id) ? `task ${k + 1} (${t.type})` : null)).filter(Boolean);
  return [...tasks, ...ROLES.filter((r) => state.roles[r].has(id))];
}

function refresh() {
  const colours = data.faces.map((f) => colourOf(f.id));  // once a face, not a triangle
  mesh.paint((id) => colours[id - 1]);
  const p = new Float32Array(state.points.flatMap((q) => q.position));
  pointGeometry.setAttribute('position', new THREE.BufferAttribute(p, 3));
  pointGeometry.computeBoundingSphere();
  showSelection();
  showTasks();
  showPoints();
  showIssues();
  document.body.dataset.selected = String(state.selection.size);
  document.body.dataset.tasks = String(state.tasks.length);
  document.body.dataset.points = String(state.points.length);
}

function showSelection() {
  const ids = [...state.selection].sort((a, b) => a - b);
  $('selection').textContent = ids.length === 0 ? 'No face selected.'
    : `${ids.length} face${ids.length > 1 ? 's' : ''}: ${ids.join(', ')}`;
  const target = $('task-target'), kept = target.value;
  target.replaceChildren(...state.tasks.map((t, k) => (FACE_TASKS.includes(t.type)
    ? el('option', { value: String(k) }, `task ${k + 1} (${t.type})`) : null)).filter(Boolean),
  ...FACE_TASKS.map((type) => el('option', { value: `new-${type}` }, `a new ${type} task`)));
  if ([...target.options].some((o) => o.value === kept)) target.value = kept;
}

function showTasks() {
  const rows = state.tasks.map((t, k) => {
    const type = el('select', { 'data-task': String(k) }, ...TASK_TYPES.map((name) => el('option', { value: name }, name)));
    type.value = t.type;
    type.addEventListener('change', () => { t.type = type.value; if (!FACE_TASKS.includes(t.type)) t.faces.clear(); refresh(); });
    const what = t.type === 'points' ? `${state.points.length} control points`
      : t.type === 'global' ? 'the whole shape'
        : [...t.faces].sort((a, b) => a - b).join(', ') || (t.type === 'gdt' && gdtFileFaces().length ? 'the file’s GD&T faces' : '–');
    const select = el('button', { onclick: () => { state.selection = new Set(t.faces); refresh(); } }, 'select');
    const remove = el('button', { onclick: () => { state.tasks.splice(k, 1); refresh(); } }, 'remove');
    return [k + 1, type, what, FACE_TASKS.includes(t.type) ? el('span', {}, select, remove) : remove];
  });
  $('tasks').replaceChildren(state.tasks.length
    ? table([{ title: 'task', num: true }, { title: 'type' }, { title: 'faces' }, { title: '' }], rows)
    : el('p', { class: 'muted' }, 'No task yet: without one the plan measures the whole shape (one global task).'));
}

function showPoints() {
  $('points-info').textContent = picking ? 'click on the part to add a point' : `${state.points.length} points`;
  const coordinate = (q, k, which) => {
    const input = el('input', { class: 'coord', type: 'number', step: 'any', value: String(q[which][k]) });
    input.addEventListener('change', () => { q[which][k] = Number(input.value); q.exact = false; refresh(); });
    return input;
  };
  $('points').replaceChildren(state.points.length === 0 ? el('p', { class: 'muted' }, 'None.')
    : table([{ title: '', num: true }, { title: 'x mm' }, { title: 'y mm' }, { title: 'z mm' }, { title: 'face', num: true }, { title: 'snap' }, { title: '' }],
      state.points.map((q, i) => [i + 1, coordinate(q, 0, 'position'), coordinate(q, 1, 'position'), coordinate(q, 2, 'position'),
        q.face, q.exact ? 'exact' : `mesh ±${fmt(data.deflection, 2)}`,
        el('button', { onclick: () => { state.points.splice(i, 1); refresh(); } }, 'remove')])));
}

// ---- checks, as the command line makes them ------------------------------------------------------------
function issues() {
  const found = [];
  const fileFaces = gdtFileFaces();
  if (state.document.gdt && state.document.gdt !== 'none' && fileFaces.length === 0)
    found.push(`gdt: ${state.document.gdt}, but ${data.title} carries no GD&T attached to faces`);
  state.tasks.forEach((t, k) => {
    const name = `task ${k + 1} (${t.type})`;
    if (FACE_TASKS.includes(t.type)) {
      const named = [...t.faces];
      const targets = [...named, ...(t.type === 'gdt' ? fileFaces : [])].filter((id) => !state.roles.fixture.has(id));
      if (targets.length === 0) {
        found.push(`${name} has no target faces` + (named.length ? ': all of them are fixtures'
          : t.type === 'gdt' ? ': list them, or use gdt: from-file on a part with GD&T' : ': list them'));
      }
    }
    if (t.type === 'points' && state.points.length === 0) found.push(`${name} has no control points: pick them on the part`);
  });
  if (state.points.length && !state.tasks.some((t) => t.type === 'points'))
    found.push(`${state.points.length} control points, but no points task measures them`);
  const m = state.document.markers;
  if (m && typeof m === 'object' && !(m.grid > 0)) found.push('markers.grid must be a positive step in mm');
  return found;
}
function showIssues() {
  const found = issues();
  $('issues').replaceChildren(...(found.length ? found.map((text) => el('li', { class: 'bad' }, text))
    : [el('li', { class: 'muted' }, 'The spec is complete.')]));
  $('download-spec').disabled = found.length > 0;
  $('download-points').disabled = state.points.length === 0;
  document.body.dataset.issues = String(found.length);
  $('preview').textContent = specText();
}

// ---- selecting faces -----------------------------------------------------------------------------------
const raycaster = new THREE.Raycaster();
function hitAt(e) {
  raycaster.setFromCamera(ndc(e), camera);
  return raycaster.intersectObject(mesh.object)[0] || null;
}
let picking = false;  // clicks add control points instead of selecting faces
onClick((e) => {
  const hit = hitAt(e);
  if (picking) return hit && addPoint(hit);
  const id = hit ? mesh.triangleFaces[hit.faceIndex] : 0;
  if (!e.shiftKey) state.selection = new Set(id ? [id] : []);
  else if (id && state.selection.has(id)) state.selection.delete(id);
  else if (id) state.selection.add(id);
  refresh();
});

// Shift-drag: a box; the faces whose triangles all fall inside it join the selection.
let boxStart = null;
viewport.addEventListener('pointerdown', (e) => {
  if (!e.shiftKey || e.button !== 0 || picking) return;
  controls.enabled = false;
  boxStart = [e.clientX, e.clientY];
}, true);
window.addEventListener('pointermove', (e) => {
  if (boxStart) {
    const r = viewport.getBoundingClientRect(), b = $('box');
    Object.assign(b.style, { display: 'block', left: `${Math.min(e.clientX, boxStart[0]) - r.left}px`, top: `${Math.min(e.clientY, boxStart[1]) - r.top}px`,
      width: `${Math.abs(e.clientX - boxStart[0])}px`, height: `${Math.abs(e.clientY - boxStart[1])}px` });
  }
});
window.addEventListener('pointerup', (e) => {
  if (!boxStart) return;
  const [x0, y0] = boxStart;
  boxStart = null;
  controls.enabled = true;
  $('box').style.display = 'none';
  if (Math.hypot(e.clientX - x0, e.clientY - y0) > 4) selectInBox(ndc({ clientX: x0, clientY: y0 }), ndc(e));
});
function selectInBox(a, b) {
  const [xmin, xmax, ymin, ymax] = [Math.min(a.x, b.x), Math.max(a.x, b.x), Math.min(a.y, b.y), Math.max(a.y, b.y)];
  const outside = new Set(), seen = new Set(), p = new THREE.Vector3();
  for (let t = 0; t < mesh.triangleFaces.length; ++t) {
    const id = mesh.triangleFaces[t];
    seen.add(id);
    for (let k = 0; k < 3 && !outside.has(id); ++k) {
      p.fromArray(mesh.positions, 3 * mesh.indices[3 * t + k]).applyMatrix4(partFrame.matrixWorld).project(camera);
      if (p.x < xmin || p.x > xmax || p.y < ymin || p.y > ymax || p.z > 1) outside.add(id);
    }
  }
  for (const id of seen) if (!outside.has(id)) state.selection.add(id);
  refresh();
}

// The face under the pointer, named in a tag beside it.
viewport.addEventListener('pointermove', (e) => {
  const tag = $('hover');
  const hit = boxStart ? null : hitAt(e);
  if (!hit) { tag.style.display = 'none'; return; }
  const id = mesh.triangleFaces[hit.faceIndex], r = viewport.getBoundingClientRect(), on = assignments(id);
  tag.textContent = faceLabel(id) + (on.length ? ` · ${on.join(', ')}` : '');
  Object.assign(tag.style, { display: 'block', left: `${e.clientX - r.left + 14}px`, top: `${e.clientY - r.top + 10}px` });
});

// ---- control points ------------------------------------------------------------------------------------
// A clicked point, snapped onto its face's exact surface where the page has it (planes,
// cylinders, cones, spheres, tori), else on the mesh; with the outward normal there.
function addPoint(hit) {
  const id = mesh.triangleFaces[hit.faceIndex];
  const inverse = partFrame.matrixWorld.clone().invert();
  const local = hit.point.clone().applyMatrix4(inverse);
  const normal = hit.face.normal.clone().normalize();  // the triangle's, in the part frame
  const exact = snapToSurface(faceOf(id).surface, local.toArray(), normal.toArray());
  state.points.push(exact ? { position: exact.position, normal: exact.normal, face: id, exact: true }
    : { position: local.toArray(), normal: normal.toArray(), face: id, exact: false });
  if (!state.tasks.some((t) => t.type === 'points')) state.tasks.push({ type: 'points', faces: new Set() });
  refresh();
}
$('pick-points').addEventListener('click', () => {
  picking = !picking;
  $('pick-points').classList.toggle('on', picking);
  showPoints();
});

// ---- assigning the selection ---------------------------------------------------------------------------
$('assign-task').addEventListener('click', () => {
  const target = $('task-target').value;
  let task;
  if (target.startsWith('new-')) {
    task = { type: target.slice(4), faces: new Set() };
    state.tasks.push(task);
  } else {
    task = state.tasks[Number(target)];
  }
  for (const id of state.selection) task.faces.add(id);
  refresh();
});
for (const role of ROLES) {
  $(`role-${role}`).addEventListener('click', () => { for (const id of state.selection) state.roles[role].add(id); refresh(); });
}
$('role-none').addEventListener('click', () => { for (const r of ROLES) for (const id of state.selection) state.roles[r].delete(id); refresh(); });
$('clear-selection').addEventListener('click', () => { state.selection.clear(); refresh(); });
{
  const type = $('new-task-type');
  type.append(...TASK_TYPES.map((name) => el('option', { value: name }, name)));
  $('add-task').addEventListener('click', () => {
    state.tasks.push({ type: type.value, faces: FACE_TASKS.includes(type.value) ? new Set(state.selection) : new Set() });
    refresh();
  });
}

// ---- characteristics -----------------------------------------------------------------------------------
if (data.characteristics.length === 0) {
  $('characteristics').append(el('p', { class: 'muted' }, 'The part carries no GD&T the reader found.'));
} else {
  const limits = (c) => (c.dimension ? `${fmt(c.value, 3)} (${fmt(c.limits[0], 3)} to ${fmt(c.limits[1], 3)})` : fmt(c.value, 3));
  $('characteristics').append(table([{ title: 'id', num: true }, { title: 'kind' }, { title: 'value', num: true }, { title: 'datums' },
    { title: 'faces' }], data.characteristics.map((c) => [c.id, c.kind, limits(c), c.datums.join(' | '), c.faces.join(', ')]),
  (i) => {
    state.selection = new Set(data.characteristics[i].faces);
    $('characteristics').querySelectorAll('tbody tr').forEach((row, k) => row.classList.toggle('selected', k === i));
    frameOn(box(boxOf(state.selection)));
    refresh();
  }));
}
function boxOf(ids) {
  const b = mesh.facesBox(ids, partBounds.radius / 4);
  const c = b.centre.clone().applyMatrix4(partFrame.matrixWorld);
  return { min: c.clone().subScalar(b.radius).toArray(), max: c.clone().addScalar(b.radius).toArray() };
}

// ---- settings -------------------------------------------------------------------------------------------
// Each control writes its key of the spec, and removes it when set back to the default.
function setKey(path, value) {
  let node = state.document;
  for (const key of path.slice(0, -1)) node = node[key] && typeof node[key] === 'object' ? node[key] : (node[key] = {});
  if (value === undefined) delete node[path.at(-1)];
  else node[path.at(-1)] = value;
  if (path[0] === 'part' && Object.keys(state.document.part).length === 0) delete state.document.part;
}
function options(select, entries, value) {
  select.replaceChildren(...entries.map(([v, text]) => el('option', { value: v }, text)));
  select.value = value;
}
{
  const own = state.document.scanner && typeof state.document.scanner === 'object';
  options($('scanner'), [['', `default (${data.default_preset})`], ...(own ? [['own', 'the spec’s own scanner']] : []),
    ...data.presets.map((p) => [p, p])], own ? 'own' : state.document.scanner || '');
  $('scanner').addEventListener('change', (e) => { if (e.target.value !== 'own') setKey(['scanner'], e.target.value || undefined); refresh(); });
}
{
  const rests = [['cad', 'as modelled'], ['auto', 'auto (the steadiest)'], ['all', 'all (planned one after another)'],
    ...data.rests.map((r, k) => [`rest-${k}`, `${k + 1}: ${r.face ? `on face ${r.face}` : `down ${r.down.map((x) => fmt(x, 2)).join(' ')}`}, ` +
      `margin ${fmt(r.margin, 2)}, contact ${fmt(r.contact_area, 0)} mm²`])];
  const given = state.document.part?.rest;
  let value = given === undefined ? 'cad' : typeof given === 'string' ? given : null;
  if (typeof given === 'number') {
    const k = data.rests.findIndex((r) => r.face === given);
    value = k >= 0 ? `rest-${k}` : null;
  }
  if (value === null) { rests.push(['given', 'as the spec gives it']); value = 'given'; }
  options($('rest'), rests, value);
  $('rest').addEventListener('change', (e) => {
    const v = e.target.value;
    if (v === 'given') return;
    const r = v.startsWith('rest-') ? data.rests[Number(v.slice(5))] : null;
    setKey(['part', 'rest'], v === 'cad' ? undefined : r ? (r.face || r.part_to_world) : v);
    placePart();
    refresh();
  });
}
{
  options($('gdt'), [['', 'no'], ['from-file', 'from-file: toleranced and datum faces'], ['all', 'all: dimensioned faces too']],
    state.document.gdt === 'none' ? '' : state.document.gdt || '');
  $('gdt').addEventListener('change', (e) => { setKey(['gdt'], e.target.value || (state.document.gdt === 'none' ? 'none' : undefined)); refresh(); });
}
{
  const m = state.document.markers;
  const file = typeof m === 'string';
  $('marker-grid').value = m && !file ? m.grid : 0;
  $('marker-margin').value = m && !file && m.margin !== undefined ? m.margin : 100;
  // Markers on the fixture models, when the spec has some; a list of places stays as given.
  const places = [['plate', 'plate'], ['part', 'part'], ['both', 'both']];
  if (Array.isArray(state.document.fixtures) && state.document.fixtures.length) places.push(['fixture', 'fixture models']);
  const listed = Array.isArray(m?.on);
  options($('marker-on'), places, m && !file && m.on && !listed ? m.on : 'plate');
  for (const id of ['marker-grid', 'marker-margin', 'marker-on']) $(id).disabled = file;
  if (listed) $('marker-on').disabled = true;
  if (file) $('markers-file').textContent = `markers from ${m} (kept as the spec gives them)`;
  const update = () => {
    const grid = Number($('marker-grid').value);
    if (grid === 0) { setKey(['markers'], undefined); refresh(); return; }
    const markers = { grid };
    const margin = Number($('marker-margin').value), on = $('marker-on').value;
    if (margin !== 100 || state.document.markers?.margin !== undefined) markers.margin = margin;
    if (listed) markers.on = state.document.markers.on;
    else if (on !== 'plate' || state.document.markers?.on !== undefined) markers.on = on;
    setKey(['markers'], markers);
    refresh();
  };
  for (const id of ['marker-grid', 'marker-margin', 'marker-on']) $(id).addEventListener('change', update);
}

// ---- writing the files ---------------------------------------------------------------------------------
function specText() {
  return specYaml(state, data);
}
function download(name, text) {
  const a = el('a', { href: URL.createObjectURL(new Blob([text], { type: 'text/plain' })), download: name });
  document.body.append(a);
  a.click();
  a.remove();
}
$('download-spec').addEventListener('click', () => download('spec.yaml', specText()));
$('download-points').addEventListener('click', () => download('points.csv', pointsCsv(state.points)));

// For the page's tests: a visible point of face `id` on the screen (client pixels), or null.
window.scanplanEditor = {
  pointOnFace(id) {
    const p = new THREE.Vector3(), q = new THREE.Vector3(), r = renderer.domElement.getBoundingClientRect();
    for (let t = 0; t < mesh.triangleFaces.length; ++t) {
      if (mesh.triangleFaces[t] !== id) continue;
      p.set(0, 0, 0);
      for (let k = 0; k < 3; ++k) p.add(q.fromArray(mesh.positions, 3 * mesh.indices[3 * t + k]));
      p.divideScalar(3).applyMatrix4(partFrame.matrixWorld);
      const s = p.clone().project(camera);
      if (Math.abs(s.x) > 0.9 || Math.abs(s.y) > 0.9) continue;
      raycaster.setFromCamera(new THREE.Vector2(s.x, s.y), camera);
      const hit = raycaster.intersectObject(mesh.object)[0];
      if (hit && hit.faceIndex === t) return { x: r.left + ((s.x + 1) / 2) * r.width, y: r.top + ((1 - s.y) / 2) * r.height };
    }
    return null;
  },
};

placePart();
refresh();
start();
requestAnimationFrame(() => { document.body.dataset.ready = '1'; });
