// A Bezier patch's field (GET /v1/surfaces/{id}/field) moved by an edit of
// its control points, at once, before the server's field for the edit comes.
//
// A Bezier patch is linear in its control points: moving point (i, j) by d
// moves the surface point at parameters (u, v) by B_i(u) B_j(v) d, the
// Bernstein weights of degrees degree_u and degree_v (u fastest in the
// list, as the API has it). The field carries the (u, v) of each lattice
// point (`params`), so its positions move exactly as the surface does there.
// Normals turn as the lattice's own finite-difference normals turn. What
// this leaves out is the flat sheet's own change (the flattening of the
// edited surface), second order in a small edit: the server's field for the
// pose replaces the moved one when it comes.

import { sampleField } from './field_sampling.js';

// The n + 1 Bernstein weights of degree n at t (de Casteljau's recurrence;
// t may lie past [0, 1], where the field continues the surface).
export function bernstein(n, t) {
  const b = new Float64Array(n + 1);
  b[0] = 1;
  for (let k = 1; k <= n; ++k) {
    let saved = 0;
    for (let i = 0; i < k; ++i) {
      const bi = b[i];
      b[i] = saved + (1 - t) * bi;
      saved = t * bi;
    }
    b[k] = saved;
  }
  return b;
}

// Unit normals of the lattice's positions by central differences (one-sided
// at its border), as [x, y, z] per point.
function latticeNormals(positions, n) {
  const out = new Array(n * n);
  for (let j = 0; j < n; ++j) {
    for (let i = 0; i < n; ++i) {
      const at = (a, b) => positions[a + n * b];
      const i0 = Math.max(i - 1, 0),
        i1 = Math.min(i + 1, n - 1);
      const j0 = Math.max(j - 1, 0),
        j1 = Math.min(j + 1, n - 1);
      const du = [0, 1, 2].map((c) => at(i1, j)[c] - at(i0, j)[c]);
      const dv = [0, 1, 2].map((c) => at(i, j1)[c] - at(i, j0)[c]);
      const x = [du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]];
      const len = Math.hypot(...x);
      out[i + n * j] = len > 0 ? x.map((c) => c / len) : [0, 0, 0];
    }
  }
  return out;
}

// The field of the patch `after`, moved from `field`, the field of the patch
// `before`; null where that cannot be done (not two Bezier patches of one
// shape, or a field without params: the server's field is then waited for).
// `field` itself is left as it is.
export function movedField(field, before, after) {
  if (
    !field ||
    !field.params ||
    !before ||
    !after ||
    before.kind !== 'bezier' ||
    after.kind !== 'bezier' ||
    before.degree_u !== after.degree_u ||
    before.degree_v !== after.degree_v ||
    before.control_points.length !== after.control_points.length
  ) {
    return null;
  }
  const du = after.degree_u,
    dv = after.degree_v,
    count = field.n * field.n;
  const moves = [];
  after.control_points.forEach((p, k) => {
    const d = p.map((x, c) => x - before.control_points[k][c]);
    if (d.some((x) => x !== 0)) moves.push({ i: k % (du + 1), j: Math.floor(k / (du + 1)), d });
  });
  if (!moves.length) return field;
  const positions = new Array(count);
  for (let k = 0; k < count; ++k) {
    const [u, v] = field.params[k];
    const bu = bernstein(du, u),
      bv = bernstein(dv, v);
    const p = [...field.positions[k]];
    for (const m of moves) {
      const w = bu[m.i] * bv[m.j];
      for (let c = 0; c < 3; ++c) p[c] += w * m.d[c];
    }
    positions[k] = p;
  }
  // The given normals turned as the lattice's own turn: N + s (n' - n), s the
  // side the lattice's normal n takes of N (the sheet may be mirrored).
  const was = latticeNormals(field.positions, field.n),
    now = latticeNormals(positions, field.n);
  const normals = field.normals.map((q, k) => {
    const s = q[0] * was[k][0] + q[1] * was[k][1] + q[2] * was[k][2] < 0 ? -1 : 1;
    const x = q.map((c, i) => c + s * (now[k][i] - was[k][i]));
    const len = Math.hypot(...x);
    return len > 0 ? x.map((c) => c / len) : q;
  });
  return { ...field, positions, normals, moved: true };
}

// A sheet point moved as `motion` says ({rotation_deg, translation}, a
// POST /v1/surfaces reply's warm_start.motion: from the sheet it started
// from to its own); unmoved without one.
export function moveSheetPoint([x, y], motion) {
  if (!motion) return [x, y];
  const t = (motion.rotation_deg * Math.PI) / 180,
    c = Math.cos(t),
    s = Math.sin(t);
  return [c * x - s * y + motion.translation[0], s * x + c * y + motion.translation[1]];
}

// How far field `b` takes the sheet points of field `a`'s lattice (moved by
// `motion` onto b's sheet, if given) from where `a` takes them (b sampled
// there as the preview samples it), at most over the points on both sheets,
// relative to a's sheet's diagonal: what a person sees move when b replaces
// a under the preview (and the placement moves with the sheet).
export function fieldGap(a, b, motion = null) {
  const n = a.n,
    [lo, hi] = a.bounds;
  const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
  let worst = 0;
  a.positions.forEach((p, k) => {
    if (!a.on_sheet[k]) return;
    const x = lo[0] + ((k % n) * (hi[0] - lo[0])) / (n - 1);
    const y = lo[1] + (Math.floor(k / n) * (hi[1] - lo[1])) / (n - 1);
    const s = sampleField(b, ...moveSheetPoint([x, y], motion));
    if (s.on) worst = Math.max(worst, Math.hypot(...p.map((v, c) => v - s.p[c])));
  });
  return worst / diagonal;
}
