// viewer_feel: live editing in the viewer as a person feels it, in Debian's
// Chromium (software WebGL, as on this machine) driven by puppeteer-core, for
// the bunny and for a model of about a million triangles. For each: the
// frames the page draws while idle (none: it draws only when something
// changed), its drawing rate while the view is orbited (what it draws at with
// no edit to do: the baseline) and during a footprint drag and a
// control-point drag, the share of drawn frames in which the model moved,
// how long pointer moves waited for the page, and the time from release to
// the exact result on screen (drawn) against the server's time plus the
// page's decoding.
// Ratios to the page's own orbiting frame rate in the same run are what hold
// on a shared machine.
// Usage: node bench/viewer_feel.mjs SERVER_BINARY [seconds per phase, default 4]
//        [models, default bunny,relief-1m; relief-1m-stl: the relief as a binary STL;
//        word: the page's opening sample]
// (puppeteer-core comes from tests/browser/node_modules: scripts/setup.sh).
import { mkdtempSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '../tests/browser/package.json'));
const puppeteer = require('puppeteer-core');
const [serverBin, secondsArg = '4', modelsArg = 'bunny,relief-1m'] = process.argv.slice(2);
const seconds = Number(secondsArg);
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// A relief of about a million triangles (binary PLY, or binary STL with
// every triangle's own corners): a 708 x 708 grid of vertices, 0.4 high
// over 10 x 10, gently waved.
const { gridPly, gridStl } = await import(path.join(here, '../tests/browser/grid_ply.mjs'));
const relief = (x, y) => 0.2 + 0.1 * Math.sin(2 * x) * Math.cos(3 * y);
function millionTriangles(format) {
  return (format === 'stl' ? gridStl : gridPly)(708, 0, 0, 10, relief).bytes;
}

