// The placement panel: where the model lies on the flat sheet (centre,
// rotation, scale, up axis, anchor, rigid parts), its footprint and the live
// preview there, and the marks drawn on the sheet.
import { mapOnSurface } from './api.js';
import { $, fmt } from './dom.js';
import { footprint, placementFrame } from './footprint.js';
import { thawed } from './store.js';

const kSettings = ['up', 'anchor', 'rigid', 'subdivision', 'distortion'];

// The settings' controls as the page opens.
export function placementControls() {
  return Object.fromEntries(kSettings.map((id) => [id, id === 'distortion' ? $(id).checked : $(id).value]));
}

export function installPlacementPanel(page) {
  const { store, sheetView, preview, modelView } = page;
  const outlines = new WeakMap(); // per model: its footprint per up axis

  // The up axis the footprint is drawn with: "auto" is the server's to
  // resolve (by format and shape), known from the last deformation's stats.
  page.effectiveUp = () => {
    const { settings, upResolved } = store.state;
    return settings.up === 'auto' ? upResolved || '+z' : settings.up;
  };

  // The model's outline for the up axis in use, kept per model and axis: a
  // million-triangle model's hull takes ~0.2-0.3 s on the page's thread, and
  // the first exact result's resolved axis ("auto") is most often the one
  // assumed before it came.
  page.updateFootprint = () => {
    const m = store.state.model;
    if (!m) return sheetView.setFootprint(null);
    const up = page.effectiveUp();
    const key = m.bytes;
    if (!outlines.has(key)) outlines.set(key, new Map());
    const byUp = outlines.get(key);
    if (!byUp.has(up)) byUp.set(up, footprint(m.positions, up));
    sheetView.setFootprint(byUp.get(up));
  };

  // The preview placed where the model is now; whether it can be shown (not
  // without a field, a model the browser read or a fitted scale).
  page.placePreview = () => {
    const { model, field, placement, settings } = store.state;
    if (!model || !model.positions || !field || typeof placement.scale !== 'number') return false;
    preview.setPlacement(placementFrame(model.positions, page.effectiveUp(), settings.anchor), placement);
    return preview.ready();
  };

  // The preview at the current placement, in place of the exact model; false
  // when it cannot be shown (no field yet, a model the browser cannot read, a
  // scale still to be fitted).
  page.showLivePreview = () => {
    if (!page.placePreview()) return false;
    preview.shown();
    modelView.showPreview(true);
    store.dispatch('previewShown');
    return true;
  };

  // A text's origin (its baseline's centre) is where the server puts the
  // placement's centre; the page places the footprint's centre. `center` moved
  // between the two: sign -1 from the page's to the server's, +1 back.
  page.offsetCenter = (center, p, sign) => {
    const m = store.state.model;
    if (!center || !m || !m.positions || typeof p.scale !== 'number') return center;
    const f = placementFrame(m.positions, page.effectiveUp(), store.state.settings.anchor);
    const [bx, by] = f.centre;
    const a = (p.rotation_deg * Math.PI) / 180,
      s = p.scale;
    return [
      center[0] + sign * s * (Math.cos(a) * bx - Math.sin(a) * by),
      center[1] + sign * s * (Math.sin(a) * bx + Math.cos(a) * by),
    ];
  };

  // --- marks ---------------------------------------------------------------
  // "Draw a mark": clicks on the sheet add points to a polyline, which the
  // server resamples onto the surface (POST /v1/surfaces/{id}/map) and the 3D
  // view draws on it.
  page.showMark = async (points) => {
    const surfaceId = store.state.surfaceId;
    if (!surfaceId || points.length < 2) {
      modelView.setMarks([]);
      return;
    }
    try {
      const mapped = await page.latest('mark', (signal) => mapOnSurface(surfaceId, { polylines: [points] }, signal));
      if (!mapped) return; // a newer mark is on its way
      modelView.setMarks(mapped.polylines);
      store.dispatch('markMapped', mapped.polylines[0]);
    } catch (e) {
      page.showError(e);
    }
  };

  $('mark').addEventListener('click', () => {
    const on = $('mark').getAttribute('aria-pressed') !== 'true';
    $('mark').setAttribute('aria-pressed', String(on));
    $('mark').textContent = on ? 'Done marking' : 'Draw a mark';
    sheetView.setMarking(on ? (points) => page.showMark(points) : null);
  });
  $('clear-marks').addEventListener('click', () => {
    sheetView.setMark([]);
    store.dispatch('marksCleared');
    modelView.setMarks([]);
  });

  // --- the controls --------------------------------------------------------
  $('rotation').addEventListener('input', () => {
    store.dispatch('placed', { rotation_deg: Number($('rotation').value) });
    page.showLivePreview();
    page.holdDeform();
  });
  $('rotation').addEventListener('change', () => page.scheduleDeform(0));
  $('scale').addEventListener('change', () => {
    const s = Number($('scale').value);
    if (s > 0) {
      store.dispatch('scaled', s);
      page.scheduleDeform(0);
    }
  });
  $('fit').addEventListener('click', () => {
    store.dispatch('fitAsked');
    page.scheduleDeform(0);
  });
  for (const id of kSettings) {
    $(id).addEventListener('change', () => {
      store.dispatch('settingChanged', id, id === 'distortion' ? $(id).checked : $(id).value);
      if (id === 'up') page.updateFootprint();
      page.scheduleDeform(0);
    });
  }

  // Renders the placement and the settings where they changed. The sheet
  // view is given a copy: it moves the placement it holds while dragged.
  store.subscribe((s, old) => {
    if (s.placement !== old.placement) {
      const p = s.placement;
      $('rotation').value = p.rotation_deg;
      $('rotation-value').textContent = `${Math.round(p.rotation_deg)}°`;
      if (typeof p.scale === 'number') $('scale').value = fmt(p.scale, 5);
      sheetView.setPlacement(thawed(p));
    }
    if (s.settings !== old.settings) {
      for (const id of kSettings) {
        if (id === 'distortion') $(id).checked = s.settings[id];
        else $(id).value = s.settings[id];
      }
    }
    if (s.upResolved !== old.upResolved && s.settings.up === 'auto') page.updateFootprint();
  });
}
