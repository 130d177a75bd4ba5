// The live preview: the model bent on the GPU while a person drags, from the
// field of the sheet-to-surface map (GET /v1/surfaces/{id}/field). Each
// vertex is placed on the sheet exactly as the server places it (up axis,
// anchor, centre, rotation, scale: engine/placement.cpp), then a vertex
// shader samples the field: position = P(a, b) + h N(a, b), P and N
// interpolated bilinearly between lattice points (past the lattice, the
// border cell's map continues). Vertices whose cell has a lattice point off
// the sheet are tinted: that part would leave the sheet. Moving, scaling or
// rotating the footprint changes uniforms only; a new surface, two textures.
// On a whole cylinder, parts past the seam are bent a period away.
//
// previewPositions() (field_sampling.js) is the same computation on the CPU,
// for measuring the preview against the exact result.
import * as THREE from 'three';
import { computeNormals } from './vertex_normals.js';

const kVertexHead = /* glsl */ `
uniform sampler2D sdFieldP;  // xyz: surface point, w: 1 on the sheet
uniform sampler2D sdFieldN;  // xyz: unit normal
uniform vec2 sdLo;
uniform vec2 sdHi;
uniform float sdN;
uniform mat3 sdBasis;
uniform vec2 sdCentre;
uniform float sdH0;
uniform vec2 sdRotation;  // cos, sin
uniform float sdScale;
uniform vec2 sdTarget;
uniform vec2 sdPeriod;  // a sheet that repeats by this translation; (0, 0): none
uniform vec2 sdPeriodV;  // the same in v (a whole torus)
uniform float sdRotAngle;  // a sheet that repeats by this rotation (a whole cone); 0: none
uniform vec2 sdRotCentre;  // about this point (the apex)
uniform float sdRotStart;  // the seam's angle about it
varying float sdOff;
`;

const kVertexPlace = /* glsl */ `
vec3 sdQ = sdBasis * position;
vec2 sdQab = sdQ.xy - sdCentre;
vec2 sdAB = sdTarget + sdScale * vec2(sdRotation.x * sdQab.x - sdRotation.y * sdQab.y,
                                      sdRotation.y * sdQab.x + sdRotation.x * sdQab.y);
float sdH = sdScale * (sdQ.z - sdH0);
// The seams' rules are compiled in only for sheets that have them: a
// software renderer runs both sides of a branch for every vertex.
#ifdef SD_ROTATION
{  // past a cone's seam: the same point a turn of the sector away
  vec2 sdD = sdAB - sdRotCentre;
  float sdSpan = abs(sdRotAngle), sdGap = 6.283185307179586 - sdSpan;
  float sdPhi = sign(sdRotAngle) * (atan(sdD.y, sdD.x) - sdRotStart);
  sdPhi -= 6.283185307179586 * floor((sdPhi + 0.5 * sdGap) / 6.283185307179586);
  float sdR = -floor(sdPhi / sdSpan) * sdRotAngle;
  sdAB = sdRotCentre + mat2(cos(sdR), sin(sdR), -sin(sdR), cos(sdR)) * sdD;
}
#endif
#ifdef SD_PERIOD  // past the seam: the same point a period away
sdAB -= floor(dot(sdAB - sdLo, sdPeriod) / dot(sdPeriod, sdPeriod)) * sdPeriod;
#endif
#ifdef SD_PERIOD_V
sdAB -= floor(dot(sdAB - sdLo, sdPeriodV) / dot(sdPeriodV, sdPeriodV)) * sdPeriodV;
#endif
vec2 sdT = (sdAB - sdLo) / (sdHi - sdLo) * (sdN - 1.0);
vec2 sdI = clamp(floor(sdT), vec2(0.0), vec2(sdN - 2.0));
vec2 sdF = sdT - sdI;  // past the lattice, the border cell's map continues
ivec2 sdC = ivec2(sdI);
vec4 sdP00 = texelFetch(sdFieldP, sdC, 0);
vec4 sdP10 = texelFetch(sdFieldP, sdC + ivec2(1, 0), 0);
vec4 sdP01 = texelFetch(sdFieldP, sdC + ivec2(0, 1), 0);
vec4 sdP11 = texelFetch(sdFieldP, sdC + ivec2(1, 1), 0);
vec3 sdN00 = texelFetch(sdFieldN, sdC, 0).xyz;
vec3 sdN10 = texelFetch(sdFieldN, sdC + ivec2(1, 0), 0).xyz;
vec3 sdN01 = texelFetch(sdFieldN, sdC + ivec2(0, 1), 0).xyz;
vec3 sdN11 = texelFetch(sdFieldN, sdC + ivec2(1, 1), 0).xyz;
vec3 sdP = mix(mix(sdP00.xyz, sdP10.xyz, sdF.x), mix(sdP01.xyz, sdP11.xyz, sdF.x), sdF.y);
vec3 sdNrm = normalize(mix(mix(sdN00, sdN10, sdF.x), mix(sdN01, sdN11, sdF.x), sdF.y));
vec3 sdPa = normalize(mix(sdP10.xyz - sdP00.xyz, sdP11.xyz - sdP01.xyz, sdF.y));
vec3 sdPb = normalize(mix(sdP01.xyz - sdP00.xyz, sdP11.xyz - sdP10.xyz, sdF.x));
bool sdInside = all(greaterThanEqual(sdT, vec2(0.0))) && all(lessThanEqual(sdT, vec2(sdN - 1.0)));
sdOff = (sdInside && min(min(sdP00.w, sdP10.w), min(sdP01.w, sdP11.w)) > 0.5) ? 0.0 : 1.0;
// The model's normal turns with the sheet's frame (the map keeps lengths).
vec3 sdNq = sdBasis * normal;
vec2 sdNab = vec2(sdRotation.x * sdNq.x - sdRotation.y * sdNq.y, sdRotation.y * sdNq.x + sdRotation.x * sdNq.y);
vec3 objectNormal = normalize(sdNab.x * sdPa + sdNab.y * sdPb + sdNq.z * sdNrm);
vec3 sdTransformed = sdP + sdH * sdNrm;
`;

