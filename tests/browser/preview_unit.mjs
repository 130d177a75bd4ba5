// The viewer's field sampling (client/web/public/field_sampling.js) in Node, without
// a browser: the surface point and the surface parameters at a sheet point,
// interpolated over the field's lattice as the shader does. And the
// placement's model frame (footprint.js), kept per model between moves, the
// exact result's vertex normals (vertex_normals.js) against three.js's, and
// the preview's mesh (preview_mesh.js, meshoptimizer's JS build as the
// worker runs it): reordered for the vertex cache, simplified, welded. And
// the undo history's steps (edit_history.js).
import assert from 'node:assert/strict';
// The client's own three.js (the module its files import as 'three').
import * as THREE from '../../client/web/node_modules/three/build/three.module.js';
import {
  footprint,
  mergedGeometry,
  placementFrame,
  positionsOf,
  readModel,
} from '../../client/web/public/footprint.js';
import { sampleField, sampleParams } from '../../client/web/public/field_sampling.js';
import { MeshoptEncoder } from '../../client/web/node_modules/meshoptimizer/meshopt_encoder.js';
import { MeshoptSimplifier } from '../../client/web/node_modules/meshoptimizer/meshopt_simplifier.js';
import {
  kPreviewError,
  kPreviewMinTriangles,
  orderForVertexCache,
  previewMesh,
  simplifyTriangles,
  weldTriangles,
} from '../../client/web/public/preview_mesh.js';
import { computeNormals } from '../../client/web/public/vertex_normals.js';
import { EditHistory } from '../../client/web/public/edit_history.js';

// A 3 x 3 lattice over [0, 2] x [0, 2] whose points are (a, b, a b) and whose
// parameters are (a / 2, b / 2 + a / 10): bilinear in each cell.
const n = 3;
const positions = [],
  normals = [],
  params = [],
  onSheet = [];
for (let j = 0; j < n; ++j) {
  for (let i = 0; i < n; ++i) {
    positions.push([i, j, i * j]);
    normals.push([0, 0, 1]);
    params.push([i / 2, j / 2 + i / 10]);
    onSheet.push(1);
  }
}
const field = {
  n,
  bounds: [
    [0, 0],
    [2, 2],
  ],
  positions,
  normals,
  params,
  on_sheet: onSheet,
};

let checks = 0;
const near = (a, b, what) => {
  assert.ok(Math.abs(a - b) < 1e-12, `${what}: ${a} against ${b}`);
  ++checks;
};
// At lattice points: the lattice's own values.
for (let j = 0; j < n; ++j) {
  for (let i = 0; i < n; ++i) {
    const [u, v] = sampleParams(field, i, j);
    near(u, i / 2, `u at (${i}, ${j})`);
    near(v, j / 2 + i / 10, `v at (${i}, ${j})`);
    const { p, on } = sampleField(field, i, j);
    near(p[2], i * j, `z at (${i}, ${j})`);
    assert.ok(on);
  }
}
// Inside a cell: bilinear, as the surface point is.
for (const [a, b] of [
  [0.25, 0.75],
  [1.5, 1.2],
  [1.9, 0.1],
]) {
  const [u, v] = sampleParams(field, a, b);
  near(u, a / 2, `u at (${a}, ${b})`);
  near(v, b / 2 + a / 10, `v at (${a}, ${b})`);
  near(sampleField(field, a, b).p[2], a * b, `z at (${a}, ${b})`);
}
// A field without parameters (version 1) has none to give.
assert.equal(sampleParams({ ...field, params: undefined }, 1, 1), null);

// The model's frame: the box's middle in (a, b), its bottom, middle or top
// along up; the same object for the same model, up and anchor, a new one
// when either changes.
const model = new Float32Array([0, 0, 0, 1, 2, 3, -1, 0, 1]);
const bottom = placementFrame(model, '+z', 'bottom');
assert.deepEqual(bottom.centre, [0, 1]);
near(bottom.h0, 0, 'the bottom along +z');
assert.equal(placementFrame(model, '+z', 'bottom'), bottom);
near(placementFrame(model, '+z', 'top').h0, 3, 'the top along +z');
near(placementFrame(model, '+z', 'center').h0, 1.5, 'the middle along +z');
near(placementFrame(model, '+y', 'top').h0, 2, 'the top along +y');
assert.notEqual(placementFrame(model, '+z', 'bottom'), bottom, 'asked again after others: made again');
near(placementFrame(new Float32Array([0, 0, 5, 1, 1, 7]), '+z', 'bottom').h0, 5, 'another model');

