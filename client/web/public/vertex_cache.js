// The preview's triangles in an order the vertex stage can reuse: a model as
// read (a scanned PLY) lists its triangles in no useful order, so a renderer
// shades most vertices twice or more, and the preview's vertex shader (eight
// field fetches per vertex) is the costly one. meshoptimizer's vertex cache
// optimisation reorders the index only; the attributes stay as they are.
//
// Measured in Chromium with software WebGL, the bunny at half its fitted
// scale: average cache miss ratio 2.31 -> 0.68 (a 16-entry FIFO), the
// preview's frame 76 -> 69 ms against 55 ms for the exact result
// (BENCHMARKS.md). Where meshoptimizer is not there (a viewer folder
// installed before it), the order is left as it is.

import { meshopt } from './meshopt.js';

// Reorders `geometry`'s triangles (an indexed triangle list) for the vertex
// cache, in place; true when it did.
export async function reorderForVertexCache(geometry) {
  const index = geometry && geometry.index;
  if (!index || index.count < 3 || index.count % 3 !== 0) return false;
  const encoder = await meshopt('encoder');
  if (!encoder) return false;
  // reorderMesh also renumbers the vertices for fetch order (remap: old ->
  // new); the triangles are put back on the old numbers, so that no
  // attribute has to move.
  const indices = Uint32Array.from(index.array);
  const [remap] = encoder.reorderMesh(indices, true, false);
  const old = new Uint32Array(remap.length);
  for (let v = 0; v < remap.length; ++v) if (remap[v] !== 0xffffffff) old[remap[v]] = v;
  for (let k = 0; k < indices.length; ++k) index.array[k] = old[indices[k]];
  index.needsUpdate = true;
  return true;
}
