// What the browser tests share: headless Chromium with WebGL in software, and a wait for
// the viewer to draw.
import { chromium } from 'playwright-core';

// Debian's Chromium (or $CHROMIUM), WebGL by SwiftShader.
export const launchChromium = () => chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});

// Until the page has drawn what the last action changed: the viewer redraws in its next
// animation frame, so two frames on it has.
export const nextFrames = (page) => page.evaluate(() => new Promise((done) =>
  requestAnimationFrame(() => requestAnimationFrame(done))));
