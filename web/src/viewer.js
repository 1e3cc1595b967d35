// The report's page: reads the plan's data from the page, draws the 3D scene with three.js
// and fills the tables. Bundled with three.js by esbuild into one script (src/CMakeLists.txt).

import * as THREE from 'three';
import { CSS2DRenderer, CSS2DObject } from 'three/addons/renderers/CSS2DRenderer.js';
import { $, bytes, box, createViewport, el, f32, fmt, partMesh, pct, rgb, table, u32, workingPlane } from './common.js';

const data = JSON.parse(document.getElementById('scanplan-data').textContent);
const plan = data.plan;
const colour3 = (c) => new THREE.Color(c[0] / 255, c[1] / 255, c[2] / 255);

// Blue at normal incidence through green to red at 90°, as the PLY export colours it.
function incidenceColour(degrees) {
  const t = Math.min(Math.max(degrees / 90, 0), 1);
  const r = Math.min(2 * t, 1), b = Math.min(Math.max(2 - 2 * t, 0), 1);
  const g = 1 - Math.abs(2 * t - 1);
  return [r, 0.78 * g, b];
}

// ---- header and legend ----------------------------------------------------------------------
const summary = plan.summary;
document.title = `scanplan report – ${data.title}`;
$('title').textContent = `scanplan report – ${data.title}`;
$('headline').textContent =
  `${summary.views} views, ${summary.measured} of ${summary.samples} samples measured ` +
  `(${pct(summary.measured, summary.samples)}), ${summary.not_coverable} not coverable` +
  (summary.registrable_views !== undefined && summary.registrable_views !== null
    ? `, ${summary.registrable_views} views registered` : '') +
  (summary.path_length !== undefined ? `, path ${fmt(summary.path_length / 1000, 2)} m` : '') +
  (summary.cycle ? `, cycle ${fmt(summary.cycle.seconds)} s` : '');
{
  const h = data.header, sc = plan.scanner;
  $('report-header').replaceChildren(
    el('span', {}, `part ${h.part}`),
    el('span', {}, `scanner ${sc.name}: standoff ${fmt(sc.standoff)} mm, field ${fmt(sc.fov_width)} × ${fmt(sc.fov_height)} mm, ` +
      `spacing ${fmt(sc.point_spacing, 3)} mm, noise ${fmt(sc.noise_sigma, 3)} mm`),
    el('span', {}, `spec ${h.spec || 'default'}`), el('span', {}, `scanplan ${h.version}`), el('span', {}, h.date));
}
$('view-count').textContent = `(${data.views.length})`;
document.body.dataset.views = String(data.views.length);

