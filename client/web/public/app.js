// The surfdeform viewer: pick or edit a surface, see its flat sheet and the
// model's footprint on it, place the model, see it deformed in 3D.
//
// Flow: surface spec -> POST /v1/surfaces?field=64 (flattened once, cached
// by the server; with the field of its map) -> GET /v1/surfaces/{id} (sheet
// and samples) -> POST /v1/deform by surface and model id with the placement
// -> GLB with Draco -> three.js. Edits coalesce: while a request runs, later
// edits wait and only the newest is sent.
//
// Live editing: while the person drags, the model is a GPU preview bent by
// the field (preview.js). Dragging, wheel-scaling or rotating the footprint
// sends no request; dragging a control point moves the field with the
// patch at once (field_edit.js: a Bezier patch is linear in its control
// points) and sends one POST /v1/surfaces per move (at most one in flight,
// the newest pose wins) for the edited surface's own field.
// The exact deformation replaces the preview on release (for the wheel, 150
// ms after its last event; never while a button is held).
//
// document.body.dataset.state is "loading", "ready" or "error" (tests wait on
// it): "loading" from the moment an edit schedules work until the newest
// exact deformation is on screen, so "ready" always shows the current inputs.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

import { createSurface, deform, getSurface, mapOnSurface, uploadModel } from './api.js';
import { AnimationPanel } from './animation_panel.js';
import { EditHistory } from './edit_history.js';
import { dracoLoader, footprint, placementFrame, readModel } from './footprint.js';
import { ModelView } from './model_view.js';
import { fieldGap, movedField, moveSheetPoint } from './field_edit.js';
import { FieldPreview, nearestDistances, previewPositions, sampleParams } from './preview.js';
import { sampleModel, surfacePreset } from './samples.js';
import { fonts, textMesh } from './api.js';
import { scheduler } from './scheduler.js';
import { SheetView } from './sheet_view.js';

const $ = (id) => document.getElementById(id);

// `request(signal)` on the scheduler's `lane`, the newest wins (an older one
// is aborted): its value, or undefined when a newer one superseded it.
async function latest(lane, request) {
  const r = await scheduler.run(lane, request);
  return r.done ? r.value : undefined;
}

// Lattice points per side of the field the preview samples: a settled
// surface's, and a control-point drag's (a quarter of the bytes and the
// page's work per pose; the exact result replaces it on release).
const kFieldSide = 64;
const kLiveFieldSide = 32;

const state = {
  spec: null, // the surface spec being shown
  grid: 16,
  surfaceId: null,
  model: null, // {name, bytes, positions}
  placement: { center: null, rotation_deg: 0, scale: 'fit' },
  fitNext: true, // the next deformation fits the model to the sheet
  recentre: true, // a new surface: centre and fit the model when its sheet arrives
  surfacePending: false, // a surface is being flattened: deformations wait for it
  lastStats: null,
  lastError: null,
  lastMark: null, // the mark on the surface, as /map returned it
  upResolved: null, // the axis "auto" chose for the current model
  field: null, // the current surface's field (preview.js), as the server gave it
  fieldSpec: null, // the spec that field is of (a copy)
  placementSheet: null, // the id of the surface whose sheet the placement is on
  specVersion: 0, // bumped by every control-point move
  fieldVersion: -1, // the spec version the field shows
  releasedVersion: -1, // the spec version of the last control-point release
  // Live edits: surfaces fetched, fields moved at once with a control point,
  // previews shown, and the largest gap between a moved field and the
  // server's field of the same pose (of the sheet's diagonal).
  live: { surfaces: 0, moved: 0, previews: 0, gap: 0 },
  lastPreview: null, // how far the last preview was from the exact result
  sheetPending: false, // a new surface's exact result is shown, its sheet not yet
  edited: false, // a control point or the placement changed since the last step
  historyReset: true, // a new model or surface: the next exact result starts the history
};

// Undo and redo (edit_history.js): a step is the surface's spec and the
// placement (with the sheet it is on) of an exact result shown after an edit.
const editHistory = new EditHistory({ derived: ['placementSheet'] });

const preview = new FieldPreview();

const sheetView = new SheetView($('sheet'), (placement, final, how) => {
  state.placement = placement;
  state.edited = true;
  showPlacement();
  if (final) return scheduleDeform(0);
  showLivePreview();
  // The wheel has no release: the exact result 150 ms after its last event.
  if (how === 'wheel') scheduleDeform(150);
  else holdDeform();
});
// Control point `index` of the spec moved to `point` (to 1e-6): a new
// surface version when it changed. Whether it changed.
function setControlPoint(index, point) {
  const rounded = point.map((x) => Math.round(x * 1e6) / 1e6);
  const changed = rounded.some((x, c) => x !== state.spec.control_points[index][c]);
  if (changed) ++state.specVersion;
  state.spec.control_points[index] = rounded;
  return changed;
}

let pointerMoved = false; // the control point held has moved since it was pressed
const modelView = new ModelView($('view3d'), (index, point, final) => {
  // A release where the last move left the point: the same surface.
  const changed = setControlPoint(index, point);
  showControlPoint();
  if (final) {
    // A press without a move selects the point (its numbers), nothing more.
    const moved = pointerMoved || changed;
    pointerMoved = false;
    if (!moved) return;
    state.edited = true;
    return releaseControlPoint();
  }
  pointerMoved = true;
  state.edited = true;
  showMovedField();
  liveSurface();
});
modelView.setPreview(preview.mesh);
preview.onChange = () => modelView.invalidate();
// Exact results come as meshopt GLB (some 10x faster for the server to
// encode than Draco, decoded here at GB/s); downloads stay Draco (smaller).
const gltf = new GLTFLoader().setDRACOLoader(dracoLoader()).setMeshoptDecoder(MeshoptDecoder);

function setState(s) {
  document.body.dataset.state = s;
}

function showError(error) {
  state.lastError = error ? String(error.message || error) : null;
  $('error').hidden = !error;
  $('error').textContent = state.lastError || '';
  if (error) setState('error');
}

function list(el, entries) {
  el.replaceChildren(
    ...entries.flatMap(([k, v]) => {
      const dt = document.createElement('dt');
      dt.textContent = k;
      const dd = document.createElement('dd');
      dd.textContent = v;
      return [dt, dd];
    }),
  );
}

const fmt = (x, digits = 4) => (typeof x === 'number' ? Number(x.toPrecision(digits)).toString() : String(x));