// Vertex normals of a bumpy 20 x 20 grid, as three.js computes them: from
// Float32 positions, and from quantized ones as the exact result's GLB has
// them (normalized Int16, interleaved four to a vertex).
const side = 20;
const grid = [],
  index = [];
for (let j = 0; j < side; ++j) {
  for (let i = 0; i < side; ++i) grid.push(i / side, j / side, 0.1 * Math.sin(i) * Math.cos(0.7 * j));
}
for (let j = 0; j + 1 < side; ++j) {
  for (let i = 0; i + 1 < side; ++i) {
    const a = i + side * j;
    index.push(a, a + 1, a + side + 1, a, a + side + 1, a + side);
  }
}
const reference = new THREE.BufferGeometry();
reference.setAttribute('position', new THREE.Float32BufferAttribute(grid, 3));
reference.setIndex(index);
reference.computeVertexNormals();
const want = reference.getAttribute('normal');
const sameNormals = (geometry, what) => {
  const got = geometry.getAttribute('normal');
  assert.equal(got.count, want.count, what);
  let worst = 0;
  for (let k = 0; k < want.count; ++k) {
    worst = Math.max(
      worst,
      Math.abs(got.getX(k) - want.getX(k)),
      Math.abs(got.getY(k) - want.getY(k)),
      Math.abs(got.getZ(k) - want.getZ(k)),
    );
  }
  assert.ok(worst < 1e-6, `${what}: off by ${worst}`);
  ++checks;
};
const plain = new THREE.BufferGeometry();
plain.setAttribute('position', new THREE.Float32BufferAttribute(grid, 3));
plain.setIndex(index);
computeNormals(plain);
sameNormals(plain, 'Float32 positions');
// Quantized to [-32767, 32767] over the grid's box, one scale for x, y and z.
const quantized = new Int16Array(4 * side * side);
for (let v = 0; v < side * side; ++v) {
  for (let c = 0; c < 3; ++c) quantized[4 * v + c] = Math.round(grid[3 * v + c] * 32767);
}
const packed = new THREE.BufferGeometry();
packed.setAttribute(
  'position',
  new THREE.InterleavedBufferAttribute(new THREE.InterleavedBuffer(quantized, 4), 3, 0, true),
);
packed.setIndex(index);
computeNormals(packed);
// Against three.js's on the same quantized positions.
const packedReference = packed.clone();
packedReference.deleteAttribute('normal');
packedReference.computeVertexNormals();
const quantizedWant = packedReference.getAttribute('normal');
let worst = 0;
for (let k = 0; k < quantizedWant.count; ++k) {
  worst = Math.max(worst, Math.abs(packed.getAttribute('normal').getZ(k) - quantizedWant.getZ(k)));
}
assert.ok(worst < 1e-6, `quantized interleaved positions: off by ${worst}`);
++checks;