const legend = $('legend');
// A legend per colouring of the faces (shown with it), then the views' and the rest, which
// do not change with it.
const coverageLegend = el('div', { 'data-mode': 'coverage' });
for (const [name, title] of [['measured', 'face measured'], ['partly measured', 'face partly measured'],
  ['not measured', 'face not measured'], ['not a target', 'not a target'], ['fixture', 'fixture']]) {
  coverageLegend.append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(data.palette[name])}` }), title));
}
legend.append(coverageLegend);
const viewLegend = el('div', { 'data-mode': 'views' });
for (const [name, title] of [['registered', 'view registered'], ['bridge', 'bridging view'], ['unregistrable', 'view unregistrable']]) {
  viewLegend.append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(data.palette[name])}` }), title));
}
for (const name of ['path', 'markers', 'proposed markers'])
  viewLegend.append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(data.palette[name])}` }), name));

// ---- 3D scene ---------------------------------------------------------------------------------
const viewport = $('viewport');
const all = box(data.bounds), partBox = box(data.part_bounds);
const radius = all.radius;
const labels = new CSS2DRenderer();
const { renderer, scene, camera, frameOn, resizers, start, ndc, onClick } =
  createViewport(viewport, radius, () => labels.render(scene, camera));
labels.domElement.style.position = 'absolute';
labels.domElement.style.top = '0';
labels.domElement.style.pointerEvents = 'none';
labels.domElement.style.zIndex = '1';  // its labels stay under the legend and toggles
viewport.append(labels.domElement);
resizers.push((w, h) => labels.setSize(w, h));
frameOn(partBox);

// The part, coloured per face by coverage.
const partMeshData = partMesh(data.mesh);
const { triangleFaces, facesBox } = partMeshData;
// Colours of the faces by the reason their samples are not measured (the commonest).
const reasonColours = {
  occluded_by_working_plane: [140, 90, 200], occluded_by_part: [240, 140, 40], no_valid_pose: [150, 100, 60],
  lost_in_simulation: [215, 50, 50], unreachable_by_robot: [40, 60, 160], '': [205, 210, 216],
};
// Faces by the mean density of their samples' points: a blue to yellow ramp over the
// decades between the sparsest and the densest face, grey without samples.
const densities = data.faces.map((f) => f.density).filter((d) => d > 0);
const densityRange = [Math.log10(Math.min(...densities, 1)), Math.log10(Math.max(...densities, 1))];
function densityColour(d) {
  if (d === null || d === undefined) return [205, 210, 216];
  if (!(d > 0)) return [60, 20, 90];
  const t = Math.min(Math.max((Math.log10(d) - densityRange[0]) / Math.max(densityRange[1] - densityRange[0], 1e-9), 0), 1);
  return [Math.round(40 + 215 * t), Math.round(60 + 170 * t), Math.round(200 - 170 * t)];
}
let colourBy = 'coverage';
let highlightedFaces = new Set();
// Colours the faces by coverage (or by reason), the `highlighted` ones (face ids) magenta.
// The highlighted faces drawn once more over everything, so that a face hidden behind or
// under the part (its bottom on the plate, a pocket's floor) shows through it.
let throughPart = null;
function showThrough(ids) {
  if (throughPart) { scene.remove(throughPart); throughPart.geometry.dispose(); throughPart = null; }
  const picked = [];
  const { indices } = partMeshData;
  for (let t = 0; t < triangleFaces.length; ++t)
    if (ids.has(triangleFaces[t])) picked.push(indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]);
  document.body.dataset.throughTriangles = String(picked.length / 3);
  if (picked.length === 0) return;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', partMeshData.geometry.attributes.position);
  g.setIndex(picked);
  throughPart = new THREE.Mesh(g, new THREE.MeshBasicMaterial({
    color: 0xff00aa, transparent: true, opacity: 0.55, depthTest: false, side: THREE.DoubleSide }));
  throughPart.renderOrder = 10;
  scene.add(throughPart);
}
function paintFaces(highlighted = highlightedFaces) {
  highlightedFaces = highlighted;
  showThrough(highlighted);
  const painted = new Set();  // the colours faces take, for checking them against the legend
  partMeshData.paint((id) => {
    if (highlighted.has(id)) return [255, 0, 170];
    const face = data.faces[id - 1];
    const c = colourBy === 'reason' ? reasonColours[face ? face.reason : ''] || reasonColours['']
      : colourBy === 'density' ? densityColour(face ? face.density : null)
        : data.palette[face ? (face.fixture ? 'fixture' : face.coverage) : 'not a target'];
    painted.add(c.join(','));
    return c;
  });
  document.body.dataset.painted = [...painted].join(';');
  document.body.dataset.highlighted = String(highlighted.size);
}
paintFaces();
const part = partMeshData.object;
scene.add(part);

// The fixture models of the plan's spec, in their own colour.
const fixtureData = partMesh(data.fixtures);
fixtureData.paint(() => data.palette.fixture);
const fixtures = fixtureData.object;
document.body.dataset.fixtureTriangles = String(fixtureData.triangleFaces.length);
scene.add(fixtures);

// The working plane the part stands on (z = 0), when the plan's spec has one.
if (data.working_plane) scene.add(workingPlane(partBox));

function lines(points, colour, opacity = 1) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(points, 3));
  return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: colour, transparent: opacity < 1, opacity }));
}
const outlines = lines(f32(data.mesh.outlines), 0x111111);
scene.add(outlines);

// Samples: measured green, not measured amber, not coverable red.
const sampleState = bytes(data.samples.state);
const samplePositions = f32(data.samples.positions);
const sampleColours = new Float32Array(samplePositions.length);
const stateColour = [data.palette.measured, data.palette['partly measured'], data.palette['not measured']];
for (let i = 0; i < sampleState.length; ++i) {
  const c = stateColour[sampleState[i]];
  sampleColours.set([c[0] / 255, c[1] / 255, c[2] / 255], 3 * i);
}
const sampleGeometry = new THREE.BufferGeometry();
sampleGeometry.setAttribute('position', new THREE.BufferAttribute(samplePositions, 3));
sampleGeometry.setAttribute('color', new THREE.BufferAttribute(sampleColours, 3));
const samples = new THREE.Points(sampleGeometry, new THREE.PointsMaterial({ size: 4, sizeAttenuation: false, vertexColors: true }));
samples.visible = false;
scene.add(samples);

// Views: short frusta (a quarter of the measuring frustum, so that the part stays visible)
// coloured by registration state, a pickable ball at each camera, a label with the view's
// place in the sequence. The selected view shows its whole frustum.
const views = new THREE.Group();
const cameraBalls = [];
const viewLabels = [];
const kAllLabels = 40;  // up to this many views, every label shows; beyond, on hover or pick
let selectedView = -1;
const ballGeometry = new THREE.SphereGeometry(Math.min(radius / 120, partBox.radius / 20), 12, 8);
data.views.forEach((v, index) => {
  const f = v.frustum.map((p) => new THREE.Vector3(...p));
  for (let k = 1; k <= 4; ++k) f[k].lerp(f[0], 0.75);
  const segments = [];
  for (let k = 1; k <= 4; ++k) segments.push(f[0], f[k], f[k], f[(k % 4) + 1]);
  const g = new THREE.BufferGeometry().setFromPoints(segments);
  const colour = colour3(data.palette[v.state]);
  const frustum = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: colour }));
  frustum.userData.index = index;
  views.add(frustum);
  const ball = new THREE.Mesh(ballGeometry, new THREE.MeshBasicMaterial({ color: colour }));
  ball.position.copy(f[0]);
  ball.userData.index = index;
  ball.userData.colour = colour;
  frustum.userData.colour = colour;
  ball.userData.frustum = frustum;
  cameraBalls.push(ball);
  views.add(ball);
  const label = new CSS2DObject(el('div', { class: 'label' }, viewName(v)));
  label.position.copy(f[0]);
  label.center.set(-0.3, 1.2);
  label.visible = data.views.length <= kAllLabels;
  viewLabels.push(label);
  views.add(label);
});
scene.add(views);
// Many views: their frusta faded, so that the part and the picked view stand out.
if (data.views.length > kAllLabels)
  for (const object of views.children)
    if (object.material) { object.material.transparent = true; object.material.opacity = 0.35; }
document.body.dataset.labelsShown = String(viewLabels.filter((l) => l.visible).length);

// Shows the label of view `index` (hovered or selected) besides the always shown ones.
function showLabel(index, on) {
  if (data.views.length <= kAllLabels || !viewLabels[index]) return;
  viewLabels[index].visible = on || index === selectedView;
  document.body.dataset.labelsShown = String(viewLabels.filter((l) => l.visible).length);
}

// The path through the views in sequence order.
const route = data.path.map((i) => new THREE.Vector3(...data.views[i].frustum[0]));
const path = new THREE.Line(new THREE.BufferGeometry().setFromPoints(route), new THREE.LineBasicMaterial({ color: colour3(data.palette.path) }));
scene.add(path);

const markerPositions = f32(data.markers);
const markerGeometry = new THREE.BufferGeometry();
markerGeometry.setAttribute('position', new THREE.BufferAttribute(markerPositions, 3));
const markers = new THREE.Points(markerGeometry, new THREE.PointsMaterial({ color: colour3(data.palette.markers), size: 6, sizeAttenuation: false }));
scene.add(markers);
// Markers the plan proposes where views register to nothing (proposed-markers.csv).
const proposedGeometry = new THREE.BufferGeometry();
proposedGeometry.setAttribute('position', new THREE.BufferAttribute(f32(data.proposed_markers || ''), 3));
const proposedMarkers = new THREE.Points(proposedGeometry, new THREE.PointsMaterial({ color: colour3(data.palette['proposed markers']), size: 8, sizeAttenuation: false }));
scene.add(proposedMarkers);

let cloud = null;      // the selected view's simulated cloud
let clusterPoints = null;  // the selected cluster's samples
const selectedMarker = new THREE.Mesh(new THREE.SphereGeometry(Math.min(radius / 60, partBox.radius / 12), 16, 12),
  new THREE.MeshBasicMaterial({ color: 0xff00aa, wireframe: true }));
selectedMarker.visible = false;
scene.add(selectedMarker);
const selectedFrustum = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xff00aa }));
scene.add(selectedFrustum);

// Framing buttons, the faces' colouring, and toggles for each layer.
$('toggles').append(el('button', { onclick: () => frameOn(partBox) }, 'part'), ' ',
  el('button', { onclick: () => frameOn(all) }, 'all views'));
{
  const select = el('select', { id: 'colour-by' }, el('option', { value: 'coverage' }, 'coverage'),
    el('option', { value: 'reason' }, 'reason not measured'), el('option', { value: 'density' }, 'point density'));
  select.addEventListener('change', () => {
    colourBy = select.value;
    paintFaces();
    coverageLegend.style.display = colourBy === 'coverage' ? '' : 'none';
    reasonLegend.style.display = colourBy === 'reason' ? '' : 'none';
    densityLegend.style.display = colourBy === 'density' ? '' : 'none';
    document.body.dataset.colourBy = colourBy;
  });
  $('toggles').append(el('label', {}, 'colour by ', select));
}
const reasonLegend = el('div', { style: 'display:none', 'data-mode': 'reason' });
for (const [reason, c] of Object.entries(reasonColours))
  reasonLegend.append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(c)}` }), reason ? reason.replaceAll('_', ' ') : 'measured or not a target'));