function showPlacement() {
  const p = state.placement;
  $('rotation').value = p.rotation_deg;
  $('rotation-value').textContent = `${Math.round(p.rotation_deg)}°`;
  if (typeof p.scale === 'number') $('scale').value = fmt(p.scale, 5);
  sheetView.setPlacement(p);
}

// The up axis the footprint is drawn with: "auto" is the server's to
// resolve (by format and shape), known from the last deformation's stats.
function effectiveUp() {
  return $('up').value === 'auto' ? state.upResolved || '+z' : $('up').value;
}

// The model's outline for the up axis in use, kept per model and axis: a
// million-triangle model's hull takes ~0.2-0.3 s on the page's thread, and
// the first exact result's resolved axis ("auto") is most often the one
// assumed before it came.
function updateFootprint() {
  const m = state.model;
  if (!m) return sheetView.setFootprint(null);
  const up = effectiveUp();
  m.outlines ||= new Map();
  if (!m.outlines.has(up)) m.outlines.set(up, footprint(m.positions, up));
  sheetView.setFootprint(m.outlines.get(up));
}

// --- live preview ---------------------------------------------------------

// The preview placed where the model is now; whether it can be shown (not
// without a field, a model the browser read or a fitted scale).
function placePreview() {
  const m = state.model;
  if (!m || !m.positions || !state.field || typeof state.placement.scale !== 'number') return false;
  preview.setPlacement(placementFrame(m.positions, effectiveUp(), $('anchor').value), state.placement);
  return preview.ready();
}

// The preview at the current placement, in place of the exact model; false
// when it cannot be shown (no field yet, a model the browser cannot read, a
// scale still to be fitted).
function showLivePreview() {
  if (!placePreview()) return false;
  preview.shown();
  modelView.showPreview(true);
  ++state.live.previews;
  return true;
}

// What an exact result or a preview shows: its surface, placement and the
// settings the preview follows ("rigid" parts it does not: none).
function shownKey(surfaceId) {
  return JSON.stringify([surfaceId, state.placement, $('up').value, $('anchor').value, $('rigid').value]);
}

// Whether the preview may stand in for the exact result while the view
// moves (model_view.js): it shows the same surface and placement, and it
// is simplified (a quarter of the triangles).
modelView.standInAllowed = () =>
  // m.lod: the worker's mesh, with its normals.
  Boolean(state.model?.lod) &&
  $('rigid').value === 'none' &&
  state.exactShown === shownKey(state.fieldSurface) &&
  placePreview();

function useField(field, version, spec, surfaceId) {
  state.field = field;
  state.fieldSurface = surfaceId;
  state.fieldSpec = spec;
  state.fieldVersion = version;
  preview.setField(field);
}

// An edited surface's sheet lies turned and shifted against the one it
// started from (the canonical frame moves with an edit near sample (0, 0)):
// the placement moves with it (the reply's warm_start.motion), so that the
// model stays on the same part of the surface.
function followSheet(summary) {
  const w = summary.warm_start;
  if (w && w.motion && w.from === state.placementSheet && state.placement.center) {
    state.placement.center = moveSheetPoint(state.placement.center, w.motion);
    state.placement.rotation_deg += w.motion.rotation_deg;
    showPlacement();
  }
  state.placementSheet = summary.id;
}

// The field of the surface being edited now (state.spec), moved at once
// from the last field the server gave (field_edit.js), drawn as the surface
// and under the preview; false where it cannot be moved (not a Bezier
// patch), and the server's field is waited for.
function showMovedField() {
  const moved = movedField(state.field, state.fieldSpec, state.spec);
  if (!moved) return false;
  preview.setField(moved);
  modelView.setSurfaceFromField(moved);
  if (moved !== state.field) ++state.live.moved;
  showLivePreview();
  return true;
}

// A control point moved: the new surface's field, one request at a time,
// the newest pose each time (the "live" lane: the pose in flight finishes,
// the newest waiting one follows it). Errors wait for the release (the
// exact request shows them).
function liveSurface() {
  if (!scheduler.busy('live')) holdDeform();
  const settle = () => {
    if (!scheduler.busy('live')) settleRelease();
  };
  scheduler.run('live', livePose, { policy: 'queue' }).then(settle, settle);
}

async function livePose(signal) {
  const version = state.specVersion;
  if (version <= state.releasedVersion) return; // released: the release flattens it
  // Each pose starts from the sheet of the one before (warm_start): the
  // sheet the placement is on, whose motion to the new sheet it follows.
  const request = JSON.parse(
    JSON.stringify({
      surface: state.spec,
      sampling: { nu: state.grid, nv: state.grid },
      warm_start: state.placementSheet || state.surfaceId,
    }),
  );
  const t0 = performance.now();
  const summary = await createSurface(request, kLiveFieldSide, signal);
  const t1 = performance.now();
  // The release's surface came first, or the release has this pose.
  if (version <= state.fieldVersion || version <= state.releasedVersion) return;
  // How far the field moved at once for this pose was from its own.
  const moved = movedField(state.field, state.fieldSpec, request.surface);
  if (moved && moved !== state.field) {
    state.live.gap = Math.max(state.live.gap, fieldGap(moved, summary.field, summary.warm_start?.motion));
  }
  useField(summary.field, version, request.surface, summary.id);
  followSheet(summary);
  // Then moved on to where the control point is now.
  if (!showMovedField()) {
    modelView.setSurfaceFromField(summary.field);
    showLivePreview();
  }
  ++state.live.surfaces;
  state.live.last = { request_ms: t1 - t0, apply_ms: performance.now() - t1 };
  state.liveSummary = { summary, version, spec: request.surface };
}

// A control point let go: the exact result of its last pose, at once, from
// the live edit's surface when that is the last pose (no second
// flattening), else flattened now, warm from the last live surface. A live
// request still in flight is not waited for (its reply, of an older pose,
// is dropped; for the same pose the server flattens it once).
let releasePending = false;
function releaseControlPoint() {
  performance.mark('surfdeform:release-control-point');
  releasePending = true;
  state.releasedVersion = state.specVersion;
  state.surfacePending = true;
  holdDeform();
  settleRelease();
}

function settleRelease() {
  if (!releasePending) return;
  performance.mark('surfdeform:settle-release');
  releasePending = false;
  const live = state.liveSummary;
  if (live && live.version === state.specVersion) return refreshSurface(live);
  // Where the model stays put on the sheet: the edit flattened and the model
  // deformed on it in one request, the placement moved with the sheet by
  // the server; the new sheet and its field after the result is shown.
  if (state.placementSheet && state.placement.center && !state.recentre && state.model && !scheduler.busy('exact')) {
    return releaseEdit();
  }
  refreshSurface(null);
}

