// window.surfdeformTest: what the browser tests and benchmarks read of the
// page, beside its DOM (docs/viewer.md, "The test surface"). The state comes
// as a snapshot (plain JSON, a model's bytes and positions as counts); the
// rest are measurements a person sees but a script cannot read from pixels
// alone (how far the preview was, what the GPU holds, where a handle is).
import * as THREE from 'three';

import { createSurface, deform, mapOnSurface } from './api.js';
import { fieldGap, movedField } from './field_edit.js';
import { nearestDistances, sampleParams } from './field_sampling.js';
import { readableJson } from './dom.js';
import { handleClientPoint, modelCoverage, modelMask, pixelCounts, texturedMeshes } from './view_probes.js';

// The store's state as plain JSON.
function snapshot(s) {
  const m = s.model;
  return JSON.parse(
    JSON.stringify({
      ...s,
      model: m && {
        name: m.name,
        bytes: m.bytes.byteLength,
        vertices: m.positions ? m.positions.length / 3 : null,
        text: m.text || null,
        lod: m.lod ? { triangles: m.lod.triangles, error: m.lod.error } : null,
      },
      field: s.field && { n: s.field.n, bounds: s.field.bounds },
      liveSummary: s.liveSummary && { version: s.liveSummary.version, id: s.liveSummary.summary.id },
    }),
  );
}