// The grid's triangles shuffled (as a scanned model lists them), then
// reordered: the same triangles with the same winding, in an order that
// misses a 16-entry FIFO cache far less.
const shuffled = [];
for (let t = 0; t < index.length; t += 3) shuffled.push([index[t], index[t + 1], index[t + 2]]);
let seed = 12345;
const random = () => (seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648;
for (let k = shuffled.length - 1; k > 0; --k) {
  const j = Math.floor(random() * (k + 1));
  [shuffled[k], shuffled[j]] = [shuffled[j], shuffled[k]];
}
const missRatio = (idx) => {
  const fifo = [],
    cached = new Set();
  let misses = 0;
  for (const v of idx) {
    if (cached.has(v)) continue;
    ++misses;
    fifo.push(v);
    cached.add(v);
    if (fifo.length > 16) cached.delete(fifo.shift());
  }
  return misses / (idx.length / 3);
};
const canonical = (idx) => {
  const tris = [];
  for (let t = 0; t < idx.length; t += 3) {
    const tri = [idx[t], idx[t + 1], idx[t + 2]];
    const k = tri.indexOf(Math.min(...tri)); // rotated to its smallest vertex: winding kept
    tris.push([tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]].join());
  }
  return tris.sort();
};
await Promise.all([MeshoptEncoder.ready, MeshoptSimplifier.ready]);
const meshopt = { encoder: MeshoptEncoder, simplifier: MeshoptSimplifier };
{
  const before = shuffled.flat();
  const reordered = Uint32Array.from(before);
  orderForVertexCache(MeshoptEncoder, reordered);
  const after = Array.from(reordered);
  assert.deepEqual(canonical(after), canonical(before), 'the same triangles, the same winding');
  assert.ok(
    missRatio(after) < 0.5 * missRatio(before),
    `cache misses per triangle ${missRatio(before).toFixed(2)} -> ${missRatio(after).toFixed(2)}`,
  );
  checks += 2;
}

// The preview's triangles simplified: a waved relief, the cells of a 180 x
// 180 grid within a disk (50,000 triangles or so), keeps a quarter of them,
// on its own vertices, within the error asked; every vertex of its border
// stays (the outline the sheet shows), and so its footprint (the area
// projected on the plane); no triangle turns over (the signed and unsigned
// projected areas agree).
{
  const side = 181,
    vertices = [],
    triangles = [];
  for (let j = 0; j < side; ++j) {
    for (let i = 0; i < side; ++i) {
      const x = (10 * i) / (side - 1),
        y = (10 * j) / (side - 1);
      vertices.push(x, y, 0.2 + 0.1 * Math.sin(2 * x) * Math.cos(3 * y));
    }
  }
  const inDisk = (v) => (vertices[3 * v] - 5) ** 2 + (vertices[3 * v + 1] - 5) ** 2 <= 25;
  for (let j = 0; j + 1 < side; ++j) {
    for (let i = 0; i + 1 < side; ++i) {
      const a = i + side * j;
      if (![a, a + 1, a + side, a + side + 1].every(inDisk)) continue;
      triangles.push(a, a + 1, a + side + 1, a, a + side + 1, a + side);
    }
  }
  const positions = new Float32Array(vertices);
  const projected = (idx) => {
    let signed = 0,
      unsigned = 0;
    for (let t = 0; t < idx.length; t += 3) {
      const [p, q, r] = [idx[t], idx[t + 1], idx[t + 2]].map((v) => [vertices[3 * v], vertices[3 * v + 1]]);
      const area = ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / 2;
      signed += area;
      unsigned += Math.abs(area);
    }
    return { signed, unsigned };
  };
  // The vertices on the border: those of edges with one triangle.
  const borderOf = (idx) => {
    const edges = new Map();
    for (let t = 0; t < idx.length; t += 3) {
      for (let k = 0; k < 3; ++k) {
        const a = idx[t + k],
          b = idx[t + ((k + 1) % 3)];
        const key = `${Math.min(a, b)},${Math.max(a, b)}`;
        edges.set(key, (edges.get(key) || 0) + 1);
      }
    }
    const out = new Set();
    for (const [key, count] of edges) if (count === 1) for (const v of key.split(',')) out.add(Number(v));
    return [...out].sort((a, b) => a - b);
  };
  const before = projected(triangles);
  const lod = simplifyTriangles(MeshoptSimplifier, Uint32Array.from(triangles), positions);
  assert.ok(lod, `a relief of ${triangles.length / 3} triangles is simplified`);
  const kept = Array.from(lod.index);
  assert.ok(
    kept.length / 3 <= 0.25 * (triangles.length / 3) + 1,
    `a quarter of the triangles or fewer (${kept.length / 3} of ${triangles.length / 3})`,
  );
  assert.ok(lod.error <= kPreviewError, `within the error asked (${lod.error})`);
  assert.ok(
    kept.every((v) => Number.isInteger(v) && v >= 0 && v < side * side),
    "on the model's own vertices",
  );
  const after = projected(kept);
  assert.deepEqual(borderOf(kept), borderOf(triangles), 'every border vertex stays');
  assert.ok(
    Math.abs(after.signed - before.signed) < 1e-9 * before.signed,
    `the footprint stays (projected area ${after.signed} against ${before.signed})`,
  );
  assert.ok(
    Math.abs(after.unsigned - after.signed) < 1e-9 * after.signed,
    `no triangle turns over (${after.unsigned} against ${after.signed})`,
  );
  checks += 7;
  // The whole mesh as the worker makes it: the same simplification, the
  // vertices and their normals as they were (an index was given).
  const mesh = previewMesh(meshopt, positions, Uint32Array.from(triangles));
  assert.deepEqual(
    mesh.lod,
    { triangles: [triangles.length / 3, kept.length / 3], error: lod.error },
    'the counts and error reported',
  );
  assert.deepEqual(canonical(Array.from(mesh.index)), canonical(kept), 'its triangles, reordered');
  assert.ok(mesh.positions === positions && !mesh.welded, 'the vertices kept');
  // Their normals, made by the worker over every triangle (before the
  // simplification), as three.js computes them.
  const whole = new THREE.BufferGeometry();
  whole.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  whole.setIndex(triangles);
  whole.computeVertexNormals();
  const wholeNormals = whole.getAttribute('normal').array;
  let off = 0;
  for (let k = 0; k < wholeNormals.length; ++k) off = Math.max(off, Math.abs(mesh.normals[k] - wholeNormals[k]));
  assert.ok(
    mesh.normals.length === wholeNormals.length && off < 1e-6,
    `the worker's normals are the whole model's (off by ${off})`,
  );
  checks += 4;
  // A small model is drawn whole.
  const small = Uint32Array.from(triangles.slice(0, 3 * (kPreviewMinTriangles - 1)));
  assert.equal(simplifyTriangles(MeshoptSimplifier, small, positions), null, 'fewer than 20,000 triangles: left whole');
  assert.equal(previewMesh(meshopt, positions, small).index.length, small.length, 'every triangle drawn');
  checks += 2;
}

