// The peer of bench/text_bench: the same texts made the way a web page
// would, with opentype.js (outlines, kerning, ligatures) and earcut
// (triangles), extruded to the same closed solids: each glyph's quadratic
// and cubic pieces cut by the same rule (Wang's bound for the tolerance),
// its contours sorted into outer rings and their holes, each ring with its
// holes triangulated by earcut, top and bottom faces and a wall of two
// triangles per boundary edge. Prints JSON: per text, the median time and
// the triangles.
// Usage: node peer.mjs FONT TOLERANCE_MM SIZE_MM REPEAT TEXT...
import { readFileSync } from 'node:fs';
import opentype from 'opentype.js';
import earcut from 'earcut';

const [fontPath, tolerance, size, repeat, ...texts] = process.argv.slice(2);
const tol = Number(tolerance),
  em = Number(size),
  runs = Number(repeat);
const bytes = readFileSync(fontPath);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);

function pieces(bound) {
  return Math.max(1, Math.min(65536, Math.ceil(Math.sqrt(bound / (8 * tol)))));
}

// A glyph's path as closed contours of [x, y] points.
function contours(path) {
  const out = [];
  let cur = null,
    x = 0,
    y = 0;
  for (const c of path.commands) {
    if (c.type === 'M') {
      cur = [[c.x, c.y]];
      out.push(cur);
    } else if (c.type === 'L') {
      cur.push([c.x, c.y]);
    } else if (c.type === 'Q') {
      const n = pieces(2 * Math.hypot(x - 2 * c.x1 + c.x, y - 2 * c.y1 + c.y));
      for (let k = 1; k <= n; ++k) {
        const t = k / n,
          s = 1 - t;
        cur.push([s * s * x + 2 * s * t * c.x1 + t * t * c.x, s * s * y + 2 * s * t * c.y1 + t * t * c.y]);
      }
    } else if (c.type === 'C') {
      const m = Math.max(
        Math.hypot(x - 2 * c.x1 + c.x2, y - 2 * c.y1 + c.y2),
        Math.hypot(c.x1 - 2 * c.x2 + c.x, c.y1 - 2 * c.y2 + c.y),
      );
      const n = pieces(6 * m);
      for (let k = 1; k <= n; ++k) {
        const t = k / n,
          s = 1 - t;
        cur.push([
          s * s * s * x + 3 * s * s * t * c.x1 + 3 * s * t * t * c.x2 + t * t * t * c.x,
          s * s * s * y + 3 * s * s * t * c.y1 + 3 * s * t * t * c.y2 + t * t * t * c.y,
        ]);
      }
    } else if (c.type === 'Z') {
      if (cur && cur.length > 1) {
        const [a, b] = [cur[0], cur[cur.length - 1]];
        if (a[0] === b[0] && a[1] === b[1]) cur.pop();
      }
      continue;
    }
    if (c.type !== 'Z') {
      x = c.x;
      y = c.y;
    }
  }
  return out.filter((r) => r.length >= 3);
}

const area = (r) => {
  let a = 0;
  for (let i = 0, j = r.length - 1; i < r.length; j = i++) a += (r[j][0] - r[i][0]) * (r[j][1] + r[i][1]);
  return a / 2;
};
const inside = (p, r) => {
  let c = false;
  for (let i = 0, j = r.length - 1; i < r.length; j = i++) {
    if (
      r[i][1] > p[1] !== r[j][1] > p[1] &&
      p[0] < ((r[j][0] - r[i][0]) * (p[1] - r[i][1])) / (r[j][1] - r[i][1]) + r[i][0]
    )
      c = !c;
  }
  return c;
};

// One glyph's solid: positions (top then bottom) and triangles.
function solid(rings, depth, mesh) {
  if (!rings.length) return;
  // Outer rings turn the way the largest ring turns; the others are holes,
  // each in the smallest outer ring that holds its first point.
  const sign = Math.sign(area(rings.reduce((a, b) => (Math.abs(area(a)) > Math.abs(area(b)) ? a : b))));
  const outers = rings.filter((r) => Math.sign(area(r)) === sign).map((r) => ({ r, holes: [] }));
  for (const h of rings.filter((r) => Math.sign(area(r)) !== sign)) {
    const o = outers.filter((o) => inside(h[0], o.r)).sort((a, b) => Math.abs(area(a.r)) - Math.abs(area(b.r)))[0];
    if (o) o.holes.push(h);
  }
  for (const { r, holes } of outers) {
    const flat = [],
      holeIndex = [];
    for (const p of r) flat.push(p[0], p[1]);
    for (const h of holes) {
      holeIndex.push(flat.length / 2);
      for (const p of h) flat.push(p[0], p[1]);
    }
    const tri = earcut(flat, holeIndex);
    const n = flat.length / 2,
      base = mesh.positions.length / 3;
    for (let k = 0; k < n; ++k) mesh.positions.push(flat[2 * k], flat[2 * k + 1], depth);
    for (let k = 0; k < n; ++k) mesh.positions.push(flat[2 * k], flat[2 * k + 1], 0);
    for (let k = 0; k < tri.length; k += 3) {
      mesh.triangles.push(base + tri[k], base + tri[k + 1], base + tri[k + 2]);
      mesh.triangles.push(base + n + tri[k], base + n + tri[k + 2], base + n + tri[k + 1]);
    }
    const loops = [
      [0, r.length],
      ...holes.map((h, i) => {
        const start = holeIndex[i];
        return [start, start + h.length];
      }),
    ];
    for (const [s, e] of loops) {
      for (let k = s; k < e; ++k) {
        const a = base + k,
          b = base + (k + 1 < e ? k + 1 : s);
        mesh.triangles.push(a + n, b + n, b, a + n, b, a);
      }
    }
  }
}

function make(font, text) {
  const mesh = { positions: [], triangles: [] };
  for (const path of font.getPaths(text, 0, 0, em, { kerning: true, features: { liga: true } })) {
    solid(contours(path), 0.6, mesh);
  }
  return { positions: new Float32Array(mesh.positions), triangles: new Uint32Array(mesh.triangles) };
}

const median = (xs) => xs.sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const t0 = performance.now();
const font = opentype.parse(buffer);
const openMs = performance.now() - t0;
const results = texts.map((text) => {
  for (let k = 0; k < 5; ++k) make(font, text); // the JIT warm
  const times = [];
  let made = null;
  for (let k = 0; k < runs; ++k) {
    const s = performance.now();
    made = make(font, text);
    times.push(performance.now() - s);
  }
  return { chars: text.length, ms: median(times), triangles: made.triangles.length / 3 };
});
console.log(JSON.stringify({ peer: 'opentype.js 1.3.4 + earcut 3.0.2', open_ms: openMs, texts: results }));