// The "surface" lane: a release's edit, or a new surface, aborts the one
// before it (its requests, and what it would show).
function releaseEdit() {
  return scheduler.run('surface', releaseEditTask);
}

async function releaseEditTask(signal) {
  state.sheetPending = true;
  clearTimeout(deformTimer);
  const edit = JSON.parse(
    JSON.stringify({
      surface: state.spec,
      sampling: { nu: state.grid, nv: state.grid },
      warm_start: state.placementSheet,
    }),
  );
  const version = state.specVersion;
  const done = await runDeform(edit);
  if (signal.aborted) return;
  // Failed (shown), or a newer deformation asked in between: as before.
  if (!done || version !== state.specVersion) return refreshSurface(null);
  refreshSurface(null, true);
}

// --- surface -------------------------------------------------------------

// An edit's exact result came (runDeform with `edit`): its surface is the
// current one, and the placement is on its sheet, as the server moved it
// when it is the one sent (`sent`, JSON), else moved here by the same motion
// (it changed in flight) and deformed again.
function followEdit(stats, sent) {
  const w = stats.warm_start || {};
  state.surfaceId = stats.surface_id;
  state.surfacePending = false;
  const changed = JSON.stringify(state.placement) !== sent;
  if (w.placement && !changed) {
    state.placement.rotation_deg = w.placement.rotation_deg;
    if (w.placement.center) {
      state.placement.center =
        state.model && state.model.text ? offsetCenter(w.placement.center, state.placement, 1) : w.placement.center;
    }
    state.placementSheet = stats.surface_id;
    showPlacement();
  } else {
    followSheet({ id: stats.surface_id, warm_start: w });
    if (changed) deformAgain();
  }
}

// The surface of state.spec: flattened (POST, with its field), or `known`
// ({summary, version}: a live edit's reply for this very spec); then its
// sheet. Where the placement stays, the exact deformation comes first and
// the sheet after it: with software WebGL, drawing the new sheet and surface
// while the exact reply was on its way held that reply for a frame or two.
// With `deformed`, the exact result of this very spec is on screen already
// (releaseEdit), and the surface is held by the server: its field and sheet.
function refreshSurface(known = null, deformed = false) {
  return scheduler.run('surface', (signal) => refreshSurfaceTask(known, deformed, signal));
}

async function refreshSurfaceTask(known, deformed, signal) {
  setState('loading');
  try {
    const version = known ? known.version : state.specVersion;
    const request = JSON.parse(JSON.stringify({ surface: state.spec, sampling: { nu: state.grid, nv: state.grid } }));
    // From the sheet the placement is on (after live poses, the last one):
    // the reply's motion keeps the placement on the surface.
    if (!known && state.placementSheet) request.warm_start = state.placementSheet;
    const summary = known ? known.summary : await createSurface(request, kFieldSide, signal);
    if (signal.aborted) return; // a newer edit is on its way
    useField(summary.field, version, known ? known.spec : request.surface, summary.id);
    if (!known) followSheet(summary); // a live reply was followed when it came
    state.surfaceId = summary.id;
    state.surfacePending = false;
    const early = deformed || (Boolean(state.placement.center) && !state.recentre);
    if (early && !deformed) {
      clearTimeout(deformTimer);
      state.sheetPending = true; // the page is not settled until the sheet is shown
      await runDeform();
      if (signal.aborted) return;
    }
    const sheet = await getSurface(summary.id, signal);
    if (signal.aborted) return;
    const q = summary.quality;
    const piece = sheet.mesh ? 'triangle' : 'cell';
    state.surfaceInfo = [
      ['surface id', summary.id.slice(0, 12) + '…'],
      ...(sheet.mesh ? [['mesh', `${summary.mesh.vertices} vertices, ${summary.mesh.triangles} triangles`]] : []),
      ['flatten', `${summary.method}, ${fmt(summary.timing_ms.flatten, 3)} ms${summary.cached ? ' (cached)' : ''}`],
      ['stress', fmt(q.stress)],
      ['max edge error', fmt(q.max_edge_error)],
      [`${piece} area ratio`, `${fmt(q.area_ratio_min)} … ${fmt(q.area_ratio_max)}`],
      [`folded ${piece}s`, q.folded_cells],
    ];
    list($('quality'), state.surfaceInfo);
    sheetView.setSheet(sheet);
    preview.setPeriod(sheet);
    if (sheet.mesh) {
      modelView.setSurfaceMesh(sheet.mesh.points, sheet.mesh.triangles.flat());
    } else {
      modelView.setSurface(sheet.points, sheet.grid.nu, sheet.grid.nv);
    }
    showMark(sheetView.mark); // the mark stays where it was on the sheet
    modelView.setControlPoints(state.spec.kind === 'bezier' ? state.spec.control_points : []);
    showControlPoint();
    if (!state.placement.center || state.recentre) {
      state.placement.center = sheetView.sheetCentre();
      state.fitNext = !(state.model && state.model.text); // a text keeps its millimetres
      state.recentre = false;
    }
    showPlacement();
    if (!early) {
      showError(null);
      scheduleDeform(0);
    } else {
      state.sheetPending = false;
      if (!scheduler.busy('exact')) setState(state.lastError ? 'error' : 'ready');
    }
  } catch (e) {
    if (!signal.aborted) {
      state.surfacePending = false;
      state.sheetPending = false;
      showError(e);
    }
  }
}

let surfaceTimer = 0;
function scheduleSurface() {
  setState('loading');
  state.surfacePending = true;
  clearTimeout(surfaceTimer);
  surfaceTimer = setTimeout(refreshSurface, 150);
}

// --- deformation ---------------------------------------------------------

// `edit` ({surface, sampling, warm_start}): the surface inline, an edit of
// the one the placement is on (/v1/deform flattens it and moves the
// placement with its sheet); else the current surface by id.
function deformParams(format, compression, edit = null) {
  const p = state.placement;
  const text = state.model && state.model.text;
  return {
    ...(edit || { surface_id: state.surfaceId }),
    ...(text ? { text } : {}),
    placement: {
      up: $('up').value,
      anchor: $('anchor').value,
      rigid: $('rigid').value,
      center: text ? offsetCenter(p.center, p, -1) : p.center,
      rotation_deg: p.rotation_deg,
      scale: state.fitNext ? 'fit' : p.scale,
    },
    subdivision: { mode: $('subdivision').value },
    // The distortion map travels in GLB (and PLY) only.
    output: {
      format,
      ...(compression ? { compression } : {}),
      ...(format === 'glb' && $('distortion').checked ? { distortion: true } : {}),
    },
  };
}

