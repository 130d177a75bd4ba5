// The flat sheet in 2D: its cells coloured by how much flattening changed
// their area (like the paper's Figure 11), and the model's footprint on it,
// which the person drags (move), wheels (scale) and Shift-wheels (rotate).
// In marking mode a click adds a point to the mark (a polyline) instead.
// On a closed surface the seam is drawn (both seams on a whole torus), the
// footprint is drawn where it lands past the seam too, and a footprint
// released past the seam comes back onto the sheet by the period.

import { byPeriods, cellArea, periodMoves, sheetCentre, wrapAcrossSeam } from './sheet_geometry.js';

export class SheetView {
  // onPlacement({center, rotation_deg, scale}, final, how) is called while
  // the person edits: final on releasing a drag; how is "drag" or "wheel"
  // (wheel events never end: the caller decides when the person stopped).
  constructor(canvas, onPlacement) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.onPlacement = onPlacement;
    this.sheet = null;
    this.footprint = null;
    this.placement = null;
    this.marking = null; // while drawing a mark: onMark(points) after each click
    this.mark = []; // the mark's points, sheet units
    canvas.addEventListener('pointerdown', (e) => this.down(e));
    canvas.addEventListener('pointermove', (e) => this.move(e));
    canvas.addEventListener('pointerup', (e) => this.up(e));
    canvas.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
  }

  setSheet(sheet) {
    const { nu, nv } = sheet.grid;
    if (sheet.mesh) {
      this.setMeshSheet(sheet);
      return;
    }
    const ratios = [];
    for (let j = 0; j + 1 < nv; ++j) {
      for (let i = 0; i + 1 < nu; ++i) {
        const k = [i + nu * j, i + 1 + nu * j, i + 1 + nu * (j + 1), i + nu * (j + 1)];
        const flat = cellArea(...k.map((x) => sheet.flat[x]));
        const surf = cellArea(...k.map((x) => sheet.points[x]));
        ratios.push(surf > 0 ? flat / surf : 1);
      }
    }
    let lo = [Infinity, Infinity],
      hi = [-Infinity, -Infinity];
    for (const [x, y] of sheet.flat) {
      lo = [Math.min(lo[0], x), Math.min(lo[1], y)];
      hi = [Math.max(hi[0], x), Math.max(hi[1], y)];
    }
    const spread = Math.max(0.01, ...ratios.map((r) => Math.abs(Math.log(r))));
    // A surface closed in u (a full cylinder or cone): the motion that takes
    // the seam's column u = 0 onto u = 1, and the sheet's outline.
    const period =
      sheet.periodic_u && sheet.period
        ? { angle: (sheet.period.angle_deg * Math.PI) / 180, t: sheet.period.translation }
        : null;
    // Closed in v too (a torus round its tube): the translation of row v = 0 onto v = 1.
    const periodV = sheet.periodic_v && sheet.period_v ? sheet.period_v.translation : null;
    const outline = [];
    for (let i = 0; i < nu; ++i) outline.push(sheet.flat[i]);
    for (let j = 1; j < nv; ++j) outline.push(sheet.flat[nu - 1 + nu * j]);
    for (let i = nu - 2; i >= 0; --i) outline.push(sheet.flat[i + nu * (nv - 1)]);
    for (let j = nv - 2; j > 0; --j) outline.push(sheet.flat[nu * j]);
    this.sheet = { nu, nv, flat: sheet.flat, ratios, spread, lo, hi, period, periodV, outline };
    this.draw();
  }

  // A surface given as a mesh: the sheet is its flat triangles (their box's
  // lattice is only sampled), each coloured by its own area ratio.
  setMeshSheet(sheet) {
    const { flat, points, triangles } = sheet.mesh;
    const ratios = triangles.map(([a, b, c]) => {
      const s = cellArea(points[a], points[b], points[c], points[c]);
      return s > 0 ? cellArea(flat[a], flat[b], flat[c], flat[c]) / s : 1;
    });
    let lo = [Infinity, Infinity],
      hi = [-Infinity, -Infinity];
    for (const [x, y] of flat) {
      lo = [Math.min(lo[0], x), Math.min(lo[1], y)];
      hi = [Math.max(hi[0], x), Math.max(hi[1], y)];
    }
    const spread = Math.max(0.01, ...ratios.map((r) => Math.abs(Math.log(r))));
    const { nu, nv } = sheet.grid;
    const outline = [sheet.flat[0], sheet.flat[nu - 1], sheet.flat[nu * nv - 1], sheet.flat[nu * (nv - 1)]];
    this.sheet = {
      nu,
      nv,
      flat: sheet.flat,
      ratios,
      spread,
      lo,
      hi,
      period: null,
      periodV: null,
      outline,
      mesh: { flat, triangles },
    };
    this.draw();
  }

  // The centre of the sheet: the image of (u, v) = (1/2, 1/2), as the server's "center".
  sheetCentre() {
    return sheetCentre(this.sheet);
  }

  // Marking mode on (onMark(points) after each point) or off (null).
  setMarking(onMark) {
    this.marking = onMark;
    this.canvas.style.cursor = onMark ? 'crosshair' : '';
  }
  setMark(points) {
    this.mark = points;
    this.draw();
  }

  setFootprint(footprint) {
    this.footprint = footprint;
    this.draw();
  }
  setPlacement(placement) {
    this.placement = placement;
    this.draw();
  }

  // Sheet units <-> canvas pixels (y up on the sheet).
  frame() {
    const { lo, hi } = this.sheet;
    const w = this.canvas.width,
      h = this.canvas.height,
      pad = 16;
    const k = Math.min((w - 2 * pad) / (hi[0] - lo[0] || 1), (h - 2 * pad) / (hi[1] - lo[1] || 1));
    const ox = (w - k * (hi[0] - lo[0])) / 2,
      oy = (h - k * (hi[1] - lo[1])) / 2;
    return {
      toPx: ([x, y]) => [ox + k * (x - lo[0]), h - oy - k * (y - lo[1])],
      toSheet: ([px, py]) => [lo[0] + (px - ox) / k, lo[1] + (h - oy - py) / k],
    };
  }

  placed() {
    // the footprint's hull on the sheet
    const f = this.footprint,
      p = this.placement;
    if (!f || !p || !p.center || typeof p.scale !== 'number') return null;
    const a = (p.rotation_deg * Math.PI) / 180,
      c = Math.cos(a),
      s = Math.sin(a);
    return f.hull.map(([x, y]) => {
      const dx = x - f.centre[0],
        dy = y - f.centre[1];
      return [p.center[0] + p.scale * (c * dx - s * dy), p.center[1] + p.scale * (s * dx + c * dy)];
    });
  }

  // The sheet's cells and seams, painted once per sheet and canvas size into
  // a canvas of their own: a drag repaints only the footprint over them (a
  // 64 x 64 sheet's 3,969 cells took ~18 ms to paint in Chromium, and a
  // pointer move painted them twice).
  sheetLayer() {
    const { width, height } = this.canvas;
    const kept = this.layer;
    if (kept && kept.sheet === this.sheet && kept.canvas.width === width && kept.canvas.height === height) {
      return kept.canvas;
    }
    const canvas = kept ? kept.canvas : document.createElement('canvas');
    canvas.width = width;
    canvas.height = height;
    this.paintSheet(canvas.getContext('2d'));
    this.layer = { canvas, sheet: this.sheet };
    return canvas;
  }

  paintSheet(ctx) {
    ctx.fillStyle = '#fafafa';
    ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
    const { nu, nv, flat, ratios, spread, mesh } = this.sheet;
    const { toPx } = this.frame();
    const patch = (corners, ratio) => {
      const x = Math.log(ratio) / spread; // -1 .. 1
      const w = Math.round(255 * (1 - Math.abs(x)));
      ctx.fillStyle = x > 0 ? `rgb(255,${w},${w})` : `rgb(${w},${w},255)`;
      ctx.strokeStyle = mesh ? '#8884' : '#8888';
      ctx.beginPath();
      for (const p of corners) ctx.lineTo(...toPx(p));
      ctx.closePath();
      ctx.fill();
      ctx.stroke();
    };
    if (mesh) {
      mesh.triangles.forEach((t, k) =>
        patch(
          t.map((v) => mesh.flat[v]),
          ratios[k],
        ),
      );
    } else {
      for (let j = 0; j + 1 < nv; ++j) {
        for (let i = 0; i + 1 < nu; ++i) {
          patch(
            [
              [i, j],
              [i + 1, j],
              [i + 1, j + 1],
              [i, j + 1],
            ].map(([a, b]) => flat[a + nu * b]),
            ratios[i + (nu - 1) * j],
          );
        }
      }
    }
    if (this.sheet.period || this.sheet.periodV) {
      // the seams, both sides of each
      ctx.strokeStyle = '#c60';
      ctx.lineWidth = 2;
      ctx.setLineDash([6, 4]);
      for (const i of this.sheet.period ? [0, nu - 1] : []) {
        ctx.beginPath();
        for (let j = 0; j < nv; ++j) ctx.lineTo(...toPx(flat[i + nu * j]));
        ctx.stroke();
      }
      for (const j of this.sheet.periodV ? [0, nv - 1] : []) {
        ctx.beginPath();
        for (let i = 0; i < nu; ++i) ctx.lineTo(...toPx(flat[i + nu * j]));
        ctx.stroke();
      }
      ctx.setLineDash([]);
      ctx.lineWidth = 1;
    }
  }

  draw() {
    const ctx = this.ctx;
    if (!this.sheet) {
      ctx.fillStyle = '#fafafa';
      ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
      return;
    }
    ctx.drawImage(this.sheetLayer(), 0, 0);
    const { spread } = this.sheet;
    const { toPx } = this.frame();
    const hull = this.placed();
    if (hull) {
      // On a closed surface, the footprint also where it lands past the
      // seam, a period away (paler).
      for (const move of [null, ...periodMoves(this.sheet)]) {
        ctx.fillStyle = move ? 'rgba(30, 120, 60, 0.12)' : 'rgba(30, 120, 60, 0.25)';
        ctx.strokeStyle = move ? '#1746' : '#174';
        ctx.lineWidth = 2;
        ctx.beginPath();
        for (const p of hull) ctx.lineTo(...toPx(move ? byPeriods(this.sheet, p, move) : p));
        ctx.closePath();
        ctx.fill();
        ctx.stroke();
      }
      ctx.lineWidth = 1;
    }
    if (this.mark.length) {
      ctx.strokeStyle = '#0a0';
      ctx.fillStyle = '#0a0';
      ctx.lineWidth = 2;
      ctx.beginPath();
      for (const p of this.mark) ctx.lineTo(...toPx(p));
      ctx.stroke();
      for (const p of this.mark) {
        const [x, y] = toPx(p);
        ctx.fillRect(x - 3, y - 3, 6, 6);
      }
      ctx.lineWidth = 1;
    }
    ctx.fillStyle = '#333';
    ctx.font = '12px sans-serif';
    ctx.fillText(`area change up to ${(100 * (Math.exp(spread) - 1)).toFixed(2)}%`, 8, 16);
  }

  eventPoint(e) {
    const r = this.canvas.getBoundingClientRect();
    return this.frame().toSheet([
      (e.clientX - r.left) * (this.canvas.width / r.width),
      (e.clientY - r.top) * (this.canvas.height / r.height),
    ]);
  }

  down(e) {
    if (this.sheet && this.marking) {
      this.mark = [...this.mark, this.eventPoint(e)];
      this.draw();
      this.marking(this.mark);
      return;
    }
    if (!this.sheet || !this.placement || typeof this.placement.scale !== 'number') return;
    this.drag = { start: this.eventPoint(e), center: [...this.placement.center] };
    this.canvas.setPointerCapture(e.pointerId);
    this.canvas.style.cursor = 'grabbing';
  }

  move(e) {
    if (!this.drag) return;
    const p = this.eventPoint(e);
    this.placement.center = [
      this.drag.center[0] + p[0] - this.drag.start[0],
      this.drag.center[1] + p[1] - this.drag.start[1],
    ];
    this.draw();
    this.onPlacement(this.placement, false, 'drag');
  }

  up() {
    if (!this.drag) return;
    this.drag = null;
    this.canvas.style.cursor = 'grab';
    if (wrapAcrossSeam(this.sheet, this.placement)) this.draw();
    this.onPlacement(this.placement, true, 'drag');
  }

  wheel(e) {
    if (!this.placement || typeof this.placement.scale !== 'number') return;
    e.preventDefault();
    if (e.shiftKey) {
      this.placement.rotation_deg =
        ((this.placement.rotation_deg + Math.sign(e.deltaY || e.deltaX) * 5 + 540) % 360) - 180;
    } else {
      this.placement.scale *= e.deltaY < 0 ? 1.05 : 1 / 1.05;
    }
    this.draw();
    this.onPlacement(this.placement, false, 'wheel');
  }
}
