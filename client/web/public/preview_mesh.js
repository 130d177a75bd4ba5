// The preview's own mesh, made cheap to bend on the GPU while a person
// drags: welded, given vertex normals, simplified and ordered for the
// vertex cache. Plain arrays in and out, and no imports but normals.js's
// plain arrays: preview_mesh_worker.js runs it off the page's thread with
// meshoptimizer's JS build (npm), and the Node tests run it with the same.
//
// Welded: a model read as separate triangles (STL, OBJ: three.js's loaders
// give every triangle its own corners) gets an index over its distinct
// positions, as the server's readers weld it, so that the vertex cache
// shares the corners and the normals are the exact result's: smooth over
// the welded vertices, where they were flat per triangle.
//
// Normals: every vertex's, over all the model's triangles (before they are
// simplified), as the page computes the exact result's (vertex_normals.js).
// Computed here, off the page's thread: ~0.1-0.2 s for a million triangles
// on the page's, at load.
//
// Fewer triangles: a model of 20,000 triangles or more is drawn with a
// quarter of them, simplified by meshoptimizer within 5e-4 of the model's
// size (its error measure, relative to the model's extent; a scanned model
// may stop short of the quarter there), its borders locked (the outline
// the sheet shows). The exact result replaces the preview on release, with
// every triangle. The preview's vertex shader (the field's fetches and the
// normal's turn) costs about twice the exact result's per vertex, and with
// software WebGL a large model's frame is mostly that stage (a million
// triangles: ~5.5 frames a second orbiting the exact result, ~3.5 dragging
// the whole preview; BENCHMARKS.md). Simplification keeps a subset of the
// vertices where they are, with their normals, so every vertex drawn is
// still placed exactly.
//
// Ordered: a model as read (a scanned PLY) lists its triangles in no useful
// order, so a renderer shades most vertices twice or more; meshoptimizer's
// vertex cache optimisation reorders the index (the vertices keep their
// numbers). Measured in Chromium with software WebGL, the bunny at half its
// fitted scale: average cache miss ratio 2.31 -> 0.68 (a 16-entry FIFO),
// the whole preview's frame 76 -> 69 ms.

import { vertexNormals } from './normals.js';

export const kPreviewShare = 0.25; // of the triangles
export const kPreviewError = 5e-4; // of the model's extent
export const kPreviewMinTriangles = 20000; // below: drawn whole

// `positions` (x, y, z per corner, three corners a triangle) welded:
// {positions, index} over the distinct positions (meshoptimizer's position
// remap: bitwise-equal positions), in the order they are first used.
export function weldTriangles(simplifier, positions) {
  const index = Uint32Array.from(simplifier.generatePositionRemap(positions, 3));
  const [remap, count] = simplifier.compactMesh(index); // remap: corner -> vertex
  const kept = new Float32Array(3 * count);
  for (let v = 0; v < remap.length; ++v) {
    if (remap[v] !== 0xffffffff) kept.set(positions.subarray(3 * v, 3 * v + 3), 3 * remap[v]);
  }
  return { positions: kept, index };
}

// `index` (Uint32Array) simplified as described above: {index, error}, or
// null for a model drawn whole.
export function simplifyTriangles(simplifier, index, positions) {
  if (index.length / 3 < kPreviewMinTriangles) return null;
  const target = 3 * Math.floor((kPreviewShare * index.length) / 3);
  const [kept, error] = simplifier.simplify(index, positions, 3, target, kPreviewError, ['LockBorder']);
  return { index: kept, error };
}

// `index` reordered for the vertex cache, in place. reorderMesh also
// renumbers the vertices for fetch order (remap: old -> new); the triangles
// are put back on the old numbers, so that no attribute has to move.
export function orderForVertexCache(encoder, index) {
  const renumbered = Uint32Array.from(index);
  const [remap] = encoder.reorderMesh(renumbered, true, false);
  const old = new Uint32Array(remap.length);
  for (let v = 0; v < remap.length; ++v) if (remap[v] !== 0xffffffff) old[remap[v]] = v;
  for (let k = 0; k < index.length; ++k) index[k] = old[renumbered[k]];
}

// The preview's mesh from the model as read: `positions` and `index`
// (null: separate triangles). {positions, normals, index, welded (new
// vertices; else the model's), lod: {triangles: [before, after], error} or
// null}.
export function previewMesh({ simplifier, encoder }, positions, index) {
  const welded = !index;
  if (welded) ({ positions, index } = weldTriangles(simplifier, positions));
  const normals = vertexNormals(positions, 3, 0, positions.length / 3, index);
  const before = index.length / 3;
  const simplified = simplifyTriangles(simplifier, index, positions);
  if (simplified) index = simplified.index;
  orderForVertexCache(encoder, index);
  const lod = simplified ? { triangles: [before, index.length / 3], error: simplified.error } : null;
  return { positions, normals, index, welded, lod };
}