// The worker that makes preview meshes (preview_mesh_worker.js), started
// when first needed; false where it cannot run (then models are drawn as
// read).
let meshWorker = null;
let meshAsks = 0;
const meshReplies = new Map();
function previewMeshWorker() {
  if (meshWorker === null) {
    try {
      meshWorker = new Worker(new URL('./preview_mesh_worker.js', import.meta.url), { type: 'module' });
      meshWorker.onmessage = ({ data }) => {
        meshReplies.get(data.id)?.(data);
        meshReplies.delete(data.id);
      };
      meshWorker.onerror = () => {
        for (const reply of meshReplies.values()) reply({ error: 'the preview mesh worker failed' });
        meshReplies.clear();
        meshWorker.terminate();
        meshWorker = false;
      };
    } catch {
      meshWorker = false;
    }
  }
  return meshWorker || null;
}

// x, y, z per vertex in a Float32Array of their own (a copy: an attribute
// may be interleaved, or of another type).
function packedPositions(position) {
  if (position.array instanceof Float32Array && !position.isInterleavedBufferAttribute && position.itemSize === 3) {
    return position.array.slice(0, 3 * position.count);
  }
  const out = new Float32Array(3 * position.count);
  for (let v = 0; v < position.count; ++v) {
    out[3 * v] = position.getX(v);
    out[3 * v + 1] = position.getY(v);
    out[3 * v + 2] = position.getZ(v);
  }
  return out;
}

// {geometry, lod} for the preview of `geometry` (positions, normals, an
// index or none), made by the worker; null where it was not made.
async function previewMeshOf(geometry) {
  const position = geometry && geometry.getAttribute('position');
  if (!position || position.count < 3 || (!geometry.index && position.count % 3 !== 0)) return null;
  const worker = previewMeshWorker();
  if (!worker) return null;
  const id = ++meshAsks;
  const reply = await new Promise((resolve) => {
    meshReplies.set(id, resolve);
    // Copies, handed over (not copied again).
    const positions = packedPositions(position);
    const index = geometry.index ? Uint32Array.from(geometry.index.array) : null;
    worker.postMessage({ id, positions, index }, index ? [positions.buffer, index.buffer] : [positions.buffer]);
  });
  if (reply.error) return null;
  const mesh = new THREE.BufferGeometry();
  // Welded: new vertices; else the model's, a new index over them. Their
  // normals, computed by the worker, either way.
  const vertices = reply.positions.length / 3;
  mesh.setIndex(new THREE.BufferAttribute(vertices < 65536 ? Uint16Array.from(reply.index) : reply.index, 1));
  mesh.setAttribute('position', reply.welded ? new THREE.BufferAttribute(reply.positions, 3) : position);
  mesh.setAttribute('normal', new THREE.BufferAttribute(reply.normals, 3));
  return { geometry: mesh, lod: reply.lod };
}

