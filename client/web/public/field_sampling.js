// The field of the sheet-to-surface map, sampled on the CPU as the preview's
// vertex shader samples it (preview.js): the surface point and parameters at
// a sheet point, bilinear between lattice points; a model placed on the sheet
// and bent by it; and how far two point sets are from each other (the
// preview against the exact result).

// (a, b, h) of model point (x, y, z): `frame` from placementFrame(), and the
// placement's centre (the sheet point the footprint's centre goes to),
// rotation_deg and scale.
export function placePoint(x, y, z, frame, placement) {
  const m = frame.basis;
  const qa = m[0][0] * x + m[0][1] * y + m[0][2] * z - frame.centre[0];
  const qb = m[1][0] * x + m[1][1] * y + m[1][2] * z - frame.centre[1];
  const qh = m[2][0] * x + m[2][1] * y + m[2][2] * z;
  const t = (placement.rotation_deg * Math.PI) / 180;
  const c = Math.cos(t),
    s = Math.sin(t),
    k = placement.scale;
  return [
    placement.center[0] + k * (c * qa - s * qb),
    placement.center[1] + k * (s * qa + c * qb),
    k * (qh - frame.h0),
  ];
}

// The field's P, N at sheet point (a, b), bilinear, and whether the cell's
// lattice points are all on the sheet (as the shader computes them).
// The lattice cell that sheet point (a, b) falls in (clamped to the
// field's box), its corners and the point's place in it.
function fieldCell(field, a, b) {
  const n = field.n,
    [lo, hi] = field.bounds;
  const tx = ((a - lo[0]) / (hi[0] - lo[0])) * (n - 1),
    ty = ((b - lo[1]) / (hi[1] - lo[1])) * (n - 1);
  const ix = Math.min(Math.max(Math.floor(tx), 0), n - 2),
    iy = Math.min(Math.max(Math.floor(ty), 0), n - 2);
  const fx = tx - ix,
    fy = ty - iy;
  const k00 = ix + n * iy,
    k10 = k00 + 1,
    k01 = k00 + n,
    k11 = k01 + 1;
  const lerp = (arr, c) =>
    (1 - fy) * ((1 - fx) * arr[k00][c] + fx * arr[k10][c]) + fy * ((1 - fx) * arr[k01][c] + fx * arr[k11][c]);
  return { tx, ty, corners: [k00, k10, k01, k11], lerp };
}

export function sampleField(field, a, b) {
  const n = field.n;
  const {
    tx,
    ty,
    corners: [k00, k10, k01, k11],
    lerp,
  } = fieldCell(field, a, b);
  const p = [0, 1, 2].map((c) => lerp(field.positions, c));
  const nr = [0, 1, 2].map((c) => lerp(field.normals, c));
  const len = Math.hypot(...nr);
  const inside = tx >= 0 && ty >= 0 && tx <= n - 1 && ty <= n - 1;
  const on = inside && [k00, k10, k01, k11].every((k) => field.on_sheet[k]);
  return { p, n: nr.map((x) => x / len), on };
}

// The surface parameters (u, v) at sheet point (a, b), interpolated as
// sampleField interpolates the surface point (the field's `params`, given
// since version 2; null without them).
export function sampleParams(field, a, b) {
  if (!field.params) return null;
  const { lerp } = fieldCell(field, a, b);
  return [0, 1].map((c) => lerp(field.params, c));
}

// On a surface closed in u whose sheet repeats by a translation `period` (a
// whole cylinder's strip, (2 pi R, 0)): sheet point (a, b) moved by whole
// periods onto the field's box, as the shader does. Unchanged without one.
// A sheet closed in v too (a whole torus) is wrapped by each period in turn.
export function wrapByPeriod(a, b, field, period) {
  if (!period) return [a, b];
  const lo = field.bounds[0];
  const k = Math.floor(
    ((a - lo[0]) * period[0] + (b - lo[1]) * period[1]) / (period[0] * period[0] + period[1] * period[1]),
  );
  return [a - k * period[0], b - k * period[1]];
}

