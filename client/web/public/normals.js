// Vertex normals of an indexed triangle mesh from plain typed arrays, with
// no imports: the preview's worker (preview_mesh.js) and the page
// (vertex_normals.js) both use it. Each vertex gets the sum of its
// triangles' (c - b) x (a - b), normalised, as three.js's
// BufferGeometry.computeVertexNormals gives them; a vertex of no triangle
// (or of degenerate ones only) gets zero.
//
// `array` holds vertex v's x, y, z at offset + stride * v (a plain or
// interleaved attribute's array, of any number type: a normalized integer
// attribute's common divisor scales every cross product alike and drops out
// when normalising); `count` vertices; `index` three vertices a triangle.
export function vertexNormals(array, stride, offset, count, index) {
  const a = array;
  const sum = new Float64Array(3 * count);
  for (let t = 0; t + 2 < index.length; t += 3) {
    const ia = index[t],
      ib = index[t + 1],
      ic = index[t + 2];
    const pa = offset + stride * ia,
      pb = offset + stride * ib,
      pc = offset + stride * ic;
    const bx = a[pb],
      by = a[pb + 1],
      bz = a[pb + 2];
    const cbx = a[pc] - bx,
      cby = a[pc + 1] - by,
      cbz = a[pc + 2] - bz;
    const abx = a[pa] - bx,
      aby = a[pa + 1] - by,
      abz = a[pa + 2] - bz;
    const nx = cby * abz - cbz * aby,
      ny = cbz * abx - cbx * abz,
      nz = cbx * aby - cby * abx;
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
  // The root of the sum of squares, not Math.hypot (which guards against
  // overflow at some 3x the cost here): the sums are doubles of float32 or
  // integer data, whose squares stay far inside double range.
  const normals = new Float32Array(3 * count);
  for (let v = 0; v < 3 * count; v += 3) {
    const x = sum[v],
      y = sum[v + 1],
      z = sum[v + 2];
    const len = Math.sqrt(x * x + y * y + z * z);
    const k = len > 0 ? 1 / len : 0;
    normals[v] = x * k;
    normals[v + 1] = y * k;
    normals[v + 2] = z * k;
  }
  return normals;
}
