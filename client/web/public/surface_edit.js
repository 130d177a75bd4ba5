// The surface's requests: flattening a new surface (POST /v1/surfaces with
// its field, then GET its sheet), the live poses of a control-point drag,
// and a release's exact result.
//
// While a control point is dragged, the field moves with the patch at once
// (field_edit.js: a Bezier patch is linear in its control points) and one
// POST /v1/surfaces per move fetches the pose's own field (the "live" lane:
// the pose in flight finishes, the newest waiting one follows it). The
// exact deformation replaces the preview on release.
import { createSurface, getSurface } from './api.js';
import { fmt } from './dom.js';
import { fieldGap, movedField, moveSheetPoint } from './field_edit.js';

// Lattice points per side of the field the preview samples: a settled
// surface's, and a control-point drag's (a quarter of the bytes and the
// page's work per pose; the exact result replaces it on release).
export const kFieldSide = 64;
const kLiveFieldSide = 32;

// A request's surface part for the current spec (plain JSON, a copy).
function surfaceRequest(s, warmStart) {
  return JSON.parse(
    JSON.stringify({
      surface: s.spec,
      sampling: { nu: s.grid, nv: s.grid },
      ...(warmStart ? { warm_start: warmStart } : {}),
    }),
  );
}

export function installSurfaceEdit(page) {
  const { store, scheduler, sheetView, modelView, preview } = page;
  let surfaceTimer = 0;

  function useField(field, version, spec, surfaceId) {
    store.dispatch('fieldArrived', field, version, spec, surfaceId);
    preview.setField(field);
  }

  // An edited surface's sheet lies turned and shifted against the one it
  // started from (the canonical frame moves with an edit near sample (0, 0)):
  // the placement moves with it (the reply's warm_start.motion), so that the
  // model stays on the same part of the surface.
  function followSheet(summary) {
    const s = store.state;
    const w = summary.warm_start;
    const follows = w && w.motion && w.from === s.placementSheet && s.placement.center;
    store.dispatch(
      'sheetFollowed',
      summary.id,
      follows ? { center: moveSheetPoint(s.placement.center, w.motion), rotation_deg: w.motion.rotation_deg } : null,
    );
  }

  // The field of the surface being edited now, moved at once from the last
  // field the server gave (field_edit.js), drawn as the surface and under
  // the preview; false where it cannot be moved (not a Bezier patch), and
  // the server's field is waited for.
  page.showMovedField = () => {
    const s = store.state;
    const moved = movedField(s.field, s.fieldSpec, s.spec);
    if (!moved) return false;
    preview.setField(moved);
    modelView.setSurfaceFromField(moved);
    if (moved !== s.field) store.dispatch('fieldMoved');
    page.showLivePreview();
    return true;
  };

  // A control point moved: the new surface's field, one request at a time,
  // the newest pose each time. Errors wait for the release (the exact
  // request shows them).
  page.liveSurface = () => {
    if (!scheduler.busy('live')) page.holdDeform();
    const settle = () => {
      if (!scheduler.busy('live')) settleRelease();
    };
    scheduler.run('live', livePose, { policy: 'queue' }).then(settle, settle);
  };

  async function livePose(signal) {
    const s = store.state;
    const version = s.specVersion;
    if (version <= s.releasedVersion) return; // released: the release flattens it
    // Each pose starts from the sheet of the one before (warm_start): the
    // sheet the placement is on, whose motion to the new sheet it follows.
    const request = surfaceRequest(s, s.placementSheet || s.surfaceId);
    const t0 = performance.now();
    const summary = await createSurface(request, kLiveFieldSide, signal);
    const t1 = performance.now();
    const now = store.state;
    // The release's surface came first, or the release has this pose.
    if (version <= now.fieldVersion || version <= now.releasedVersion) return;
    // How far the field moved at once for this pose was from its own.
    const moved = movedField(now.field, now.fieldSpec, request.surface);
    if (moved && moved !== now.field) {
      store.dispatch('liveGapMeasured', fieldGap(moved, summary.field, summary.warm_start?.motion));
    }
    useField(summary.field, version, request.surface, summary.id);
    followSheet(summary);
    // Then moved on to where the control point is now.
    if (!page.showMovedField()) {
      modelView.setSurfaceFromField(summary.field);
      page.showLivePreview();
    }
    store.dispatch(
      'livePoseApplied',
      { summary, version, spec: request.surface },
      { request_ms: t1 - t0, apply_ms: performance.now() - t1 },
    );
  }

  // A control point let go: the exact result of its last pose, at once, from
  // the live edit's surface when that is the last pose (no second
  // flattening), else flattened now, warm from the last live surface. A live
  // request still in flight is not waited for (its reply, of an older pose,
  // is dropped; for the same pose the server flattens it once).
  page.releaseControlPoint = () => {
    performance.mark('surfdeform:release-control-point');
    store.dispatch('controlPointReleased');
    page.holdDeform();
    settleRelease();
  };

  function settleRelease() {
    if (!store.state.releasePending) return;
    performance.mark('surfdeform:settle-release');
    store.dispatch('releaseSettled');
    const s = store.state;
    const live = s.liveSummary;
    if (live && live.version === s.specVersion) return refreshSurface(live);
    // Where the model stays put on the sheet: the edit flattened and the model
    // deformed on it in one request, the placement moved with the sheet by
    // the server; the new sheet and its field after the result is shown.
    if (s.placementSheet && s.placement.center && !s.recentre && s.model && !scheduler.busy('exact')) {
      return scheduler.run('surface', releaseEdit);
    }
    refreshSurface(null);
  }

  // The "surface" lane: a release's edit, or a new surface, aborts the one
  // before it (its requests, and what it would show).
  async function releaseEdit(signal) {
    store.dispatch('sheetAwaited');
    page.cancelScheduledDeform();
    const s = store.state;
    const edit = surfaceRequest(s, s.placementSheet);
    const version = s.specVersion;
    const done = await page.runDeform(edit);
    if (signal.aborted) return;
    // Failed (shown), or a newer deformation asked in between: as before.
    if (!done || version !== store.state.specVersion) return refreshSurface(null);
    refreshSurface(null, true);
  }

  // An edit's exact result came (runDeform with `edit`): its surface is the
  // current one, and the placement is on its sheet, as the server moved it
  // when it is the one sent (`sent`, JSON), else moved here by the same motion
  // (it changed in flight) and deformed again.
  page.followEdit = (stats, sent) => {
    const s = store.state;
    const w = stats.warm_start || {};
    const changed = JSON.stringify(s.placement) !== sent;
    if (w.placement && !changed) {
      const center = w.placement.center
        ? s.model && s.model.text
          ? page.offsetCenter(w.placement.center, s.placement, 1)
          : w.placement.center
        : s.placement.center;
      store.dispatch('editFollowed', stats.surface_id, { rotation_deg: w.placement.rotation_deg, center });
    } else {
      store.dispatch('editFollowed', stats.surface_id, null);
      followSheet({ id: stats.surface_id, warm_start: w });
      if (changed) page.deformAgain();
    }
  };

  // The surface of the current spec: flattened (POST, with its field), or
  // `known` ({summary, version, spec}: a live edit's reply for this very
  // spec); then its sheet. Where the placement stays, the exact deformation
  // comes first and the sheet after it: with software WebGL, drawing the new
  // sheet and surface while the exact reply was on its way held that reply
  // for a frame or two. With `deformed`, the exact result of this very spec
  // is on screen already (releaseEdit), and the surface is held by the
  // server: its field and sheet.
  function refreshSurface(known = null, deformed = false) {
    return scheduler.run('surface', (signal) => refreshSurfaceTask(known, deformed, signal));
  }
  page.refreshSurface = refreshSurface;

  async function refreshSurfaceTask(known, deformed, signal) {
    store.dispatch('busy');
    try {
      const s = store.state;
      const version = known ? known.version : s.specVersion;
      // From the sheet the placement is on (after live poses, the last one):
      // the reply's motion keeps the placement on the surface.
      const request = surfaceRequest(s, !known && s.placementSheet);
      const summary = known ? known.summary : await createSurface(request, kFieldSide, signal);
      if (signal.aborted) return; // a newer edit is on its way
      useField(summary.field, version, known ? known.spec : request.surface, summary.id);
      if (!known) followSheet(summary); // a live reply was followed when it came
      store.dispatch('surfaceFlattened', summary.id);
      const early = deformed || (Boolean(store.state.placement.center) && !store.state.recentre);
      if (early && !deformed) {
        page.cancelScheduledDeform();
        store.dispatch('sheetAwaited'); // the page is not settled until the sheet is shown
        await page.runDeform();
        if (signal.aborted) return;
      }
      const sheet = await getSurface(summary.id, signal);
      if (signal.aborted) return;
      sheetView.setSheet(sheet);
      preview.setPeriod(sheet);
      if (sheet.mesh) {
        modelView.setSurfaceMesh(sheet.mesh.points, sheet.mesh.triangles.flat());
      } else {
        modelView.setSurface(sheet.points, sheet.grid.nu, sheet.grid.nv);
      }
      page.showMark(sheetView.mark); // the mark stays where it was on the sheet
      const spec = store.state.spec;
      modelView.setControlPoints(spec.kind === 'bezier' ? spec.control_points : []);
      page.showControlPoint();
      store.dispatch('sheetShown', surfaceFigures(summary, sheet), sheetView.sheetCentre());
      if (!early) {
        page.showError(null);
        page.scheduleDeform(0);
      } else {
        store.dispatch('sheetSettled');
        if (!scheduler.busy('exact')) store.dispatch('settled');
      }
    } catch (e) {
      if (!signal.aborted) {
        store.dispatch('surfaceFailed');
        page.showError(e);
      }
    }
  }

  // A new surface to flatten, 150 ms after the last change asking for one.
  page.scheduleSurface = () => {
    store.dispatch('surfaceRequested');
    clearTimeout(surfaceTimer);
    surfaceTimer = setTimeout(refreshSurface, 150);
  };
}

// The flattening's figures, as listed on the page.
function surfaceFigures(summary, sheet) {
  const q = summary.quality;
  const piece = sheet.mesh ? 'triangle' : 'cell';
  return [
    ['surface id', summary.id.slice(0, 12) + '…'],
    ...(sheet.mesh ? [['mesh', `${summary.mesh.vertices} vertices, ${summary.mesh.triangles} triangles`]] : []),
    ['flatten', `${summary.method}, ${fmt(summary.timing_ms.flatten, 3)} ms${summary.cached ? ' (cached)' : ''}`],
    ['stress', fmt(q.stress)],
    ['max edge error', fmt(q.max_edge_error)],
    [`${piece} area ratio`, `${fmt(q.area_ratio_min)} … ${fmt(q.area_ratio_max)}`],
    [`folded ${piece}s`, q.folded_cells],
  ];
}