let deformTimer = 0;
function scheduleDeform(delay) {
  setState('loading');
  clearTimeout(deformTimer);
  // Now, not a task later: on a busy page a task waits for the next frame.
  if (delay === 0) runDeform();
  else deformTimer = setTimeout(runDeform, delay);
}

// An edit in progress: the exact deformation waits for its release.
function holdDeform() {
  setState('loading');
  clearTimeout(deformTimer);
}

// How far the preview of `placement` was from the exact result now shown.
function measurePreview(placement) {
  const m = state.model;
  if (!m || !m.positions || !state.field || typeof placement.scale !== 'number') return null;
  const frame = placementFrame(m.positions, effectiveUp(), $('anchor').value);
  // About 4000 of the model's vertices, bent as the preview bent them.
  const stride = 3 * Math.max(1, Math.floor(m.positions.length / 3 / 4000));
  const some = [];
  for (let k = 0; k < m.positions.length; k += stride)
    some.push(m.positions[k], m.positions[k + 1], m.positions[k + 2]);
  const shown = previewPositions(
    some,
    frame,
    placement,
    state.field,
    preview.period,
    preview.periodV,
    preview.rotation,
  );
  const [lo, hi] = state.field.bounds;
  const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
  const d = nearestDistances(shown, modelView.shownPositions(), diagonal / 100, Infinity);
  return { max: d.max, mean: d.mean, diagonal, relative: d.max / diagonal };
}

// Resolves once the next frame has been drawn (or skipped: nothing changed),
// or after 250 ms where no frame comes (a hidden tab draws none).
function afterNextFrame() {
  return new Promise((resolve) => {
    const timer = setTimeout(resolve, 250);
    requestAnimationFrame(() =>
      setTimeout(() => {
        clearTimeout(timer);
        resolve();
      }, 0),
    );
  });
}

// The exact deformation of the current placement, on the current surface or
// (`edit`, see deformParams) on an edit of it flattened by the same request;
// true once it is shown. One at a time, on the "exact" lane: asked for while
// one is in flight, the page asks again, for what it shows then, once that
// one is done.
async function runDeform(edit = null) {
  if (!deformWanted(edit)) return false;
  if (scheduler.busy('exact')) {
    deformAgain();
    return false;
  }
  const shown = await scheduler.run('exact', (signal) => exactDeform(edit, signal), { policy: 'queue' });
  return shown.done && shown.value;
}

// After the exact request in flight: the exact result of what the page
// shows then (the newest such ask wins).
function deformAgain() {
  scheduler.run('exact', (signal) => (deformWanted(null) ? exactDeform(null, signal) : false), {
    policy: 'queue',
  });
}

// Whether there is an exact deformation to ask for: never while a button is
// held (the release asks again); not without a model or a surface, or while
// a new surface is on its way (which deforms when it arrives).
function deformWanted(edit) {
  if (sheetView.drag || modelView.drag) return false;
  performance.mark('surfdeform:run-deform');
  if (!edit && (!state.surfaceId || !state.model || state.surfacePending)) {
    if (!state.surfacePending && !state.sheetPending) setState(state.lastError ? 'error' : 'ready');
    return false;
  }
  return true;
}

async function exactDeform(edit, signal) {
  setState('loading');
  try {
    const t0 = performance.now();
    const asked = state.fitNext ? null : { ...state.placement, center: [...state.placement.center] };
    const sent = JSON.stringify(state.placement);
    const specSent = JSON.stringify(state.spec);
    const { bytes, stats, timing } = await deform(
      state.model.bytes,
      state.model.name,
      deformParams('glb', 'meshopt', edit),
      'model/gltf-binary',
      signal,
    );
    const t1 = performance.now();
    performance.mark('surfdeform:exact-received');
    if (edit) followEdit(stats, sent);
    const scene = (await gltf.parseAsync(bytes, '')).scene;
    modelView.setModel(scene, { distortion: $('distortion').checked });
    // What the exact result cost: the round trip, the server's part of it,
    // and decoding here (bench/viewer_feel.mjs reads it).
    state.lastExact = {
      round_trip_ms: t1 - t0,
      server_ms: timing.total || 0,
      decode_ms: performance.now() - t1,
      done_at: performance.now(),
    };
    state.lastPreview = null;
    if (state.fitNext) {
      state.fitNext = false;
      state.placement.scale = stats.placement.scale;
      showPlacement();
    }
    state.lastStats = stats;
    state.exactShown = shownKey(stats.surface_id);
    settleHistory(specSent);
    if (stats.placement.up !== state.upResolved) {
      state.upResolved = stats.placement.up;
      if ($('up').value === 'auto') updateFootprint();
    }
    const sub = stats.subdivision || {};
    const roundTrip = performance.now() - t0;
    const timings = () => [
      ['vertices', `${stats.vertices} (${sub.vertices_added || 0} added)`],
      ['triangles', stats.triangles],
      ['subdivision', `${sub.mode}${sub.tolerance ? `, tolerance ${fmt(sub.tolerance, 3)}` : ''}`],
      ...(stats.distortion
        ? [
            [
              'distortion',
              `max ${fmt(stats.distortion.max, 3)}, p95 ` +
                `${fmt(stats.distortion.p95, 3)}, mean ${fmt(stats.distortion.mean, 3)}`,
            ],
          ]
        : []),
      ...['parse', 'flatten', 'deform', 'subdivide', 'encode'].map((k) => [k, `${fmt(timing[k] || 0, 3)} ms`]),
      ['round trip', `${fmt(roundTrip, 3)} ms, ${bytes.byteLength} bytes`],
      ...(state.lastPreview
        ? [
            [
              'preview vs exact',
              `${fmt(state.lastPreview.max, 2)} ` + `(${fmt(100 * state.lastPreview.relative, 2)}% of the sheet)`,
            ],
          ]
        : []),
      ...(state.model && state.model.lod
        ? [
            [
              'preview triangles',
              `${state.model.lod.triangles[1]} of ` +
                `${state.model.lod.triangles[0]} (simplified within ${fmt(100 * state.model.lod.error, 2)}% of the model's size)`,
            ],
          ]
        : []),
      ...(state.live.gap
        ? [
            [
              'moved field vs server',
              `${fmt(100 * state.live.gap, 2)}% of the sheet ` + `(largest over ${state.live.surfaces} live surfaces)`,
            ],
          ]
        : []),
    ];
    list($('timings'), timings());
    // How far the preview was from it, once it is on screen: measuring takes
    // ~40 ms for the bunny, which held the exact result's frame as long.
    if (asked) {
      await afterNextFrame(); // drawn
      await afterNextFrame(); // shown
      if (modelView.model === scene) {
        state.lastPreview = measurePreview(asked);
        list($('timings'), timings());
      }
    }
    showError(null);
    setState(state.sheetPending ? 'loading' : 'ready');
    return true;
  } catch (e) {
    if (signal.aborted) return false;
    showError(e);
    return false;
  }
}

