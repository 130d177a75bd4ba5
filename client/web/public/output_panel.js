// The output panel: the deformed model downloaded (GLB or Draco), and what
// the page shows saved as one /v1/deform request for batch jobs, or such a
// request opened.
import { deform } from './api.js';
import { $, readableJson, saveBlob } from './dom.js';

const kSelects = ['up', 'anchor', 'rigid', 'subdivision'];

export function installOutputPanel(page) {
  const { store } = page;

  // `blob` saved as the file `suffix` after the model's name.
  const save = (blob, suffix) => saveBlob(blob, `${store.state.model.name.replace(/\.[^.]*$/, '')}-${suffix}`);

  async function download(format) {
    try {
      const { model } = store.state;
      const accept = format === 'glb' ? 'model/gltf-binary' : 'application/octet-stream';
      const made = await page.latest(`download-${format}`, (signal) =>
        deform(model.bytes, model.name, page.deformParams(format), accept, signal),
      );
      if (made) save(new Blob([made.bytes]), `deformed.${format}`);
    } catch (e) {
      page.showError(e);
    }
  }

  // What the page shows as one /v1/deform request, for batch jobs: the
  // surface inline (its spec and sampling; the same spec flattens to the same
  // id), the placement on its sheet, the subdivision, GLB out. With the model:
  //   curl -F mesh=@MODEL -F params=@REQUEST -o out.glb http://HOST/v1/deform
  //   surfdeform deform MODEL --params REQUEST -o out.glb
  page.deformRequest = () => {
    const s = store.state;
    return page.deformParams('glb', null, { surface: s.spec, sampling: { nu: s.grid, nv: s.grid } });
  };

  // A saved request (the page's, or written by hand) opened: its surface,
  // grid, placement and settings, with the model already shown (a request
  // holds none). Its "flatten" and "output" are not the page's to set.
  page.openRequest = async (name, bytes) => {
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
    const settings = { up: p.up, anchor: p.anchor, rigid: p.rigid, subdivision: r.subdivision?.mode };
    for (const id of kSelects) {
      const value = settings[id];
      if (value === undefined) delete settings[id];
      else if (![...$(id).options].some((o) => o.value === value)) {
        throw new Error(`${name}: the page has no ${id} "${value}"`);
      }
    }
    store.dispatch('requestOpened', {
      spec: r.surface,
      grid: nu,
      settings,
      placement: {
        center: Array.isArray(p.center) ? p.center : null,
        rotation_deg: Number(p.rotation_deg) || 0,
        scale: typeof p.scale === 'number' ? p.scale : 'fit',
      },
    });
    page.modelView.framed = false;
    page.scheduleSurface();
  };

  $('download-glb').addEventListener('click', () => download('glb'));
  $('download-drc').addEventListener('click', () => download('drc'));
  $('save-request').addEventListener('click', () =>
    save(new Blob([`${readableJson(page.deformRequest())}\n`], { type: 'application/json' }), 'request.json'),
  );
  $('open-request').addEventListener('change', (e) => page.useFile(e.target.files[0], page.openRequest));
}
