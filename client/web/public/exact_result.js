// The exact result: POST /v1/deform of what the page shows, as meshopt GLB
// (some 10x faster for the server to encode than Draco, decoded here at
// GB/s), on the "exact" lane: one at a time, the newest ask after it. And
// its figures on the page, with how far the last preview was from it.
import { deform } from './api.js';
import { $, afterNextFrame, fmt, list } from './dom.js';
import { placementFrame } from './footprint.js';
import { nearestDistances, previewPositions } from './field_sampling.js';
import { shownKey } from './viewer_state.js';
import { shownPositions } from './view_probes.js';

export function installExactResult(page) {
  const { store, scheduler, sheetView, modelView, preview, gltf } = page;
  let deformTimer = 0;

  // What an exact result or a preview shows: its surface, placement and the
  // settings the preview follows ("rigid" parts it does not: none).
  page.shownKey = (surfaceId) => shownKey(store.state, surfaceId);

  // `edit` ({surface, sampling, warm_start}): the surface inline, an edit of
  // the one the placement is on (/v1/deform flattens it and moves the
  // placement with its sheet); else the current surface by id.
  page.deformParams = (format, compression, edit = null) => {
    const s = store.state;
    const p = s.placement;
    const text = s.model && s.model.text;
    return {
      ...(edit || { surface_id: s.surfaceId }),
      ...(text ? { text } : {}),
      placement: {
        up: s.settings.up,
        anchor: s.settings.anchor,
        rigid: s.settings.rigid,
        center: text ? page.offsetCenter(p.center, p, -1) : p.center,
        rotation_deg: p.rotation_deg,
        scale: s.fitNext ? 'fit' : p.scale,
      },
      subdivision: { mode: s.settings.subdivision },
      // The distortion map travels in GLB (and PLY) only.
      output: {
        format,
        ...(compression ? { compression } : {}),
        ...(format === 'glb' && s.settings.distortion ? { distortion: true } : {}),
      },
    };
  };

  page.scheduleDeform = (delay) => {
    store.dispatch('busy');
    clearTimeout(deformTimer);
    // Now, not a task later: on a busy page a task waits for the next frame.
    if (delay === 0) page.runDeform();
    else deformTimer = setTimeout(page.runDeform, delay);
  };

  // An edit in progress: the exact deformation waits for its release.
  page.holdDeform = () => {
    store.dispatch('busy');
    clearTimeout(deformTimer);
  };

  page.cancelScheduledDeform = () => clearTimeout(deformTimer);

  // The exact deformation of the current placement, on the current surface or
  // (`edit`, see deformParams) on an edit of it flattened by the same request;
  // true once it is shown. Asked for while one is in flight, the page asks
  // again, for what it shows then, once that one is done.
  page.runDeform = async (edit = null) => {
    if (!deformWanted(edit)) return false;
    if (scheduler.busy('exact')) {
      page.deformAgain();
      return false;
    }
    const shown = await scheduler.run('exact', (signal) => exactDeform(edit, signal), { policy: 'queue' });
    return shown.done && shown.value;
  };

  // After the exact request in flight: the exact result of what the page
  // shows then (the newest such ask wins).
  page.deformAgain = () => {
    scheduler.run('exact', (signal) => (deformWanted(null) ? exactDeform(null, signal) : false), {
      policy: 'queue',
    });
  };

  // Whether there is an exact deformation to ask for: never while a button is
  // held (the release asks again); not without a model or a surface, or while
  // a new surface is on its way (which deforms when it arrives).
  function deformWanted(edit) {
    if (sheetView.drag || modelView.drag) return false;
    performance.mark('surfdeform:run-deform');
    const s = store.state;
    if (!edit && (!s.surfaceId || !s.model || s.surfacePending)) {
      if (!s.surfacePending && !s.sheetPending) store.dispatch('settled');
      return false;
    }
    return true;
  }

  // How far the preview of `placement` was from the exact result now shown.
  function measurePreview(placement) {
    const { model: m, field, settings } = store.state;
    if (!m || !m.positions || !field || typeof placement.scale !== 'number') return null;
    const frame = placementFrame(m.positions, page.effectiveUp(), settings.anchor);
    // About 4000 of the model's vertices, bent as the preview bent them.
    const stride = 3 * Math.max(1, Math.floor(m.positions.length / 3 / 4000));
    const some = [];
    for (let k = 0; k < m.positions.length; k += stride)
      some.push(m.positions[k], m.positions[k + 1], m.positions[k + 2]);
    const shown = previewPositions(some, frame, placement, field, preview.period, preview.periodV, preview.rotation);
    const [lo, hi] = field.bounds;
    const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
    const d = nearestDistances(shown, shownPositions(modelView.model), diagonal / 100, Infinity);
    return { max: d.max, mean: d.mean, diagonal, relative: d.max / diagonal };
  }

  async function exactDeform(edit, signal) {
    store.dispatch('busy');
    try {
      const t0 = performance.now();
      const s = store.state;
      const asked = s.fitNext ? null : s.placement;
      const sent = JSON.stringify(s.placement);
      const specSent = JSON.stringify(s.spec);
      const { bytes, stats, timing } = await deform(
        s.model.bytes,
        s.model.name,
        page.deformParams('glb', 'meshopt', edit),
        'model/gltf-binary',
        signal,
      );
      const t1 = performance.now();
      performance.mark('surfdeform:exact-received');
      if (edit) page.followEdit(stats, sent);
      const scene = (await gltf.parseAsync(bytes, '')).scene;
      modelView.setModel(scene, { distortion: store.state.settings.distortion });
      // What the exact result cost: the round trip, the server's part of it,
      // and decoding here (bench/viewer_feel.mjs reads it).
      const cost = {
        round_trip_ms: t1 - t0,
        server_ms: timing.total || 0,
        decode_ms: performance.now() - t1,
        done_at: performance.now(),
      };
      store.dispatch('exactShown', stats, cost);
      page.settleHistory(specSent);
      const roundTrip = performance.now() - t0;
      list($('timings'), timings(stats, timing, roundTrip, bytes.byteLength));
      // How far the preview was from it, once it is on screen: measuring takes
      // ~40 ms for the bunny, which held the exact result's frame as long.
      if (asked) {
        await afterNextFrame(); // drawn
        await afterNextFrame(); // shown
        if (modelView.model === scene) {
          store.dispatch('previewMeasured', measurePreview(asked));
          list($('timings'), timings(stats, timing, roundTrip, bytes.byteLength));
        }
      }
      page.showError(null);
      store.dispatch(store.state.sheetPending ? 'busy' : 'settled');
      return true;
    } catch (e) {
      if (signal.aborted) return false;
      page.showError(e);
      return false;
    }
  }

  // The exact result's figures, as listed on the page.
  function timings(stats, timing, roundTrip, byteLength) {
    const { lastPreview, model, live } = store.state;
    const sub = stats.subdivision || {};
    const d = stats.distortion;
    return [
      ['vertices', `${stats.vertices} (${sub.vertices_added || 0} added)`],
      ['triangles', stats.triangles],
      ['subdivision', `${sub.mode}${sub.tolerance ? `, tolerance ${fmt(sub.tolerance, 3)}` : ''}`],
      ...(d ? [['distortion', `max ${fmt(d.max, 3)}, p95 ${fmt(d.p95, 3)}, mean ${fmt(d.mean, 3)}`]] : []),
      ...['parse', 'flatten', 'deform', 'subdivide', 'encode'].map((k) => [k, `${fmt(timing[k] || 0, 3)} ms`]),
      ['round trip', `${fmt(roundTrip, 3)} ms, ${byteLength} bytes`],
      ...(lastPreview
        ? [['preview vs exact', `${fmt(lastPreview.max, 2)} (${fmt(100 * lastPreview.relative, 2)}% of the sheet)`]]
        : []),
      ...(model && model.lod
        ? [
            [
              'preview triangles',
              `${model.lod.triangles[1]} of ${model.lod.triangles[0]} ` +
                `(simplified within ${fmt(100 * model.lod.error, 2)}% of the model's size)`,
            ],
          ]
        : []),
      ...(live.gap
        ? [
            [
              'moved field vs server',
              `${fmt(100 * live.gap, 2)}% of the sheet (largest over ${live.surfaces} live surfaces)`,
            ],
          ]
        : []),
    ];
  }
}