// `blob` saved as the file `suffix` after the model's name.
function saveBlob(blob, suffix) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = `${state.model.name.replace(/\.[^.]*$/, '')}-${suffix}`;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

async function download(format) {
  try {
    const accept = format === 'glb' ? 'model/gltf-binary' : 'application/octet-stream';
    const made = await latest(`download-${format}`, (signal) =>
      deform(state.model.bytes, state.model.name, deformParams(format), accept, signal),
    );
    if (made) saveBlob(new Blob([made.bytes]), `deformed.${format}`);
  } catch (e) {
    showError(e);
  }
}

// What the page shows as one /v1/deform request, for batch jobs: the
// surface inline (its spec and sampling; the same spec flattens to the same
// id), the placement on its sheet, the subdivision, GLB out. With the model:
//   curl -F mesh=@MODEL -F params=@REQUEST -o out.glb http://HOST/v1/deform
//   surfdeform deform MODEL --params REQUEST -o out.glb
function deformRequest() {
  return deformParams('glb', null, { surface: state.spec, sampling: { nu: state.grid, nv: state.grid } });
}

// Indented JSON whose arrays of numbers stay on a line (a control point, a centre).
function readableJson(value) {
  return JSON.stringify(value, null, 2).replace(
    /\[\s+([^[\]{}]*?)\s+\]/g,
    (_, inner) => `[${inner.split(/,\s+/).join(', ')}]`,
  );
}

function saveRequest() {
  const text = `${readableJson(deformRequest())}\n`;
  saveBlob(new Blob([text], { type: 'application/json' }), 'request.json');
}

// A saved request (saveRequest, or written by hand) opened: its surface,
// grid, placement and settings, with the model already shown (a request
// holds none). Its "flatten" and "output" are not the page's to set.
async function openRequest(name, bytes) {
  let r;
  try {
    r = JSON.parse(new TextDecoder().decode(bytes));
  } catch (e) {
    throw new Error(`${name} is not JSON: ${e.message}`);
  }
  if (!r || typeof r !== 'object' || !r.surface || typeof r.surface !== 'object') {
    throw new Error(`${name} is not a deformation request: it has no "surface" object`);
  }
  const nu = r.sampling?.nu ?? 16,
    nv = r.sampling?.nv ?? nu;
  if (nu !== nv || !(nu >= 4 && nu <= 64)) {
    throw new Error(`the page samples square grids of 4 to 64 per side; ${name} asks for ${nu} x ${nv}`);
  }
  const p = r.placement || {};
  const settings = [
    ['up', p.up],
    ['anchor', p.anchor],
    ['rigid', p.rigid],
    ['subdivision', r.subdivision?.mode],
  ];
  for (const [id, value] of settings) {
    if (value !== undefined && ![...$(id).options].some((o) => o.value === value)) {
      throw new Error(`${name}: the page has no ${id} "${value}"`);
    }
  }
  for (const [id, value] of settings) if (value !== undefined) $(id).value = value;
  state.spec = r.surface;
  state.grid = nu;
  $('grid').value = nu;
  state.placement = {
    center: Array.isArray(p.center) ? p.center : null,
    rotation_deg: Number(p.rotation_deg) || 0,
    scale: typeof p.scale === 'number' ? p.scale : 'fit',
  };
  state.fitNext = typeof p.scale !== 'number';
  state.recentre = !state.placement.center;
  state.placementSheet = null; // the placement lies on the sheet its spec flattens to
  state.historyReset = true;
  $('preset').selectedIndex = -1; // none of the presets: the request's own surface
  modelView.framed = false;
  showPlacement();
  scheduleSurface();
}

// --- marks -----------------------------------------------------------------
// "Draw a mark": clicks on the sheet add points to a polyline, which the
// server resamples onto the surface (POST /v1/surfaces/{id}/map) and the 3D
// view draws on it.

async function showMark(points) {
  if (!state.surfaceId || points.length < 2) {
    modelView.setMarks([]);
    return;
  }
  try {
    const surfaceId = state.surfaceId;
    const mapped = await latest('mark', (signal) => mapOnSurface(surfaceId, { polylines: [points] }, signal));
    if (!mapped) return; // a newer mark is on its way
    const { polylines } = mapped;
    modelView.setMarks(polylines);
    state.lastMark = polylines[0];
  } catch (e) {
    showError(e);
  }
}

$('mark').addEventListener('click', () => {
  const on = $('mark').getAttribute('aria-pressed') !== 'true';
  $('mark').setAttribute('aria-pressed', String(on));
  $('mark').textContent = on ? 'Done marking' : 'Draw a mark';
  sheetView.setMarking(on ? (points) => showMark(points) : null);
});
$('clear-marks').addEventListener('click', () => {
  sheetView.setMark([]);
  state.lastMark = null;
  modelView.setMarks([]);
});

// --- a control point's numbers ----------------------------------------------
// The control point last pressed in the 3D view: its x, y and z, to read and
// to type. A typed value is an edit as a drag's release is (one exact
// request, a step to undo), with the preview moved at once.

function showControlPoint() {
  const k = modelView.selected;
  const spec = state.spec;
  const points = spec && spec.kind === 'bezier' ? spec.control_points : null;
  const shown = Boolean(points && k >= 0 && k < points.length);
  $('cp-edit').hidden = !shown;
  if (!shown) return;
  const columns = spec.degree_u + 1;
  $('cp-index').textContent = `${k} (row ${Math.floor(k / columns)}, column ${k % columns})`;
  ['x', 'y', 'z'].forEach((c, i) => {
    if (document.activeElement !== $(`cp-${c}`)) $(`cp-${c}`).value = points[k][i];
  });
}
modelView.onSelect = showControlPoint;

