// What the 3D view (model_view.js) holds on the GPU and how it is released,
// the distortion map's colours, and whether WebGL is drawn by the CPU.
import * as THREE from 'three';

// Per vertex, the sheet view's colour scale: white where lengths keep, towards
// red where the larger change stretches, towards blue where it shrinks; full
// colour at |log s| = spread. `d` holds (s1 - 1, s2 - 1).
export function distortionColours(d, spread) {
  const rgb = new Float32Array(3 * d.count);
  for (let k = 0; k < d.count; ++k) {
    const a = Math.log1p(d.getX(k)),
      b = Math.log1p(d.getY(k));
    const x = Math.max(-1, Math.min(1, (Math.abs(a) >= Math.abs(b) ? a : b) / spread));
    const w = 1 - Math.abs(x);
    rgb.set(x > 0 ? [1, w, w] : [w, w, 1], 3 * k);
  }
  // The sheet's colours are sRGB; three.js lights in linear space.
  const c = new THREE.Color();
  for (let k = 0; k < d.count; ++k) {
    c.setRGB(rgb[3 * k], rgb[3 * k + 1], rgb[3 * k + 2], THREE.SRGBColorSpace);
    rgb.set([c.r, c.g, c.b], 3 * k);
  }
  return new THREE.BufferAttribute(rgb, 3);
}

// Frees what `object` holds on the GPU (geometries, materials, their
// textures): three.js keeps a geometry's buffers until it is disposed, and
// a control-point drag replaces the surface at every pointer move. The
// view's own materials (keptMaterial) stay: disposing a material releases
// its shader program, and the next object drawn with the same kind of
// material compiled it again (SwiftShader: tens of ms a pointer move).
export function disposeObject(object) {
  object.traverse((o) => {
    if (o.geometry) o.geometry.dispose();
    for (const m of [o.material || []].flat()) {
      if (m.userData.kept) continue;
      if (m.map) m.map.dispose();
      m.dispose();
    }
  });
}

// A material the view keeps for every object of one role (the surface, the
// handles, the model's plain and distortion colours), never disposed.
export function keptMaterial(material) {
  material.userData.kept = true;
  return material;
}

// Whether WebGL here is drawn by the CPU (SwiftShader, llvmpipe).
export function softwareWebGl() {
  try {
    const gl = document.createElement('canvas').getContext('webgl2');
    const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
    const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : '';
    gl?.getExtension('WEBGL_lose_context')?.loseContext();
    return /swiftshader|llvmpipe|softpipe|software/i.test(name);
  } catch {
    return false;
  }
}