// Separate triangles welded: the label sample (OBJ, which three.js reads as
// separate triangles) gets an index over its distinct positions, as many as
// the file's vertices, every triangle's corners where they were (winding
// kept).
{
  const { readFileSync } = await import('node:fs');
  const text = readFileSync(new URL('../../client/web/samples/label.obj', import.meta.url), 'utf8');
  const fileVertices = text.split('\n').filter((l) => l.startsWith('v ')).length;
  const read = await readModel('label.obj', new TextEncoder().encode(text).buffer);
  assert.equal(read.geometry.index, null, 'three.js reads an OBJ as separate triangles');
  const separate = read.geometry.getAttribute('position').array;
  const welded = weldTriangles(MeshoptSimplifier, separate);
  assert.equal(welded.index.length, separate.length / 3, 'the same triangles');
  assert.equal(
    welded.positions.length / 3,
    fileVertices,
    `one vertex per distinct position (${welded.positions.length / 3}, the file has ${fileVertices})`,
  );
  for (let k = 0; k < welded.index.length; ++k) {
    for (let c = 0; c < 3; ++c) {
      if (welded.positions[3 * welded.index[k] + c] !== separate[3 * k + c]) assert.fail(`corner ${k} moved`);
    }
  }
  // The worker's mesh of separate triangles: welded, with smooth normals
  // over the welded vertices (as three.js computes them for the welded mesh).
  const mesh = previewMesh(meshopt, separate, null);
  assert.ok(mesh.welded, 'the worker welds separate triangles');
  assert.deepEqual(Array.from(mesh.positions), Array.from(welded.positions), 'to the same vertices');
  const smooth = new THREE.BufferGeometry();
  smooth.setAttribute('position', new THREE.BufferAttribute(welded.positions, 3));
  smooth.setIndex(Array.from(welded.index));
  smooth.computeVertexNormals();
  const want = smooth.getAttribute('normal').array;
  let off = 0;
  for (let k = 0; k < want.length; ++k) off = Math.max(off, Math.abs(mesh.normals[k] - want[k]));
  assert.ok(
    mesh.normals.length === want.length && off < 1e-6,
    `smooth normals over the welded vertices (off by ${off})`,
  );
  checks += 7;
}