const { startServer } = await import(path.join(here, '../tests/browser/start_server.mjs'));
const { server, port } = await startServer(serverBin);
const { chromiumLaunchOptions } = await import(path.join(here, '../tests/browser/chromium.mjs'));
const browser = await puppeteer.launch(chromiumLaunchOptions({ protocolTimeout: 600000 }));
const results = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 });
  // Every display frame, once its animation-frame callbacks (the view's
  // drawing among them) have run: when, what the model showed (the preview's
  // uniforms and field, which model object) and how many frames the view had
  // drawn; every pointer move: how long it waited. (Read at the start of the
  // callbacks instead, before the view's own, a frame drawn for a pointer
  // move that came just before it was counted as one that did not move the
  // model: at ~40 frames a second, 10-20% of them.)
  await page.evaluateOnNewDocument(() => {
    window.feel = { frames: [], waits: [] };
    const sample = () => {
      const v = window.surfdeformTest;
      let shown = '';
      if (v) {
        shown = v.previewPose();
      }
      window.feel.frames.push([performance.now(), shown, v ? v.framesDrawn() : 0]);
    };
    const loop = () => {
      setTimeout(sample, 0);
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
    window.addEventListener('pointermove', (e) => window.feel.waits.push(performance.now() - e.timeStamp), true);
  });
  const ready = (what) =>
    page
      .waitForFunction(() => document.body.dataset.state === 'ready', { timeout: 600000 })
      .catch(() => {
        throw new Error(`${what}: the page did not settle`);
      });
  const reset = () =>
    page.evaluate(() => {
      window.feel.frames = [];
      window.feel.waits = [];
    });
  // Frames drawn per second, and the share of them that showed the model
  // moved (from the display frame before each drawn one).
  const collect = () =>
    page.evaluate(() => {
      const f = window.feel.frames;
      let moved = 0,
        drawn = 0;
      for (let k = 1; k < f.length; ++k) {
        if (f[k][2] === f[k - 1][2]) continue;
        drawn += f[k][2] - f[k - 1][2];
        moved += f[k][1] !== f[k - 1][1];
      }
      const span = f.length > 1 ? (f[f.length - 1][0] - f[0][0]) / 1000 : 0;
      const w = [...window.feel.waits].sort((a, b) => a - b);
      return {
        fps: span ? drawn / span : 0,
        moved: drawn ? moved / drawn : 0,
        wait_median: w.length ? w[Math.floor(w.length / 2)] : 0,
        wait_p95: w.length ? w[Math.floor(0.95 * (w.length - 1))] : 0,
        moves: w.length,
      };
    });
  // Pointer moves every 16 ms (or as fast as the page takes them) for the
  // phase's length, along `path(t)`; then the release, and the time until
  // the exact result is on screen.
  const hold = async (from, pathAt) => {
    await page.mouse.move(...from);
    await page.mouse.down();
    await reset();
    const t0 = Date.now();
    while (Date.now() - t0 < seconds * 1000) {
      const p = pathAt((Date.now() - t0) / 1000);
      await page.mouse.move(from[0] + p[0], from[1] + p[1]);
      await sleep(16);
    }
    return collect();
  };
  const drag = async (from, pathAt) => {
    const during = await hold(from, pathAt);
    during.live = await page.evaluate(() => window.surfdeformTest.snapshot().live);
    const released = await page.evaluate(() => performance.now());
    await page.mouse.up();
    await ready('after the release');
    const exact = await page.evaluate(() => window.surfdeformTest.snapshot().lastExact);
    // On screen: the end of the first frame the view drew with it.
    await page.waitForFunction(
      (t) => {
        const f = window.feel.frames;
        return f.length > 1 && f[f.length - 1][0] > t && f[f.length - 1][2] > f.findLast((e) => e[0] <= t)[2];
      },
      { timeout: 60000 },
      exact.done_at,
    );
    const shown_at = await page.evaluate((t) => {
      const f = window.feel.frames;
      const before = f.findLast((e) => e[0] <= t)[2];
      return f.find((e) => e[0] > t && e[2] > before)[0];
    }, exact.done_at);
    // The page's marks since the release (app.js), ms after it.
    const marks = await page.evaluate(
      (t) =>
        performance
          .getEntriesByType('mark')
          .filter((m) => m.startTime >= t)
          .map((m) => `${m.name.replace('surfdeform:', '')} +${Math.round(m.startTime - t)}`),
      released,
    );
    return { ...during, release_ms: shown_at - released, exact, marks };
  };

  await page.goto(`http://127.0.0.1:${port}/`);
  await ready('the page');
  const dir = mkdtempSync(path.join(os.tmpdir(), 'viewer-feel-'));
  const big = { ply: path.join(dir, 'relief-1m.ply'), stl: path.join(dir, 'relief-1m.stl') };
  writeFileSync(big.ply, millionTriangles('ply'));
  writeFileSync(big.stl, millionTriangles('stl'));
  for (const model of modelsArg.split(',')) {
    if (model === 'bunny' || model === 'word') {
      // samples
      await page.select('#sample', model);
    } else {
      await (await page.$('#upload')).uploadFile(model === 'relief-1m-stl' ? big.stl : big.ply);
    }
    await sleep(300);
    await ready(model);
    await page.$eval('#scale', (e) => {
      e.value = String(window.surfdeformTest.snapshot().placement.scale / 2);
      e.dispatchEvent(new Event('change'));
    });
    await sleep(300);
    await ready(`${model} at half scale`);
    const triangles = await page.evaluate(() => window.surfdeformTest.snapshot().lastStats.triangles);
    await reset();
    await sleep(seconds * 1000);
    const still = await collect();
    // The baseline: the view orbited (dragged where no control point is),
    // a frame drawn at every pointer move and nothing else to do.
    const view = await (await page.$('#view3d')).boundingBox();
    const idle = await hold([view.x + 0.06 * view.width, view.y + 0.94 * view.height], (t) => [
      40 * Math.sin(2 * t),
      0,
    ]);
    await page.mouse.up();
    const box = await (await page.$('#sheet')).boundingBox();
    const centre = [box.x + box.width / 2, box.y + box.height / 2];
    const r = 0.06 * box.width;
    const footprint = await drag(centre, (t) => [r * Math.sin(3 * t), r * (1 - Math.cos(3 * t))]);
    const handle = await page.evaluate(() => window.surfdeformTest.handlePoint(5));
    const control = await drag(handle, (t) => [0, -40 * Math.sin(2 * t)]);
    results.push({ model, triangles, still, idle, footprint, control });
    const line = (name, d) =>
      `  ${name.padEnd(18)} ${d.fps.toFixed(1).padStart(5)} fps ` +
      `(${(d.fps / idle.fps).toFixed(2)} of orbiting), model moved in ${(100 * d.moved).toFixed(0)}% of frames, ` +
      `pointer wait median ${d.wait_median.toFixed(0)} ms, p95 ${d.wait_p95.toFixed(0)} ms` +
      (d.exact
        ? `; release to exact ${d.release_ms.toFixed(0)} ms = ` +
          `${(d.release_ms / (d.exact.server_ms + d.exact.decode_ms)).toFixed(2)}x (server ` +
          `${d.exact.server_ms.toFixed(0)} ms + decode ${d.exact.decode_ms.toFixed(0)} ms)`
        : '');
    console.log(`${model} (${triangles} triangles shown exact)`);
    console.log(`  idle               ${still.fps.toFixed(1).padStart(5)} frames drawn a second`);
    console.log(
      `  orbiting the view  ${idle.fps.toFixed(1).padStart(5)} fps, pointer wait median ` +
        `${idle.wait_median.toFixed(0)} ms`,
    );
    console.log(line('footprint drag', footprint));
    console.log(line('control-point drag', control));
    console.log(`  live surfaces during the control-point drag: ${JSON.stringify(control.live)}`);
    console.log(
      `  after the releases: footprint ${footprint.marks.join(', ')}; control point ${control.marks.join(', ')}`,
    );
  }
  console.log(JSON.stringify(results));
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
