// A model's footprint on the flat sheet, computed in the browser so that it
// can be drawn and dragged before the server deforms the model: the model is
// read with three.js's loaders, turned by the placement's up axis exactly as
// the server turns it (engine/placement.cpp), and outlined by its convex hull.
import * as THREE from 'three';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { PLYLoader } from 'three/addons/loaders/PLYLoader.js';
import { STLLoader } from 'three/addons/loaders/STLLoader.js';
import { mergeGeometries } from 'three/addons/utils/BufferGeometryUtils.js';

let draco = null;
export function dracoLoader() {
  if (!draco) {
    draco = new DRACOLoader();
    draco.setDecoderPath('/vendor/three/examples/jsm/libs/draco/');
  }
  return draco;
}

// The triangle meshes under `object`, each with positions: what the
// server reads of a model (a glTF's point and line primitives, which
// three.js reads as Points and Lines, it ignores), and what the 3D view
// colours of the exact result.
export function meshesOf(object) {
  const meshes = [];
  object.traverse((o) => {
    if (o.isMesh && o.geometry && o.geometry.getAttribute('position')) meshes.push(o);
  });
  return meshes;
}

// Every mesh's positions in world space, x, y, z per vertex (a
// Float64Array: a million-triangle STL has nine million numbers, which a
// plain array grown by push took ~0.2 s to hold). World matrices are affine.
export function positionsOf(object) {
  object.updateMatrixWorld(true);
  const parts = [];
  let total = 0;
  for (const o of meshesOf(object)) {
    const p = o.geometry.getAttribute('position');
    parts.push([p, o.matrixWorld.elements]);
    total += p.count;
  }
  const out = new Float64Array(3 * total);
  let w = 0;
  for (const [p, e] of parts) {
    // A plain array is read as it is (the accessors cost ~0.1 s for a
    // million-triangle STL's three million corners).
    const a = !p.isInterleavedBufferAttribute && !p.normalized && p.itemSize === 3 ? p.array : null;
    for (let k = 0; k < p.count; ++k, w += 3) {
      const x = a ? a[3 * k] : p.getX(k),
        y = a ? a[3 * k + 1] : p.getY(k),
        z = a ? a[3 * k + 2] : p.getZ(k);
      out[w] = e[0] * x + e[4] * y + e[8] * z + e[12];
      out[w + 1] = e[1] * x + e[5] * y + e[9] * z + e[13];
      out[w + 2] = e[2] * x + e[6] * y + e[10] * z + e[14];
    }
  }
  return out;
}

const kIdentity = new THREE.Matrix4();

// One geometry of every mesh in `object`, in world space, with positions
// only (what the preview bends; its worker computes the normals); null for
// none. Indexed where every mesh is; where some are and some are not (a
// glTF may mix them), separate triangles throughout, which the preview's
// worker welds as it welds an STL's (mergeGeometries merges only alike
// geometries).
export function mergedGeometry(object) {
  object.updateMatrixWorld(true);
  const meshes = meshesOf(object);
  const indexed = meshes.every((o) => o.geometry.index);
  const parts = meshes.map((o) => {
    let g = new THREE.BufferGeometry();
    g.setAttribute('position', o.geometry.getAttribute('position').clone());
    if (o.geometry.index) g.setIndex(o.geometry.index.clone());
    if (!indexed && g.index) g = g.toNonIndexed();
    if (!o.matrixWorld.equals(kIdentity)) g.applyMatrix4(o.matrixWorld);
    return g;
  });
  if (parts.length <= 1) return parts[0] || null;
  return mergeGeometries(parts);
}

