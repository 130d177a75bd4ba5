// The model panel: a sample, a file (chosen or dropped), or a text typed on
// the page (shaped by the server, POST /v1/text), shown as the preview at
// once and deformed exactly after.
import { fonts, textMesh } from './api.js';
import { $, fmt } from './dom.js';
import { readModel } from './footprint.js';
import { sampleModel } from './samples.js';

// The text controls as the page opens.
export function textControls() {
  return {
    string: $('text').value,
    font: $('font').value,
    size_mm: Number($('text-size').value),
    depth_mm: Number($('text-depth').value),
  };
}

// The text to ask for: the typed settings within their bounds.
function textSettings(t) {
  const size = Math.max(0.05, Number(t.size_mm) || 0.6);
  return {
    string: t.string,
    font: t.font,
    size_mm: size,
    depth_mm: Math.max(0, Number(t.depth_mm) || 0),
    tolerance_mm: size / 100,
  };
}

export function installModelPanel(page) {
  const { store, preview, sheetView } = page;

  // The preview's simplified mesh of `model`, when the worker has made it.
  const simplify = (model, geometry) =>
    preview.setModelGeometry(geometry, (lod) => store.dispatch('modelSimplified', model, lod));

  // The typed text on the surface: its flat mesh from POST /v1/text (the
  // newest keystroke's: an older request in flight is aborted), bent by the
  // preview at once; the exact result `delay` ms after the typing pauses.
  page.useText = async (delay = 0) => {
    const text = textSettings(store.state.text);
    if (!text.string.trim()) return;
    performance.mark('surfdeform:text-typed');
    let made;
    try {
      // The "text" lane: a newer keystroke aborts this one's request.
      made = await page.latest('text', (signal) => textMesh(text, signal));
    } catch (e) {
      page.showError(e);
      return;
    }
    if (!made) return; // a newer keystroke's is coming
    performance.mark('surfdeform:text-received');
    const read = await readModel('text.ply', made.bytes);
    performance.mark('surfdeform:text-read');
    const first = !store.state.model || !store.state.model.text;
    const model = { name: 'text.ply', bytes: made.bytes, positions: read.positions, lod: null, text };
    if (first) {
      // Letters stand on the surface, each rigid, at their size in mm.
      store.dispatch('modelChosen', model, {
        settings: { up: '+z', anchor: 'bottom', rigid: 'components' },
        placement: {
          scale: 1,
          rotation_deg: 0,
          ...(sheetView.sheet ? { center: sheetView.sheetCentre() } : {}),
        },
        fitNext: false,
      });
    } else {
      store.dispatch('textModelChanged', model);
    }
    simplify(model, read.geometry);
    const t = made.stats.text;
    $('model-name').textContent =
      `"${text.string}": ${t.glyphs} glyphs in ${t.family} ${t.style}, ${fmt(t.width_mm, 3)} mm long`;
    page.updateFootprint();
    page.showError(null);
    if (page.showLivePreview()) {
      performance.mark('surfdeform:text-preview');
      // The frame that draws it (bench/text_keystroke.mjs reads both).
      requestAnimationFrame(() => performance.mark('surfdeform:text-drawn'));
    }
    if (delay > 0) page.holdDeform();
    page.scheduleDeform(delay);
  };

  // The built-in fonts, each with the scripts it covers.
  page.listFonts = async () => {
    const found = await page.latest('fonts', (signal) => fonts(signal));
    if (!found) return;
    $('font').replaceChildren(
      ...found.fonts.map((f) => {
        const o = document.createElement('option');
        o.value = f.name;
        o.textContent = `${f.name} (${f.scripts.join(', ')})`;
        return o;
      }),
    );
    store.dispatch('textEdited', { font: found.default });
    $('font').value = found.default;
  };

  // A model file (or a sample) read and deformed, fitted to the sheet.
  page.useModel = async (name, bytes) => {
    const read = await readModel(name, bytes);
    const model = { name, bytes, positions: read.positions, lod: null };
    store.dispatch('modelChosen', model, {
      // a text's settings go with it
      settings: store.state.model?.text ? { up: 'auto', anchor: 'center', rigid: 'none' } : null,
      placement: { rotation_deg: 0, ...(sheetView.sheet ? { center: sheetView.sheetCentre() } : {}) },
    });
    simplify(model, read.geometry);
    $('model-name').textContent =
      `${name} (${bytes.byteLength} bytes)` +
      (model.positions ? '' : ' — the browser cannot outline it; the server reads it');
    page.updateFootprint();
    page.scheduleDeform(0);
  };

  // The sample chosen: a model, or the text box.
  page.useSample = async () => {
    if (store.state.sample === 'text') return page.useText(0);
    const m = await page.latest('sample', (signal) => sampleModel(store.state.sample, signal));
    if (m) await page.useModel(m.name, m.bytes);
  };

  // A chosen or dropped file, read and handed to use(name, bytes): the model
  // (useModel), the surface (useSurfaceMesh) or a saved request.
  page.useFile = async (file, use = page.useModel) => {
    if (!file) return;
    store.dispatch('busy');
    try {
      await use(file.name, await file.arrayBuffer());
    } catch (e) {
      page.showError(e);
    }
  };

  $('text').addEventListener('input', () => {
    store.dispatch('textEdited', { string: $('text').value });
    page.useText(250);
  });
  const number = { 'text-size': 'size_mm', 'text-depth': 'depth_mm' };
  for (const id of ['font', 'text-size', 'text-depth']) {
    $(id).addEventListener('change', () => {
      store.dispatch('textEdited', { [number[id] || id]: number[id] ? Number($(id).value) : $(id).value });
      page.useText(0);
    });
  }
  $('sample').addEventListener('change', async () => {
    store.dispatch('sampleChosen', $('sample').value);
    store.dispatch('busy');
    try {
      await page.useSample();
    } catch (e) {
      page.showError(e);
    }
  });
  $('upload').addEventListener('change', (e) => page.useFile(e.target.files[0]));
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
    page.useFile(file, json ? page.openRequest : onSheet ? page.useSurfaceMesh : page.useModel);
  });

  store.subscribe((s, old) => {
    if (s.sample !== old.sample) {
      $('sample').value = s.sample;
      $('text-controls').hidden = s.sample !== 'text';
    }
  });
  $('text-controls').hidden = store.state.sample !== 'text';
}
