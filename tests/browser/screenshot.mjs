// The README's picture of the viewer, made from the real page: the real
// server on loopback, Debian's Chromium (software WebGL) in a laptop's window,
// the page as it opens (a name in relief on the default surface), saved as
// a PNG once the exact result is on screen (body[data-state="ready"]).
// Usage: node tests/browser/screenshot.mjs SERVER_BINARY OUT.png
// (scripts/screenshot.sh builds the server and writes docs/viewer.png.)
import puppeteer from 'puppeteer-core';

import { chromiumLaunchOptions } from './chromium.mjs';
import { startServer } from './start_server.mjs';

const [serverBin, out] = process.argv.slice(2);
if (!serverBin || !out) {
  console.error('usage: node screenshot.mjs SERVER_BINARY OUT.png');
  process.exit(2);
}
const { server, port } = await startServer(serverBin);
const browser = await puppeteer.launch(chromiumLaunchOptions());
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 });
  await page.goto(`http://127.0.0.1:${port}/`);
  await page.waitForSelector('body[data-state="ready"]', { timeout: 120000 });
  // Two frames after the exact result: drawn and composited.
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await page.screenshot({ path: out, type: 'png' });
  console.log(`screenshot: ${out}`);
} finally {
  await browser.close();
  server.kill();
}
