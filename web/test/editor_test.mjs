// Drives the spec editor in headless Chromium (Debian's /usr/bin/chromium, driven by
// playwright-core) as an engineer would, and checks that the command line takes what it
// downloads.
//
//   node web/test/editor_test.mjs new|given SCANPLAN PART OUTDIR [SCREENSHOT.png]
//
// new:
// 1. `scanplan spec PART` writes the editor; it opens without console errors or network.
// 2. Two faces clicked go to a trim task, a characteristic picked goes to a gdt task, two
//    control points are clicked onto the part (one on a cylinder, snapped onto it exactly).
// 3. spec.yaml and points.csv are downloaded, and `scanplan sample` samples them as planning
//    does: the trim and gdt samples lie on exactly those faces, and each point lies on the
//    part within 0.01 mm (the distance to where sampling projects it onto the exact face).
// given: the editor of OUTDIR/given.yaml; the spec downloaded unchanged is written to
// OUTDIR/roundtrip.yaml (tests/editor_browser_test.sh compares it with the original), then
// the page is edited (editSettings).
// Exits 0 when every check passes, 1 otherwise, printing each check.

import { launchChromium, nextFrames } from './browser.mjs';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [mode, scanplan, part, out, screenshot] = process.argv.slice(2);
if (!['new', 'given'].includes(mode) || !scanplan || !part || !out) {
  console.error('usage: node editor_test.mjs new|given SCANPLAN PART OUTDIR [SCREENSHOT.png]');
  process.exit(2);
}
const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};
const run = (...args) => execFileSync(scanplan, ['-q', ...args], { encoding: 'utf8' });

// Opens `page` on `file` and waits until it is ready; returns the console errors seen.
async function open(page, file) {
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) errors.push(`request ${r.url()}`); });
  await page.goto(pathToFileURL(file).href);
  await page.waitForSelector('body[data-ready="1"]', { state: 'attached', timeout: 60000 });
  await nextFrames(page);
  return errors;
}
async function saveDownload(page, button, path) {
  const [download] = await Promise.all([page.waitForEvent('download'), page.click(button)]);
  await download.saveAs(path);
  return readFileSync(path, 'utf8');
}
// Clicks a visible point of face `id`; false when none is visible.
async function clickFace(page, id, modifiers = []) {
  const at = await page.evaluate((f) => window.scanplanEditor.pointOnFace(f), id);
  if (!at) return false;
  await page.mouse.move(at.x, at.y);
  for (const m of modifiers) await page.keyboard.down(m);
  await page.mouse.down();
  await page.mouse.up();
  for (const m of modifiers) await page.keyboard.up(m);
  await nextFrames(page);
  return true;
}
// On an editor open on a spec: an empty task is flagged and blocks the download; a face
// made a fixture, and the settings changed, reach the spec, which `scanplan sample` reads.
async function editSettings(page, data) {
  await page.click('#clear-selection');
  await page.selectOption('#new-task-type', 'surface');
  await page.click('#add-task');
  const flagged = await page.evaluate(() => ({
    issues: document.body.dataset.issues, text: document.getElementById('issues').textContent,
    disabled: document.getElementById('download-spec').disabled,
  }));
  check(flagged.issues === '1' && flagged.disabled && /task \d+ \(surface\) has no target faces: list them/.test(flagged.text),
    `an empty surface task is flagged and blocks the download: ${flagged.text}`);
  await page.click('#tasks tbody tr:last-child button:has-text("remove")');
  check(await page.evaluate(() => document.body.dataset.issues) === '0', 'removing it clears the flag');

  let fixture = 0, at = null;
  for (const f of data.faces) {
    if (at || f.id <= 2) continue;
    at = await page.evaluate((id) => window.scanplanEditor.pointOnFace(id), f.id);
    fixture = f.id;
  }
  await page.mouse.click(at.x, at.y);
  await page.click('#role-fixture');
  await page.selectOption('#scanner', 'generic-structured-light');
  await page.selectOption('#rest', 'rest-1');
  await page.selectOption('#gdt', 'all');
  await page.fill('#marker-grid', '30');
  await page.dispatchEvent('#marker-grid', 'change');
  const text = await saveDownload(page, '#download-spec', join(out, 'settings.yaml'));
  const rest = data.rests[1];
  const expected = ['scanner: generic-structured-light', 'gdt: all', 'grid: 30', rest.face ? `rest: ${rest.face}` : 'rest:'];
  check(expected.every((line) => text.includes(line)) && new RegExp(`fixture: \\[[^\\]]*\\b${fixture}\\b`).test(text),
    `the settings and fixture face ${fixture} reach the spec (${expected.join('; ')})`);
  const sampled = run('sample', part, '--spec', join(out, 'settings.yaml'));
  check(/samples/.test(sampled), 'scanplan sample reads the edited spec');
}
const dataOf = (page) => page.evaluate(() => JSON.parse(document.getElementById('scanplan-data').textContent));

