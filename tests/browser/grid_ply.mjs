// A height field as a binary PLY: an n x n grid of vertices over
// [x0, x0 + size] x [y0, y0 + size] at height(x, y), two triangles a cell.
// Shared by viewer_test.mjs (a Draco answer large enough to come in pieces)
// and bench/viewer_feel.mjs (a relief of a million triangles). gridStl: the
// same triangles as a binary STL (each with its own corners).
// Grid point (i, j): [x, y, height(x, y)].
function gridPoint(n, x0, y0, size, height) {
  return (i, j) => {
    const x = x0 + (size * i) / (n - 1),
      y = y0 + (size * j) / (n - 1);
    return [x, y, height(x, y)];
  };
}

export function gridPly(n, x0, y0, size, height) {
  const point = gridPoint(n, x0, y0, size, height);
  const verts = n * n,
    tris = 2 * (n - 1) * (n - 1);
  const header =
    `ply\nformat binary_little_endian 1.0\nelement vertex ${verts}\n` +
    'property float x\nproperty float y\nproperty float z\n' +
    `element face ${tris}\nproperty list uchar int vertex_indices\nend_header\n`;
  const body = Buffer.alloc(12 * verts + 13 * tris);
  let o = 0;
  for (let j = 0; j < n; ++j) {
    for (let i = 0; i < n; ++i) {
      for (const x of point(i, j)) {
        body.writeFloatLE(x, o);
        o += 4;
      }
    }
  }
  for (let j = 0; j + 1 < n; ++j) {
    for (let i = 0; i + 1 < n; ++i) {
      const a = i + n * j,
        b = a + 1,
        c = a + n + 1,
        d = a + n;
      for (const [p, q, r] of [
        [a, b, c],
        [a, c, d],
      ]) {
        body.writeUInt8(3, o);
        body.writeInt32LE(p, o + 1);
        body.writeInt32LE(q, o + 5);
        body.writeInt32LE(r, o + 9);
        o += 13;
      }
    }
  }
  return { bytes: Buffer.concat([Buffer.from(header), body]), vertices: verts, triangles: tris };
}

export function gridStl(n, x0, y0, size, height) {
  const point = gridPoint(n, x0, y0, size, height);
  const tris = 2 * (n - 1) * (n - 1);
  const body = Buffer.alloc(84 + 50 * tris);
  body.writeUInt32LE(tris, 80);
  let o = 84;
  for (let j = 0; j + 1 < n; ++j) {
    for (let i = 0; i + 1 < n; ++i) {
      const a = point(i, j),
        b = point(i + 1, j),
        c = point(i + 1, j + 1),
        d = point(i, j + 1);
      for (const corners of [
        [a, b, c],
        [a, c, d],
      ]) {
        o += 12; // the facet normal: zero, readers compute it
        for (const q of corners)
          for (const x of q) {
            body.writeFloatLE(x, o);
            o += 4;
          }
        o += 2;
      }
    }
  }
  return { bytes: body, triangles: tris };
}
