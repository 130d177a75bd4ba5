// The preview's own mesh, made cheap to bend on the GPU while a person drags.
//
// Welded: a model read as separate triangles (STL, OBJ: three.js's loaders
// give every triangle its own corners) gets an index over its distinct
// positions, as the server welds it, so that the vertex cache shares the
// corners (a third of the vertex work) and the normals are the exact
// result's (smooth over the welded vertices, where they were flat per
// triangle).
//
// Fewer triangles: the preview draws the model with a quarter of its
// triangles, simplified by meshoptimizer within 5e-4 of the model's size
// (its error measure, relative to the model's extent; a scanned model may
// stop short of the quarter there). The exact result replaces it on
// release, with every triangle. The preview's vertex shader (the field's
// fetches and the normal's turn) costs about twice the exact result's per
// vertex, and with software WebGL a large model's frame is mostly that
// stage (a million triangles: ~5.7 frames a second orbiting the exact
// result, ~3.4 dragging the preview; BENCHMARKS.md). Simplification keeps
// a subset of the vertices where they are, with their normals, so every
// vertex drawn is still placed exactly; and it keeps open models' borders,
// the outline the sheet shows. Models under 20,000 triangles are drawn
// whole.
//
// Where meshoptimizer is not there, the mesh is left as it is.
import * as THREE from 'three';
import { meshopt } from './meshopt.js';

export const kPreviewShare = 0.25;         // of the triangles
export const kPreviewError = 5e-4;         // of the model's extent
export const kPreviewMinTriangles = 20000;  // below: drawn whole

// `geometry` (positions, no index) welded: a new geometry whose index runs
// over its distinct positions (meshoptimizer's position remap: bitwise
// equal positions, as the server's readers weld), with normals computed
// over them. The same geometry where it has an index already, or without
// meshoptimizer.
export async function weldForPreview(geometry) {
  const position = geometry && geometry.getAttribute('position');
  if (!position || geometry.index || position.count < 3 || position.count % 3 !== 0) return geometry;
  const simplifier = await meshopt('simplifier');
  if (!simplifier) return geometry;
  const positions = packedPositions(position);
  const indices = Uint32Array.from(simplifier.generatePositionRemap(positions, 3));
  // Renumbered to the distinct positions used (remap: corner -> vertex).
  const [remap, count] = simplifier.compactMesh(indices);
  const kept = new Float32Array(3 * count);
  for (let v = 0; v < remap.length; ++v) {
    if (remap[v] !== 0xffffffff) kept.set(positions.subarray(3 * v, 3 * v + 3), 3 * remap[v]);
  }
  const welded = new THREE.BufferGeometry();
  welded.setAttribute('position', new THREE.BufferAttribute(kept, 3));
  welded.setIndex(new THREE.BufferAttribute(count < 65536 ? Uint16Array.from(indices) : indices, 1));
  welded.computeVertexNormals();
  return welded;
}

// Replaces `geometry`'s index (an indexed triangle list) by the simplified
// one, in place: {triangles: [before, after], error (relative to the
// extent)}, or null where it was left whole (no index, few triangles, no
// meshoptimizer).
export async function simplifyForPreview(geometry) {
  const index = geometry && geometry.index;
  const position = geometry && geometry.getAttribute('position');
  if (!index || !position || index.count % 3 !== 0 || index.count / 3 < kPreviewMinTriangles) return null;
  const simplifier = await meshopt('simplifier');
  if (!simplifier) return null;
  const indices = Uint32Array.from(index.array);
  const positions = packedPositions(position);
  const target = 3 * Math.floor((kPreviewShare * indices.length) / 3);
  const [kept, error] = simplifier.simplify(indices, positions, 3, target, kPreviewError, ['LockBorder']);
  // In the old index's type (Uint16 for models under 65,536 vertices).
  const array = index.array instanceof Uint16Array ? Uint16Array.from(kept) : kept;
  geometry.setIndex(new THREE.BufferAttribute(array, 1));
  return { triangles: [indices.length / 3, kept.length / 3], error };
}

// x, y, z per vertex in a Float32Array of their own (an attribute may be
// interleaved, or of another type).
function packedPositions(position) {
  if (position.array instanceof Float32Array && !position.isInterleavedBufferAttribute &&
      position.itemSize === 3) {
    return position.array;
  }
  const out = new Float32Array(3 * position.count);
  for (let v = 0; v < position.count; ++v) {
    out[3 * v] = position.getX(v);
    out[3 * v + 1] = position.getY(v);
    out[3 * v + 2] = position.getZ(v);
  }
  return out;
}