['x', 'y', 'z'].forEach((c, i) => {
  $(`cp-${c}`).addEventListener('change', () => {
    const k = modelView.selected;
    const input = $(`cp-${c}`);
    const value = Number(input.value);
    const points = state.spec && state.spec.kind === 'bezier' ? state.spec.control_points : null;
    if (
      !points ||
      !points[k] ||
      input.value.trim() === '' ||
      !Number.isFinite(value) ||
      modelView.drag ||
      !setControlPoint(
        k,
        points[k].map((x, j) => (j === i ? value : x)),
      )
    ) {
      input.value = points && points[k] ? points[k][i] : '';
      return;
    }
    state.edited = true;
    modelView.setControlPoints(points);
    showMovedField();
    releaseControlPoint();
  });
});

// --- undo and redo ---------------------------------------------------------
// Ctrl+Z (Cmd+Z) undoes an edit of the surface's control points or of the
// placement (moved, scaled, rotated, fitted), Ctrl+Shift+Z or Ctrl+Y redoes
// it; so do the header's buttons. A step is an exact result shown after an
// edit; choosing another model, preset or grid starts the history anew.

function editStep() {
  return { spec: state.spec, placement: state.placement, placementSheet: state.placementSheet };
}

// An exact result is on screen (runDeform; `specSent`: the spec it was asked
// for, JSON): the history's new start, or its next step where something was
// edited. Not while an edit goes on or a newer result is on its way: that
// one settles it.
function settleHistory(specSent) {
  if (sheetView.drag || modelView.drag || scheduler.queued('exact') || JSON.stringify(state.spec) !== specSent) {
    return;
  }
  if (state.historyReset) {
    editHistory.reset(editStep());
  } else if (state.edited) {
    editHistory.record(editStep());
  }
  state.historyReset = false;
  state.edited = false;
  showHistory();
}

function showHistory() {
  $('undo').disabled = !editHistory.canUndo();
  $('redo').disabled = !editHistory.canRedo();
}

// The page as `step` had it: the preview at once (the field moved to its
// control points, as a drag does), then its surface and exact result.
function restoreStep(step) {
  const specChanged = JSON.stringify(step.spec) !== JSON.stringify(state.spec);
  state.placement = step.placement;
  state.placementSheet = step.placementSheet;
  state.fitNext = false;
  state.recentre = false;
  state.edited = false;
  showPlacement();
  showHistory();
  if (!specChanged) {
    showLivePreview();
    scheduleDeform(0);
    return;
  }
  state.spec = step.spec;
  ++state.specVersion;
  modelView.setControlPoints(state.spec.kind === 'bezier' ? state.spec.control_points : []);
  showControlPoint();
  showMovedField();
  refreshSurface(null);
}

function undoEdit() {
  if (sheetView.drag || modelView.drag || state.historyReset) return;
  // An edit not settled yet (a wheel's, within its 150 ms) goes back to the
  // last step; else the step before it.
  const step = state.edited ? editHistory.currentStep() : editHistory.undo();
  if (step) restoreStep(step);
}

function redoEdit() {
  if (sheetView.drag || modelView.drag || state.historyReset) return;
  const step = editHistory.redo();
  if (step) restoreStep(step);
}

$('undo').addEventListener('click', undoEdit);
$('redo').addEventListener('click', redoEdit);
document.addEventListener('keydown', (e) => {
  if (!(e.ctrlKey || e.metaKey) || e.altKey) return;
  // Text and number fields keep their own undo.
  const t = e.target;
  if (t && (t.tagName === 'TEXTAREA' || (t.tagName === 'INPUT' && ['text', 'number', 'search'].includes(t.type))))
    return;
  const key = e.key.toLowerCase();
  if (key === 'z' && !e.shiftKey) undoEdit();
  else if ((key === 'z' && e.shiftKey) || key === 'y') redoEdit();
  else return;
  e.preventDefault();
});

// --- text ----------------------------------------------------------------

// A text's origin (its baseline's centre) is where the server puts the
// placement's centre; the page places the footprint's centre. `center` moved
// between the two: sign -1 from the page's to the server's, +1 back.
function offsetCenter(center, p, sign) {
  const m = state.model;
  if (!center || !m || !m.positions || typeof p.scale !== 'number') return center;
  const f = placementFrame(m.positions, effectiveUp(), $('anchor').value);
  const [bx, by] = f.centre;
  const a = (p.rotation_deg * Math.PI) / 180,
    s = p.scale;
  return [
    center[0] + sign * s * (Math.cos(a) * bx - Math.sin(a) * by),
    center[1] + sign * s * (Math.sin(a) * bx + Math.cos(a) * by),
  ];
}

function textSettings() {
  const size = Math.max(0.05, Number($('text-size').value) || 0.6);
  return {
    string: $('text').value,
    font: $('font').value,
    size_mm: size,
    depth_mm: Math.max(0, Number($('text-depth').value) || 0),
    tolerance_mm: size / 100,
  };
}

// The typed text on the surface: its flat mesh from POST /v1/text (the
// newest keystroke's: an older request in flight is aborted), bent by the
// preview at once; the exact result `delay` ms after the typing pauses.
async function useText(delay = 0) {
  const text = textSettings();
  if (!text.string.trim()) return;
  performance.mark('surfdeform:text-typed');
  let made;
  try {
    // The "text" lane: a newer keystroke aborts this one's request.
    made = await latest('text', (signal) => textMesh(text, signal));
  } catch (e) {
    showError(e);
    return;
  }
  if (!made) return; // a newer keystroke's is coming
  performance.mark('surfdeform:text-received');
  const read = await readModel('text.ply', made.bytes);
  performance.mark('surfdeform:text-read');
  const first = !state.model || !state.model.text;
  const model = { name: 'text.ply', bytes: made.bytes, positions: read.positions, lod: null, text };
  state.model = model;
  preview.setModelGeometry(read.geometry, (lod) => {
    model.lod = lod;
  });
  $('model-name').textContent =
    `"${text.string}": ${made.stats.text.glyphs} glyphs in ` +
    `${made.stats.text.family} ${made.stats.text.style}, ${fmt(made.stats.text.width_mm, 3)} mm long`;
  if (first) {
    // Letters stand on the surface, each rigid, at their size in mm.
    $('up').value = '+z';
    $('anchor').value = 'bottom';
    $('rigid').value = 'components';
    state.upResolved = null;
    state.historyReset = true;
    state.fitNext = false;
    state.placement.scale = 1;
    state.placement.rotation_deg = 0;
    if (sheetView.sheet) state.placement.center = sheetView.sheetCentre();
  }
  updateFootprint();
  showPlacement();
  showError(null);
  if (showLivePreview()) {
    performance.mark('surfdeform:text-preview');
    // The frame that draws it (bench/text_keystroke.mjs reads both).
    requestAnimationFrame(() => performance.mark('surfdeform:text-drawn'));
  }
  if (delay > 0) holdDeform();
  scheduleDeform(delay);
}

