// The viewer's state and the named actions that change it (store.js). Each
// action returns the fields it changes; the panels dispatch them and render
// what changed.

// The state the page opens with; `controls` holds the form's initial values.
export function initialState(controls) {
  return {
    status: 'loading', // document.body.dataset.state: "loading", "ready" or "error"
    error: null, // the message shown, or null
    // The form: which preset and sample, the grid, the text and the settings
    // sent with each deformation.
    preset: controls.preset, // null: a surface of the page's own (a request, a mesh)
    sample: controls.sample,
    grid: 16,
    text: controls.text, // {string, font, size_mm, depth_mm}
    settings: controls.settings, // {up, anchor, rigid, subdivision, distortion}
    // The surface: its spec, the server's id for it, its field and sheet.
    spec: null,
    surfaceId: null,
    surfaceInfo: [], // the flattening's figures, as listed on the page
    surfacePending: false, // a surface is being flattened: deformations wait for it
    sheetPending: false, // a new surface's exact result is shown, its sheet not yet
    field: null, // the current surface's field (preview.js), as the server gave it
    fieldSpec: null, // the spec that field is of
    fieldSurface: null, // the id of the surface that field is of
    specVersion: 0, // bumped by every control-point move
    fieldVersion: -1, // the spec version the field shows
    releasedVersion: -1, // the spec version of the last control-point release
    pointerMoved: false, // the control point held has moved since it was pressed
    releasePending: false, // a release waits for its exact result to be asked for
    // Live edits: surfaces fetched, fields moved at once with a control point,
    // previews shown, and the largest gap between a moved field and the
    // server's field of the same pose (of the sheet's diagonal).
    live: { surfaces: 0, moved: 0, previews: 0, gap: 0, last: null },
    liveSummary: null, // the last live pose's reply: {summary, version, spec}
    // The model: {name, bytes, positions, lod, text}, and the up axis "auto"
    // chose for it.
    model: null,
    upResolved: null,
    // The placement on the sheet, and the id of the surface whose sheet it is on.
    placement: { center: null, rotation_deg: 0, scale: 'fit' },
    placementSheet: null,
    fitNext: true, // the next deformation fits the model to the sheet
    recentre: true, // a new surface: centre and fit the model when its sheet arrives
    // The exact result on screen: its stats, what it cost, what it shows, and
    // how far the last preview was from it.
    lastStats: null,
    lastExact: null,
    exactShown: null,
    lastPreview: null,
    lastMark: null, // the mark on the surface, as /map returned it
    edited: false, // a control point or the placement changed since the last step
    historyReset: true, // a new model or surface: the next exact result starts the history
  };
}

// The placement with `placement`'s fields, its centre copied (the sheet
// view's own is changed while dragged).
const placedOnSheet = (s, placement) => {
  const p = { ...s.placement, ...placement };
  return Array.isArray(p.center) ? { ...p, center: [...p.center] } : p;
};

// What an exact result or a preview shows: its surface, placement and the
// settings the preview follows ("rigid" parts it does not: none).
export function shownKey(s, surfaceId) {
  return JSON.stringify([surfaceId, s.placement, s.settings.up, s.settings.anchor, s.settings.rigid]);
}

// The fields the store freezes at their top level only: the server's
// fields of the sheet-to-surface map, thousands of small arrays each.
export const kShallow = ['field', 'liveSummary'];

