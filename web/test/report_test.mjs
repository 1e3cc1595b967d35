// Opens a scanplan report in headless Chromium (Debian's /usr/bin/chromium, driven by
// playwright-core) and checks that it works: no console errors, the 3D canvas draws, and
// the page shows the plan's view count.
//
//   node web/test/report_test.mjs REPORT.html PLAN.json [SCREENSHOT.png]
//
// Exits 0 when every check passes, 1 otherwise, printing each check.

import { chromium } from 'playwright-core';
import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const [report, planFile, screenshot] = process.argv.slice(2);
if (!report || !planFile) {
  console.error('usage: node report_test.mjs REPORT.html PLAN.json [SCREENSHOT.png]');
  process.exit(2);
}
const expectedViews = JSON.parse(readFileSync(planFile, 'utf8')).views.length;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
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
  await page.waitForTimeout(500);

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
      if (d[i + 1] > d[i] + 25 && d[i + 1] > d[i + 2] + 10) ++measured;  // shaded "measured" green
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

  if (screenshot) await page.screenshot({ path: screenshot });
} catch (e) {
  check(false, String(e));
} finally {
  await browser.close();
}
process.exit(failures.length === 0 ? 0 : 1);