function showTextControls() {
  $('text-controls').hidden = $('sample').value !== 'text';
}

// The built-in fonts, each with the scripts it covers.
async function listFonts() {
  const list = await latest('fonts', (signal) => fonts(signal));
  if (!list) return;
  const select = $('font');
  select.replaceChildren(
    ...list.fonts.map((f) => {
      const o = document.createElement('option');
      o.value = f.name;
      o.textContent = `${f.name} (${f.scripts.join(', ')})`;
      return o;
    }),
  );
  select.value = list.default;
}

// --- models --------------------------------------------------------------

async function useModel(name, bytes) {
  const read = await readModel(name, bytes);
  if (state.model && state.model.text) {
    // a text's settings go with it
    $('up').value = 'auto';
    $('anchor').value = 'center';
    $('rigid').value = 'none';
  }
  const model = { name, bytes, positions: read.positions, lod: null };
  state.model = model;
  state.historyReset = true;
  preview.setModelGeometry(read.geometry, (lod) => {
    model.lod = lod;
  });
  state.upResolved = null;
  $('model-name').textContent =
    `${name} (${bytes.byteLength} bytes)` +
    (state.model.positions ? '' : ' — the browser cannot outline it; the server reads it');
  state.fitNext = true;
  state.placement.rotation_deg = 0;
  if (sheetView.sheet) state.placement.center = sheetView.sheetCentre();
  updateFootprint();
  showPlacement();
  scheduleDeform(0);
}

// A surface given as a mesh (a disk-shaped triangle mesh file): uploaded as
// a model, then flattened as the surface {kind: "mesh", model_id}.
async function useSurfaceMesh(name, bytes) {
  const model = await latest('upload', (signal) => uploadModel(bytes, name, signal));
  if (!model) return; // another file came after it
  state.spec = { kind: 'mesh', model_id: model.id };
  state.surfaceMeshName = name;
  state.recentre = true;
  state.historyReset = true;
  modelView.framed = false;
  scheduleSurface();
}

// A chosen or dropped file, read and handed to use(name, bytes): the model
// (useModel) or the surface (useSurfaceMesh).
async function useFile(file, use = useModel) {
  if (!file) return;
  setState('loading');
  try {
    await use(file.name, await file.arrayBuffer());
  } catch (e) {
    showError(e);
  }
}

// --- wiring --------------------------------------------------------------

$('preset').addEventListener('change', async () => {
  setState('loading');
  try {
    const spec = await latest('preset', (signal) => surfacePreset($('preset').value, signal));
    if (!spec) return; // another preset was chosen meanwhile
    state.spec = spec;
    state.recentre = true;
    state.historyReset = true;
    modelView.framed = false;
    scheduleSurface();
  } catch (e) {
    showError(e);
  }
});
$('grid').addEventListener('change', () => {
  state.grid = Math.max(4, Math.min(64, Number($('grid').value) || 16));
  state.recentre = true;
  state.historyReset = true;
  scheduleSurface();
});
$('text').addEventListener('input', () => useText(250));
for (const id of ['font', 'text-size', 'text-depth']) $(id).addEventListener('change', () => useText(0));
$('sample').addEventListener('change', async () => {
  setState('loading');
  showTextControls();
  if ($('sample').value === 'text') return useText(0);
  try {
    const m = await latest('sample', (signal) => sampleModel($('sample').value, signal));
    if (m) await useModel(m.name, m.bytes);
  } catch (e) {
    showError(e);
  }
});
$('upload').addEventListener('change', (e) => useFile(e.target.files[0]));
$('surface-upload').addEventListener('change', (e) => useFile(e.target.files[0], useSurfaceMesh));
document.addEventListener('dragover', (e) => {
  e.preventDefault();
  document.body.classList.add('dragover');
});
document.addEventListener('dragleave', () => document.body.classList.remove('dragover'));
document.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragover');
  // A .json file is a saved request; on the flat sheet, a mesh is the
  // surface; anywhere else, the model.
  const file = e.dataTransfer.files[0];
  const onSheet = e.target.closest && e.target.closest('#sheet');
  const json = file && /\.json$/i.test(file.name);
  useFile(file, json ? openRequest : onSheet ? useSurfaceMesh : useModel);
});
$('rotation').addEventListener('input', () => {
  state.placement.rotation_deg = Number($('rotation').value);
  state.edited = true;
  showPlacement();
  showLivePreview();
  holdDeform();
});
$('rotation').addEventListener('change', () => scheduleDeform(0));
$('scale').addEventListener('change', () => {
  const s = Number($('scale').value);
  if (s > 0) {
    state.placement.scale = s;
    state.fitNext = false;
    state.edited = true;
    showPlacement();
    scheduleDeform(0);
  }
});
$('fit').addEventListener('click', () => {
  state.fitNext = true;
  state.edited = true;
  scheduleDeform(0);
});
for (const id of ['up', 'anchor', 'rigid', 'subdivision', 'distortion']) {
  $(id).addEventListener('change', () => {
    if (id === 'up') {
      state.fitNext = true;
      updateFootprint();
    }
    scheduleDeform(0);
  });
}
$('download-glb').addEventListener('click', () => download('glb'));
$('download-drc').addEventListener('click', () => download('drc'));
$('save-request').addEventListener('click', saveRequest);
$('open-request').addEventListener('change', (e) => useFile(e.target.files[0], openRequest));

// The animation panel: the current model, placed as on the sheet (fitted to
// every frame's sheet, rotated, with the chosen axes).
const animationPanel = new AnimationPanel(
  modelView,
  () => ({
    model: state.model,
    placement: {
      scale: 'fit',
      rotation_deg: state.placement.rotation_deg,
      up: $('up').value,
      anchor: $('anchor').value,
    },
  }),
  showError,
);

