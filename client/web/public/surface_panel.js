// The surface panel: a preset, a mesh as the surface, the sampling grid, the
// flattening's figures, and the Bezier control points: dragged in the 3D
// view, or pressed there and typed as numbers.
import { uploadModel } from './api.js';
import { $, list } from './dom.js';
import { surfacePreset } from './samples.js';

export function installSurfacePanel(page) {
  const { store, modelView } = page;

  // Control point `index` of the spec moved to `point` (to 1e-6): a new
  // surface version when it changed. Whether it changed.
  page.setControlPoint = (index, point) => {
    const before = store.state.specVersion;
    store.dispatch(
      'controlPointMoved',
      index,
      point.map((x) => Math.round(x * 1e6) / 1e6),
    );
    return store.state.specVersion !== before;
  };

  // The 3D view's control-point drags: the field and the preview move at
  // once, one live pose per move; the release asks for the exact result.
  modelView.onControlPoint = (index, point, final) => {
    // A release where the last move left the point: the same surface.
    const changed = page.setControlPoint(index, point);
    page.showControlPoint();
    if (final) {
      // A press without a move selects the point (its numbers), nothing more.
      const moved = store.state.pointerMoved || changed;
      store.dispatch('pointerMoved', false);
      if (!moved) return;
      store.dispatch('edited');
      return page.releaseControlPoint();
    }
    store.dispatch('pointerMoved', true);
    store.dispatch('edited');
    page.showMovedField();
    page.liveSurface();
  };

  // --- a control point's numbers --------------------------------------------
  // The control point last pressed in the 3D view: its x, y and z, to read
  // and to type. A typed value is an edit as a drag's release is (one exact
  // request, a step to undo), with the preview moved at once.
  page.showControlPoint = () => {
    const k = modelView.selected;
    const spec = store.state.spec;
    const points = spec && spec.kind === 'bezier' ? spec.control_points : null;
    const shown = Boolean(points && k >= 0 && k < points.length);
    $('cp-edit').hidden = !shown;
    if (!shown) return;
    const columns = spec.degree_u + 1;
    $('cp-index').textContent = `${k} (row ${Math.floor(k / columns)}, column ${k % columns})`;
    ['x', 'y', 'z'].forEach((c, i) => {
      if (document.activeElement !== $(`cp-${c}`)) $(`cp-${c}`).value = points[k][i];
    });
  };
  modelView.onSelect = page.showControlPoint;

  ['x', 'y', 'z'].forEach((c, i) => {
    $(`cp-${c}`).addEventListener('change', () => {
      const k = modelView.selected;
      const input = $(`cp-${c}`);
      const value = Number(input.value);
      const spec = store.state.spec;
      const points = spec && spec.kind === 'bezier' ? spec.control_points : null;
      if (
        !points ||
        !points[k] ||
        input.value.trim() === '' ||
        !Number.isFinite(value) ||
        modelView.drag ||
        !page.setControlPoint(
          k,
          points[k].map((x, j) => (j === i ? value : x)),
        )
      ) {
        input.value = points && points[k] ? points[k][i] : '';
        return;
      }
      store.dispatch('edited');
      modelView.setControlPoints(store.state.spec.control_points);
      page.showMovedField();
      page.releaseControlPoint();
    });
  });

  // --- a new surface ---------------------------------------------------------

  // The spec of the preset chosen, or undefined when another was chosen
  // while it was on its way.
  page.presetSpec = () => page.latest('preset', (signal) => surfacePreset(store.state.preset, signal));

  // A surface given as a mesh (a disk-shaped triangle mesh file): uploaded as
  // a model, then flattened as the surface {kind: "mesh", model_id}.
  page.useSurfaceMesh = async (name, bytes) => {
    const model = await page.latest('upload', (signal) => uploadModel(bytes, name, signal));
    if (!model) return; // another file came after it
    store.dispatch('surfaceChosen', { kind: 'mesh', model_id: model.id });
    modelView.framed = false;
    page.scheduleSurface();
  };

  $('preset').addEventListener('change', async () => {
    store.dispatch('presetChosen', $('preset').value);
    store.dispatch('busy');
    try {
      const spec = await page.presetSpec();
      if (!spec) return; // another preset was chosen meanwhile
      store.dispatch('surfaceChosen', spec);
      modelView.framed = false;
      page.scheduleSurface();
    } catch (e) {
      page.showError(e);
    }
  });
  $('grid').addEventListener('change', () => {
    store.dispatch('surfaceChosen', store.state.spec, Math.max(4, Math.min(64, Number($('grid').value) || 16)));
    page.scheduleSurface();
  });
  $('surface-upload').addEventListener('change', (e) => page.useFile(e.target.files[0], page.useSurfaceMesh));

  store.subscribe((s, old) => {
    if (s.surfaceInfo !== old.surfaceInfo) list($('quality'), s.surfaceInfo);
    if (s.grid !== old.grid) $('grid').value = s.grid;
    if (s.preset !== old.preset) {
      if (s.preset === null) $('preset').selectedIndex = -1;
      else $('preset').value = s.preset;
    }
  });
}