function offPositions(text) {
  const words = text
    .replace(/#[^\n]*/g, ' ')
    .split(/\s+/)
    .filter(Boolean);
  if (!/OFF$/.test(words[0])) return [];
  const n = Number(words[1]);
  return words.slice(4, 4 + 3 * n).map(Number);
}

// Three.js's reading of a mesh file: an object, or null when the browser
// cannot read it (OFF: positions only).
async function readObject(ext, bytes) {
  switch (ext) {
    case 'ply':
      return new THREE.Mesh(new PLYLoader().parse(bytes));
    case 'stl':
      return new THREE.Mesh(new STLLoader().parse(bytes));
    case 'obj':
      return new OBJLoader().parse(new TextDecoder().decode(bytes));
    case 'glb':
    case 'gltf': {
      const loader = new GLTFLoader().setDRACOLoader(dracoLoader());
      return (await loader.parseAsync(bytes, '')).scene;
    }
    case 'drc': {
      const geometry = await new Promise((resolve, reject) => {
        dracoLoader().parse(bytes, resolve, reject);
      });
      return new THREE.Mesh(geometry);
    }
    default:
      return null;
  }
}

// A mesh file as the browser reads it: {positions: [x, y, z, ...] or null,
// geometry: the merged triangles (for the preview) or null}. Null parts are
// what the browser cannot read (the server may still: its errors are shown
// then).
export async function readModel(name, bytes) {
  const ext = name.toLowerCase().split('.').pop();
  try {
    if (ext === 'off') return { positions: offPositions(new TextDecoder().decode(bytes)), geometry: null };
    const object = await readObject(ext, bytes);
    if (!object) return { positions: null, geometry: null };
    return { positions: positionsOf(object), geometry: mergedGeometry(object) };
  } catch {
    return { positions: null, geometry: null };
  }
}

// Model axis -> (a, b, h), rows as the server's AxisBasis.
export const kBasis = {
  '+z': [
    [1, 0, 0],
    [0, 1, 0],
    [0, 0, 1],
  ],
  '-z': [
    [1, 0, 0],
    [0, -1, 0],
    [0, 0, -1],
  ],
  '+x': [
    [0, 1, 0],
    [0, 0, 1],
    [1, 0, 0],
  ],
  '-x': [
    [0, 1, 0],
    [0, 0, -1],
    [-1, 0, 0],
  ],
  '+y': [
    [0, 0, 1],
    [1, 0, 0],
    [0, 1, 0],
  ],
  '-y': [
    [0, 0, 1],
    [-1, 0, 0],
    [0, -1, 0],
  ],
};

// {hull: [[a, b], ...] counter-clockwise, centre: [a, b]} in model units
// before placement; null without positions. Points strictly inside the
// polygon of the extreme points along eight directions are on neither the
// hull nor its edges, and are left out before the sort (Akl and
// Toussaint's heuristic): a million-triangle STL's three million corners
// took ~0.9 s to sort here, on the page's thread.
export function footprint(positions, up) {
  if (!positions || positions.length < 3) return null;
  const [ra, rb] = kBasis[up] || kBasis['+z'];
  const count = positions.length / 3;
  const as = new Float64Array(count),
    bs = new Float64Array(count);
  // The first point furthest along each of eight directions, counter-
  // clockwise from -a: -a, -(a + b), -b, a - b, a, a + b, b, b - a (one
  // comparison each, unrolled: the loop runs over every corner of the
  // model, three million for a million-triangle STL).
  let t0 = -Infinity,
    t1 = -Infinity,
    t2 = -Infinity,
    t3 = -Infinity;
  let t4 = -Infinity,
    t5 = -Infinity,
    t6 = -Infinity,
    t7 = -Infinity;
  let e0 = 0,
    e1 = 0,
    e2 = 0,
    e3 = 0,
    e4 = 0,
    e5 = 0,
    e6 = 0,
    e7 = 0;
  for (let v = 0; v < count; ++v) {
    const x = positions[3 * v],
      y = positions[3 * v + 1],
      z = positions[3 * v + 2];
    const a = (as[v] = ra[0] * x + ra[1] * y + ra[2] * z);
    const b = (bs[v] = rb[0] * x + rb[1] * y + rb[2] * z);
    const s = a + b,
      d = a - b;
    if (-a > t0) {
      t0 = -a;
      e0 = v;
    }
    if (-s > t1) {
      t1 = -s;
      e1 = v;
    }
    if (-b > t2) {
      t2 = -b;
      e2 = v;
    }
    if (d > t3) {
      t3 = d;
      e3 = v;
    }
    if (a > t4) {
      t4 = a;
      e4 = v;
    }
    if (s > t5) {
      t5 = s;
      e5 = v;
    }
    if (b > t6) {
      t6 = b;
      e6 = v;
    }
    if (-d > t7) {
      t7 = -d;
      e7 = v;
    }
  }
  const extreme = [e0, e1, e2, e3, e4, e5, e6, e7];
  // The bounds' centre, from the extremes along the axes.
  const loA = as[e0],
    hiA = as[e4],
    loB = bs[e2],
    hiB = bs[e6];
  // Their polygon (counter-clockwise, repeats dropped) as edges: p is
  // strictly left of edge k where ea[k] a + eb[k] b + ec[k] > 0. A point
  // strictly left of every edge of any closed polygon of the points is
  // strictly inside their hull (the polygon winds round it), so ties that
  // leave the polygon odd can only leave in more points.
  const corners = extreme.filter((v, k) => v !== extreme[(k + 7) % 8]);
  const ea = [],
    eb = [],
    ec = [];
  for (let k = 0; corners.length >= 3 && k < corners.length; ++k) {
    const p = corners[k],
      q = corners[(k + 1) % corners.length];
    ea.push(-(bs[q] - bs[p]));
    eb.push(as[q] - as[p]);
    ec.push((bs[q] - bs[p]) * as[p] - (as[q] - as[p]) * bs[p]);
  }
  const pts = [];
  for (let v = 0; v < count; ++v) {
    let inside = ea.length >= 3;
    for (let k = 0; inside && k < ea.length; ++k) inside = ea[k] * as[v] + eb[k] * bs[v] + ec[k] > 0;
    if (!inside) pts.push([as[v], bs[v]]);
  }
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  pts.sort((p, q) => p[0] - q[0] || p[1] - q[1]);
  const lower = [],
    upper = [];
  for (const p of pts) {
    while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop();
    lower.push(p);
  }
  for (let k = pts.length - 1; k >= 0; --k) {
    const p = pts[k];
    while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], p) <= 0) upper.pop();
    upper.push(p);
  }
  const hull = lower.slice(0, -1).concat(upper.slice(0, -1));
  return { hull, centre: [(loA + hiA) / 2, (loB + hiB) / 2] };
}

