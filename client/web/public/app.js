// The surfdeform viewer: pick or edit a surface, see its flat sheet and the
// model's footprint on it, place the model, see it deformed in 3D.
//
// Flow: surface spec -> POST /v1/surfaces?field=64 (flattened once, cached
// by the server; with the field of its map) -> GET /v1/surfaces/{id} (sheet
// and samples) -> POST /v1/deform by surface and model id with the placement
// -> GLB -> three.js. While the person drags, the model is a GPU preview bent
// by the field (preview.js); the exact deformation replaces it on release.
//
// This file is the composition root. The state is one store (store.js,
// viewer_state.js: named actions); every request runs on the one scheduler
// (scheduler.js: lanes, the newest wins). The panels read the store,
// dispatch actions and render what changed:
//   surface_panel.js    presets, a mesh as the surface, the grid, control points
//   surface_edit.js     flattening, live poses of a drag, a release's result
//   model_panel.js      samples, files, the text box
//   placement_panel.js  placement controls, footprint, preview placing, marks
//   exact_result.js     the exact deformation and its figures
//   output_panel.js     downloads, saved requests
//   part_panel.js       a printable part of the surface: its report, 3MF, STL
//   history_panel.js    undo and redo
//   animation_panel.js  animation
//   test_surface.js     window.surfdeformTest, for the browser tests
// They share `page`: the store, the views, and the operations each panel
// adds to it (page.scheduleDeform, page.useModel, ...).
//
// document.body.dataset.state is "loading", "ready" or "error" (tests wait on
// it): "loading" from the moment an edit schedules work until the newest
// exact deformation is on screen, so "ready" always shows the current inputs.
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

import { AnimationPanel } from './animation_panel.js';
import { $ } from './dom.js';
import { installExactResult } from './exact_result.js';
import { dracoLoader } from './footprint.js';
import { installHistoryPanel } from './history_panel.js';
import { installModelPanel, textControls } from './model_panel.js';
import { ModelView } from './model_view.js';
import { installOutputPanel } from './output_panel.js';
import { installPartPanel } from './part_panel.js';
import { installPlacementPanel, placementControls } from './placement_panel.js';
import { FieldPreview } from './preview.js';
import { scheduler } from './scheduler.js';
import { SheetView } from './sheet_view.js';
import { createStore } from './store.js';
import { installSurfaceEdit } from './surface_edit.js';
import { installSurfacePanel } from './surface_panel.js';
import { installTestSurface } from './test_surface.js';
import { actions, initialState, kShallow } from './viewer_state.js';

const store = createStore(
  initialState({
    preset: $('preset').value,
    sample: $('sample').value,
    text: textControls(),
    settings: placementControls(),
  }),
  actions,
  { shallow: kShallow },
);

const page = {
  store,
  scheduler,
  preview: new FieldPreview(),
  // Exact results come as meshopt GLB; downloads stay Draco (smaller).
  gltf: new GLTFLoader().setDRACOLoader(dracoLoader()).setMeshoptDecoder(MeshoptDecoder),
  // `request(signal)` on the scheduler's `lane`, the newest wins (an older one
  // is aborted): its value, or undefined when a newer one superseded it.
  latest: async (lane, request) => {
    const r = await scheduler.run(lane, request);
    return r.done ? r.value : undefined;
  },
  // An error shown on the page (null: none).
  showError: (error) =>
    error ? store.dispatch('failed', String(error.message || error)) : store.dispatch('errorCleared'),
};

// The flat sheet: a footprint dragged, wheeled or released.
page.sheetView = new SheetView($('sheet'), (placement, final, how) => {
  store.dispatch('placed', placement);
  if (final) return page.scheduleDeform(0);
  page.showLivePreview();
  // The wheel has no release: the exact result 150 ms after its last event.
  if (how === 'wheel') page.scheduleDeform(150);
  else page.holdDeform();
});
// The 3D view; its control-point drags are the surface panel's.
page.modelView = new ModelView($('view3d'), () => {});
page.modelView.setPreview(page.preview.mesh);
page.preview.onChange = () => page.modelView.invalidate();

installPlacementPanel(page);
installExactResult(page);
installSurfaceEdit(page);
installSurfacePanel(page);
installModelPanel(page);
installOutputPanel(page);
installHistoryPanel(page);
installPartPanel(page);

// Whether the preview may stand in for the exact result while the view
// moves (model_view.js): it shows the same surface and placement, and it
// is simplified (a quarter of the triangles: the model's lod).
page.modelView.standInAllowed = () => {
  const s = store.state;
  return (
    Boolean(s.model?.lod) &&
    s.settings.rigid === 'none' &&
    s.exactShown === page.shownKey(s.fieldSurface) &&
    page.placePreview()
  );
};

// The animation panel: the current model, placed as on the sheet (fitted to
// every frame's sheet, rotated, with the chosen axes).
const animationPanel = new AnimationPanel(
  page.modelView,
  () => {
    const s = store.state;
    return {
      model: s.model,
      placement: { scale: 'fit', rotation_deg: s.placement.rotation_deg, up: s.settings.up, anchor: s.settings.anchor },
    };
  },
  page.showError,
);

installTestSurface(page, animationPanel);

// The page's status and error, rendered.
store.subscribe((s, old) => {
  if (s.status !== old.status) document.body.dataset.state = s.status;
  if (s.error !== old.error) {
    $('error').hidden = !s.error;
    $('error').textContent = s.error || '';
  }
});

(async () => {
  try {
    const spec = await page.presetSpec();
    // Else another preset was chosen, and is on its way.
    if (spec) store.dispatch('surfaceChosen', spec);
    store.dispatch('surfaceRequested');
    if (store.state.sample === 'text') await page.listFonts();
    await page.useSample();
    await page.refreshSurface();
  } catch (e) {
    page.showError(e);
  }
})();