// The current deformation as the viewer receives it (meshopt GLB) against
// the Draco GLB of the same request, both decoded by three.js: every vertex
// of each lies within the two quantizations of the other (Draco's 14-bit
// positions over its bounding box, meshopt's over the node's scale).
async function compareEncodings() {
  const decoded = async (compression) => {
    const { bytes } = await deform(
      state.model.bytes,
      state.model.name,
      deformParams('glb', compression),
      'model/gltf-binary',
    );
    const scene = (await gltf.parseAsync(bytes, '')).scene;
    scene.updateMatrixWorld(true);
    const positions = [];
    let scale = 1;
    const v = new THREE.Vector3();
    scene.traverse((o) => {
      if (!o.isMesh) return;
      scale = o.getWorldScale(new THREE.Vector3()).x;
      const pos = o.geometry.getAttribute('position');
      for (let k = 0; k < pos.count; ++k) {
        v.fromBufferAttribute(pos, k).applyMatrix4(o.matrixWorld);
        positions.push(v.x, v.y, v.z);
      }
    });
    return { positions, scale, bytes: bytes.byteLength };
  };
  const meshopt = await decoded('meshopt');
  const draco = await decoded('draco');
  const lo = [Infinity, Infinity, Infinity],
    hi = [-Infinity, -Infinity, -Infinity];
  for (let k = 0; k < draco.positions.length; ++k) {
    lo[k % 3] = Math.min(lo[k % 3], draco.positions[k]);
    hi[k % 3] = Math.max(hi[k % 3], draco.positions[k]);
  }
  const dracoStep = Math.max(...hi.map((h, c) => h - lo[c])) / (2 ** 14 - 1);
  const meshoptStep = meshopt.scale / 32767;
  const bound = (Math.sqrt(3) / 2) * (dracoStep + meshoptStep);
  const all = 1e9; // every vertex, not a sample
  const there = nearestDistances(meshopt.positions, draco.positions, bound, all);
  const back = nearestDistances(draco.positions, meshopt.positions, bound, all);
  return {
    worst: Math.max(there.max, back.max),
    bound,
    dracoStep,
    meshoptStep,
    vertices: [meshopt.positions.length / 3, draco.positions.length / 3],
    bytes: { meshopt: meshopt.bytes, draco: draco.bytes },
  };
}

// A GLB as three.js decodes it (for tests: a large Draco answer comes in
// pieces): its primitives, their vertices, and how many distinct positions
// (exact float32 bits) they hold together.
async function decodeGlb(bytes) {
  const scene = (await gltf.parseAsync(bytes, '')).scene;
  const distinct = new Set();
  let primitives = 0,
    vertices = 0,
    triangles = 0;
  scene.traverse((o) => {
    if (!o.isMesh) return;
    ++primitives;
    const p = o.geometry.getAttribute('position').array;
    vertices += p.length / 3;
    triangles += o.geometry.index ? o.geometry.index.count / 3 : p.length / 9;
    for (let k = 0; k < p.length; k += 3) distinct.add(`${p[k]},${p[k + 1]},${p[k + 2]}`);
  });
  return { primitives, vertices, triangles, distinct: distinct.size };
}

// For tests: the current field moved at once with control point `index`
// raised by `lift` (field_edit.js), against the server's surface of that
// pose: how far the moved field's points on the sheet lie from it (each
// mapped onto it by /map's surface_points), how far they moved, and how far
// they are from the server's field of that pose (which has the edited
// surface's own sheet) against how far the unmoved field is, all relative to
// the sheet's diagonal.
async function movedFieldOnSurface(index, lift) {
  const after = JSON.parse(JSON.stringify(state.fieldSpec));
  after.control_points[index][2] += lift;
  const moved = movedField(state.field, state.fieldSpec, after);
  const made = await createSurface(
    { surface: after, sampling: { nu: state.grid, nv: state.grid }, warm_start: state.placementSheet },
    state.field.n,
  );
  const motion = made.warm_start && made.warm_start.motion;
  const points = moved.positions.filter((p, k) => moved.on_sheet[k] && k % 7 === 0);
  const marks = await mapOnSurface(made.id, { surface_points: points });
  const [lo, hi] = moved.bounds;
  const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
  const worst = Math.max(...marks.surface_points.map((m) => m.distance));
  const shift = Math.max(
    ...moved.positions.map((p, k) => Math.hypot(...p.map((x, c) => x - state.field.positions[k][c]))),
  );
  return {
    points: points.length,
    worst: worst / diagonal,
    shift: shift / diagonal,
    gap: fieldGap(moved, made.field, motion),
    unmoved: fieldGap(state.field, made.field, motion),
    raw: fieldGap(moved, made.field),
  };
}

// For tests: the surface parameters (u, v) under the placement's centre,
// from the current field (bilinear, as the preview samples it).
function placementParams() {
  if (!state.field || !state.placement.center) return null;
  return sampleParams(state.field, ...state.placement.center);
}

// For tests and the curious: the state and the model's share of the 3D canvas.
window.surfdeformViewer = {
  // Resolves once no request of the page is in flight or waiting (every
  // request goes through scheduler.js).
  whenIdle: () => scheduler.whenIdle(),
  state,
  animation: animationPanel,
  preview,
  compareEncodings,
  decodeGlb,
  movedFieldOnSurface,
  placementParams,
  history: () => ({ back: editHistory.back.length, ahead: editHistory.ahead.length }),
  deformRequest: () => readableJson(deformRequest()),
  // SHA-256 (hex) of the exact result of what the page shows, as it asks for it.
  exactDigest: async () => {
    const { bytes } = await deform(
      state.model.bytes,
      state.model.name,
      deformParams('glb', 'meshopt'),
      'model/gltf-binary',
    );
    const hash = new Uint8Array(await crypto.subtle.digest('SHA-256', bytes));
    return [...hash].map((b) => b.toString(16).padStart(2, '0')).join('');
  },
  sheet: () => sheetView.sheet,
  placeAt: (center) => {
    state.placement.center = center;
    state.edited = true;
    showPlacement();
    scheduleDeform(0);
  },
  framesDrawn: () => modelView.drawn,
  software: () => modelView.software,
  standingIn: () => modelView.stoodIn,
  modelCoverage: () => modelView.modelCoverage(),
  modelMask: () => modelView.modelMask(),
  handlePoint: (k) => modelView.handleClientPoint(k),
  previewShown: () => preview.mesh.visible,
  pixelCounts: () => modelView.pixelCounts(),
  gpuMemory: () => ({ ...modelView.renderer.info.memory }),
  // The shader programs three.js holds, by id (a new id: one compiled).
  programs: () => modelView.renderer.info.programs.map((p) => p.id),
  texturedMeshes: () => modelView.texturedMeshes(),
};

(async () => {
  try {
    const spec = await latest('preset', (signal) => surfacePreset($('preset').value, signal));
    if (spec) state.spec = spec; // else another preset was chosen, and is on its way
    state.surfacePending = true;
    showTextControls();
    if ($('sample').value === 'text') {
      await listFonts();
      await useText(0);
    } else {
      const m = await latest('sample', (signal) => sampleModel($('sample').value, signal));
      if (m) await useModel(m.name, m.bytes);
    }
    await refreshSurface();
  } catch (e) {
    showError(e);
  }
})();