// placementFrame's last result per positions array: a drag asks for it at
// every pointer move, and a model of a million triangles took ~11 ms a move
// to go over its vertices again.
const frames = new WeakMap();

// The part of the server's placement (engine/placement.cpp) that depends on
// the model alone: the basis (rows: model -> a, b, h), the footprint's centre
// (the middle of its box in (a, b)) and the height h0 that lands on the
// surface (anchor bottom, center or top of the box along up). The same
// object again for the same positions (not changed in place), up and anchor.
export function placementFrame(positions, up, anchor) {
  if (!positions || positions.length < 3) return null;
  const kept = frames.get(positions);
  if (kept && kept.up === up && kept.anchor === anchor) return kept.frame;
  const frame = computePlacementFrame(positions, up, anchor);
  frames.set(positions, { up, anchor, frame });
  return frame;
}

function computePlacementFrame(positions, up, anchor) {
  const m = kBasis[up] || kBasis['+z'];
  const lo = [Infinity, Infinity, Infinity],
    hi = [-Infinity, -Infinity, -Infinity];
  for (let k = 0; k < positions.length; k += 3) {
    for (let r = 0; r < 3; ++r) {
      const q = m[r][0] * positions[k] + m[r][1] * positions[k + 1] + m[r][2] * positions[k + 2];
      lo[r] = Math.min(lo[r], q);
      hi[r] = Math.max(hi[r], q);
    }
  }
  const h0 = anchor === 'bottom' ? lo[2] : anchor === 'top' ? hi[2] : (lo[2] + hi[2]) / 2;
  return { basis: m, centre: [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2], h0 };
}
