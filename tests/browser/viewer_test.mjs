// The web viewer in a real browser: Debian's Chromium (DevTools protocol) or
// Firefox ESR (WebDriver BiDi), driven by puppeteer-core, loads the page from
// the real server in a laptop's window, opens on a word in relief, edits live
// with real pointer events (a footprint drag and a control-point drag change
// the 3D view during the drag, the latter on every pointer move, with the
// model kept on the same part of the surface; the footprint's sends no
// request; a release
// sends one exact request, whose result the preview was within 1e-3 of the
// sheet's diagonal of; parts dragged off the sheet are tinted, with no banner
// until the exact request fails), deforms the bundled bunny, checks that the 3D canvas shows
// the model (its pixels, not the DOM), switches surface and model, colours
// the model by its distortion map, draws a mark on the sheet and sees it on
// the surface, drags the
// footprint, uploads a broken mesh and expects the server's error on the
// page, and saves screenshots as test artifacts. Nothing may be fetched from
// anywhere but the server (no CDN).
// Usage: node viewer_test.mjs SERVER_BINARY ARTIFACT_DIR [chromium|firefox]
// Firefox needs a display for WebGL (headless Firefox has no GL driver here):
// ctest runs it under xvfb-run.
import { createHash } from 'node:crypto';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

import { chromiumLaunchOptions } from './chromium.mjs';
import { gridPly } from './grid_ply.mjs';
import { startServer } from './start_server.mjs';

const [serverBin, artifacts, browserName = 'chromium'] = process.argv.slice(2);
mkdirSync(artifacts, { recursive: true });
const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} [${browserName}] ${what}`);
  if (!ok) failures.push(what);
};
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

const launchOptions = {
  chromium: chromiumLaunchOptions(),
  firefox: {
    browser: 'firefox',
    executablePath: process.env.FIREFOX || '/usr/bin/firefox-esr',
    headless: false, // on xvfb's display: WebGL through Mesa's software renderer
    // WebGL on a software renderer is on Firefox's blocklist; no update or
    // telemetry traffic (the page must fetch from the server only).
    extraPrefsFirefox: {
      'webgl.force-enabled': true,
      'app.update.enabled': false,
      'datareporting.policy.dataSubmissionEnabled': false,
    },
  },
}[browserName];
if (!launchOptions) {
  console.error(`unknown browser ${browserName}: chromium or firefox`);
  process.exit(2);
}

const { server, port } = await startServer(serverBin);
const base = `http://127.0.0.1:${port}`;

