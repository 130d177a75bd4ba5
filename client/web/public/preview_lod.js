// The preview's triangles, fewer: while a person drags, the preview draws the
// model with a quarter of its triangles, simplified by meshoptimizer within
// 5e-4 of the model's size (its error measure, relative to the model's
// extent; a scanned model may stop short of the quarter there). The exact
// result replaces it on release, with every triangle.
//
// Why: the preview's vertex shader (the field's fetches and the normal's
// turn) costs about twice the exact result's per vertex, and with software
// WebGL a large model's frame is mostly that stage (a million triangles:
// ~5.7 frames a second orbiting the exact result, ~3.4 dragging the
// preview; BENCHMARKS.md). Simplification keeps a subset of the vertices
// where they are, with their normals, so every vertex drawn is still placed
// exactly; and it keeps open models' borders, the outline the sheet shows.
// Models under 20,000 triangles are drawn whole. Where meshoptimizer is not
// there, nothing changes.
import * as THREE from 'three';
import { meshopt } from './meshopt.js';

export const kPreviewShare = 0.25;         // of the triangles
export const kPreviewError = 5e-4;         // of the model's extent
export const kPreviewMinTriangles = 20000;  // below: drawn whole

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
