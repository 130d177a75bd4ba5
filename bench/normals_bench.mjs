// The page's vertex normals (client/web/public/normals.js) against three.js's
// BufferGeometry.computeVertexNormals on the same mesh: a wavy grid of about
// a million triangles in row order, as the exact result's meshopt GLB holds
// it (16-bit positions, interleaved at a stride of 4) and as plain float32
// for three.js. Medians of the runs, alternating.
//
// Usage: node bench/normals_bench.mjs [SIDE] [RUNS]   (defaults 708, 9)
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const web = path.join(here, '..', 'client', 'web');
const { vertexNormals } = await import(pathToFileURL(path.join(web, 'public', 'normals.js')));
const THREE = await import(pathToFileURL(path.join(web, 'node_modules', 'three', 'build', 'three.module.js')));

const side = Number(process.argv[2] ?? 708);
const runs = Number(process.argv[3] ?? 9);
const n = side * side;
const quantized = new Int16Array(4 * n);
const floats = new Float32Array(3 * n);
for (let j = 0; j < side; ++j) {
  for (let i = 0; i < side; ++i) {
    const v = i + side * j;
    const p = [i * 40, j * 40, Math.round(3000 * Math.sin(i * 0.1) * Math.cos(j * 0.1))];
    for (let c = 0; c < 3; ++c) {
      quantized[4 * v + c] = p[c];
      floats[3 * v + c] = p[c];
    }
  }
}
const index = new Uint32Array(6 * (side - 1) * (side - 1));
let t = 0;
for (let j = 0; j + 1 < side; ++j) {
  for (let i = 0; i + 1 < side; ++i) {
    const a = i + side * j;
    index.set([a, a + 1, a + side + 1, a, a + side + 1, a + side], t);
    t += 6;
  }
}
const geometry = new THREE.BufferGeometry();
geometry.setAttribute('position', new THREE.BufferAttribute(floats, 3));
geometry.setIndex(new THREE.BufferAttribute(index, 1));

const times = { ours: [], three: [] };
let worst = 0;
for (let r = 0; r < runs; ++r) {
  let start = performance.now();
  const ours = vertexNormals(quantized, 4, 0, n, index);
  times.ours.push(performance.now() - start);
  start = performance.now();
  geometry.computeVertexNormals();
  times.three.push(performance.now() - start);
  const theirs = geometry.getAttribute('normal').array;
  for (let k = 0; k < ours.length; ++k) worst = Math.max(worst, Math.abs(ours[k] - theirs[k]));
}
const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];
const ours = median(times.ours),
  three = median(times.three);
console.log(`${index.length / 3} triangles, ${n} vertices, ${runs} runs (medians)`);
console.log(`normals.js (16-bit, stride 4): ${ours.toFixed(1)} ms`);
console.log(`three.js computeVertexNormals (float32): ${three.toFixed(1)} ms`);
console.log(`ratio ours / three.js: ${(ours / three).toFixed(2)}; largest difference ${worst.toExponential(1)}`);
