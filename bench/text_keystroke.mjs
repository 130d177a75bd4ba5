// Keystroke to preview in the viewer, in Chromium: the page opens on its
// text, and letters are typed one at a time (600 ms apart, past the exact
// result's 250 ms pause). For each: the POST /v1/text round trip (keystroke
// to the flat mesh received), reading it (binary PLY), the preview set up
// (bent on the GPU), and keystroke to the next frame drawn after it. Beside
// them: the page's idle frame rate, and the same POST /v1/text timed alone
// in the page (no keystroke, nothing drawing). Software WebGL (SwiftShader),
// as in CI.
// Usage: node bench/text_keystroke.mjs SERVER_BINARY
import { createRequire } from 'node:module';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '../tests/browser/package.json'));
const puppeteer = require('puppeteer-core');
const { startServer } = await import(path.join(here, '../tests/browser/start_server.mjs'));
const [serverBin] = process.argv.slice(2);
const { server, port } = await startServer(serverBin);
const { chromiumLaunchOptions } = await import(path.join(here, '../tests/browser/chromium.mjs'));
const browser = await puppeteer.launch(chromiumLaunchOptions());
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 });
  await page.goto(`http://127.0.0.1:${port}/`);
  await page.waitForFunction(() => document.body.dataset.state === 'ready', { timeout: 60000 });
  await new Promise((r) => setTimeout(r, 1000));
  const fps = await page.evaluate(
    () =>
      new Promise((done) => {
        let n = 0;
        const t0 = performance.now();
        const f = () => (
          ++n,
          performance.now() - t0 < 1000 ? requestAnimationFrame(f) : done(n / ((performance.now() - t0) / 1000))
        );
        requestAnimationFrame(f);
      }),
  );
  const alone = await page.evaluate(async () => {
    const out = [];
    for (let k = 0; k < 10; ++k) {
      const t0 = performance.now();
      const r = await fetch('/v1/text', {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify({
          text: { string: `Ada Lovelace ${k}`, size_mm: 0.6, depth_mm: 0.05, tolerance_mm: 0.006 },
          output: { format: 'ply' },
        }),
      });
      await r.arrayBuffer();
      out.push(performance.now() - t0);
    }
    return out;
  });
  const rows = [];
  for (const ch of ' Byron, 1815') {
    await page.evaluate(() => performance.clearMarks());
    await page.focus('#text');
    await page.keyboard.press('End');
    await page.keyboard.type(ch);
    rows.push(
      await page
        .waitForFunction(
          () => {
            const at = (n) => performance.getEntriesByName(`surfdeform:${n}`)[0]?.startTime;
            if (at('text-drawn') === undefined) return null;
            return {
              fetch: at('text-received') - at('text-typed'),
              read: at('text-read') - at('text-received'),
              preview: at('text-preview') - at('text-read'),
              ready: at('text-preview') - at('text-typed'),
              frame: at('text-drawn') - at('text-typed'),
            };
          },
          { timeout: 10000, polling: 200 },
        )
        .then((h) => h.jsonValue()),
    );
    await new Promise((r) => setTimeout(r, 600));
  }
  const m = (k) => median(rows.map((r) => r[k])).toFixed(1);
  console.log(
    JSON.stringify({
      idle_fps: Number(fps.toFixed(1)),
      frame_ms: Number((1000 / fps).toFixed(1)),
      post_text_alone_ms: Number(median(alone).toFixed(1)),
      keystrokes: rows.length,
      median_ms: {
        fetch: m('fetch'),
        read: m('read'),
        preview: m('preview'),
        keystroke_to_preview_ready: m('ready'),
        keystroke_to_next_frame: m('frame'),
      },
    }),
  );
} finally {
  await browser.close();
  server.kill();
}