const browser = await puppeteer.launch(launchOptions);
try {
  console.log(`browser: ${await browser.version()}`);
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 }); // a laptop's window
  const foreign = [];
  const pageErrors = [];
  page.on('request', (r) => {
    const url = r.url();
    if (!url.startsWith(base) && !url.startsWith('blob:') && !url.startsWith('data:')) foreign.push(url);
  });
  // Every POST the page sends, {path, type, body}, recorded by the page's own
  // fetch (WebDriver BiDi does not give request bodies).
  await page.evaluateOnNewDocument(() => {
    window.sentPosts = [];
    const original = window.fetch;
    window.fetch = (input, init = {}) => {
      if ((init.method || 'GET') === 'POST') {
        const headers = init.headers || {};
        const path = new URL(String(input), location.href).pathname;
        window.sentPosts.push({
          path,
          type: headers['Content-Type'] || '',
          body: typeof init.body === 'string' ? init.body : '',
        });
        // A test may hold new surfaces back (a slow network), ms.
        if (path === '/v1/surfaces' && window.holdSurfaces) {
          return new Promise((resolve) => setTimeout(resolve, window.holdSurfaces)).then(() => original(input, init));
        }
      }
      return original(input, init);
    };
  });
  const posts = () => page.evaluate(() => window.sentPosts);
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  const shot = (name) => page.screenshot({ path: path.join(artifacts, `${name}.png`) });
  const text = (selector) => page.$eval(selector, (e) => e.textContent);
  const settled = async (state, what) => {
    try {
      await page.waitForFunction((s) => document.body.dataset.state === s, { timeout: 90000 }, state);
      return true;
    } catch {
      check(
        false,
        `${what}: state ${await page.evaluate(() => document.body.dataset.state)}, ` +
          `error ${await page.evaluate(() => window.surfdeformTest?.snapshot().error)}`,
      );
      await shot(`failed-${what.replace(/\W+/g, '-')}`);
      return false;
    }
  };
  const stats = () => page.evaluate(() => window.surfdeformTest.snapshot().lastStats);
  const coverage = () => page.evaluate(() => window.surfdeformTest.modelCoverage());

  await page.goto(base + '/');
  // The first thing a visitor sees: a name standing on the surface (a text
  // the server shapes, each letter rigid), in a 3D view that takes most of
  // the window, the sheet beside it, every panel reachable.
  if (await settled('ready', 'the name on Figure 10')) {
    await sleep(300);
    const s = await stats();
    check(
      s &&
        s.text &&
        s.text.glyphs === 12 &&
        s.text.solids === 11 &&
        s.placement.up === '+z' &&
        s.rigid &&
        s.rigid.parts === 11,
      `the page opens on a name standing on the surface (${s && JSON.stringify(s.text && s.text.runs)}, ` +
        `${s && s.text && s.text.glyphs} glyphs, ${s && s.rigid && s.rigid.parts} rigid parts)`,
    );
    check((await coverage()) > 0.002, `the name is on the canvas (${(100 * (await coverage())).toFixed(2)}%)`);
    // three.js reads the OBJ as separate triangles; the preview's mesh is
    // welded over its distinct positions (preview_mesh.js), with unit normals.
    const mesh = await page
      .waitForFunction(
        () => {
          return window.surfdeformTest.previewMesh();
        },
        { timeout: 10000 },
      )
      .then((h) => h.jsonValue())
      .catch(() => null);
    check(
      mesh && mesh.vertices < mesh.triangles && mesh.unitNormals === mesh.vertices, // separate: 3 per triangle
      `the name's preview is welded (${mesh && mesh.vertices} vertices for ${mesh && mesh.triangles} ` +
        `triangles, ${mesh && mesh.unitNormals} unit normals)`,
    );
    const boxOf = (sel) =>
      page.$eval(sel, (e) => {
        const r = e.getBoundingClientRect();
        return { x: r.x, y: r.y, w: r.width, h: r.height };
      });
    const view = await boxOf('#view3d'),
      sheet = await boxOf('#sheet');
    check(
      view.w * view.h > 0.4 * 1280 * 800 && view.y + view.h <= 800,
      `the 3D view takes most of the window (${Math.round(view.w)} x ${Math.round(view.h)})`,
    );
    check(sheet.x >= view.x + view.w && sheet.y < 800, 'the sheet stands beside the 3D view');
    const panels = await page.$eval('#controls', (e) => ({
      bottom: e.getBoundingClientRect().bottom,
      scrolls: getComputedStyle(e).overflowY,
      wide: e.scrollWidth,
      width: e.clientWidth,
    }));
    check(panels.bottom <= 800 && panels.scrolls === 'auto', 'every panel is reachable (the panels scroll)');
    // A fieldset as wide as a select's longest option was cut at the panel's edge.
    check(panels.wide <= panels.width, `no panel is wider than the column (${panels.wide} <= ${panels.width} px)`);
    await shot('name-figure10');
    // Typing: the new letter is on the preview (bent on the GPU) before the
    // exact result is asked for, which waits for the typing to pause.
    const before = await page.evaluate(() => window.surfdeformTest.snapshot().model.vertices);
    await page.evaluate(() => performance.clearMarks());
    await page.focus('#text');
    await page.keyboard.press('End');
    await page.keyboard.type('!');
    const typed = await page
      .waitForFunction(
        () => {
          const m = window.surfdeformTest.snapshot().model;
          const previewed = performance.getEntriesByName('surfdeform:text-preview');
          return (
            m &&
            m.text &&
            m.text.string === 'Ada Lovelace!' &&
            previewed.length > 0 && {
              vertices: m.vertices,
              preview: previewed[0].startTime - performance.getEntriesByName('surfdeform:text-typed')[0].startTime,
              exactAsked: performance.getEntriesByName('surfdeform:run-deform').map((e) => e.startTime),
              previewAt: previewed[0].startTime,
            }
          );
        },
        { timeout: 10000 },
      )
      .then((h) => h.jsonValue())
      .catch(() => null);
    check(
      typed && typed.vertices > before,
      `a typed letter is on the preview (${before} -> ${typed && typed.vertices} vertices, ` +
        `${typed && typed.preview.toFixed(1)} ms from the keystroke)`,
    );
    check(
      typed && typed.exactAsked.every((t) => t > typed.previewAt),
      'the preview came before the exact result was asked for',
    );
    await settled('ready', 'the typed name');
    const t = await stats();
    check(
      t && t.text && t.text.glyphs === 13,
      `the exact result has the new letter (${t && t.text && t.text.glyphs} glyphs)`,
    );
    // The text's size, typed: the name twice as long, in millimetres.
    const typedSize = async (mm) => {
      await page.$eval(
        '#text-size',
        (e, v) => {
          e.value = v;
          e.dispatchEvent(new Event('change', { bubbles: true }));
        },
        String(mm),
      );
      await sleep(100);
      await settled('ready', `the name at ${mm} mm`);
      return (await stats())?.text?.width_mm;
    };
    const w1 = await typedSize(1.2),
      w0 = await typedSize(0.6);
    check(
      w0 > 0 && Math.abs(w1 / w0 - 2) < 1e-3,
      `a typed text size scales the name (${w0} mm at 0.6, ${w1} mm at 1.2)`,
    );
    // A printable part of the surface: checked by the server, its report on
    // the page; a 3MF asked for by the surface's id.
    await page.click('#part-check');
    const report = await page
      .waitForFunction(() => /closed and sound/.test(document.getElementById('part-report').textContent), {
        timeout: 30000,
      })
      .then(() => text('#part-report'))
      .catch(() => text('#part-report'));
    check(/closed and sound/.test(report) && /mm³/.test(report), `the part's report is on the page (${report})`);
    // The file saved, as its name (a real download would open Firefox's
    // downloads panel, which takes the keyboard from the page).
    await page.evaluate(() => {
      window.savedFiles = [];
      const click = HTMLAnchorElement.prototype.click;
      HTMLAnchorElement.prototype.click = function () {
        if (this.download) window.savedFiles.push(this.download);
        else click.call(this);
      };
    });
    await page.click('#download-3mf');
    await page.waitForFunction(() => window.savedFiles.length > 0, { timeout: 30000 }).catch(() => null);
    await page.evaluate(() => window.surfdeformTest.whenIdle());
    const saved = await page.evaluate(() => window.savedFiles);
    check(saved.length === 1 && saved[0] === 'part.3mf', `the part is saved as a 3MF (${saved})`);
    const asked = (await posts()).filter((p) => p.path === '/v1/parts').map((p) => JSON.parse(p.body));
    const surfaceId = await page.evaluate(() => window.surfdeformTest.snapshot().surfaceId);
    check(
      asked.length === 2 && asked[1].output?.format === '3mf' && asked[1].surface_id === surfaceId,
      `the 3MF is asked for by the surface's id (${JSON.stringify(asked[1] || null)})`,
    );
  }
  await page.select('#sample', 'bunny');
  await sleep(300);
  if (await settled('ready', 'the bunny on Figure 10')) {
    await sleep(300); // a frame or two after the model arrived
    const s = await stats();
    check(s && s.input_format === 'ply' && s.triangles >= 75408, `bunny deformed (${s && s.triangles} triangles)`);
    const c = await coverage();
    check(c > 0.01, `the 3D canvas shows the model (${(100 * c).toFixed(1)}% of its pixels)`);
    check(/stress/.test(await text('#quality')), 'flatten quality shown');
    await shot('bunny-figure10');
  }

  // --- live editing, with real pointer events ------------------------------
  const toTop = () => page.evaluate(() => window.scrollTo(0, 0));
  const mask = () => page.evaluate(() => window.surfdeformTest.modelMask());
  const changed = (a, b) => a.reduce((n, x, k) => n + (x !== b[k]), 0);
  const overlap = (a, b) => {
    let both = 0,
      either = 0;
    a.forEach((x, k) => {
      both += x && b[k];
      either += x || b[k];
    });
    return either ? both / either : 0;
  };
  const viewer = (f, ...args) => page.evaluate(f, ...args);
  // What an undo restores: the surface's spec and id, and the placement.
  const pose = () =>
    viewer(() => {
      const s = window.surfdeformTest.snapshot();
      return { spec: JSON.stringify(s.spec), surface: s.surfaceId, center: s.placement.center };
    });
  const keys = async (...combo) => {
    for (const key of combo) await page.keyboard.down(key);
    for (const key of [...combo].reverse()) await page.keyboard.up(key);
  };
  let poseBeforeFootprint = null,
    poseAfterFootprint = null,
    poseAfterDrag = null,
    poseAfterQuick = null;
  // Half the fitted scale (room to move), subdivision off.
  await page.$eval('#scale', (e) => {
    e.value = String(window.surfdeformTest.snapshot().placement.scale / 2);
    e.dispatchEvent(new Event('change'));
  });
  await sleep(300);
  await settled('ready', 'the bunny at half its fitted scale');
  await page.select('#subdivision', 'off');
  await sleep(300);
  await settled('ready', 'subdivision off');
  {
    // Exact results come as meshopt GLB; decoded by three.js here, they hold
    // the Draco GLB's positions to within the two quantizations.
    const s = await stats();
    check(s && s.compression === 'meshopt', `the viewer asks for meshopt (${s && s.compression})`);
    const c = await viewer(() => window.surfdeformTest.compareEncodings());
    check(
      c.worst <= c.bound * 1.001,
      `meshopt and Draco GLB decode to the same positions (${c.worst.toExponential(2)} <= ` +
        `${c.bound.toExponential(2)}; ${c.vertices.join(' / ')} vertices, ` +
        `${c.bytes.meshopt} / ${c.bytes.draco} bytes)`,
    );
  }
  {
    // The footprint: the preview follows every move, no request; the release
    // asks once, and the exact result lands where the preview was.
    await toTop();
    const box = await (await page.$('#sheet')).boundingBox();
    const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
    const m0 = await mask();
    const sent = (await posts()).length;
    poseBeforeFootprint = await pose();
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    for (let k = 1; k <= 6; ++k) {
      await page.mouse.move(cx - 4 * k, cy + 3 * k);
      await sleep(80);
    }
    const m1 = await mask();
    const during = (await posts()).length - sent;
    check(during === 0, `a footprint drag sends no request (${during} sent)`);
    check(await viewer(() => window.surfdeformTest.previewShown()), 'the GPU preview is shown during the drag');
    check(changed(m0, m1) > 50, `the 3D view follows the footprint drag (${changed(m0, m1)} cells changed)`);
    await shot('live-footprint-drag');
    await page.mouse.up();
    if (await settled('ready', 'the exact result after the footprint drag')) {
      poseAfterFootprint = await pose();
      const after = (await posts()).slice(sent);
      check(
        after.length === 1 && after[0].path === '/v1/deform',
        `the release sends exactly one exact request (${after.map((p) => p.path).join(', ')})`,
      );
      check(!(await viewer(() => window.surfdeformTest.previewShown())), 'the exact result replaced the preview');
      const m2 = await mask();
      check(overlap(m1, m2) > 0.8, `the preview covered what the exact result covers (${overlap(m1, m2).toFixed(3)})`);
      const p = await viewer(() => window.surfdeformTest.snapshot().lastPreview);
      check(
        p && p.relative < 1e-3,
        `the preview was within 1e-3 of the sheet's diagonal of the exact result (${p && p.relative.toExponential(2)})`,
      );
      check(/preview vs exact/.test(await text('#timings')), 'the page shows how far the preview was');
      // The preview drew the bunny with a quarter of its triangles (preview_mesh.js).
      const lod = await viewer(() => window.surfdeformTest.snapshot().model.lod);
      check(
        lod && lod.triangles[1] <= 0.26 * lod.triangles[0] && lod.error <= 5e-4,
        `the preview draws the bunny simplified (${lod && lod.triangles[1]} of ${lod && lod.triangles[0]} triangles, ` +
          `error ${lod && lod.error.toExponential(2)})`,
      );
      check(/preview triangles/.test(await text('#timings')), "the page shows the preview's triangles");
      // Settled, nothing changes: no frame is drawn (software WebGL's frames
      // would hold every reply).
      const f0 = await viewer(() => window.surfdeformTest.framesDrawn());
      await sleep(500);
      const f1 = await viewer(() => window.surfdeformTest.framesDrawn());
      check(f0 > 0 && f1 === f0, `a settled page draws no frames (${f1 - f0} in 0.5 s, ${f0} before)`);
      // Orbiting the exact bunny (and back to where the view was): with
      // software WebGL its simplified preview stands in for it while the
      // view moves, and the exact result is drawn again once the view
      // stops; no request either way.
      const view = await (await page.$('#view3d')).boundingBox();
      const [ox, oy] = [view.x + 0.06 * view.width, view.y + 0.94 * view.height];
      const software = await viewer(() => window.surfdeformTest.software());
      const asked = (await posts()).length;
      await page.mouse.move(ox, oy);
      await page.mouse.down();
      for (let k = 1; k <= 5; ++k) {
        await page.mouse.move(ox + 12 * k, oy);
        await sleep(80);
      }
      await page.waitForFunction((f) => window.surfdeformTest.framesDrawn() > f + 1, {}, f1);
      const orbiting = await viewer(() => window.surfdeformTest.standingIn());
      for (let k = 4; k >= 0; --k) {
        await page.mouse.move(ox + 12 * k, oy);
        await sleep(80);
      }
      await page.mouse.up();
      const f2 = await viewer(() => window.surfdeformTest.framesDrawn());
      // 150 ms after the view stops, and then a frame (however busy the machine).
      await page
        .waitForFunction(
          (f, soft) => !window.surfdeformTest.standingIn() && (!soft || window.surfdeformTest.framesDrawn() > f),
          { timeout: 20000 },
          f2,
          software,
        )
        .catch(() => {});
      const stopped = await viewer(() => window.surfdeformTest.standingIn());
      const f3 = await viewer(() => window.surfdeformTest.framesDrawn());
      check(
        orbiting === software,
        `while the view orbits, the preview stands in for the exact bunny ` +
          `with software WebGL only (software: ${software}, stood in: ${orbiting})`,
      );
      check(
        !stopped && (!software || f3 > f2),
        `the exact bunny is drawn again once the view stops ` +
          `(stood in: ${stopped}, ${f3 - f2} frames after the release)`,
      );
      check((await posts()).length === asked, 'orbiting sends no request');
    }
  }
  {
    // A control point: the surface and the model follow during the drag,
    // one surface request at a time; the release deforms exactly once.
    const k = 5; // an inner control point of the bicubic patch
    const at = await viewer((i) => window.surfdeformTest.handlePoint(i), k);
    const m0 = await mask();
    const sent = (await posts()).length;
    const live0 = await viewer(() => window.surfdeformTest.snapshot().live.surfaces);
    const moved0 = await viewer(() => window.surfdeformTest.snapshot().live.moved);
    const uv0 = await viewer(() => window.surfdeformTest.placementParams());
    const gpu0 = await viewer(() => window.surfdeformTest.gpuMemory());
    await page.mouse.move(at[0], at[1]);
    await page.mouse.down();
    let programs0 = [];
    for (let s = 1; s <= 8; ++s) {
      await page.mouse.move(at[0], at[1] - 5 * s);
      await sleep(150);
      // From the second move on, the preview and the surface are drawn with
      // programs compiled already.
      if (s === 2) programs0 = await viewer(() => window.surfdeformTest.programs());
    }
    await sleep(300);
    const programs1 = await viewer(() => window.surfdeformTest.programs());
    const compiled = programs1.filter((id) => !programs0.includes(id));
    // A surface replaced with a new material of its own released the old
    // one's program and compiled it again, at every pointer move (SwiftShader:
    // 323 ms of a 4 s drag in getProgramInfoLog alone).
    check(
      compiled.length === 0,
      `no shader is compiled while a control point is dragged (${compiled.length} new programs; ` +
        `${programs0.length} held)`,
    );
    const m1 = await mask();
    const live = (await viewer(() => window.surfdeformTest.snapshot().live.surfaces)) - live0;
    const moved = (await viewer(() => window.surfdeformTest.snapshot().live.moved)) - moved0;
    const during = (await posts()).slice(sent);
    check(live >= 1, `the surface and the model follow a control-point drag (${live} surfaces shown)`);
    // Every pointer move moves the surface and the model at once (the field
    // moved with the patch), not only when the server's field comes.
    check(moved >= 8, `each of the 8 pointer moves moved the field at once (${moved})`);
    // How far a moved field was from the server's field of the same pose
    // depends on how far the pose moved while a request was out (the
    // machine's speed): reported, and bounded below for a fixed edit.
    const gap = await viewer(() => window.surfdeformTest.snapshot().live.gap);
    check(
      gap > 0,
      `moved fields were compared with the server's during the drag (${gap.toExponential(2)} of the diagonal at most)`,
    );
    check(
      during.length >= 1 && during.every((p) => p.path === '/v1/surfaces'),
      `only surfaces are asked for during it (${during.map((p) => p.path).join(', ')})`,
    );
    check(
      during.every((p) => /"warm_start":"[0-9a-f]{32}"/.test(p.body)),
      'each pose starts from the surface before it (warm_start)',
    );
    check(changed(m0, m1) > 50, `the 3D view changes during the control-point drag (${changed(m0, m1)} cells)`);
    await shot('live-control-point-drag');
    const before = (await posts()).length;
    await page.mouse.up();
    if (await settled('ready', 'the exact result after the control-point drag')) {
      poseAfterDrag = await pose();
      const deforms = (await posts()).slice(before).filter((p) => p.path === '/v1/deform').length;
      check(deforms === 1, `the release sends one exact deformation (${deforms})`);
      // Each pointer move replaced the surface (and the release the model):
      // the ones replaced are freed on the GPU, not kept until the page closes.
      const gpu1 = await viewer(() => window.surfdeformTest.gpuMemory());
      check(
        gpu1.geometries <= gpu0.geometries + 1 && gpu1.textures <= gpu0.textures + 2,
        `the replaced surfaces and models are freed (geometries ${gpu0.geometries} -> ` +
          `${gpu1.geometries}, textures ${gpu0.textures} -> ${gpu1.textures})`,
      );
      const uv1 = await viewer(() => window.surfdeformTest.placementParams());
      // The model stays on the same part of the surface: its placement moved
      // with each new sheet (warm_start.motion). Measured: 2.1e-4 in (u, v);
      // 7.2e-3 with the placement left where it was on the sheet.
      const slid = Math.hypot(uv1[0] - uv0[0], uv1[1] - uv0[1]);
      check(
        slid < 2e-3,
        `the placement stays on the same surface point through the edit (slid ${slid.toExponential(2)} in u, v)`,
      );
      // The moved field lies on the edited surface: the server's, for a
      // control point raised by 5% of the patch, at float32's precision.
      const on = await viewer(() => window.surfdeformTest.movedFieldOnSurface(5, 0.5));
      check(
        on.points > 50 && on.shift > 1e-3 && on.worst < 1e-6,
        `a moved field's ${on.points} points lie on the edited surface (${on.worst.toExponential(2)} ` +
          `of the diagonal off, moved ${on.shift.toExponential(2)})`,
      );
      // With the placement moved as the new sheet lies (warm_start.motion),
      // it is much nearer the server's field of that pose than the field
      // before the edit is: what is left is the flat sheet's own change.
      check(
        on.gap < 0.5 * on.unmoved,
        `the moved field is nearer the server's field for that pose than the unmoved one ` +
          `(${on.gap.toExponential(2)} against ${on.unmoved.toExponential(2)} of the diagonal; ` +
          `${on.raw.toExponential(2)} without the sheet's motion)`,
      );
    }
    // Let go at once after a move: that pose is not flattened yet (the live
    // request for it held back 1 s, as on a slow network). The release is
    // one request, the edit flattened and the model deformed on it
    // (warm_start in /v1/deform), the placement moved with the new sheet by
    // the server; the sheet and its field come after.
    const uv2 = await viewer(() => window.surfdeformTest.placementParams());
    const at2 = await viewer((i) => window.surfdeformTest.handlePoint(i), k);
    await page.mouse.move(at2[0], at2[1]);
    await page.mouse.down();
    const quick = (await posts()).length;
    await page.evaluate(() => {
      window.holdSurfaces = 1000;
    });
    await page.mouse.move(at2[0], at2[1] + 15);
    await page.mouse.up();
    const quickSettled = await settled('ready', 'the exact result after a quick control-point drag');
    await page.evaluate(() => {
      window.holdSurfaces = 0;
    });
    if (quickSettled) {
      poseAfterQuick = await pose();
      const after = (await posts()).slice(quick);
      const exact = after.filter((p) => p.path === '/v1/deform');
      check(
        exact.length === 1 && /"surface":\{/.test(exact[0].body) && /"warm_start":"[0-9a-f]{32}"/.test(exact[0].body),
        `a quick release is one deformation of the edit inline, warm (${after.map((p) => p.path).join(', ')})`,
      );
      const uv3 = await viewer(() => window.surfdeformTest.placementParams());
      const slid = Math.hypot(uv3[0] - uv2[0], uv3[1] - uv2[1]);
      check(
        slid < 2e-3,
        `the server kept the placement on the same surface point (slid ${slid.toExponential(2)} in u, v)`,
      );
      const st = await viewer(() => ({
        shown: window.surfdeformTest.snapshot().surfaceId,
        stats: window.surfdeformTest.snapshot().lastStats,
      }));
      check(
        st.stats.surface_id === st.shown && Boolean(st.stats.warm_start?.placement),
        `the page shows the surface the deformation made, the placement the server moved ` +
          `(${JSON.stringify(st.stats.warm_start)})`,
      );
    }
  }
  if (poseBeforeFootprint && poseAfterFootprint && poseAfterDrag && poseAfterQuick) {
    // Undo and redo, each as one exact deformation: back through the quick
    // control-point drag, the drag before it (the surface changes) and the
    // footprint drag (the placement only), by Ctrl+Z and the header's
    // button; forward by Ctrl+Shift+Z, Ctrl+Y and the button. The quick
    // drag is shown again at the end, for what follows.
    const h0 = await viewer(() => window.surfdeformTest.history());
    check(h0.back >= 3 && h0.ahead === 0, `every settled edit is a step to undo (${h0.back} back, ${h0.ahead} ahead)`);
    check(
      !(await page.$eval('#undo', (e) => e.disabled)) && (await page.$eval('#redo', (e) => e.disabled)),
      'Undo is enabled, Redo is not',
    );
    const same = (p, q) =>
      p.spec === q.spec &&
      p.surface === q.surface &&
      Math.hypot(p.center[0] - q.center[0], p.center[1] - q.center[1]) < 1e-9;
    const shows = async (want, how, what) => {
      const sent = (await posts()).length;
      await how();
      await sleep(100);
      if (!(await settled('ready', what))) return;
      const p = await pose();
      const deforms = (await posts()).slice(sent).filter((x) => x.path === '/v1/deform').length;
      const s = await stats();
      check(
        same(p, want) && s.surface_id === want.surface && deforms === 1,
        `${what}: the surface and placement it brings back, one exact deformation ` +
          `(${deforms}) of that surface (${p.surface === want.surface}, ${s.surface_id === want.surface})`,
      );
    };
    await toTop();
    await shows(poseAfterDrag, () => keys('Control', 'z'), 'Ctrl+Z undoes the quick drag');
    check(!(await page.$eval('#redo', (e) => e.disabled)), 'then Redo is enabled');
    await shows(poseAfterQuick, () => keys('Control', 'Shift', 'z'), 'Ctrl+Shift+Z redoes it');
    await shows(poseAfterDrag, () => page.click('#undo'), 'the Undo button undoes it');
    await shows(poseAfterFootprint, () => page.click('#undo'), 'the Undo button undoes the first control-point drag');
    await shows(poseBeforeFootprint, () => keys('Control', 'z'), 'Ctrl+Z undoes the footprint drag');
    check(
      poseBeforeFootprint.spec === poseAfterFootprint.spec &&
        poseBeforeFootprint.center[0] !== poseAfterFootprint.center[0],
      'which moved the placement only',
    );
    await shows(poseAfterFootprint, () => keys('Control', 'y'), 'Ctrl+Y redoes the footprint drag');
    await shows(poseAfterDrag, () => page.click('#redo'), 'the Redo button redoes the first control-point drag');
    await shows(poseAfterQuick, () => page.click('#redo'), 'and the quick one');
    check(await page.$eval('#redo', (e) => e.disabled), 'nothing left to redo: Redo is disabled');
  }
  {
    // "Save the request": the file the button saves, sent by curl's route
    // (multipart, the model as read from disk), gives what the page shows:
    // the same surface id, placement and mesh.
    const saved = await viewer(async () => {
      const click = HTMLAnchorElement.prototype.click;
      let file = null;
      HTMLAnchorElement.prototype.click = function () {
        file = { name: this.download, href: this.href };
      };
      try {
        document.getElementById('save-request').click();
      } finally {
        HTMLAnchorElement.prototype.click = click;
      }
      return file && { name: file.name, text: await (await fetch(file.href)).text() };
    });
    // Sent as saved, and as the page sends it, both meshopt: the same bytes.
    const request = JSON.parse(saved ? saved.text : '{}');
    const form = new FormData();
    form.append(
      'mesh',
      new Blob([readFileSync(new URL('../../client/web/samples/bunny.ply', import.meta.url))]),
      'bunny.ply',
    );
    form.append('params', JSON.stringify({ ...request, output: { ...request.output, compression: 'meshopt' } }));
    const r = await fetch(`${base}/v1/deform`, { method: 'POST', body: form });
    const digest = createHash('sha256')
      .update(Buffer.from(await r.arrayBuffer()))
      .digest('hex');
    const shown = await viewer(() => window.surfdeformTest.exactDigest());
    check(
      saved &&
        saved.name === 'bunny-request.json' &&
        request.surface?.kind === 'bezier' &&
        Array.isArray(request.placement?.center) &&
        r.ok &&
        digest === shown,
      `the saved request (${saved && saved.name}), sent by curl's route with the model's file, gives ` +
        `the page's exact result byte for byte (${r.status}, ${digest.slice(0, 12)} / ${shown.slice(0, 12)})`,
    );
    // Turned away, then the saved file opened: the page shows that request again.
    await page.$eval('#rotation', (e) => {
      e.value = String(Number(e.value) + 40);
      e.dispatchEvent(new Event('input'));
      e.dispatchEvent(new Event('change'));
    });
    await sleep(300);
    await settled('ready', 'the model turned');
    const turned = await viewer(() => window.surfdeformTest.exactDigest());
    const file = path.join(artifacts, 'bunny-request.json');
    writeFileSync(file, saved ? saved.text : '{}');
    await (await page.$('#open-request')).uploadFile(file);
    await sleep(300);
    if (await settled('ready', 'the saved request opened')) {
      const opened = await viewer(() => window.surfdeformTest.exactDigest());
      check(
        turned !== digest && opened === digest,
        `opening the saved request brings its result back, byte for byte (turned ${turned.slice(0, 12)}, ` +
          `opened ${opened.slice(0, 12)}, saved ${digest.slice(0, 12)})`,
      );
    }
    // Not a request: a clear error, nothing changed.
    const bad = path.join(artifacts, 'not-a-request.json');
    writeFileSync(bad, '{"placement": {}}');
    await (await page.$('#open-request')).uploadFile(bad);
    await sleep(300);
    await page.waitForFunction(() => document.body.dataset.state !== 'loading', { timeout: 30000 });
    check(
      /no "surface" object/.test(await text('#error')) &&
        (await viewer(() => window.surfdeformTest.exactDigest())) === digest,
      `a JSON file that is no request is refused, and the page stays (${await text('#error')})`,
    );
    // The request opened once more: the banner goes with the next result.
    const again = path.join(artifacts, 'bunny-request-again.json');
    writeFileSync(again, saved ? saved.text : '{}');
    await (await page.$('#open-request')).uploadFile(again);
    await sleep(300);
    if (await settled('ready', 'the saved request opened again')) {
      check(await page.$eval('#error', (e) => e.hidden), 'the next result clears the error');
    }
  }
  {
    // A control point's numbers: pressed without a move, it is selected and
    // nothing is sent; a z typed is one exact deformation of the edited
    // patch, and Ctrl+Z puts the point back.
    await toTop();
    const k = 5;
    const at = await viewer((i) => window.surfdeformTest.handlePoint(i), k);
    const sent = (await posts()).length;
    await page.mouse.click(at[0], at[1]);
    await sleep(300);
    const point = () => viewer((i) => window.surfdeformTest.snapshot().spec.control_points[i], k);
    const p0 = await point();
    const shownNumbers = () =>
      page.evaluate(() => ['x', 'y', 'z'].map((c) => Number(document.getElementById(`cp-${c}`).value)));
    const visible = await page.$eval('#cp-edit', (e) => !e.hidden);
    check(
      visible &&
        JSON.stringify(await shownNumbers()) === JSON.stringify(p0) &&
        (await posts()).length === sent &&
        (await page.evaluate(() => document.body.dataset.state)) === 'ready',
      `a control point pressed without a move shows its numbers and sends nothing (${await shownNumbers()})`,
    );
    await shot('control-point-numbers');
    const z = Math.round((p0[2] + 0.5) * 1e6) / 1e6;
    await page.focus('#cp-z');
    await keys('Control', 'a');
    await page.keyboard.type(String(z));
    await page.keyboard.press('Tab');
    await sleep(100);
    if (await settled('ready', 'a typed control point')) {
      const after = (await posts()).slice(sent);
      const p1 = await point();
      const st = await viewer(() => ({
        shown: window.surfdeformTest.snapshot().surfaceId,
        stats: window.surfdeformTest.snapshot().lastStats,
      }));
      check(
        p1[2] === z &&
          p1[0] === p0[0] &&
          p1[1] === p0[1] &&
          after.filter((x) => x.path === '/v1/deform').length === 1 &&
          st.stats.surface_id === st.shown,
        `a typed z moves the point (${p0[2]} -> ${p1[2]}), as one exact deformation of the new patch ` +
          `(${after.map((x) => x.path).join(', ')})`,
      );
    }
    await page.evaluate(() => document.activeElement && document.activeElement.blur());
    await keys('Control', 'z');
    await sleep(100);
    if (await settled('ready', 'the typed control point undone')) {
      const p2 = await point();
      check(
        JSON.stringify(p2) === JSON.stringify(p0) && (await shownNumbers())[2] === p0[2],
        `Ctrl+Z puts the typed point back (${p2}), and its numbers (${await shownNumbers()})`,
      );
    }
  }
  {
    // Part of the footprint dragged off the sheet: tinted during the drag,
    // no banner; the exact request's error on release, over the view
    // (nothing moves under the pointer); dragged back, all is well.
    await toTop();
    const box = await (await page.$('#sheet')).boundingBox();
    const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
    const view0 = await page.$eval('#view3d', (e) => e.getBoundingClientRect().toJSON());
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    for (let k = 1; k <= 6; ++k) {
      await page.mouse.move(cx + 0.08 * box.width * k, cy);
      await sleep(60);
    }
    const n = await page.evaluate(() => window.surfdeformTest.pixelCounts());
    const banner = await page.$eval('#error', (e) => !e.hidden);
    check(n.red > 100 && !banner, `the part off the sheet is tinted, no banner (${n.red} red pixels)`);
    await shot('live-off-the-sheet');
    await page.mouse.up();
    if (await settled('error', 'the exact request off the sheet')) {
      check(/outside the flat sheet/.test(await text('#error')), "the exact request's error is shown");
      const view1 = await page.$eval('#view3d', (e) => e.getBoundingClientRect().toJSON());
      check(view1.x === view0.x && view1.y === view0.y, 'the banner does not move the views');
    }
    await page.mouse.move(cx + 0.48 * box.width, cy);
    await page.mouse.down();
    await page.mouse.move(cx, cy, { steps: 4 });
    await page.mouse.up();
    await settled('ready', 'dragged back onto the sheet');
  }
  await page.select('#subdivision', 'adaptive');
  await sleep(300);
  await settled('ready', 'subdivision back on');

  await page.select('#preset', 'cylinder');
  await page.select('#sample', 'plate');
  await sleep(500);
  if (await settled('ready', 'the plate on a cylinder')) {
    await sleep(300);
    const s = await stats();
    check(
      s && s.subdivision.vertices_added > 0,
      `the plate follows the cylinder (${s && s.subdivision.vertices_added} vertices added)`,
    );
    check((await coverage()) > 0.005, 'the plate is on the canvas');
    await shot('plate-cylinder');
  }

  // The distortion map on the plate: its faces off the mid surface stretch
  // (outside, red) and shrink (inside, blue, the face the camera sees): red
  // and blue pixels, hardly any of the plain colour (warm counts red too).
  await page.click('#distortion');
  await sleep(300);
  if (await settled('ready', 'the plate coloured by distortion')) {
    await sleep(300);
    const s = await stats();
    const n = await page.evaluate(() => window.surfdeformTest.pixelCounts());
    check(
      s && s.distortion && s.distortion.max > 0.01,
      `distortion stats shown (max ${s && s.distortion && s.distortion.max})`,
    );
    const coloured = n.red + n.blue;
    check(
      coloured > 0.005 * n.total && n.red > 0 && n.blue > 0 && n.warm - n.red < 0.2 * coloured,
      `the model is coloured by distortion (${n.red} red, ${n.blue} blue, ${n.warm} plain pixels)`,
    );
    check(/distortion/.test(await text('#timings')), 'the distortion summary is listed');
    await shot('plate-distortion');
  }
  await page.click('#distortion');
  await sleep(300);
  await settled('ready', 'the distortion map turned off');
  check((await coverage()) > 0.005, 'the plain colour is back');
  // Clicking the controls may have scrolled the page (Firefox does): mouse
  // positions below are taken with the views in sight.
  await toTop();

  // Halve the scale (the fit fills the sheet), typed into the field as a
  // person would, then drag the footprint on the sheet: the model is deformed
  // again where it lands.
  const fitted = await page.evaluate(() => window.surfdeformTest.snapshot().placement.scale);
  await page.focus('#scale');
  await page.keyboard.down('Control');
  await page.keyboard.press('KeyA');
  await page.keyboard.up('Control');
  await page.keyboard.type(String(fitted / 2));
  await page.keyboard.press('Enter');
  await sleep(300);
  await settled('ready', 'at half the scale');
  const before = await page.evaluate(() => [...window.surfdeformTest.snapshot().placement.center]);
  await toTop();
  const box = await (await page.$('#sheet')).boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 40, box.y + box.height / 2, { steps: 5 });
  await page.mouse.up();
  await sleep(400);
  if (await settled('ready', 'after dragging the footprint')) {
    const center = await page.evaluate(() => window.surfdeformTest.snapshot().placement.center);
    const s = await stats();
    check(
      center[0] > before[0] + 0.05 && Math.abs(center[1] - before[1]) < 0.05,
      `the footprint moved right (centre ${before.map((x) => x.toFixed(2))} -> ${center.map((x) => x.toFixed(2))})`,
    );
    check(s.placement.scale === fitted / 2, `deformed at the scale the person chose (${s.placement.scale})`);
    await shot('plate-moved');
  }

  // Models travel once: the bunny and the plate were each uploaded
  // once (POST /v1/models), and every deformation since names its model by
  // id in a small JSON body.
  {
    const all = await posts();
    const uploads = all.filter((p) => p.path === '/v1/models').length;
    const deforms = all.filter((p) => p.path === '/v1/deform');
    check(
      uploads === 2,
      `each model uploaded once (${uploads} uploads for the bunny and the plate; ` +
        'the text is shaped by the server)',
    );
    check(
      deforms.length >= 4 &&
        deforms.every(
          (p) => p.type.startsWith('application/json') && /"model_id":"[0-9a-f]{32}"|"text":\{/.test(p.body),
        ),
      `every deformation names its model by id or is a text (${deforms.length} deformations, ` +
        `types ${[...new Set(deforms.map((p) => p.type))].join(', ')})`,
    );
  }

  // Draw a mark on the sheet (three clicks across it): the server resamples
  // it onto the surface and the 3D view draws it, green, on the cylinder.
  await page.click('#mark');
  await toTop();
  const sheetBox = await (await page.$('#sheet')).boundingBox();
  for (const fx of [0.2, 0.5, 0.8]) {
    await page.mouse.click(sheetBox.x + fx * sheetBox.width, sheetBox.y + 0.3 * sheetBox.height);
    await sleep(150);
  }
  try {
    await page.waitForFunction(() => (window.surfdeformTest.snapshot().lastMark || []).length > 3, { timeout: 20000 });
    await sleep(300);
    const mark = await page.evaluate(() => window.surfdeformTest.snapshot().lastMark);
    const n = await page.evaluate(() => window.surfdeformTest.pixelCounts());
    check(
      mark.every((m) => m.on_sheet && Math.abs(Math.hypot(m.point[0], m.point[1]) - 1) < 1e-6),
      `the mark lies on the cylinder (${mark.length} points)`,
    );
    check(n.green > 50, `the mark is drawn in the 3D view (${n.green} green pixels)`);
    await shot('mark-on-cylinder');
  } catch (e) {
    check(false, `the mark came back from the server: ${e}`);
  }
  await page.click('#mark'); // done marking: clicks move the footprint again
  await page.click('#clear-marks');
  await toTop();
  await sleep(200);
  const cleared = await page.evaluate(() => window.surfdeformTest.pixelCounts());
  check(cleared.green < 20, `clearing removes the mark (${cleared.green} green pixels)`);

  // A textured glTF (assimp's BoxTextured) comes back textured: three.js
  // decodes the image the server carried over, and draws the model with it.
  await (await page.$('#upload')).uploadFile('/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb');
  await sleep(500);
  if (await settled('ready', 'the textured box')) {
    try {
      await page.waitForFunction(() => window.surfdeformTest.texturedMeshes() > 0, { timeout: 20000 });
      check(true, 'the deformed box is drawn with its texture');
    } catch {
      check(false, 'the deformed box is drawn with its texture');
    }
    const s = await stats();
    check(s && s.placement.up === '+y', `a glTF model stands on its +Y (${s && s.placement.up})`);
    await sleep(300);
    await shot('textured-box');
  }

  // The animation panel: the swimming wave, 12 frames at 12 fps, played by
  // three.js's AnimationMixer from a meshopt GLB. The canvas changes as it
  // plays, and the frame shown at time k / fps is the one POST /v1/deform
  // gives for frame k (to within the positions' quantization).
  await page.select('#anim-preset', 'swim');
  await page.$eval('#anim-frames', (e) => {
    e.value = '12';
  });
  await page.$eval('#anim-fps', (e) => {
    e.value = '12';
  });
  await page.click('#anim-run');
  try {
    await page.waitForFunction(() => ['playing', 'error'].includes(document.body.dataset.animation), {
      timeout: 60000,
    });
    const animState = await page.evaluate(() => document.body.dataset.animation);
    check(animState === 'playing', `the animation plays (${animState}; ${await text('#error')})`);
    const canvas = () => page.evaluate(() => document.querySelector('#view3d canvas').toDataURL());
    const first = await canvas();
    await sleep(400);
    const later = await canvas();
    check(first !== later, 'the 3D view changes as the animation plays');
    await shot('animation-playing');
    for (const k of [0, 5, 11]) {
      const r = await page.evaluate((f) => window.surfdeformTest.compareAnimationFrame(f), k);
      const oneHot = r.weights.every((w, j) => Math.abs(w - (j === k ? 1 : 0)) < 1e-6);
      check(
        r.worst <= 0.51 * r.step + 1e-6 && oneHot,
        `frame ${k} as shown matches POST /v1/deform's frame ${k} (${r.worst.toExponential(2)}, ` +
          `step ${r.step.toExponential(2)}, weight ${r.weights[k]})`,
      );
    }
    const paused = await canvas();
    await sleep(300);
    check(paused === (await canvas()), 'scrubbing pauses the animation');
    await shot('animation-frame-11');
  } catch (e) {
    check(false, `the animation ran: ${e}`);
  }

  {
    // A Draco answer past the server's split threshold (150,000 vertices)
    // comes in pieces, one primitive each; decoded by three.js, a vertex on
    // a border has the same bits in every piece that holds it (no crack).
    const grid = gridPly(410, -2, -2, 4, (x, y) => 0.05 * Math.sin(3 * x) * Math.cos(2 * y));
    const verts = grid.vertices,
      tris = grid.triangles;
    const up = await fetch(`${base}/v1/models`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/octet-stream' },
      body: grid.bytes,
    });
    const model = (await up.json()).id;
    const d = await viewer(async (id) => {
      const v = window.surfdeformTest;
      const r = await fetch('/v1/deform', {
        method: 'POST',
        headers: { 'Content-Type': 'application/json', Accept: 'model/gltf-binary' },
        body: JSON.stringify({
          model_id: id,
          surface_id: v.snapshot().surfaceId,
          placement: { scale: 'fit' },
          subdivision: { mode: 'off' },
          output: { format: 'glb' },
        }),
      });
      if (!r.ok) return { error: `${r.status} ${await r.text()}` };
      return { ...(await v.decodeGlb(await r.arrayBuffer())), stats: JSON.parse(r.headers.get('X-Surfdeform-Stats')) };
    }, model);
    check(
      !d.error && d.primitives === 2 && d.stats.pieces === 2 && d.triangles === tris,
      `a ${verts}-vertex Draco GLB comes in pieces (${
        d.error || `${d.primitives} primitives, ` + `${d.triangles} triangles`
      })`,
    );
    check(
      !d.error && d.vertices > verts && d.distinct === verts,
      `three.js decodes the pieces without a crack (${d.distinct} distinct positions of ` +
        `${d.vertices} decoded, ${verts} vertices)`,
    );
  }

  // The can, a whole cylinder: its sheet is periodic. The footprint dragged
  // left past the seam comes back from the right, a period away, and the
  // model is deformed across the seam.
  // The sheet view paints its cells and seams once per sheet: the new
  // sheet's seams (dashed, #c60) must show where the last sheet had none.
  const seamPixels = () =>
    page.$eval('#sheet', (c) => {
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let k = 0; k < d.length; k += 4) {
        n += Math.abs(d[k] - 204) < 30 && Math.abs(d[k + 1] - 102) < 30 && d[k + 2] < 40 ? 1 : 0;
      }
      return n;
    });
  const seamsBefore = await seamPixels();
  await page.select('#preset', 'can');
  await sleep(300);
  if (await settled('ready', 'on the can')) {
    const seamsAfter = await seamPixels();
    check(
      seamsBefore < 20 && seamsAfter > 200,
      `the new sheet's seams are painted (${seamsBefore} -> ${seamsAfter} seam-coloured pixels)`,
    );
    const before = await page.evaluate(() => [...window.surfdeformTest.snapshot().placement.center]);
    await toTop();
    const canBox = await (await page.$('#sheet')).boundingBox();
    // The sheet (2 pi x 2) fills the canvas's width less 16 px each side:
    // drag the centre 0.2 past the seam, so the model straddles it.
    const width = await page.$eval('#sheet', (c) => c.width);
    const perUnit = ((width - 32) / (2 * Math.PI)) * (canBox.width / width);
    await page.mouse.move(canBox.x + canBox.width / 2, canBox.y + canBox.height / 2);
    await page.mouse.down();
    await page.mouse.move(canBox.x + canBox.width / 2 - (Math.PI + 0.2) * perUnit, canBox.y + canBox.height / 2, {
      steps: 8,
    });
    await page.mouse.up();
    await sleep(400);
    if (await settled('ready', 'after dragging the footprint past the seam')) {
      const center = await page.evaluate(() => window.surfdeformTest.snapshot().placement.center);
      const s = await stats();
      check(
        before[0] > 3 &&
          before[0] < 3.3 &&
          center[0] > 2 * Math.PI - 0.3 &&
          center[0] < 2 * Math.PI - 0.1 &&
          Math.abs(center[1] - before[1]) < 0.05,
        `the footprint went past the seam and came back from the other side (centre ` +
          `${before.map((x) => x.toFixed(2))} -> ${center.map((x) => x.toFixed(2))})`,
      );
      check(
        s && s.placement.turns > 0 && s.placement.turns <= 1,
        `deformed across the seam of the can (turns ${s && s.placement.turns})`,
      );
      // The preview bent the parts past the seam a period away, as the server.
      const p = await page.evaluate(() => window.surfdeformTest.snapshot().lastPreview);
      check(
        p && p.relative < 1e-3,
        `the preview across the seam was within 1e-3 of the sheet's diagonal of the exact ` +
          `result (${p && p.relative.toExponential(2)})`,
      );
      await shot('across-the-seam');
    }
  }

  // The bottle, a NURBS surface of revolution closed in u: flattened
  // periodic, its seam drawn, and the sample label across the seam deformed.
  await page.select('#sample', 'label');
  await sleep(300);
  await settled('ready', 'with the label sample');
  await page.select('#preset', 'bottle');
  await sleep(300);
  if (await settled('ready', 'on the bottle')) {
    const sheet = await page.evaluate(() => {
      const s = window.surfdeformTest.sheet();
      return s && { period: s.period, lo: s.lo, hi: s.hi };
    });
    check(
      sheet && sheet.period && Math.abs(sheet.period.angle) < 1e-9 && sheet.period.t[0] > 5,
      `the bottle's sheet is periodic, with a translation period ` + `(${JSON.stringify(sheet && sheet.period)})`,
    );
    const middle = sheet ? (sheet.lo[1] + sheet.hi[1]) / 2 : 1;
    await page.evaluate((y) => window.surfdeformTest.placeAt([0, y]), middle);
    await sleep(400);
    if (await settled('ready', "with the model on the bottle's seam")) {
      const s = await stats();
      check(
        s && s.placement.turns > 0 && s.placement.outside === 0,
        `deformed across the seam of the bottle (turns ${s && s.placement.turns})`,
      );
      await shot('bottle');
    }
  }

  // The ring, a whole torus: a flat torus, periodic both ways. The model
  // placed on the corner where the two seams cross is deformed.
  await page.select('#preset', 'ring');
  await sleep(300);
  if (await settled('ready', 'on the ring')) {
    const periods = await page.evaluate(() => {
      const s = window.surfdeformTest.sheet();
      return s && { u: s.period && s.period.t, v: s.periodV };
    });
    check(
      periods && periods.u && periods.v && Math.hypot(...periods.v) > 3,
      `the ring's sheet is periodic both ways (${JSON.stringify(periods)})`,
    );
    await page.evaluate(() => window.surfdeformTest.placeAt([0, 0]));
    await sleep(400);
    if (await settled('ready', "with the model on the corner of the ring's seams")) {
      const s = await stats();
      check(
        s && s.placement.turns > 0 && s.placement.outside === 0,
        `deformed across both seams of the ring (turns ${s && s.placement.turns})`,
      );
      const p = await page.evaluate(() => window.surfdeformTest.snapshot().lastPreview);
      check(
        p && p.relative < 2e-3,
        `the preview across both seams was within 2e-3 of the sheet's diagonal of the ` +
          `exact result (${p && p.relative.toExponential(2)})`,
      );
      await shot('ring');
    }
  }

  // The lampshade, a whole cone: its sheet repeats by a rotation about the
  // apex. The plate on the seam is deformed, and the preview turns the part
  // past the seam a sector's turn back, as the server does.
  await page.select('#sample', 'plate');
  await sleep(300);
  await settled('ready', 'with the plate sample');
  await page.select('#preset', 'lampshade');
  await sleep(300);
  if (await settled('ready', 'on the lampshade')) {
    const angle = await page.evaluate(() => {
      const s = window.surfdeformTest.sheet();
      return s && s.period && s.period.angle;
    });
    check(angle && Math.abs(angle) > 1, `the lampshade's sheet repeats by a rotation (${angle})`);
    // Sample (0, 0) is at the origin and the seam runs up from it.
    await page.evaluate(() => window.surfdeformTest.placeAt([0, 0.55]));
    await sleep(400);
    if (await settled('ready', "with the plate on the lampshade's seam")) {
      const s = await stats();
      check(
        s && s.placement.turns > 0 && s.placement.outside === 0,
        `deformed across the seam of the lampshade (turns ${s && s.placement.turns})`,
      );
      const p = await page.evaluate(() => window.surfdeformTest.snapshot().lastPreview);
      check(
        p && p.relative < 2e-3,
        `the preview across a cone's seam was within 2e-3 of the sheet's diagonal of the ` +
          `exact result (${p && p.relative.toExponential(2)})`,
      );
      await shot('lampshade');
    }
  }

  // Surfaces given as meshes: the panel preset (a triangle mesh
  // uploaded as a model) flattens to its flat triangles, drawn on the sheet,
  // and the plate deforms along it; a mesh dropped on the sheet becomes the
  // surface.
  await page.select('#preset', 'panel');
  await sleep(300);
  if (await settled('ready', 'on the panel mesh')) {
    const triangles = await page.evaluate(() => {
      const s = window.surfdeformTest.sheet();
      return s && s.mesh ? s.mesh.triangles.length : 0;
    });
    check(triangles === 1728, `the panel's sheet is its 1728 flat triangles (${triangles})`);
    const s = await stats();
    check(
      s && s.vertices >= 8 && s.placement.outside === 0,
      `the plate deformed along the panel mesh (${s && s.vertices} vertices)`,
    );
    const quality = await text('#quality');
    check(
      /925 vertices, 1728 triangles/.test(quality) && /folded triangles/.test(quality),
      `the quality panel describes the mesh: ${quality.replace(/\s+/g, ' ').slice(0, 100)}`,
    );
    await shot('panel');
  }
  await page.evaluate(() => {
    // Half a cylinder, 6 x 4 cells: 35 vertices, 48 triangles.
    const lines = [];
    for (let j = 0; j <= 4; ++j) {
      for (let i = 0; i <= 6; ++i) {
        const a = (Math.PI * i) / 6;
        lines.push(`v ${Math.cos(a)} ${Math.sin(a)} ${0.5 * j}`);
      }
    }
    for (let j = 0; j < 4; ++j) {
      for (let i = 0; i < 6; ++i) {
        const a = 1 + i + 7 * j,
          b = a + 1,
          c = a + 8,
          d = a + 7;
        lines.push(`f ${a} ${b} ${c}`, `f ${a} ${c} ${d}`);
      }
    }
    const file = new File([lines.join('\n') + '\n'], 'half-cylinder.obj');
    const transfer = new DataTransfer();
    transfer.items.add(file);
    document
      .querySelector('#sheet')
      .dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, bubbles: true, cancelable: true }));
  });
  await sleep(300);
  if (await settled('ready', 'after dropping a surface mesh on the sheet')) {
    const dropped = await page.evaluate(() => {
      const s = window.surfdeformTest.sheet();
      return s && s.mesh ? s.mesh.triangles.length : 0;
    });
    check(dropped === 48, `a mesh dropped on the sheet is the surface: 48 flat triangles (${dropped})`);
    await shot('dropped-surface');
  }

  // A broken upload through the file input: the server's problem detail
  // appears on the page.
  const broken = path.join(artifacts, 'broken.obj');
  writeFileSync(broken, 'v 0 0 0\nf 1 2 99999\n');
  await (await page.$('#upload')).uploadFile(broken);
  if (await settled('error', 'a broken upload')) {
    const message = await text('#error');
    check(/422/.test(message) && /mesh/i.test(message), `the server's error is shown: ${message.trim().slice(0, 120)}`);
    const visible = await page.$eval('#error', (e) => {
      const r = e.getBoundingClientRect();
      return getComputedStyle(e).visibility !== 'hidden' && r.width > 0 && r.height > 0;
    });
    check(visible, 'the error box is visible');
    await shot('broken-upload');
  }

  check(foreign.length === 0, `nothing fetched from elsewhere${foreign.length ? ': ' + foreign[0] : ''}`);
  check(pageErrors.length === 0, `no uncaught page errors${pageErrors.length ? ': ' + pageErrors[0] : ''}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
if (failures.length) {
  console.error(`${failures.length} check(s) failed; screenshots in ${artifacts}`);
  process.exit(1);
}
console.log(`viewer in ${browserName}: all checks passed; screenshots in ${artifacts}`);