function fieldTexture(data, n) {
  const t = new THREE.DataTexture(data, n, n, THREE.RGBAFormat, THREE.FloatType);
  t.minFilter = t.magFilter = THREE.NearestFilter;
  t.needsUpdate = true;
  return t;
}

export class FieldPreview {
  constructor() {
    this.uniforms = {
      sdFieldP: { value: null },
      sdFieldN: { value: null },
      sdLo: { value: new THREE.Vector2() },
      sdHi: { value: new THREE.Vector2(1, 1) },
      sdN: { value: 2 },
      sdBasis: { value: new THREE.Matrix3() },
      sdCentre: { value: new THREE.Vector2() },
      sdH0: { value: 0 },
      sdRotation: { value: new THREE.Vector2(1, 0) },
      sdScale: { value: 1 },
      sdTarget: { value: new THREE.Vector2() },
      sdPeriod: { value: new THREE.Vector2() },
      sdPeriodV: { value: new THREE.Vector2() },
      sdRotAngle: { value: 0 },
      sdRotCentre: { value: new THREE.Vector2() },
      sdRotStart: { value: 0 },
    };
    this.material = new THREE.MeshStandardMaterial({ color: 0xd9b38c, roughness: 0.6, side: THREE.DoubleSide });
    this.material.onBeforeCompile = (shader) => {
      Object.assign(shader.uniforms, this.uniforms);
      shader.vertexShader =
        kVertexHead +
        shader.vertexShader
          .replace('#include <beginnormal_vertex>', kVertexPlace)
          .replace('#include <begin_vertex>', 'vec3 transformed = sdTransformed;');
      shader.fragmentShader =
        'varying float sdOff;\n' +
        shader.fragmentShader.replace(
          '#include <color_fragment>',
          '#include <color_fragment>\n  diffuseColor.rgb = mix(diffuseColor.rgb, vec3(1.0, 0.12, 0.05), step(0.5, sdOff));',
        );
    };
    this.mesh = new THREE.Mesh(new THREE.BufferGeometry(), this.material);
    this.mesh.frustumCulled = false; // its geometry is the model before bending
    this.field = null;
    this.frame = null;
    this.placement = null;
    this.period = null;
    this.periodV = null;
    this.rotation = null;
    this.onChange = () => {}; // what is drawn changed (the view draws a frame)
  }

  // The sheet's period when it repeats by a translation (a whole cylinder,
  // from the sheet's periodic_u and period), else null: parts past the
  // seam are bent where they land, a period away.
  setPeriod(sheet) {
    const p = sheet && sheet.periodic_u && sheet.period;
    this.period = p && Math.abs(p.angle_deg) < 1e-9 ? [...p.translation] : null;
    this.uniforms.sdPeriod.value.set(...(this.period || [0, 0]));
    const pv = sheet && sheet.periodic_v && sheet.period_v;
    this.periodV = pv ? [...pv.translation] : null;
    this.uniforms.sdPeriodV.value.set(...(this.periodV || [0, 0]));
    // A rotation (a whole cone): about its fixed point c = (I - R)^-1 t, the
    // apex; the seam's column u = 0 (sample (0, 0) on it) leaves c at `start`.
    this.rotation = null;
    if (p && Math.abs(p.angle_deg) >= 1e-9 && sheet.flat && sheet.flat.length) {
      const angle = (p.angle_deg * Math.PI) / 180,
        [tx, ty] = p.translation;
      const c = Math.cos(angle),
        s = Math.sin(angle);
      const det = (1 - c) * (1 - c) + s * s; // det(I - R)
      const centre = [((1 - c) * tx - s * ty) / det, (s * tx + (1 - c) * ty) / det];
      const start = Math.atan2(sheet.flat[0][1] - centre[1], sheet.flat[0][0] - centre[0]);
      this.rotation = { angle, centre, start };
    }
    this.uniforms.sdRotAngle.value = this.rotation ? this.rotation.angle : 0;
    this.uniforms.sdRotCentre.value.set(...(this.rotation ? this.rotation.centre : [0, 0]));
    this.uniforms.sdRotStart.value = this.rotation ? this.rotation.start : 0;
    this.useDefines({
      SD_PERIOD: Boolean(this.period),
      SD_PERIOD_V: Boolean(this.periodV),
      SD_ROTATION: Boolean(this.rotation),
    });
    this.onChange();
  }