// On a surface closed in u whose sheet repeats by a rotation (a whole
// cone's sector: `rotation` {angle, centre (the apex), start (the seam's
// angle about it)}): sheet point (a, b) turned by whole periods into the
// sector, as the shader does. Points in the gap the sector leaves go to the
// nearer side. Unchanged without one.
export function wrapByRotation(a, b, rotation) {
  if (!rotation) return [a, b];
  const { angle, centre, start } = rotation;
  const turn = 2 * Math.PI,
    span = Math.abs(angle),
    gap = turn - span;
  const x = a - centre[0],
    y = b - centre[1];
  let phi = Math.sign(angle) * (Math.atan2(y, x) - start);
  phi -= turn * Math.floor((phi + gap / 2) / turn);
  const r = -Math.floor(phi / span) * angle;
  const c = Math.cos(r),
    s = Math.sin(r);
  return [centre[0] + c * x - s * y, centre[1] + s * x + c * y];
}

// The preview's position of every model vertex (`positions`: x, y, z, ...).
export function previewPositions(positions, frame, placement, field, period = null, periodV = null, rotation = null) {
  const out = new Float64Array(positions.length);
  for (let k = 0; k < positions.length; k += 3) {
    const [a0, b0, h] = placePoint(positions[k], positions[k + 1], positions[k + 2], frame, placement);
    const [a1, b1] = wrapByRotation(a0, b0, rotation);
    const [a, b] = wrapByPeriod(...wrapByPeriod(a1, b1, field, period), field, periodV);
    const f = sampleField(field, a, b);
    for (let c = 0; c < 3; ++c) out[k + c] = f.p[c] + h * f.n[c];
  }
  return out;
}

// The largest and mean distance from (up to `samples` of) the points `from`
// to their nearest point in `to` (flat x, y, z arrays): how far the preview
// was from the exact result, whose vertices include the model's own (the
// subdivision adds, never moves). A uniform grid of cell `cell` finds them.
export function nearestDistances(from, to, cell, samples = 4000) {
  // Cells by a number made of their indices, unique while each is within
  // 2^16 cells of the origin (points farther only add candidates, each
  // measured).
  const grid = new Map();
  const key = (i, j, l) => i + 65536 + 131072 * (j + 65536 + 131072 * (l + 65536));
  for (let k = 0; k < to.length; k += 3) {
    const id = key(Math.floor(to[k] / cell), Math.floor(to[k + 1] / cell), Math.floor(to[k + 2] / cell));
    const list = grid.get(id);
    if (list) list.push(k);
    else grid.set(id, [k]);
  }
  const count = from.length / 3,
    stride = Math.max(1, Math.floor(count / samples));
  let worst = 0,
    sum = 0,
    n = 0;
  for (let v = 0; v < count; v += stride) {
    const x = from[3 * v],
      y = from[3 * v + 1],
      z = from[3 * v + 2];
    const cx = Math.floor(x / cell),
      cy = Math.floor(y / cell),
      cz = Math.floor(z / cell);
    let best2 = Infinity;
    for (let ring = 1; ring <= 4 && best2 === Infinity; ++ring) {
      for (let i = -ring; i <= ring; ++i)
        for (let j = -ring; j <= ring; ++j)
          for (let l = -ring; l <= ring; ++l) {
            for (const k of grid.get(key(cx + i, cy + j, cz + l)) || []) {
              const dx = to[k] - x,
                dy = to[k + 1] - y,
                dz = to[k + 2] - z;
              best2 = Math.min(best2, dx * dx + dy * dy + dz * dz);
            }
          }
    }
    const best = Math.sqrt(best2);
    worst = Math.max(worst, best);
    sum += best;
    ++n;
  }
  return { max: worst, mean: n ? sum / n : 0 };
}