const browser = await launchChromium();
async function newSpec() {
  const editor = join(out, 'spec-editor.html');
  run('spec', part, '-o', editor);
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 }, acceptDownloads: true });
  const errors = await open(page, editor);
  const data = await dataOf(page);

  // Two faces, one clicked and one shift-clicked, to a new trim task: planes seen from the
  // default camera.
  const visible = [];
  for (const f of data.faces) {
    if (visible.length < 2 && f.type === 'Plane' && (await page.evaluate((id) => window.scanplanEditor.pointOnFace(id), f.id))) visible.push(f.id);
  }
  await clickFace(page, visible[0]);
  await clickFace(page, visible[1], ['Shift']);
  check(await page.evaluate(() => document.body.dataset.selected) === '2', `click and shift-click select faces ${visible.join(', ')}`);
  await page.selectOption('#task-target', 'new-trim');
  const hover = await page.textContent('#hover');
  check(hover.startsWith(`face ${visible[1]} `), `hovering a face names it: ${hover}`);
  await page.click('#assign-task');

  // Shift-drag a box around the whole part: every face falls inside it.
  await page.click('#frame');
  await nextFrames(page);
  const frame = await page.evaluate(() => { const r = document.querySelector('#viewport canvas').getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; });
  await page.click('#clear-selection');
  await page.keyboard.down('Shift');
  await page.mouse.move(frame[0] + 5, frame[1] + 5);
  await page.mouse.down();
  await page.mouse.move(frame[2] - 5, frame[3] - 5, { steps: 5 });
  await page.mouse.up();
  await page.keyboard.up('Shift');
  const boxed = await page.evaluate(() => document.body.dataset.selected);
  check(boxed === String(data.faces.length), `a box around the part selects its ${boxed} faces (it has ${data.faces.length})`);
  await page.click('#clear-selection');

  // A characteristic's faces to a new gdt task.
  const characteristic = data.characteristics.find((c) => c.faces.length > 0);
  await page.click(`#characteristics tbody tr:nth-child(${data.characteristics.indexOf(characteristic) + 1})`);
  check(await page.evaluate(() => document.body.dataset.selected) === String(characteristic.faces.length),
    `picking characteristic ${characteristic.id} (${characteristic.kind}) selects its ${characteristic.faces.length} faces`);
  await page.selectOption('#task-target', 'new-gdt');
  await page.click('#assign-task');

  // Two control points: one on a plane, one on a cylinder (its mesh is off by up to the
  // chordal tolerance; the page snaps it onto the exact cylinder).
  await page.click('#pick-points');
  const onScreen = async (type, least) => {
    for (const f of data.faces)
      if (f.type === type && f.area > least && (await page.evaluate((id) => window.scanplanEditor.pointOnFace(id), f.id))) return f.id;
    return 0;
  };
  const pointFaces = [await onScreen('Plane', 0), await onScreen('Cylinder', 500)];
  for (const id of pointFaces) check(id > 0 && (await clickFace(page, id)), `a point clicked on face ${id}`);
  await page.click('#pick-points');
  check(await page.evaluate(() => document.body.dataset.points) === '2', `two control points added (faces ${pointFaces.join(' and ')})`);
  const issues = await page.textContent('#issues');
  check(await page.evaluate(() => document.body.dataset.issues) === '0', `the page finds the spec complete: ${issues}`);

  const spec = await saveDownload(page, '#download-spec', join(out, 'spec.yaml'));
  const csv = await saveDownload(page, '#download-points', join(out, 'points.csv'));
  check(errors.length === 0, `no console errors or network requests${errors.length ? `: ${errors.join(' | ')}` : ''}`);
  if (screenshot) {  // the whole part with its tasks and points, nothing selected
    await page.click('#clear-selection');
    await page.click('#frame');
    await nextFrames(page);
    await page.screenshot({ path: screenshot });
  }

  // The command line samples the downloaded spec, as planning does first.
  run('sample', part, '--spec', join(out, 'spec.yaml'), '-o', join(out, 'samples.json'));
  const sampled = JSON.parse(readFileSync(join(out, 'samples.json'), 'utf8')).samples;
  const facesOf = (task) => [...new Set(sampled.filter((s) => s.task === task).map((s) => s.face))].sort((a, b) => a - b).join(',');
  check(facesOf('trim') === [...visible].sort((a, b) => a - b).join(','), `the trim task's samples are on faces ${facesOf('trim')}: ${visible.join(', ')} clicked`);
  check(facesOf('gdt') === characteristic.faces.join(','), `the gdt task's samples are on faces ${facesOf('gdt')}: the characteristic's ${characteristic.faces.join(', ')}`);
  const points = csv.trim().split('\n').slice(1).map((line) => line.split(',').map(Number));
  const planned = sampled.filter((s) => s.task === 'points');
  // Samples are in the part's frame, as the CSV is.
  const gaps = points.map((p, i) => Math.hypot(...planned[i].position.map((x, k) => x - p[k])));
  check(planned.length === 2 && gaps.every((d) => d <= 0.01) && planned.every((s, i) => s.face === pointFaces[i]),
    `the control points lie on the part: ${gaps.map((d) => d.toExponential(1)).join(', ')} mm from the exact faces (at most 0.01), ` +
    `on faces ${planned.map((s) => s.face).join(', ')}`);
  check(/faces:/.test(spec) && /type: trim/.test(spec) && /type: gdt/.test(spec) && /file: points.csv/.test(spec), 'spec.yaml lists the tasks');

}

// An existing spec, loaded and downloaded unchanged, then edited.
async function givenSpec() {
  run('spec', part, '--spec', join(out, 'given.yaml'), '-o', join(out, 'given-editor.html'));
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 }, acceptDownloads: true });
  const errors = await open(page, join(out, 'given-editor.html'));
  await saveDownload(page, '#download-spec', join(out, 'roundtrip.yaml'));
  await saveDownload(page, '#download-points', join(out, 'points.csv'));
  await editSettings(page, await dataOf(page));
  check(errors.length === 0, `the editor of an existing spec runs without errors${errors.length ? `: ${errors.join(' | ')}` : ''}`);
}

try {
  if (mode === 'new') await newSpec();
  else await givenSpec();
} catch (e) {
  check(false, String(e.stack || e));
} finally {
  await browser.close();
}
process.exit(failures.length === 0 ? 0 : 1);
