// The animation panel: the model along a moving surface (the paper's
// swimming wave, or a Bezier that bends and unbends), as one GLB of morph
// targets from POST /v1/animate, played by three.js's AnimationMixer, with
// play, pause and scrub, the fps the page achieves and the server's
// per-frame timings. document.body.dataset.animation is "loading",
// "playing", "paused" or "error" (tests wait on it).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

import { animate, deform } from './api.js';
import { surfacePreset } from './samples.js';
import { scheduler } from './scheduler.js';
import { shownPositions } from './view_probes.js';

const $ = (id) => document.getElementById(id);
const fmt = (x, digits) => Number(x).toPrecision(digits);

// Animation presets: {keyframes, interpolation} (frames and fps from the panel).
export async function animationPreset(name) {
  if (name === 'swim') {
    // The paper's Figures 12-13: a travelling wave; one key, its time advances.
    // Speed 1 over wavelength 2: 60 frames at 30 fps are one period (it loops).
    return {
      keyframes: [
        { time: 0, surface: { kind: 'wave', length: 4, width: 1.5, amplitude: 0.25, wavelength: 2, speed: 1 } },
      ],
    };
  }
  // Figure 10's Bezier bending and unbending: its heights x0.3, x1, x0.3.
  const fig10 = await surfacePreset('figure10');
  const scaled = (k) => ({ ...fig10, control_points: fig10.control_points.map(([x, y, z]) => [x, y, z * k]) });
  return {
    keyframes: [
      { time: 0, surface: scaled(0.3) },
      { time: 1, surface: fig10 },
      { time: 2, surface: scaled(0.3) },
    ],
    interpolation: 'cubic',
  };
}

export class AnimationPanel {
  // modelView: the 3D view; request(): {model, placement} for the request;
  // onError(e) shows an error.
  constructor(modelView, request, onError) {
    this.modelView = modelView;
    this.request = request;
    this.onError = onError;
    this.loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
    this.action = null;
    this.params = null; // the last request's parameters
    this.frames = 0;
    this.fps = 30;
    $('anim-run').addEventListener('click', () => this.run());
    $('anim-play').addEventListener('click', () => (this.playing() ? this.pause() : this.play()));
    $('anim-scrub').addEventListener('input', () => this.scrub(Number($('anim-scrub').value)));
    setInterval(() => this.showFps(), 500);
  }

  setState(s) {
    document.body.dataset.animation = s;
  }
  playing() {
    return this.action && !this.action.paused;
  }

  async run() {
    const { model, placement } = this.request();
    if (!model) return;
    this.setState('loading');
    try {
      const anim = await animationPreset($('anim-preset').value);
      anim.frames = Math.max(2, Math.min(600, Number($('anim-frames').value) || 60));
      anim.fps = Math.max(1, Math.min(120, Number($('anim-fps').value) || 30));
      this.params = {
        animation: anim,
        sampling: { nu: 16, nv: 16 },
        placement,
        subdivision: { mode: 'adaptive' },
        output: { compression: 'meshopt' },
      };
      const t0 = performance.now();
      // The "animation" lane: a newer Play aborts this one's request.
      const sent = await scheduler.run('animation', (signal) => animate(model.bytes, model.name, this.params, signal));
      if (!sent.done) return;
      const { bytes, stats, timing } = sent.value;
      const gltf = await this.loader.parseAsync(bytes, '');
      const mixer = new THREE.AnimationMixer(gltf.scene);
      this.action = mixer.clipAction(gltf.animations[0]);
      this.action.play();
      this.frames = anim.frames;
      this.fps = anim.fps;
      this.modelView.setModel(gltf.scene, { mixer });
      $('anim-scrub').max = String(this.frames - 1);
      $('anim-scrub').disabled = false;
      $('anim-play').disabled = false;
      $('anim-play').textContent = 'Pause';
      const each = stats.flatten?.each || [];
      const flatten = each.length ? each.reduce((a, f) => a + f.ms, 0) / each.length : 0;
      const per = (k) => `${fmt((timing[k] || 0) / this.frames, 3)} ms`;
      this.info = [
        ['frames', `${this.frames} at ${this.fps} fps, ${stats.vertices} vertices`],
        [
          'per frame',
          `flatten ${fmt(flatten, 3)} ms (${stats.flatten?.iterations_warm_mean?.toFixed(1)} ` +
            `iterations warm, ${stats.flatten?.iterations_first} cold), subdivide ${per('subdivide')}, ` +
            `deform ${per('deform')}, encode ${per('encode')}`,
        ],
        ['server', `${fmt(timing.total || 0, 3)} ms, ${stats.cached ? 'sheets cached' : 'sheets flattened'}`],
        [
          'download',
          `${(bytes.byteLength / 1024).toFixed(0)} KiB (meshopt), round trip ` + `${fmt(performance.now() - t0, 3)} ms`,
        ],
      ];
      this.showFps();
      this.onError(null);
      this.setState('playing');
    } catch (e) {
      this.setState('error');
      this.onError(e);
    }
  }

  play() {
    if (!this.action) return;
    this.action.paused = false;
    $('anim-play').textContent = 'Pause';
    this.setState('playing');
  }

  pause() {
    if (!this.action) return;
    this.action.paused = true;
    $('anim-play').textContent = 'Play';
    this.setState('paused');
  }

  // Shows frame k (paused): the mixer at time k / fps.
  scrub(k) {
    if (!this.action) return;
    this.pause();
    this.action.time = k / this.fps;
    this.modelView.mixer?.update(0);
    $('anim-scrub').value = String(k);
  }

  showFps() {
    if (!this.info) return;
    const dl = $('anim-info');
    dl.replaceChildren();
    const rows = [['achieved', `${this.modelView.achievedFps().toFixed(0)} fps drawn`], ...this.info];
    for (const [k, v] of rows) {
      const dt = document.createElement('dt');
      dt.textContent = k;
      const dd = document.createElement('dd');
      dd.textContent = v;
      dl.append(dt, dd);
    }
    if (this.action && !this.action.paused) {
      $('anim-scrub').value = String(Math.round(this.action.time * this.fps) % this.frames);
    }
  }

  // For tests: frame k as shown (scrubbed there) against frame k alone from
  // POST /v1/deform; {worst, step, weights}.
  async compareFrame(k) {
    this.scrub(k);
    const shown = shownPositions(this.modelView.model);
    const { model } = this.request();
    const params = { ...this.params, frame: k, output: { format: 'glb_plain' } };
    const { bytes } = await deform(model.bytes, model.name, params, 'model/gltf-binary');
    const scene = (await this.loader.parseAsync(bytes, '')).scene;
    scene.updateMatrixWorld(true);
    const alone = [];
    const v = new THREE.Vector3();
    scene.traverse((o) => {
      if (!o.isMesh) return;
      const pos = o.geometry.getAttribute('position');
      for (let i = 0; i < pos.count; ++i) {
        v.fromBufferAttribute(pos, i).applyMatrix4(o.matrixWorld);
        alone.push(v.x, v.y, v.z);
      }
    });
    let worst = shown.length === alone.length ? 0 : Infinity;
    for (let i = 0; i < Math.min(shown.length, alone.length); ++i) {
      worst = Math.max(worst, Math.abs(shown[i] - alone[i]));
    }
    let node = null;
    this.modelView.model.traverse((o) => {
      if (o.isMesh && !node) node = o;
    });
    const scale = node.getWorldScale(new THREE.Vector3()).x;
    return { worst, step: scale / 32767, weights: [...(node.morphTargetInfluences || [])] };
  }
}
