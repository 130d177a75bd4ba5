// Measurements of the 3D view (model_view.js) that a person sees and a
// script cannot read from the DOM: the model's vertices as drawn, the
// canvas's pixels by colour, where a control point is on the page.
import * as THREE from 'three';

// The positions the model shows now, in world space: each mesh's base with
// its morph targets at their current weights (as the GPU morphs them),
// through its world matrix. One flat array over the model's meshes.
export function shownPositions(model) {
  const out = [];
  const v = new THREE.Vector3();
  model?.updateMatrixWorld(true);
  model?.traverse((o) => {
    if (!o.isMesh) return;
    const pos = o.geometry.getAttribute('position');
    const targets = o.geometry.morphAttributes.position || [];
    const weights = o.morphTargetInfluences || [];
    const relative = o.geometry.morphTargetsRelative;
    for (let k = 0; k < pos.count; ++k) {
      v.fromBufferAttribute(pos, k);
      const base = targets.length ? v.clone() : v;
      targets.forEach((t, j) => {
        const w = weights[j] || 0;
        if (!w) return;
        const d = new THREE.Vector3().fromBufferAttribute(t, k);
        v.addScaledVector(relative ? d : d.sub(base), w);
      });
      v.applyMatrix4(o.matrixWorld);
      out.push(v.x, v.y, v.z);
    }
  });
  return out;
}

// The canvas's RGBA pixels as drawn last.
function canvasPixels(view) {
  const src = view.renderer.domElement;
  const c = document.createElement('canvas');
  c.width = src.width;
  c.height = src.height;
  const ctx = c.getContext('2d');
  ctx.drawImage(src, 0, 0);
  return { px: ctx.getImageData(0, 0, c.width, c.height).data, width: c.width, height: c.height };
}

// Counts of the canvas's pixels by hue: {warm, red, blue, green, total}.
// warm is the model's plain colour; red and blue the distortion map's
// ends; green the marks.
export function pixelCounts(view) {
  const { px } = canvasPixels(view);
  const n = { warm: 0, red: 0, blue: 0, green: 0, total: px.length / 4 };
  for (let k = 0; k < px.length; k += 4) {
    const [r, g, b] = [px[k], px[k + 1], px[k + 2]];
    if (r - b > 30) ++n.warm;
    if (r - g > 60 && r - b > 60) ++n.red;
    if (b - r > 60 && b - g > 60) ++n.blue;
    if (g - r > 60 && g - b > 60) ++n.green;
  }
  return n;
}

// Where control point k is drawn, in client (CSS pixel) coordinates; null
// without one.
export function handleClientPoint(view, k) {
  const h = view.handles.children[k];
  if (!h) return null;
  const v = h.position.clone().project(view.camera);
  const r = view.renderer.domElement.getBoundingClientRect();
  return [r.left + ((v.x + 1) / 2) * r.width, r.top + ((1 - v.y) / 2) * r.height];
}

// Which pixels show the model (its warm colour, or the preview's tint),
// every `step`-th pixel each way: an array of 0 and 1.
export function modelMask(view, step = 4) {
  const { px, width, height } = canvasPixels(view);
  const mask = [];
  for (let y = 0; y < height; y += step) {
    for (let x = 0; x < width; x += step) {
      const k = 4 * (x + width * y);
      mask.push(px[k] - px[k + 2] > 30 ? 1 : 0);
    }
  }
  return mask;
}

// Meshes of the model drawn with a texture whose image three.js decoded.
export function texturedMeshes(view) {
  let n = 0;
  view.model?.traverse((o) => {
    const image = o.isMesh && o.material.map && o.material.map.image;
    if (image && (image.width || image.naturalWidth) > 0) ++n;
  });
  return n;
}

// The share of the canvas (0..1) that shows the model: its warm colour,
// unlike the background and the bluish surface.
export function modelCoverage(view) {
  const n = pixelCounts(view);
  return n.warm / n.total;
}
