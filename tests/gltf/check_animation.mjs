// Checks an animation GLB of POST /v1/animate against its uncompressed twin
// and against single frames from POST /v1/deform:
//  - the twin has the same document but for the buffers and buffer views;
//  - three.js's MeshoptDecoder decodes every compressed view of the meshopt
//    file to the twin's bytes, byte for byte;
//  - morph target k applied to the base (through the node's dequantizing
//    transform) is frame k's positions to within half a quantization step;
//  - the weights' animation has frame k at time k / fps, weight k one-hot.
// Usage: node check_animation.mjs MESHOPT.glb PLAIN.glb FPS K FRAME_K.glb [K FRAME_K.glb ...]
// (each FRAME_K.glb a glb_plain answer of /v1/deform with "frame": K).
import { readFile } from 'node:fs/promises';
import { MeshoptDecoder } from '../../client/web/node_modules/three/examples/jsm/libs/meshopt_decoder.module.js';

function parseGlb(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error('not a GLB');
  const jsonLength = view.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jsonLength)));
  const binStart = 20 + jsonLength + 8;
  const bin = bytes.subarray(binStart, binStart + view.getUint32(20 + jsonLength, true));
  return { json, bin };
}

function viewBytes(glb, index) {
  const v = glb.json.bufferViews[index];
  return glb.bin.subarray(v.byteOffset ?? 0, (v.byteOffset ?? 0) + v.byteLength);
}

// An accessor's values as numbers (normalized integers left as integers).
function accessorValues(glb, index) {
  const a = glb.json.accessors[index];
  const comps = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 }[a.type];
  const out = new Float64Array(a.count * comps);
  if (a.bufferView === undefined) return { values: out, comps, accessor: a };
  const v = glb.json.bufferViews[a.bufferView];
  const size = { 5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4 }[a.componentType];
  const stride = v.byteStride ?? comps * size;
  const bytes = viewBytes(glb, a.bufferView);
  const dv = new DataView(bytes.buffer, bytes.byteOffset + (a.byteOffset ?? 0));
  const read = {
    5120: (o) => dv.getInt8(o),
    5121: (o) => dv.getUint8(o),
    5122: (o) => dv.getInt16(o, true),
    5123: (o) => dv.getUint16(o, true),
    5125: (o) => dv.getUint32(o, true),
    5126: (o) => dv.getFloat32(o, true),
  }[a.componentType];
  for (let i = 0; i < a.count; i++) for (let c = 0; c < comps; c++) out[i * comps + c] = read(i * stride + c * size);
  return { values: out, comps, accessor: a };
}

function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exit(1);
}

const [compressedPath, plainPath, fpsText, ...frameArgs] = process.argv.slice(2);
const compressed = parseGlb(new Uint8Array(await readFile(compressedPath)));
const plain = parseGlb(new Uint8Array(await readFile(plainPath)));

// 1. One document.
for (const key of ['accessors', 'meshes', 'nodes', 'animations', 'materials', 'scenes']) {
  if (JSON.stringify(compressed.json[key]) !== JSON.stringify(plain.json[key])) fail(`the twins differ in ${key}`);
}
if (!compressed.json.extensionsRequired.includes('EXT_meshopt_compression'))
  fail('the compressed file does not require EXT_meshopt_compression');
if (!plain.json.extensionsRequired.includes('KHR_mesh_quantization'))
  fail('the plain file does not require KHR_mesh_quantization');

// 2. Every compressed view decodes to the twin's bytes.
await MeshoptDecoder.ready;
let decoded = 0;
compressed.json.bufferViews.forEach((v, index) => {
  const ext = v.extensions?.EXT_meshopt_compression;
  if (!ext) return;
  const source = compressed.bin.subarray(ext.byteOffset ?? 0, (ext.byteOffset ?? 0) + ext.byteLength);
  const target = new Uint8Array(ext.count * ext.byteStride);
  MeshoptDecoder.decodeGltfBuffer(target, ext.count, ext.byteStride, source, ext.mode, ext.filter ?? 'NONE');
  const expected = viewBytes(plain, index);
  if (target.length !== expected.length) fail(`view ${index}: ${target.length} bytes, twin ${expected.length}`);
  for (let i = 0; i < target.length; i++) {
    if (target[i] !== expected[i]) fail(`view ${index} byte ${i} decodes to ${target[i]}, twin ${expected[i]}`);
  }
  decoded += 1;
});
if (decoded === 0) fail('no view is meshopt-compressed');

// 3. Morph target k on the base is frame k.
const node = plain.json.nodes[0];
const scale = node.scale[0];
const [tx, ty, tz] = node.translation;
const prim = plain.json.meshes[0].primitives[0];
const base = accessorValues(plain, prim.attributes.POSITION).values;
const frames = prim.targets.length;
const halfStep = (0.5 * scale) / 32767;
const shapes = [];
for (let i = 0; i < frameArgs.length; i += 2) {
  const k = Number(frameArgs[i]);
  const frame = parseGlb(new Uint8Array(await readFile(frameArgs[i + 1])));
  const positions = accessorValues(frame, frame.json.meshes[0].primitives[0].attributes.POSITION).values;
  const delta = accessorValues(plain, prim.targets[k].POSITION).values;
  if (positions.length !== base.length)
    fail(`frame ${k} has ${positions.length / 3} vertices, the animation ${base.length / 3}`);
  let worst = 0;
  for (let v = 0; v < base.length; v += 3) {
    const p = [0, 1, 2].map((c) => ((base[v + c] + delta[v + c]) / 32767) * scale + [tx, ty, tz][c]);
    for (let c = 0; c < 3; c++) worst = Math.max(worst, Math.abs(p[c] - positions[v + c]));
  }
  // Float32 rounding of the frame and of the transform on top of the half step.
  if (worst > halfStep * 1.01 + 1e-6 * scale)
    fail(`target ${k} on the base is ${worst} from frame ${k} (half a step: ${halfStep})`);
  console.log(
    `target ${k} on the base: within ${worst.toExponential(3)} of frame ${k} (half a step ${halfStep.toExponential(3)})`,
  );
  shapes.push(positions);
}
if (shapes.length >= 2) {
  let apart = 0;
  for (let v = 0; v < shapes[0].length; v++)
    apart = Math.max(apart, Math.abs(shapes[0][v] - shapes[shapes.length - 1][v]));
  if (apart < 100 * halfStep)
    fail(`the frames checked hardly differ (${apart}): the check would not see a wrong target`);
}

// 4. The weights' animation.
const fps = Number(fpsText);
const anim = plain.json.animations[0];
const sampler = anim.samplers[anim.channels[0].sampler];
if (anim.channels[0].target.path !== 'weights') fail('the animation does not drive the weights');
const times = accessorValues(plain, sampler.input).values;
const weights = accessorValues(plain, sampler.output).values;
for (let k = 0; k < frames; k++) {
  if (Math.abs(times[k] - k / fps) > 1e-6) fail(`frame ${k} at time ${times[k]}, expected ${k / fps}`);
  for (let j = 0; j < frames; j++) {
    const w = weights[k * frames + j];
    if (w !== (j === k ? 255 : 0)) fail(`weight ${j} at frame ${k} is ${w}`);
  }
}
console.log(
  `animation: ${frames} frames, ${decoded} views decoded by three.js's MeshoptDecoder ` +
    `to the twin's bytes (${compressed.bin.length} bytes against ${plain.bin.length})`,
);