  // The shader's seam rules for this sheet (recompiled when they change).
  useDefines(wanted) {
    const defines = {};
    for (const [name, on] of Object.entries(wanted)) if (on) defines[name] = '';
    if (JSON.stringify(defines) === JSON.stringify(this.material.defines || {})) return;
    this.material.defines = defines;
    this.material.needsUpdate = true;
  }

  // The field as GET /v1/surfaces/{id}/field returns it in JSON.
  setField(field) {
    const n = field.n,
      count = n * n;
    const p = new Float32Array(4 * count),
      q = new Float32Array(4 * count);
    for (let k = 0; k < count; ++k) {
      p.set(field.positions[k], 4 * k);
      p[4 * k + 3] = field.on_sheet[k] ? 1 : 0;
      q.set(field.normals[k], 4 * k);
    }
    this.uniforms.sdFieldP.value?.dispose();
    this.uniforms.sdFieldN.value?.dispose();
    this.uniforms.sdFieldP.value = fieldTexture(p, n);
    this.uniforms.sdFieldN.value = fieldTexture(q, n);
    this.uniforms.sdLo.value.set(...field.bounds[0]);
    this.uniforms.sdHi.value.set(...field.bounds[1]);
    this.uniforms.sdN.value = n;
    this.field = field;
    this.onChange();
  }

  // The model as the browser read it (positions, model space; normals are
  // computed when it is first shown without them, see shown()), or the
  // worker's mesh. The geometry it replaces is let go of on the GPU (a
  // buffer it shares with the new one is uploaded again).
  setGeometry(geometry) {
    const old = this.mesh.geometry;
    this.mesh.geometry = geometry || new THREE.BufferGeometry();
    if (old && old !== this.mesh.geometry) old.dispose();
    this.onChange();
  }

  // The model as the browser read it, drawn at once, and replaced by its
  // preview mesh (welded, simplified, ordered: preview_mesh.js, in a
  // worker) when that is ready; `onMesh(lod)` is then told what became of
  // it (lod: {triangles: [before, after], error} or null: drawn whole). A
  // newer model drops the older's mesh.
  setModelGeometry(geometry, onMesh = () => {}) {
    this.setGeometry(geometry);
    const asked = (this.meshAsked = {});
    previewMeshOf(geometry).then((mesh) => {
      if (this.meshAsked !== asked || !mesh) return;
      this.setGeometry(mesh.geometry);
      onMesh(mesh.lod);
    });
  }

  // placementFrame()'s result and the placement {center, rotation_deg, scale}.
  setPlacement(frame, placement) {
    const m = frame.basis;
    this.uniforms.sdBasis.value.set(...m[0], ...m[1], ...m[2]);
    this.uniforms.sdCentre.value.set(...frame.centre);
    this.uniforms.sdH0.value = frame.h0;
    const t = (placement.rotation_deg * Math.PI) / 180;
    this.uniforms.sdRotation.value.set(Math.cos(t), Math.sin(t));
    this.uniforms.sdScale.value = placement.scale;
    this.uniforms.sdTarget.value.set(...placement.center);
    this.frame = frame;
    this.placement = { ...placement, center: [...placement.center] };
    this.onChange();
  }

  // To be called as the preview is shown: the model as read, shown before
  // the worker's mesh (with its normals) came, gets its normals now. Not at
  // load, where the page's thread would compute them for a mesh the worker's
  // usually replaces before anyone drags.
  shown() {
    const g = this.mesh.geometry;
    if (g.getAttribute('position') && !g.getAttribute('normal')) computeNormals(g);
  }

  // Whether there is everything a preview needs.
  ready() {
    return Boolean(
      this.field &&
      this.frame &&
      this.placement &&
      this.mesh.geometry.getAttribute('position') &&
      typeof this.placement.scale === 'number',
    );
  }
}