legend.append(reasonLegend);
const densityLegend = el('div', { style: 'display:none', 'data-mode': 'density' });
for (const d of [10 ** densityRange[0], 10 ** ((densityRange[0] + densityRange[1]) / 2), 10 ** densityRange[1]])
  densityLegend.append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(densityColour(d))}` }), `${fmt(d, 1)} points/mm²`));
densityLegend.append(el('div', {}, el('span', { class: 'sw', style: `background:${rgb(densityColour(0))}` }), 'no points'));
legend.append(densityLegend);
legend.append(viewLegend);
document.body.dataset.colourBy = colourBy;
for (const [name, object] of [['part', part], ['fixtures', fixtures], ['priority outlines', outlines], ['samples', samples],
  ['views', views], ['path', path], ['markers', markers], ['proposed markers', proposedMarkers]]) {
  const box = el('input', { type: 'checkbox' });
  box.checked = object.visible;
  box.addEventListener('change', () => { object.visible = box.checked; labels.domElement.style.display = views.visible ? '' : 'none'; });
  $('toggles').append(el('label', {}, box, ` ${name}`));
}

// ---- selection ---------------------------------------------------------------------------------
const viewRows = [];
function selectView(index) {
  const v = data.views[index];
  const before = selectedView;
  selectedView = index;
  if (before >= 0) showLabel(before, false);
  showLabel(index, true);
  document.body.dataset.selectedView = String(index);
  viewRows.forEach((row, i) => row.classList.toggle('selected', i === index));
  viewRows[index]?.scrollIntoView({ block: 'nearest' });
  if (cloud) { scene.remove(cloud); cloud.geometry.dispose(); cloud = null; }
  const to = v.registration && v.registration.to ? data.views.find((w) => w.id === v.registration.to) : null;
  const details = [['view', v.order > 0 ? `${v.order} in the sequence (id ${v.id} in plan.json)` : `id ${v.id}, not in the sequence`],
    ['task', v.task || '–'], ['registration', v.registration ? `${v.state}: ${v.registration.method}${to ? ` to view ${viewName(to)}` : ''}` : v.state],
    ['measures', `${v.measured} samples on ${v.faces.length} faces`], ['faces', v.faces.join(', ') || '–']];
  if (v.orientation) details.push(['rest orientation', String(v.orientation)]);
  const robot = plan.views[index] && plan.views[index].robot;
  if (robot) {
    details.push(['robot joints', `${robot.joints.map((q) => `${fmt(q)}°`).join('  ')}` +
      (plan.cell && plan.cell.table ? `, table ${fmt(robot.table)}°` : '')]);
  } else if (plan.cell) {
    details.push(['robot', 'the cell cannot reach this view']);
  }
  if (v.cloud) {
    const p = f32(v.cloud.positions), a = bytes(v.cloud.incidence);
    const colours = new Float32Array(p.length);
    let sum = 0;
    for (let i = 0; i < a.length; ++i) { colours.set(incidenceColour(a[i]), 3 * i); sum += a[i]; }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(p, 3));
    g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    cloud = new THREE.Points(g, new THREE.PointsMaterial({ size: 3, sizeAttenuation: false, vertexColors: true }));
    scene.add(cloud);
    details.push(['simulated cloud', `${v.cloud.points} points shown, mean incidence ${fmt(sum / Math.max(a.length, 1))}° (blue 0°, red 90°)`]);
  }
  const m = v.camera_to_world;
  details.push(['camera to world', m.map((r) => r.map((x) => fmt(x, 3)).join('  ')).join('\n')]);
  selectedMarker.position.set(...v.frustum[0]);
  selectedMarker.visible = true;
  const f = v.frustum.map((p) => new THREE.Vector3(...p));
  const segments = [];
  for (let k = 1; k <= 4; ++k) segments.push(f[0], f[k], f[k], f[(k % 4) + 1]);
  selectedFrustum.geometry.dispose();
  selectedFrustum.geometry = new THREE.BufferGeometry().setFromPoints(segments);
  $('selection').replaceChildren(table([{ title: '' }, { title: '' }], details.map(([k, val]) =>
    [k, k === 'camera to world' ? el('pre', { style: 'margin:0;font-size:11px' }, val) : val])));
}

function selectFace(id) {
  const f = data.faces[id - 1];
  if (!f) return;
  const on = characteristics.filter((c) => c.faces.includes(id)).map((c) => `${c.id} ${c.kind}`);
  const rows = [['face', `${f.id} (${f.type}${f.name ? `, ${f.name}` : ''})`], ['area', `${fmt(f.area)} mm²`],
    ['area measured', areaShare(f)],
    ['coverage', f.coverage], ['samples', `${f.measured} of ${f.samples} measured`],
    ['not coverable', f.not_coverable ? `${f.not_coverable} (${causeOf(f)})` : '0'], ['priority', f.priority ? 'yes (GD&T)' : 'no'],
    ['point density', f.density === null ? '–' : `${fmt(f.density, 1)} points/mm² (mean over its samples)`],
    ['characteristics', on.join(', ') || '–']];
  $('selection').replaceChildren(table([{ title: '' }, { title: '' }], rows));
}

const raycaster = new THREE.Raycaster();
onClick((e) => {
  raycaster.setFromCamera(ndc(e), camera);
  const ball = views.visible ? raycaster.intersectObjects(cameraBalls)[0] : null;
  if (ball) return selectView(ball.object.userData.index);
  const hit = part.visible ? raycaster.intersectObject(part)[0] : null;
  if (hit) selectFace(triangleFaces[hit.faceIndex]);
});

// ---- tables ---------------------------------------------------------------------------------------
// The views in the order the cell takes them, those outside the sequence last.
const inSequence = data.views.map((v, i) => i)
  .sort((a, b) => (data.views[a].order || Infinity) - (data.views[b].order || Infinity) || a - b);
$('views-table').append(table(
  [{ title: 'view', num: true }, { title: 'task' }, { title: 'state' }, { title: 'samples', num: true }],
  inSequence.map((i) => { const v = data.views[i]; return [viewName(v), v.task || '', v.state, v.measured]; }),
  (k) => selectView(inSequence[k])));
$('views-table').querySelectorAll('tbody tr').forEach((row, k) => {
  const i = inSequence[k];
  viewRows[i] = row;
  row.addEventListener('mouseenter', () => showLabel(i, true));
  row.addEventListener('mouseleave', () => showLabel(i, false));
});

const summaryRows = [
  ['model faces', summary.model_faces], ['fixture faces', summary.fixture_faces], ['samples', summary.samples],
  ['measured', `${summary.measured} (${pct(summary.measured, summary.samples)})`],
  ...(summary.measured_area ? [['measured area', `${fmt(summary.measured_area.measured)} of ${fmt(summary.measured_area.area)} mm² ` +
    `(${pct(summary.measured_area.share, 1)})`]] : []),
  ['not coverable', summary.not_coverable], ['views', summary.views]];
for (const [reason, count] of Object.entries(summary.not_coverable_by_reason || {})) summaryRows.push([`  not coverable: ${reason}`, count]);
for (const s of summary.priority_faces_short || []) {
  const f = data.faces[s.face - 1];
  summaryRows.push([`priority face short: ${s.face}${f && f.name ? ` (${f.name})` : ''}`, `${s.measured} of ${s.samples} measured`]);
}
if (summary.registrable_views !== null && summary.registrable_views !== undefined) {
  summaryRows.push(['views registered', `${summary.registrable_views} (${pct(summary.registrable_views, summary.views)})`],
    ['measured by registered views', summary.measured_by_registered_views], ['bridging views', summary.bridging_views],
    ['unregistrable views', (summary.unregistrable_views || [])
      .map((id) => viewName(data.views.find((v) => v.id === id) || { id, order: 0 })).join(', ') || 'none'],
    ['registration components', summary.registration_components]);
}
if (summary.path_length !== undefined) {
  summaryRows.push(['path length', `${fmt(summary.path_length)} mm (nearest neighbour: ${fmt(summary.nearest_neighbour_path_length)} mm)`]);
}
if (summary.orientations !== undefined) summaryRows.push(['rest orientations', summary.orientations]);
const setups = summary.setups ? summary.setups.by_setup || [] : [];
if (setups.length > 1) {
  const frames = new Set(setups.map((s) => s.frame)).size;
  const joined = frames === 1 ? 'joined by markers on the part' : frames === setups.length ? 'not joined' : `in ${frames} frames`;
  summaryRows.push(['setups', `${setups.length}, ${joined}; ${summary.setups.registered_in_one_frame} of ${summary.views} views registered in one frame`],
    ['  registered within each', setups.map((s) => `${s.registered} of ${s.views}`).join(', ')]);
}
if (summary.robot) {
  const r = summary.robot;
  summaryRows.push(['robot', plan.cell ? plan.cell.model : ''],
    ['robot joint travel', `${fmt(r.travel_seconds)} s, largest step ${fmt(r.max_joint_step)}° (axis ${r.max_joint_step_joint})`],
    ['table moves', r.table_moves], ['views the robot cannot reach', r.unreached_views]);
}
if (summary.cycle) {
  const c = summary.cycle;
  summaryRows.push(['cycle time', `${fmt(c.seconds)} s (${c.model === 'cell' ? 'the robot program' : 'generic positioning, no cell'})`],
    ['  acquisition', `${fmt(c.acquisition)} s over ${c.views} views`], ['  motion', `${fmt(c.motion)} s`],
    ['  table', `${fmt(c.table)} s`], ['  settling and handshakes', `${fmt(c.other)} s`]);
  if (c.turns) summaryRows.push(['  turning the part over by hand', `${fmt(c.turning)} s, ${c.turns} time${c.turns === 1 ? '' : 's'}`]);
}
if (summary.sweep_views !== undefined) summaryRows.push(['sweep views', summary.sweep_views]);
summaryRows.push(['planning time', `${fmt(summary.seconds, 2)} s`]);
for (const [stage, seconds] of Object.entries(summary.stage_seconds || {})) summaryRows.push([`  ${stage}`, `${fmt(seconds, 2)} s`]);
$('summary').append(table([{ title: 'quantity' }, { title: 'value' }], summaryRows));

// Coverage against views and against cycle time: a line of the share the first k views
// measure over their count or their estimated cycle, and where it reaches 90, 95, 98 and
// 100 %.
function coverageChart(xs, measured, coverable, unit) {
  const n = measured.length, w = 480, h = 200, m = 36, top = Math.max(xs[n - 1], 1e-9);
  const x = (v) => m + (w - 2 * m) * v / top, y = (share) => h - m + (2 * m - h) * share;
  const svg = (tag, attrs) => {
    const e = document.createElementNS('http://www.w3.org/2000/svg', tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    return e;
  };
  const chart = svg('svg', { width: w, height: h, viewBox: `0 0 ${w} ${h}`, role: 'img', 'data-unit': unit });
  const points = [[0, 0], ...measured.map((c, k) => [xs[k], c / Math.max(coverable, 1)])];
  chart.append(svg('polyline', { points: points.map(([v, sh]) => `${x(v)},${y(sh)}`).join(' '),
    fill: 'none', stroke: '#2a6fdb', 'stroke-width': 2 }));
  chart.append(svg('line', { x1: m, y1: h - m, x2: w - m, y2: h - m, stroke: '#888' }),
    svg('line', { x1: m, y1: h - m, x2: m, y2: m, stroke: '#888' }));
  const label = (text, attrs) => { const t = svg('text', { 'font-size': 11, ...attrs }); t.textContent = text; return t; };
  const amount = (v) => unit === 'views' ? `${v} views` : `${fmt(v)} s`;
  chart.append(label(amount(xs[n - 1]), { x: w - m, y: h - m + 16, 'text-anchor': 'end' }),
    label('100 %', { x: m - 4, y: m + 4, 'text-anchor': 'end' }), label('0', { x: m - 4, y: h - m + 4, 'text-anchor': 'end' }));
  const reach = [];
  for (const target of [0.9, 0.95, 0.98, 1]) {
    const k = measured.findIndex((c) => c >= Math.ceil(target * coverable - 1e-9));
    if (k < 0) continue;
    reach.push(`${Math.round(target * 100)} %: ${amount(xs[k])}`);
    chart.append(svg('circle', { cx: x(xs[k]), cy: y(measured[k] / Math.max(coverable, 1)), r: 3, fill: '#d9534f' }));
  }
  return [chart, el('p', {}, reach.join(' · '))];
}
if (summary.coverage_by_views && summary.coverage_by_views.measured.length > 0) {
  const { coverable, measured } = summary.coverage_by_views;
  $('coverage-curve').append(...coverageChart(measured.map((_, k) => k + 1), measured, coverable, 'views'));
  const seconds = summary.cycle && summary.cycle.by_views;
  if (seconds && seconds.length === measured.length)
    $('coverage-curve').append(...coverageChart(seconds, measured, coverable, 'seconds'));
}
if (summary.capable_by_views) {
  const { views, capable } = summary.capable_by_views;
  const toleranced = (plan.characteristics || []).filter((c) => c.capability && c.capability.verdict !== 'untoleranced').length;
  const seconds = summary.cycle && summary.cycle.by_views;
  const timed = seconds && seconds.length >= views[views.length - 1];
  $('capable-curve').append(...coverageChart(timed ? views.map((v) => seconds[v - 1]) : views, capable, toleranced,
    timed ? 'seconds' : 'views'));
  $('capable-curve').dataset.capable = capable.join(' ');
}

// Per task and role: samples, measured, not coverable.
{
  const task = bytes(data.samples.task), role = bytes(data.samples.role);
  const groups = new Map();
  for (let i = 0; i < task.length; ++i) {
    const key = `${data.samples.tasks[task[i]]}|${data.samples.roles[role[i]]}`;
    const g = groups.get(key) || [0, 0, 0];
    g[0] += 1; if (sampleState[i] === 0) g[1] += 1; if (sampleState[i] === 2) g[2] += 1;
    groups.set(key, g);
  }
  $('tasks').append(table([{ title: 'task' }, { title: 'role' }, { title: 'samples', num: true }, { title: 'measured', num: true },
    { title: 'share', num: true }, { title: 'not coverable', num: true }],
  [...groups.entries()].map(([k, g]) => [...k.split('|'), g[0], g[1], pct(g[1], g[0]), g[2]])));
}

// ---- characteristics and what is missing -------------------------------------------------------
const characteristics = plan.characteristics || [];
const characteristicRows = [];
// What scanplan inspect measured of each characteristic, by id, when the report has it.
const inspected = new Map(((data.inspection || {}).characteristics || []).map((k) => [k.id, k]));
function inspectedText(k) {
  if (!k) return '–';
  return k.evaluated ? k.verdict.replaceAll('_', ' ') : `not evaluated: ${k.not_evaluated}`;
}
function selectCharacteristic(index) {
  const c = characteristics[index], k = c.capability || {};
  characteristicRows.forEach((row, i) => row.classList.toggle('selected', i === index));
  const faces = new Set(c.faces);
  paintFaces(faces);
  const serving = new Set(k.views || []);
  const measuring = serving.size > 0 ? data.views.filter((v) => serving.has(v.id))
    : data.views.filter((v) => v.faces.some((f) => faces.has(f)));
  paintViews(new Set(measuring.map((v) => v.id)));
  const rows = [['characteristic', `${c.id}: ${c.kind}`], ['value', limits(c)], ['datums', c.datums.join(' | ') || '–'],
    ['faces', c.faces.join(', ')], ['views serving it', measuring.map(viewName).join(', ') || 'none']];
  if (c.capability) {
    rows.push(['covered', pct(k.covered, 1)], ['points', `${fmt(k.points, 0)} (${fmt(k.density, 2)} per mm²)`],
      ['largest gap', k.largest_gap === null ? '–' : `${fmt(k.largest_gap, 2)} mm`], ['U (95 % of the errors under it)', `${fmt(k.uncertainty, 4)} mm`],
      ['ratio', fmt(k.ratio, 2)], ['verdict', verdictText(k)], ['beyond the views', limitText(k)]);
    if (k.inspected_uncertainty !== null && k.inspected_uncertainty !== undefined)
      rows.push(['inspected U (k = 2), planned', `${fmt(k.inspected_uncertainty, 4)} mm, bias ${fmt(k.inspected_bias, 4)}` +
        (typeof k.inspected_precision === 'number' ? `, U + |bias| ± ${fmt(k.inspected_precision, 4)} at 95 %` : '')]);
    if (k.budget) {
      rows.push(['U from the noise', `${fmt(k.budget.noise, 4)} mm`],
        ['U from the registration', `${fmt(k.budget.registration, 4)} mm`],
        ['U from the scanner\'s acceptance figures', `${fmt(k.budget.scanner, 4)} mm`]);
    }
  }
  const m = inspected.get(c.id);
  if (m && m.evaluated) {
    rows.push(['inspected: value of the part', fmt(m.true_value, 4)], ['inspected: measured', fmt(m.mean, 4)],
      ['inspected: bias', fmt(m.bias, 4)], ['inspected: U (k = 2)', `${fmt(m.uncertainty, 4)} mm`],
      ['inspected: U + |bias| known within', precisionText(m)],
      ['inspected: error 95 % of the runs stay under (as the planned U)',
        typeof m.error_95 === 'number' ? `${fmt(m.error_95, 4)} mm` : '–'],
      ['inspected: ratio', fmt(m.ratio, 2)], ['inspected: verdict', inspectedText(m)]);
  } else if (m) {
    rows.push(['inspected', inspectedText(m)]);
  }
  $('selection').replaceChildren(table([{ title: '' }, { title: '' }], rows));
}
// How precisely the inspection's runs know U + |bias| (inspection.json's precision).
function precisionText(m) {
  const runs = (data.inspection || {}).runs;
  return typeof m.precision === 'number' ? `± ${fmt(m.precision, 4)} mm at 95 % (${runs} runs)` : '–';
}
function limits(c) {
  return c.dimension ? `${fmt(c.value, 3)} (${fmt(c.limits[0], 3)} to ${fmt(c.limits[1], 3)})` : fmt(c.value, 3);
}
// Why a characteristic left short is out of the views' reach, as plan.json says it.
function limitText(k) { return k.limit && k.limit !== 'none' ? k.limit.replaceAll('_', ' ') : '–'; }
function verdictText(k) {
  return `${k.verdict.replaceAll('_', ' ')}${k.reason !== 'none' ? ` (${k.reason.replaceAll('_', ' ')})` : ''}` +
    (k.rest_orientation ? `; rest orientation ${k.rest_orientation} reaches it` : '');
}
// Paints the cameras and frusta of the views `ids` magenta, the others by their state.
function paintViews(ids = new Set()) {
  for (const ball of cameraBalls) {
    const on = ids.has(data.views[ball.userData.index].id);
    ball.material.color.copy(on ? new THREE.Color(0xff00aa) : ball.userData.colour);
    ball.userData.frustum.material.color.copy(on ? new THREE.Color(0xff00aa) : ball.userData.colour);
    ball.scale.setScalar(on ? 1.8 : 1);
  }
  document.body.dataset.highlightedViews = String(ids.size);
}

// A view as the report numbers it: its place in the sequence (the id, plan.json's, only
// for a view outside the sequence and in the view's details).
function viewName(v) { return v.order > 0 ? String(v.order) : `id ${v.id}`; }

if (characteristics.length === 0) {
  $('characteristics').append(el('p', { class: 'muted' }, 'The part carries no GD&T the reader found.'));
} else {
  const columns = [{ title: 'id', num: true }, { title: 'kind' },
    { title: 'value', num: true }, { title: 'faces' }, { title: 'covered', num: true }, { title: 'points', num: true },
    { title: 'U mm', num: true }, { title: 'ratio', num: true }, { title: 'verdict' }, { title: 'views', num: true },
    { title: 'beyond the views' }];
  const planned = characteristics.some((c) => c.capability && typeof c.capability.inspected_uncertainty === 'number');
  if (planned && inspected.size === 0) columns.push({ title: 'inspected U mm', num: true });
  if (inspected.size > 0) {
    columns.push({ title: 'inspected bias', num: true }, { title: 'inspected U mm', num: true },
      { title: 'U + |bias| ± mm', num: true }, { title: 'inspected verdict' });
  }
  $('characteristics').append(el('div', { class: 'scroll' }, table(columns,
    characteristics.map((c) => {
      const k = c.capability;
      const row = [c.id, c.kind, limits(c), c.faces.join(', '), k ? pct(k.covered, 1) : '–', k ? fmt(k.points, 0) : '–',
        k ? fmt(k.uncertainty, 4) : '–', k ? fmt(k.ratio, 2) : '–', k ? verdictText(k) : '–',
        k && k.views ? k.views.length : '–', k ? limitText(k) : '–'];
      if (planned && inspected.size === 0)
        row.push(k && typeof k.inspected_uncertainty === 'number' ? fmt(k.inspected_uncertainty, 4) : '–');
      if (inspected.size > 0) {
        const m = inspected.get(c.id);
        const known = m && m.evaluated;
        row.push(known ? fmt(m.bias, 4) : '–', known ? fmt(m.uncertainty, 4) : '–',
          known && typeof m.precision === 'number' ? fmt(m.precision, 4) : '–', inspectedText(m));
      }
      return row;
    }), selectCharacteristic)));
  characteristicRows.push(...$('characteristics').querySelectorAll('tbody tr'));
}

// Why a face's samples are not measured, as plan.json says it: the reason, and for those
// lost in the simulation the test that lost them (camera occluded, camera angle, ...).
function causeOf(f) {
  if (!f.reason) return 'not measured by the views chosen';
  const reason = f.reason.replaceAll('_', ' ');
  return f.reason === 'lost_in_simulation' && f.loss ? `${reason}: ${f.loss.replaceAll('_', ' ')}` : reason;
}

// Faces with samples left unmeasured, by reason; a click flies to the face, shown through
// the part where the part hides it.
{
  const missing = data.faces.filter((f) => f.samples > f.measured)
    .sort((a, b) => a.reason.localeCompare(b.reason) || b.samples - b.measured - (a.samples - a.measured));
  if (missing.length === 0) {
    $('missing').append(el('p', { class: 'muted' }, 'Every target face is measured.'));
  } else {
    $('missing').append(el('div', { class: 'scroll' }, table([{ title: 'reason' }, { title: 'face', num: true }, { title: 'type' },
      { title: 'samples unmeasured', num: true }, { title: 'area mm²', num: true }],
    missing.map((f) => [causeOf(f), f.id, f.type,
      `${f.samples - f.measured} of ${f.samples}`, fmt(f.area)]),
    (i) => { const f = missing[i]; paintFaces(new Set([f.id])); frameOn(facesBox(new Set([f.id]), partBox.radius / 10)); selectFace(f.id); })));
  }
}

{
  const reg = plan.registration;
  if (!reg) {
    $('registration').append(el('p', { class: 'muted' }, 'The plan was made without the registration check.'));
  } else {
    const pairs = reg.pairs || [];
    const rows = [['reference view', reg.reference], ['pairs checked', pairs.length],
      ['pairs that register', pairs.filter((p) => p.registrable).length],
      ['by shared markers', pairs.filter((p) => p.markers).length],
      ['by ICP', pairs.filter((p) => !p.markers && p.registrable).length],
      ['markers in the cell', (reg.markers || []).length]];
    $('registration').append(table([{ title: 'quantity' }, { title: 'value' }], rows));
  }
}

const areaShare = (f) => (f.area_measured === null || f.area_measured === undefined ? '–' : pct(f.area_measured, 1));
$('faces').append(el('div', { class: 'scroll' }, table([{ title: 'face', num: true }, { title: 'type' }, { title: 'area mm²', num: true },
  { title: 'area measured', num: true }, { title: 'priority' }, { title: 'coverage' }, { title: 'samples', num: true },
  { title: 'measured', num: true }, { title: 'not coverable' }],
data.faces.map((f) => [f.id, f.type, fmt(f.area), areaShare(f), f.priority ? 'yes' : '',
  f.coverage, f.samples, f.measured, f.not_coverable ? `${f.not_coverable} (${f.reason})` : '']),
(i) => selectFace(data.faces[i].id))));

// ---- Combined Visibility Maps --------------------------------------------------------------------
function showCluster(index) {
  const c = data.clusters[index];
  const canvas = $('cvm-canvas');
  const scale = Math.max(2, Math.floor(720 / c.azimuths));
  const left = 44, bottom = 30;  // room for the axes' labels
  const w = c.azimuths * scale, h = c.elevations * scale;
  canvas.width = left + w + 24;
  canvas.height = h + bottom + 10;
  const g = canvas.getContext('2d');
  g.fillStyle = '#fff';
  g.fillRect(0, 0, canvas.width, canvas.height);
  const cells = bytes(c.cvm);
  for (let a = 0; a < c.azimuths; ++a) {
    for (let e = 0; e < c.elevations; ++e) {
      const v = cells[a * c.elevations + e] / 255;
      g.fillStyle = v === 0 ? '#20242c' : `hsl(${(1 - v) * 240}, 85%, ${35 + 25 * v}%)`;
      g.fillRect(left + a * scale, 10 + (c.elevations - 1 - e) * scale, scale, scale);
    }
  }
  g.fillStyle = '#333';
  g.font = '11px system-ui, sans-serif';
  g.textAlign = 'center';
  for (let az = 0; az <= 360; az += 45) g.fillText(`${az}°`, left + (az / 360) * w, h + 26);
  g.textAlign = 'right';
  for (let el = -90; el <= 90; el += 45) g.fillText(`${el}°`, left - 6, 14 + ((90 - el) / 180) * h);
  $('cvm-info').textContent = `${c.samples} samples; the brightest direction sees ${c.max}; grid ${c.step}°`;
  if (clusterPoints) { scene.remove(clusterPoints); clusterPoints.geometry.dispose(); }
  const members = u32(c.members);
  const p = new Float32Array(members.length * 3);
  members.forEach((m, i) => p.set(samplePositions.subarray(3 * m, 3 * m + 3), 3 * i));
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(p, 3));
  clusterPoints = new THREE.Points(geometry, new THREE.PointsMaterial({ color: 0xff00cc, size: 5, sizeAttenuation: false }));
  scene.add(clusterPoints);
}
if (data.clusters.length === 0) {
  $('cvm-select').disabled = true;
  $('cvm-info').textContent = 'not computed for this report';
} else {
  data.clusters.forEach((c, i) => $('cvm-select').append(el('option', { value: i }, `${c.id} (${c.samples} samples)`)));
  $('cvm-select').addEventListener('change', (e) => showCluster(Number(e.target.value)));
  showCluster(0);
}

start();
requestAnimationFrame(() => { document.body.dataset.ready = '1'; });