export function installTestSurface(page, animationPanel) {
  const { store, scheduler, modelView, sheetView, preview, gltf } = page;

  // The exact result of what the page shows, in `compression`, as three.js
  // decodes it: world positions and the node's scale.
  const decoded = async (compression) => {
    const { model } = store.state;
    const params = page.deformParams('glb', compression);
    const { bytes } = await deform(model.bytes, model.name, params, 'model/gltf-binary');
    const scene = (await gltf.parseAsync(bytes, '')).scene;
    scene.updateMatrixWorld(true);
    const positions = [];
    let scale = 1;
    const v = new THREE.Vector3();
    scene.traverse((o) => {
      if (!o.isMesh) return;
      scale = o.getWorldScale(new THREE.Vector3()).x;
      const pos = o.geometry.getAttribute('position');
      for (let k = 0; k < pos.count; ++k) {
        v.fromBufferAttribute(pos, k).applyMatrix4(o.matrixWorld);
        positions.push(v.x, v.y, v.z);
      }
    });
    return { positions, scale, bytes };
  };

  window.surfdeformTest = {
    // Resolves once no request of the page is in flight or waiting.
    whenIdle: () => scheduler.whenIdle(),
    snapshot: () => snapshot(store.state),
    // The names of the last actions dispatched, oldest first.
    actions: () => store.recentActions(),
    history: () => page.history(),
    deformRequest: () => readableJson(page.deformRequest()),
    // The flat sheet as the sheet view holds it.
    sheet: () => sheetView.sheet,
    // The placement's centre moved to `center` on the sheet, as a drag's release does.
    placeAt: (center) => {
      store.dispatch('placed', { center });
      page.scheduleDeform(0);
    },
    // The surface parameters (u, v) under the placement's centre, from the
    // current field (bilinear, as the preview samples it).
    placementParams: () => {
      const { field, placement } = store.state;
      return field && placement.center ? sampleParams(field, ...placement.center) : null;
    },
    // SHA-256 (hex) of the exact result of what the page shows, as it asks for it.
    exactDigest: async () => {
      const { model } = store.state;
      const params = page.deformParams('glb', 'meshopt');
      const { bytes } = await deform(model.bytes, model.name, params, 'model/gltf-binary');
      const hash = new Uint8Array(await crypto.subtle.digest('SHA-256', bytes));
      return [...hash].map((b) => b.toString(16).padStart(2, '0')).join('');
    },
    // The current deformation as the viewer receives it (meshopt GLB)
    // against the Draco GLB of the same request: every vertex of each lies
    // within the two quantizations of the other (Draco's 14-bit positions
    // over its bounding box, meshopt's over the node's scale).
    compareEncodings: async () => {
      const meshopt = await decoded('meshopt');
      const draco = await decoded('draco');
      const lo = [Infinity, Infinity, Infinity],
        hi = [-Infinity, -Infinity, -Infinity];
      for (let k = 0; k < draco.positions.length; ++k) {
        lo[k % 3] = Math.min(lo[k % 3], draco.positions[k]);
        hi[k % 3] = Math.max(hi[k % 3], draco.positions[k]);
      }
      const dracoStep = Math.max(...hi.map((h, c) => h - lo[c])) / (2 ** 14 - 1);
      const meshoptStep = meshopt.scale / 32767;
      const bound = (Math.sqrt(3) / 2) * (dracoStep + meshoptStep);
      const all = 1e9; // every vertex, not a sample
      const there = nearestDistances(meshopt.positions, draco.positions, bound, all);
      const back = nearestDistances(draco.positions, meshopt.positions, bound, all);
      return {
        worst: Math.max(there.max, back.max),
        bound,
        dracoStep,
        meshoptStep,
        vertices: [meshopt.positions.length / 3, draco.positions.length / 3],
        bytes: { meshopt: meshopt.bytes.byteLength, draco: draco.bytes.byteLength },
      };
    },
    // A GLB as three.js decodes it (a large Draco answer comes in pieces):
    // its primitives, their vertices, and how many distinct positions (exact
    // float32 bits) they hold together.
    decodeGlb: async (bytes) => {
      const scene = (await gltf.parseAsync(bytes, '')).scene;
      const distinct = new Set();
      let primitives = 0,
        vertices = 0,
        triangles = 0;
      scene.traverse((o) => {
        if (!o.isMesh) return;
        ++primitives;
        const p = o.geometry.getAttribute('position').array;
        vertices += p.length / 3;
        triangles += o.geometry.index ? o.geometry.index.count / 3 : p.length / 9;
        for (let k = 0; k < p.length; k += 3) distinct.add(`${p[k]},${p[k + 1]},${p[k + 2]}`);
      });
      return { primitives, vertices, triangles, distinct: distinct.size };
    },
    // The current field moved at once with control point `index` raised by
    // `lift` (field_edit.js), against the server's surface of that pose: how
    // far the moved field's points on the sheet lie from it (each mapped onto
    // it by /map's surface_points), how far they moved, and how far they are
    // from the server's field of that pose (which has the edited surface's
    // own sheet) against how far the unmoved field is, all relative to the
    // sheet's diagonal.
    movedFieldOnSurface: async (index, lift) => {
      const { field, fieldSpec, grid, placementSheet } = store.state;
      const after = JSON.parse(JSON.stringify(fieldSpec));
      after.control_points[index][2] += lift;
      const moved = movedField(field, fieldSpec, after);
      const made = await createSurface(
        { surface: after, sampling: { nu: grid, nv: grid }, warm_start: placementSheet },
        field.n,
      );
      const motion = made.warm_start && made.warm_start.motion;
      const points = moved.positions.filter((p, k) => moved.on_sheet[k] && k % 7 === 0);
      const marks = await mapOnSurface(made.id, { surface_points: points });
      const [lo, hi] = moved.bounds;
      const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
      const worst = Math.max(...marks.surface_points.map((m) => m.distance));
      const shift = Math.max(
        ...moved.positions.map((p, k) => Math.hypot(...p.map((x, c) => x - field.positions[k][c]))),
      );
      return {
        points: points.length,
        worst: worst / diagonal,
        shift: shift / diagonal,
        gap: fieldGap(moved, made.field, motion),
        unmoved: fieldGap(field, made.field, motion),
        raw: fieldGap(moved, made.field),
      };
    },
    // One animation frame of the server's against the page's (animation_panel.js).
    compareAnimationFrame: (k) => animationPanel.compareFrame(k),
    // The preview: whether it is shown, its welded mesh, and what it shows
    // now (changes when it moves or gets a new field).
    previewShown: () => preview.mesh.visible,
    previewMesh: () => {
      const g = preview.mesh.geometry;
      const n = g.getAttribute('normal');
      if (!g.index || !n) return null;
      let unit = 0;
      for (let k = 0; k < n.count; ++k) unit += Math.abs(Math.hypot(n.getX(k), n.getY(k), n.getZ(k)) - 1) < 1e-5;
      return { vertices: g.getAttribute('position').count, triangles: g.index.count / 3, unitNormals: unit };
    },
    previewPose: () => {
      const u = preview.uniforms;
      const last = store.state.lastExact;
      return [
        u.sdTarget.value.x,
        u.sdTarget.value.y,
        u.sdScale.value,
        u.sdRotation.value.x,
        u.sdFieldP.value && u.sdFieldP.value.uuid,
        preview.mesh.visible,
        last && last.done_at,
      ].join();
    },
    // The 3D view: frames drawn, its WebGL, the model's pixels, a control
    // point's place on the page, what the GPU holds.
    framesDrawn: () => modelView.drawn,
    software: () => modelView.software,
    standingIn: () => modelView.stoodIn,
    modelCoverage: () => modelCoverage(modelView),
    modelMask: () => modelMask(modelView),
    handlePoint: (k) => handleClientPoint(modelView, k),
    pixelCounts: () => pixelCounts(modelView),
    gpuMemory: () => ({ ...modelView.renderer.info.memory }),
    // The shader programs three.js holds, by id (a new id: one compiled).
    programs: () => modelView.renderer.info.programs.map((p) => p.id),
    texturedMeshes: () => texturedMeshes(modelView),
  };
}
