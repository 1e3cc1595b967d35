// Opens a scanplan report in headless Chromium (Debian's /usr/bin/chromium, driven by
// playwright-core) and checks that it works: no console errors, the 3D canvas draws, and
// the page shows the plan's view count.
//
//   node web/test/report_test.mjs REPORT.html PLAN.json [SCREENSHOT.png]
//
// Exits 0 when every check passes, 1 otherwise, printing each check.

import { launchChromium, nextFrames } from './browser.mjs';
import { existsSync, readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const [report, planFile, screenshot] = process.argv.slice(2);
if (!report || !planFile) {
  console.error('usage: node report_test.mjs REPORT.html PLAN.json [SCREENSHOT.png]');
  process.exit(2);
}
const expectedViews = JSON.parse(readFileSync(planFile, 'utf8')).views.length;

const browser = await launchChromium();
const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
  const requests = [];
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) requests.push(r.url()); });

  // Ready, or the first uncaught error, whichever comes first.
  const failed = new Promise((resolve) => page.on('pageerror', resolve));
  await page.goto(pathToFileURL(report).href);
  const error = await Promise.race([
    page.waitForSelector('body[data-ready="1"]', { state: 'attached', timeout: 60000 }).then(() => null),
    failed,
  ]);
  if (error) throw new Error(`the page failed before it was ready: ${error}`);
  await nextFrames(page);

  check(errors.length === 0, `no console errors${errors.length ? `: ${errors.join(' | ')}` : ''}`);
  check(requests.length === 0, `no network requests${requests.length ? `: ${requests.join(' ')}` : ''}`);

  const shown = await page.evaluate(() => ({
    count: document.getElementById('view-count').textContent,
    rows: document.querySelectorAll('#views-table tbody tr').length,
    attribute: document.body.dataset.views,
  }));
  check(shown.count === `(${expectedViews})` && shown.attribute === String(expectedViews) &&
        shown.rows === Number(expectedViews),
        `view count shown ${shown.count}, ${shown.rows} rows, plan has ${expectedViews}`);

  // The coverage curve: one point per view and the origin, ending at the share the plan
  // measures of its coverable samples, read from plan.json.
  const planned = JSON.parse(readFileSync(planFile, 'utf8'));
  const curve = planned.summary.coverage_by_views;
  const curves = await page.evaluate(() => [...document.querySelectorAll('#coverage-curve svg')].map((chart) => ({
    unit: chart.dataset.unit, points: chart.querySelector('polyline').getAttribute('points').trim().split(/\s+/).length,
  })));
  const curvePoints = curves.length > 0 ? curves[0].points : 0;
  check(curves.length === (planned.summary.cycle && planned.summary.cycle.by_views ? 2 : 1) &&
        curves.every((c) => c.points === curvePoints) &&
        curvePoints === curve.measured.length + 1 &&
        curve.measured[curve.measured.length - 1] === planned.summary.measured,
        `coverage curves ${JSON.stringify(curves)} for ${curve.measured.length} views, ending at ` +
        `${curve.measured[curve.measured.length - 1]} of ${planned.summary.measured} measured`);
  // The capability curve: one point per count of views plan.json gives and the origin, its
  // last the characteristics capable in the characteristics table.
  const capableCurve = planned.summary.capable_by_views;
  if (capableCurve) {
    const drawn = await page.evaluate(() => {
      const chart = document.querySelector('#capable-curve svg');
      return chart ? chart.querySelector('polyline').getAttribute('points').trim().split(/\s+/).length : 0;
    });
    const capableRows = (planned.characteristics || []).filter((c) => c.capability && c.capability.verdict === 'capable').length;
    check(drawn === capableCurve.views.length + 1 && capableCurve.capable[capableCurve.capable.length - 1] === capableRows,
          `capability curve: ${drawn} points for ${capableCurve.views.length} counts of views, ending at ` +
          `${capableCurve.capable[capableCurve.capable.length - 1]} capable of ${capableRows} in the table`);
  }

  // The WebGL canvas: share of pixels off the background colour, and distinct colours.
  const pixels = await page.evaluate(() => {
    const gl = document.querySelector('#viewport canvas');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const g = c.getContext('2d');
    g.drawImage(gl, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let drawn = 0, measured = 0;
    const colours = new Set();
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - 0xee) + Math.abs(d[i + 1] - 0xf1) + Math.abs(d[i + 2] - 0xf4) > 12) ++drawn;
      colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
      if (d[i + 1] > d[i] + 25 && d[i + 1] > d[i + 2] + 10) ++measured;  // shaded "measured" bluish green
    }
    const n = d.length / 4;
    return { share: drawn / n, measured: measured / n, colours: colours.size };
  });
  check(pixels.share > 0.02 && pixels.colours > 20 && pixels.measured > 0.01,
        `the canvas draws: ${(100 * pixels.share).toFixed(1)} % of pixels off the background, ` +
        `${(100 * pixels.measured).toFixed(1)} % in the measured faces' green, ${pixels.colours} colours`);

  // Selecting a view shows its details and its simulated cloud.
  await page.click('#views-table tbody tr');
  const selection = await page.textContent('#selection');
  check(/view\s*\d+/.test(selection) && /measures/.test(selection), 'clicking a view shows what it measures');
  const cvm = await page.evaluate(() => document.getElementById('cvm-canvas').width);
  check(cvm > 0, 'the Combined Visibility Map of a cluster is drawn');

  // The characteristics table: a row per characteristic of the plan; a click paints its
  // faces and names the views measuring them.
  const plan = JSON.parse(readFileSync(planFile, 'utf8'));
  const characteristics = plan.characteristics || [];
  const rows = await page.evaluate(() => document.querySelectorAll('#characteristics tbody tr').length);
  check(characteristics.length > 0 && rows === characteristics.length,
        `characteristics table: ${rows} rows, plan has ${characteristics.length}`);
  if (characteristics.length > 0) {
    await page.click('#characteristics tbody tr');
    const picked = await page.evaluate(() => ({
      text: document.getElementById('selection').textContent, highlighted: Number(document.body.dataset.highlighted),
      views: Number(document.body.dataset.highlightedViews),
    }));
    // The views serving it, as plan.json lists them (else those measuring a sample on one of
    // its faces).
    const faces = new Set(characteristics[0].faces), measuring = new Set();
    const serving = (characteristics[0].capability || {}).views || [];
    if (serving.length > 0) serving.forEach((id) => measuring.add(id));
    else for (const s of plan.samples) if (faces.has(s.face)) s.measured_by.forEach((id) => measuring.add(id));
    check(/characteristic/.test(picked.text) && /views serving it/.test(picked.text) &&
          picked.highlighted === characteristics[0].faces.length && picked.views === measuring.size,
          `clicking characteristic 1 selects its ${picked.highlighted} faces (it has ${characteristics[0].faces.length}) ` +
          `and ${picked.views} views (${measuring.size} measure its samples)`);
  }
  // With an inspection beside the plan (scanplan inspect), each row gives its inspected
  // verdict, as inspection.json has it.
  const inspectionFile = planFile.replace(/plan\.json$/, 'inspection.json');
  if (existsSync(inspectionFile)) {
    const inspection = JSON.parse(readFileSync(inspectionFile, 'utf8'));
    const cells = await page.evaluate(() => [...document.querySelectorAll('#characteristics tbody tr')]
      .map((row) => row.lastElementChild.textContent));
    const expected = inspection.characteristics.map((k) =>
      (k.evaluated ? k.verdict.replaceAll('_', ' ') : `not evaluated: ${k.not_evaluated}`));
    check(cells.length === expected.length && cells.every((c, i) => c === expected[i]),
          `inspected verdicts in the table: ${JSON.stringify(cells)} against ${JSON.stringify(expected)}`);
  }
  // The missing panel lists the faces left unmeasured, and a click flies to one.
  const unmeasured = plan.samples.filter((s) => s.measured_by.length === 0).length;
  const missing = await page.evaluate(() => document.querySelectorAll('#missing tbody tr').length);
  check(unmeasured === 0 ? missing === 0 : missing > 0, `missing panel: ${missing} faces, ${unmeasured} samples unmeasured`);
  if (missing > 0) {
    await page.click('#missing tbody tr');
    check(/face/.test(await page.textContent('#selection')), 'clicking a missing face selects it');
  }
  // Colouring the faces by the reason they are not measured.
  await page.selectOption('#colour-by', 'reason');
  await nextFrames(page);
  check(errors.length === 0, `colouring by reason runs${errors.length ? `: ${errors.join(' | ')}` : ''}`);
  await page.selectOption('#colour-by', 'density');
  await nextFrames(page);
  check(errors.length === 0, `colouring by point density runs${errors.length ? `: ${errors.join(' | ')}` : ''}`);
  await page.selectOption('#colour-by', 'coverage');
  // Each measured face's density is positive and below what every view at the near end of
  // its depth of field would lay on it straight on: views / (spacing (1 - dof / 2 standoff))².
  const density = await page.evaluate(() => {
    const d = JSON.parse(document.getElementById('scanplan-data').textContent);
    const sc = d.plan.scanner, pitch = sc.point_spacing * (1 - sc.depth_of_field / (2 * sc.standoff));
    const bound = d.views.length / (pitch * pitch);
    const measured = d.faces.filter((f) => f.coverage === 'measured');
    return { bound, measured: measured.length, ok: measured.every((f) => f.density > 0 && f.density <= bound) };
  });
  check(density.measured > 0 && density.ok,
        `point density of the ${density.measured} measured faces within (0, ${density.bound.toFixed(0)}] points/mm²`);
  const header = await page.textContent('#report-header');
  check(header.includes(plan.scanner.name) && /scanplan \d+\.\d+\.\d+/.test(header) && /UTC/.test(header),
        `the header names the scanner, the version and the date: ${header}`);

  // One numbering: the views' list gives each view's place in the sequence, and a view's
  // details name its plan.json id beside it.
  const numbers = await page.evaluate(() => [...document.querySelectorAll('#views-table tbody tr')]
    .map((row) => row.firstElementChild.textContent));
  // In the order the cell takes them (plan.json's sequence), the others by id after.
  const sequence = plan.sequence || [];
  const expectedNumbers = [...sequence.map((id, k) => String(k + 1)),
    ...plan.views.filter((v) => !sequence.includes(v.id)).map((v) => `id ${v.id}`)];
  check(numbers.join() === expectedNumbers.join(), `the views' list numbers them by the sequence: ${numbers.join(' ')}`);
  await page.click('#views-table tbody tr');
  const picked = await page.textContent('#selection');
  check(sequence.length === 0 || new RegExp(`1 in the sequence \\(id ${sequence[0]} in plan\\.json\\)`).test(picked),
        'the first row is the sequence\'s first view, its details giving its number and its id');
  await page.mouse.move(1, 1);  // off the list: no view hovered
  await nextFrames(page);
  const labelled = Number(await page.evaluate(() => document.body.dataset.labelsShown));
  check(labelled === (plan.views.length > 40 ? 1 : plan.views.length),
        `${labelled} views labelled: every view up to 40 of them, else the one picked`);
  // Each colouring shows its own legend, and paints faces only in its legend's colours (the
  // density ramp aside, which its legend samples).
  for (const mode of ['coverage', 'reason', 'density']) {
    await page.selectOption('#colour-by', mode);
    await nextFrames(page);
    const shown = await page.evaluate(() => {
      const groups = [...document.querySelectorAll('#legend [data-mode]')].filter((g) => getComputedStyle(g).display !== 'none');
      const swatches = groups.flatMap((g) => [...g.querySelectorAll('.sw')].map((s) =>
        getComputedStyle(s).backgroundColor.replace(/[^\d,]/g, '')));
      return { modes: groups.map((g) => g.dataset.mode), swatches, painted: document.body.dataset.painted.split(';') };
    });
    check(shown.modes.join() === `${mode},views`, `colouring by ${mode} shows the legends ${shown.modes.join(', ')}`);
    if (mode !== 'density') {
      const strays = shown.painted.filter((c) => !shown.swatches.includes(c));
      check(strays.length === 0, `colouring by ${mode} paints faces only in its legend's colours${strays.length ? `: ${strays.join(' ')} not in it` : ''}`);
    }
  }
  await page.selectOption('#colour-by', 'coverage');
  // A face of the missing panel is drawn through the part, whatever hides it, and its
  // cause is plan.json's: for samples lost in the simulation, the test that lost them.
  if (missing > 0) {
    await page.click('#missing tbody tr');
    check(Number(await page.evaluate(() => document.body.dataset.throughTriangles)) > 0,
          'a face picked in the missing panel is drawn through the part');
    // Per face, the causes its samples give in plan.json: a not-coverable reason, and for
    // those lost in the simulation the test that lost them.
    const given = new Map();
    for (const s of plan.samples) {
      if (!s.not_coverable) continue;
      const reason = s.not_coverable.replaceAll('_', ' ');
      if (!given.has(s.face)) given.set(s.face, new Set());
      given.get(s.face).add(s.not_coverable === 'lost_in_simulation' ? `${reason}: ${s.loss.replaceAll('_', ' ')}` : reason);
    }
    const causes = await page.evaluate(() => [...document.querySelectorAll('#missing tbody tr')]
      .map((row) => [Number(row.children[1].textContent), row.children[0].textContent]));
    const unexplained = causes.filter(([face, cause]) => (given.has(face)
      ? !given.get(face).has(cause) : cause !== 'not measured by the views chosen'));
    check(causes.length > 0 && unexplained.length === 0,
          `each face of the missing panel gives a cause its samples give in plan.json (${causes.length} faces)` +
          `${unexplained.length ? `: ${JSON.stringify(unexplained)}` : ''}`);
  }

  if (screenshot) await page.screenshot({ path: screenshot });

  // The print layout: A4 pages with the scene's picture and the tables.
  await page.click('#toggles button');  // frame the part again
  await nextFrames(page);
  await page.emulateMedia({ media: 'print' });
  await nextFrames(page);
  const printed = await page.evaluate(() => ({
    aside: getComputedStyle(document.querySelector('aside')).display,
    canvas: document.querySelector('#viewport canvas').getBoundingClientRect().height,
    box: document.getElementById('viewport').getBoundingClientRect().height,
  }));
  // The whole picture within its box: a canvas taller than the box is cut off on paper.
  check(printed.aside === 'none' && printed.canvas > 100 && printed.canvas <= printed.box + 1,
        `print layout: panel hidden, picture ${printed.canvas} px high in its box of ${printed.box} px`);
  // The first A4 page as a picture: the scene is drawn in it.
  const pageShot = await page.screenshot({ clip: { x: 0, y: 0, width: 1280, height: Math.round(1280 * 297 / 210) } });
  const drawn = await page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    // The measured faces' green, or the magenta the selected faces are drawn in through it.
    let part = 0;
    for (let i = 0; i < d.length; i += 4) {
      const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
      if ((g > r + 25 && g > b + 10) || (r > g + 60 && b > g + 40)) ++part;
    }
    return part / (d.length / 4);
  }, pageShot.toString('base64'));
  check(drawn > 0.005, `the first printed page shows the part: ${(100 * drawn).toFixed(1)} % of it in the measured green or the selection's magenta`);
  const pdf = await page.pdf({ format: 'A4', printBackground: true });
  check(pdf.length > 20000 && pdf.subarray(0, 5).toString() === '%PDF-', `prints to PDF (${pdf.length} bytes)`);
  if (screenshot) await page.screenshot({ path: screenshot.replace(/\.png$/, '-print.png'), fullPage: true });
} catch (e) {
  check(false, String(e));
} finally {
  await browser.close();
}
process.exit(failures.length === 0 ? 0 : 1);
