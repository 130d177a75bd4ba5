// preview_mesh.js off the page's thread: a million-triangle model takes
// ~1.5 s to weld, simplify and order (Chromium, this machine), which held
// the page when done there. A message {id, positions, index (or null)}
// gets {id, positions, normals, index, welded, lod} back, or {id, error}.
// Workers have no import map: meshoptimizer by the path the server serves
// it at.
import { MeshoptEncoder } from '/vendor/meshoptimizer/meshopt_encoder.js';
import { MeshoptSimplifier } from '/vendor/meshoptimizer/meshopt_simplifier.js';
import { previewMesh } from './preview_mesh.js';

self.onmessage = async ({ data }) => {
  try {
    await Promise.all([MeshoptSimplifier.ready, MeshoptEncoder.ready]);
    const out = previewMesh({ simplifier: MeshoptSimplifier, encoder: MeshoptEncoder }, data.positions, data.index);
    self.postMessage({ id: data.id, ...out }, [
      ...new Set([out.positions.buffer, out.normals.buffer, out.index.buffer]),
    ]);
  } catch (e) {
    self.postMessage({ id: data.id, error: String(e && e.message ? e.message : e) });
  }
};