// The footprint's hull, points inside the extremes' polygon left out before
// the sort, against the same monotone chain over every point: random points
// in a disk, a grid (collinear points and ties), separate triangles' corners
// (every point several times), a line, one point.
{
  const fullHull = (pairs) => {
    const pts = [...pairs].sort((p, q) => p[0] - q[0] || p[1] - q[1]);
    const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    const lower = [],
      upper = [];
    for (const p of pts) {
      while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop();
      lower.push(p);
    }
    for (let k = pts.length - 1; k >= 0; --k) {
      while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], pts[k]) <= 0) upper.pop();
      upper.push(pts[k]);
    }
    return lower.slice(0, -1).concat(upper.slice(0, -1));
  };
  let seed = 7;
  const random = () => (seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648;
  const sets = {
    disk: Array.from({ length: 5000 }, () => {
      const r = 3 * Math.sqrt(random()),
        t = 2 * Math.PI * random();
      return [1 + r * Math.cos(t), -2 + r * Math.sin(t), random()];
    }),
    grid: Array.from({ length: 41 * 41 }, (_, k) => [k % 41, Math.floor(k / 41), 0]),
    corners: Array.from({ length: 3 * 600 }, (_, k) => {
      const v = (k * 7) % 200; // 200 vertices of a 20 x 10 grid, each several times
      return [v % 20, Math.floor(v / 20) * 0.5, 1];
    }),
    line: Array.from({ length: 50 }, (_, k) => [k, 2 * k, 0]),
    point: [
      [3, 4, 5],
      [3, 4, 5],
    ],
  };
  for (const [name, points] of Object.entries(sets)) {
    const got = footprint(points.flat(), '+z');
    assert.deepEqual(got.hull, fullHull(points.map(([x, y]) => [x, y])), `the ${name}'s hull`);
    const mid = (c) => (Math.min(...points.map((p) => p[c])) + Math.max(...points.map((p) => p[c]))) / 2;
    assert.deepEqual(got.centre, [mid(0), mid(1)], `the ${name}'s centre: its bounds' middle`);
    checks += 2;
  }
  assert.equal(footprint(sets.grid.flat(), '+z').hull.length, 4, "a grid's hull is its four corners");
  ++checks;
}