// The actions, by name.
export const actions = {
  // --- status -------------------------------------------------------------
  busy: () => ({ status: 'loading' }),
  settled: (s) => ({ status: s.error ? 'error' : 'ready' }),
  failed: (s, message) => ({ error: message, status: 'error' }),
  errorCleared: (s) => (s.error === null ? null : { error: null }),

  // --- the form -----------------------------------------------------------
  presetChosen: (s, preset) => ({ preset }),
  sampleChosen: (s, sample) => ({ sample }),
  textEdited: (s, text) => ({ text: { ...s.text, ...text } }),
  // A select of the placement's settings changed; a new up axis fits again.
  settingChanged: (s, id, value) => ({
    settings: { ...s.settings, [id]: value },
    ...(id === 'up' ? { fitNext: true } : {}),
  }),

  // --- the surface --------------------------------------------------------
  // A new surface to flatten (a preset, a mesh, a grid): the model is
  // centred and fitted on its sheet, and the history starts anew.
  surfaceChosen: (s, spec, grid = s.grid) => ({
    spec,
    grid,
    recentre: true,
    historyReset: true,
  }),
  surfaceRequested: () => ({ status: 'loading', surfacePending: true }),
  // Control point `index` moved to `point` (rounded): a new spec version
  // when it changed.
  controlPointMoved: (s, index, point) => {
    const old = s.spec.control_points[index];
    if (point.every((x, c) => x === old[c])) return null;
    const control_points = s.spec.control_points.map((p, k) => (k === index ? point : p));
    return { spec: { ...s.spec, control_points }, specVersion: s.specVersion + 1 };
  },
  pointerMoved: (s, moved) => (s.pointerMoved === moved ? null : { pointerMoved: moved }),
  edited: (s) => (s.edited ? null : { edited: true }),
  controlPointReleased: (s) => ({
    releasePending: true,
    releasedVersion: s.specVersion,
    surfacePending: true,
  }),
  releaseSettled: () => ({ releasePending: false }),
  fieldArrived: (s, field, version, spec, surfaceId) => ({
    field,
    fieldVersion: version,
    fieldSpec: spec,
    fieldSurface: surfaceId,
  }),
  // A surface's sheet came (`id`): the placement moved with it by `motion`
  // when it is on the sheet the edit started from.
  sheetFollowed: (s, id, motion) => ({
    placementSheet: id,
    ...(motion
      ? {
          placement: placedOnSheet(s, {
            center: motion.center,
            rotation_deg: s.placement.rotation_deg + motion.rotation_deg,
          }),
        }
      : {}),
  }),
  fieldMoved: (s) => ({ live: { ...s.live, moved: s.live.moved + 1 } }),
  previewShown: (s) => ({ live: { ...s.live, previews: s.live.previews + 1 } }),
  liveGapMeasured: (s, gap) => ({ live: { ...s.live, gap: Math.max(s.live.gap, gap) } }),
  livePoseApplied: (s, liveSummary, last) => ({
    live: { ...s.live, surfaces: s.live.surfaces + 1, last },
    liveSummary,
  }),
  surfaceFlattened: (s, id) => ({ surfaceId: id, surfacePending: false }),
  sheetAwaited: () => ({ sheetPending: true }),
  // The sheet is drawn: its figures, and the model centred on it (`centre`)
  // where it is new.
  sheetShown: (s, surfaceInfo, centre) =>
    !s.placement.center || s.recentre
      ? {
          surfaceInfo,
          placement: placedOnSheet(s, { center: centre }),
          fitNext: !s.model?.text, // a text keeps its millimetres
          recentre: false,
        }
      : { surfaceInfo },
  sheetSettled: () => ({ sheetPending: false }),
  surfaceFailed: () => ({ surfacePending: false, sheetPending: false }),
  // An edit's exact result came: its surface is the current one; `placement`,
  // where the server moved it, the placement on its sheet.
  editFollowed: (s, surfaceId, placement) => ({
    surfaceId,
    surfacePending: false,
    ...(placement ? { placement: placedOnSheet(s, placement), placementSheet: surfaceId } : {}),
  }),

  // --- the model ----------------------------------------------------------
  // A model read (a file, a sample, a text): `settings` and `placement`
  // replace the page's where given.
  modelChosen: (s, model, { settings = null, placement = {}, fitNext = true } = {}) => ({
    model,
    historyReset: true,
    upResolved: null,
    fitNext,
    placement: placedOnSheet(s, placement),
    ...(settings ? { settings: { ...s.settings, ...settings } } : {}),
  }),
  // A new keystroke's text, the same model otherwise.
  textModelChanged: (s, model) => ({ model }),
  // The worker's simplified mesh of `model` for the preview.
  modelSimplified: (s, model, lod) => (s.model === model ? { model: { ...model, lod } } : null),

  // --- the placement ------------------------------------------------------
  placed: (s, placement) => ({ placement: placedOnSheet(s, placement), edited: true }),
  scaled: (s, scale) => ({ placement: placedOnSheet(s, { scale }), fitNext: false, edited: true }),
  fitAsked: () => ({ fitNext: true, edited: true }),
  markMapped: (s, polyline) => ({ lastMark: polyline }),
  marksCleared: () => ({ lastMark: null }),

  // --- the exact result ---------------------------------------------------
  // Its stats and what it cost; a fitted scale becomes the placement's.
  exactShown: (s, stats, cost) => {
    const placement = s.fitNext ? placedOnSheet(s, { scale: stats.placement.scale }) : s.placement;
    return {
      lastStats: stats,
      lastExact: cost,
      exactShown: shownKey({ ...s, placement }, stats.surface_id),
      lastPreview: null,
      upResolved: stats.placement.up,
      fitNext: false,
      placement,
    };
  },
  previewMeasured: (s, lastPreview) => ({ lastPreview }),

  // --- history and saved requests -----------------------------------------
  historySettled: () => ({ historyReset: false, edited: false }),
  // An undo or redo: the step's spec and placement.
  stepRestored: (s, step) => ({
    placement: step.placement,
    placementSheet: step.placementSheet,
    fitNext: false,
    recentre: false,
    edited: false,
    ...(JSON.stringify(step.spec) !== JSON.stringify(s.spec)
      ? { spec: step.spec, specVersion: s.specVersion + 1 }
      : {}),
  }),
  // A saved request opened (output_panel.js read and checked it).
  requestOpened: (s, { spec, grid, settings, placement }) => ({
    spec,
    grid,
    settings: { ...s.settings, ...settings },
    placement,
    fitNext: typeof placement.scale !== 'number',
    recentre: !placement.center,
    placementSheet: null, // the placement lies on the sheet its spec flattens to
    historyReset: true,
    preset: null, // none of the presets: the request's own surface
  }),
};
