// The flat sheet's geometry (sheet_view.js holds the sheet): cell areas,
// the moves by whole periods on a closed surface, whether a point is on the
// sheet, and its centre.

export function cellArea(p, q, r, s) {
  // quad p q r s, as two triangles (2D or 3D)
  const tri = (a, b, c) => {
    const u = a.map((x, i) => b[i] - x),
      v = a.map((x, i) => c[i] - x);
    if (u.length === 2) return Math.abs(u[0] * v[1] - u[1] * v[0]) / 2;
    const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    return Math.hypot(...n) / 2;
  };
  return tri(p, q, r) + tri(p, r, s);
}

// The moves by whole periods that land a point on the same surface point:
// [ku, kv] for the periods in u and v (each -1, 0 or 1, not both 0).
export function periodMoves(sheet) {
  const us = sheet.period ? [0, 1, -1] : [0];
  const vs = sheet.periodV ? [0, 1, -1] : [0];
  const moves = [];
  for (const ku of us) for (const kv of vs) if (ku || kv) moves.push([ku, kv]);
  return moves;
}

// Point p moved by [ku, kv] periods (periodMoves).
export function byPeriods(sheet, p, [ku, kv]) {
  const [x, y] = ku ? byPeriod(sheet, p, ku) : p;
  const t = sheet.periodV;
  return kv ? [x + kv * t[0], y + kv * t[1]] : [x, y];
}

// Point p moved by the period in u k times (k = 1 or -1): the same surface point.
function byPeriod(sheet, [x, y], k) {
  const { angle, t } = sheet.period;
  if (k > 0) {
    const c = Math.cos(angle),
      s = Math.sin(angle);
    return [c * x - s * y + t[0], s * x + c * y + t[1]];
  }
  const c = Math.cos(-angle),
    s = Math.sin(-angle),
    u = x - t[0],
    v = y - t[1];
  return [c * u - s * v, s * u + c * v];
}

// Whether p is inside the sheet's outline (even-odd rule).
function onSheet(sheet, [x, y]) {
  let inside = false;
  const o = sheet.outline;
  for (let a = 0, b = o.length - 1; a < o.length; b = a++) {
    if (o[a][1] > y !== o[b][1] > y && x < ((o[b][0] - o[a][0]) * (y - o[a][1])) / (o[b][1] - o[a][1]) + o[a][0])
      inside = !inside;
  }
  return inside;
}

// On a closed surface, a footprint centre dragged past the seam comes
// back onto the sheet by the period (turned with it on a cone): the same
// placement on the surface. True when it moved.
export function wrapAcrossSeam(sheet, placement) {
  if (!sheet || onSheet(sheet, placement.center)) return false;
  for (const move of periodMoves(sheet)) {
    const moved = byPeriods(sheet, placement.center, move);
    if (!onSheet(sheet, moved)) continue;
    placement.center = moved;
    if (move[0]) placement.rotation_deg += (move[0] * sheet.period.angle * 180) / Math.PI;
    placement.rotation_deg = ((placement.rotation_deg + 540) % 360) - 180;
    return true;
  }
  return false;
}

// The centre of the sheet: the image of (u, v) = (1/2, 1/2), as the server's "center".
export function sheetCentre(sheet) {
  const { nu, nv, flat } = sheet;
  const gu = (nu - 1) / 2,
    gv = (nv - 1) / 2;
  const i = Math.min(Math.floor(gu), nu - 2),
    j = Math.min(Math.floor(gv), nv - 2);
  const s = gu - i,
    t = gv - j;
  const p = (a, b) => flat[a + nu * b];
  return [0, 1].map(
    (c) =>
      (1 - s) * (1 - t) * p(i, j)[c] +
      s * (1 - t) * p(i + 1, j)[c] +
      s * t * p(i + 1, j + 1)[c] +
      (1 - s) * t * p(i, j + 1)[c],
  );
}