// A model's positions in world space: two meshes, one under a turned,
// scaled and moved group, as three.js's applyMatrix4 puts them.
{
  const box = new THREE.Mesh(new THREE.BoxGeometry(1, 2, 3));
  const ball = new THREE.Mesh(new THREE.SphereGeometry(0.5, 6, 4));
  const group = new THREE.Group();
  group.position.set(1, -2, 3);
  group.rotation.set(0.3, -0.2, 0.9);
  group.scale.set(2, 0.5, 1.5);
  ball.position.set(0, 4, 0);
  group.add(ball);
  const scene = new THREE.Group();
  scene.add(box, group);
  const got = positionsOf(scene);
  const want = [];
  scene.updateMatrixWorld(true);
  for (const mesh of [box, ball]) {
    const p = mesh.geometry.getAttribute('position');
    for (let k = 0; k < p.count; ++k) {
      const v = new THREE.Vector3().fromBufferAttribute(p, k).applyMatrix4(mesh.matrixWorld);
      want.push(v.x, v.y, v.z);
    }
  }
  assert.equal(got.length, want.length, 'every vertex of both meshes');
  let off = 0;
  for (let k = 0; k < want.length; ++k) off = Math.max(off, Math.abs(got[k] - want[k]));
  assert.ok(off < 1e-12, `positions in world space as three.js puts them (off by ${off})`);
  checks += 2;
}
// A model whose meshes are some indexed and some not (a glTF may mix
// them), with a point cloud and a line beside them (which the server
// ignores): its footprint counts the triangle meshes' vertices only, and
// its preview has every triangle, as separate triangles the worker welds.
// Where every mesh is indexed, the merged geometry is too.
{
  const box = new THREE.Mesh(new THREE.BoxGeometry(1, 2, 3));
  const ball = new THREE.Mesh(new THREE.SphereGeometry(0.5, 6, 4).toNonIndexed());
  ball.position.set(0, 4, 0);
  const cloud = new THREE.Points(
    new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute([9, 9, 9, -9, -9, -9], 3)),
  );
  const line = new THREE.Line(
    new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute([20, 0, 0, -20, 0, 0], 3)),
  );
  const scene = new THREE.Group();
  scene.add(box, ball, cloud, line);
  const boxCount = box.geometry.getAttribute('position').count;
  const ballCount = ball.geometry.getAttribute('position').count;
  assert.equal(
    positionsOf(scene).length,
    3 * (boxCount + ballCount),
    "the triangle meshes' vertices, no points or lines",
  );
  const merged = mergedGeometry(scene);
  assert.ok(merged, 'indexed and separate triangles merge');
  assert.equal(merged.index, null, 'as separate triangles');
  const triangles = box.geometry.index.count / 3 + ballCount / 3;
  assert.equal(merged.getAttribute('position').count, 3 * triangles, 'every triangle of both');
  const mesh = previewMesh(meshopt, merged.getAttribute('position').array, null);
  assert.ok(mesh.welded && mesh.index.length === 3 * triangles, 'welded by the worker, every triangle kept');
  const sphere = new THREE.Mesh(new THREE.SphereGeometry(0.5, 6, 4));
  const both = mergedGeometry(new THREE.Group().add(new THREE.Mesh(box.geometry), sphere));
  assert.ok(both.index, 'indexed meshes merge indexed');
  checks += 5;
}
{
  // Undo and redo: steps of a spec and a placement; the sheet's id is
  // derived (no step of its own), steps are copies, a new edit drops what
  // was undone, and a reset forgets everything.
  const h = new EditHistory({ limit: 3, derived: ['placementSheet'] });
  const step = (x, sheet = 's0') => ({ spec: { p: [0, 0, x] }, placement: { center: [x, 0] }, placementSheet: sheet });
  assert.equal(h.record(step(0)), false, 'the first state is the start, not a step');
  assert.ok(!h.canUndo() && !h.canRedo(), 'nothing to undo at the start');
  assert.equal(h.record(step(0, 's1')), false, 'the same state on another sheet id is no step');
  assert.equal(h.currentStep().placementSheet, 's1', 'but takes the new id');
  const given = step(1);
  assert.equal(h.record(given), true, 'an edit is a step');
  given.spec.p[2] = 99;
  assert.equal(h.currentStep().spec.p[2], 1, 'a step is a copy of what was given');
  h.record(step(2));
  const back = h.undo();
  assert.equal(back.placement.center[0], 1, 'undo gives the step before');
  back.placement.center[0] = -5;
  assert.equal(h.currentStep().placement.center[0], 1, 'and a copy of it');
  assert.equal(h.undo().placement.center[0], 0, 'undo again: the start');
  assert.equal(h.undo(), null, 'nothing before the start');
  assert.equal(h.redo().placement.center[0], 1, 'redo');
  assert.ok(h.canRedo(), 'one more to redo');
  h.record(step(7));
  assert.ok(!h.canRedo(), 'a new edit drops what was undone');
  assert.equal(h.undo().placement.center[0], 1, 'and undoes to where it branched');
  for (let x = 10; x < 16; ++x) h.record(step(x));
  let undone = 0;
  while (h.undo()) ++undone;
  assert.equal(undone, 3, 'at most `limit` steps back');
  h.reset(step(20));
  assert.ok(!h.canUndo() && !h.canRedo() && h.currentStep().placement.center[0] === 20, 'reset: a new start');
  checks += 20;
}
console.log(`preview_unit: ${checks + 1} checks passed`);
