// Surface presets (the paper's Bezier figures and the NURBS bottle, served
// from /samples/, analytic kinds, and the panel: a surface given as a mesh,
// uploaded as a model) and sample models.

import { uploadModel } from './api.js';

export async function surfacePreset(name, signal = undefined) {
  if (name.startsWith('figure') || name === 'bottle') {
    const r = await fetch(`/samples/${name}.json`, { signal });
    if (!r.ok) throw new Error(`cannot load the preset ${name}`);
    const spec = await r.json();
    delete spec.description; // a note for people; the API takes surface fields only
    return spec;
  }
  if (name === 'panel') {
    const r = await fetch('/samples/panel.obj', { signal });
    if (!r.ok) throw new Error('cannot load the panel mesh');
    const model = await uploadModel(await r.arrayBuffer(), 'panel.obj', signal);
    return { kind: 'mesh', model_id: model.id };
  }
  switch (name) {
    case 'cylinder':
      return { kind: 'cylinder', radius: 1, height: 2, angle_deg: 180 };
    case 'can':
      return { kind: 'cylinder', radius: 1, height: 2, angle_deg: 360 };
    case 'ring':
      return {
        kind: 'torus',
        major_radius: 2,
        minor_radius: 0.6,
        u_min_deg: 0,
        u_max_deg: 360,
        v_min_deg: 0,
        v_max_deg: 360,
      };
    case 'cone':
      return { kind: 'cone', radius_bottom: 1, radius_top: 0.5, height: 1, angle_deg: 240 };
    case 'lampshade':
      return { kind: 'cone', radius_bottom: 1, radius_top: 0.5, height: 1, angle_deg: 360 };
    case 'wave':
      return { kind: 'wave', length: 4, width: 1.5, amplitude: 0.25, wavelength: 2 };
    default:
      throw new Error(`no preset ${name}`);
  }
}

// The paper's thin plate: a box of 6 quads (OBJ), 1 x 0.6 x 0.05.
export function thinPlateObj() {
  const v = [];
  for (let k = 0; k < 8; ++k) {
    v.push(`v ${k & 1 ? 0.5 : -0.5} ${k & 2 ? 0.3 : -0.3} ${k & 4 ? 0.025 : -0.025}`);
  }
  return `${v.join('\n')}\nf 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n`;
}

export async function sampleModel(name, signal = undefined) {
  if (name === 'plate') {
    return { name: 'thin-plate.obj', bytes: new TextEncoder().encode(thinPlateObj()).buffer };
  }
  const files = { word: 'word.obj', label: 'label.obj' };
  const file = files[name] || 'bunny.ply';
  const r = await fetch(`/samples/${file}`, { signal });
  if (!r.ok) throw new Error(`cannot load the sample ${file}`);
  return { name: file, bytes: await r.arrayBuffer() };
}
