// The 3D view (three.js): the surface, its Bezier control points (draggable),
// and the deformed model the server returned, with orbit controls.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { meshesOf } from './footprint.js';
import { computeNormals } from './vertex_normals.js';
import { disposeObject, distortionColours, keptMaterial, softwareWebGl } from './view_resources.js';

export class ModelView {
  // onControlPoint(index, [x, y, z], final) when the person drags a control point.
  constructor(container, onControlPoint) {
    this.container = container;
    this.onControlPoint = onControlPoint;
    // preserveDrawingBuffer: tests (and screenshots) read the canvas's pixels.
    // Software WebGL draws without multisampling: it halves the frame's time
    // there (6.5 -> 14.4 fps for the bunny in Chromium's SwiftShader), and
    // every pointer move and reply waits for the frame.
    this.software = softwareWebGl();
    this.renderer = new THREE.WebGLRenderer({ antialias: !this.software, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xeef1f4);
    this.camera = new THREE.PerspectiveCamera(40, 4 / 3, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(3, -4, 3);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x666677, 2.0));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(2, -3, 5);
    this.scene.add(sun);
    this.surface = null;
    this.model = null;
    this.materials = {
      // Lambert, not the standard (physically based) material: at its default
      // roughness of 1 they look alike, and the translucent surface covers
      // most of the view, drawn twice (both sides): with software WebGL it
      // was 70% of a frame of the word sample (29 -> 19 ms a frame).
      surface: keptMaterial(
        new THREE.MeshLambertMaterial({
          color: 0x88aacc,
          transparent: true,
          opacity: 0.35,
          side: THREE.DoubleSide,
          depthWrite: false,
        }),
      ),
      handle: keptMaterial(new THREE.MeshStandardMaterial({ color: 0xff8822 })),
      selected: keptMaterial(new THREE.MeshStandardMaterial({ color: 0xcc2266 })),
      mark: keptMaterial(new THREE.LineBasicMaterial({ color: 0x00aa00, depthTest: false })),
      model: keptMaterial(new THREE.MeshStandardMaterial({ color: 0xd9b38c, roughness: 0.6, side: THREE.DoubleSide })),
      distortion: keptMaterial(
        new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.6, side: THREE.DoubleSide }),
      ),
    };
    this.marks = new THREE.Group(); // polylines on the surface
    this.scene.add(this.marks);
    this.handles = new THREE.Group();
    this.scene.add(this.handles);
    this.selected = -1; // the control point last pressed (its numbers are shown), or -1
    this.onSelect = () => {};
    this.framed = false;
    this.raycaster = new THREE.Raycaster();
    const el = this.renderer.domElement;
    el.addEventListener('pointerdown', (e) => this.down(e));
    el.addEventListener('pointermove', (e) => this.move(e));
    el.addEventListener('pointerup', (e) => this.up(e));
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    this.mixer = null; // an animation's AnimationMixer, when one plays
    this.clock = new THREE.Clock();
    this.rendered = []; // the times of the last frames drawn, for the achieved fps
    this.drawn = 0; // frames drawn since the page opened
    // A frame is drawn only when something shown changed (every method below
    // that changes the scene, the camera, a playing animation, the preview's
    // uniforms) or the view was resized. With software WebGL a frame holds
    // the page for ~70 ms; drawn at every display frame while nothing moved,
    // it made every reply's await wait for one (release to exact: the
    // server's 14 ms took ~290 ms to reach the page).
    this.dirty = true;
    this.controls.addEventListener('change', () => this.invalidate());
    // While the view is orbited, panned or zoomed with software WebGL, the
    // live preview (simplified: preview_mesh.js) stands in for the exact
    // model shown, in the plain colour (the preview has no distortion map
    // and no texture), where the page says it may (`standInAllowed`: the
    // preview is of the same surface and placement, and much lighter): a
    // million-triangle exact result drew ~5 frames a second orbiting. The
    // exact model is drawn again 150 ms after the view stops (the wheel's
    // events each start and end).
    this.standInAllowed = () => false;
    this.standIn = false; // decided as the view starts moving
    this.navigating = false; // the view is being moved
    this.stoodIn = false; // the last frame drawn showed the stand-in
    this.controls.addEventListener('start', () => {
      clearTimeout(this.navigationEnd);
      if (!this.navigating) {
        this.standIn =
          this.software &&
          Boolean(this.model) &&
          !this.distortionSpread &&
          meshesOf(this.model).every((o) => o.material === this.materials.model) &&
          this.standInAllowed();
      }
      this.navigating = true;
    });
    this.controls.addEventListener('end', () => {
      clearTimeout(this.navigationEnd);
      this.navigationEnd = setTimeout(() => {
        this.navigating = false;
        if (this.stoodIn) this.invalidate();
      }, 150);
    });
    this.renderer.setAnimationLoop(() => {
      const dt = this.clock.getDelta();
      if (this.mixer) {
        this.mixer.update(dt);
        this.dirty = true;
      }
      this.controls.update();
      if (!this.dirty) return;
      this.dirty = false;
      // A control point's drag starts the controls too (they see the press
      // first): not a navigation.
      const standIn =
        this.standIn &&
        this.navigating &&
        !this.drag &&
        this.model &&
        this.model.visible &&
        this.preview &&
        !this.preview.visible &&
        !this.mixer;
      if (standIn) {
        this.model.visible = false;
        this.preview.visible = true;
      }
      this.renderer.render(this.scene, this.camera);
      if (standIn) {
        this.model.visible = true;
        this.preview.visible = false;
      }
      this.stoodIn = Boolean(standIn);
      ++this.drawn;
      this.rendered.push(performance.now());
      if (this.rendered.length > 60) this.rendered.shift();
    });
  }

  // Something shown changed: draw at the next display frame.
  invalidate() {
    this.dirty = true;
  }

  resize() {
    this.invalidate();
    const w = this.container.clientWidth || 480;
    const h = this.container.clientHeight || Math.round((w * 3) / 4);
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // The sampled surface (points u fastest), a translucent sheet; `keep`
  // (optional, per quad) leaves quads out.
  setSurface(points, nu, nv, keep = null) {
    const index = [];
    for (let j = 0; j + 1 < nv; ++j) {
      for (let i = 0; i + 1 < nu; ++i) {
        const a = i + nu * j,
          b = a + 1,
          c = a + nu + 1,
          d = a + nu;
        if (!keep || keep(a, b, c, d)) index.push(a, b, c, a, c, d);
      }
    }
    this.setSurfaceMesh(points, index);
  }

  // The surface as triangles: points [x, y, z] and a flat index list (a
  // surface given as a mesh is drawn as its own triangles).
  setSurfaceMesh(points, index) {
    this.invalidate();
    if (this.surface) {
      this.scene.remove(this.surface);
      disposeObject(this.surface);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(points.flat(), 3));
    geometry.setIndex(index);
    geometry.computeVertexNormals();
    this.surface = new THREE.Mesh(geometry, this.materials.surface);
    this.scene.add(this.surface);
    if (!this.framed) this.frame(this.surface);
  }

  // The surface from a field (GET /v1/surfaces/{id}/field): its lattice
  // cells on the sheet. Drawn while a control point is dragged, before the
  // sheet's own samples arrive.
  setSurfaceFromField(field) {
    const on = field.on_sheet;
    this.setSurface(field.positions, field.n, field.n, (a, b, c, d) => on[a] && on[b] && on[c] && on[d]);
  }

  // The live preview's mesh (preview.js): added once, shown in place of the
  // exact model while the person edits.
  setPreview(mesh) {
    this.invalidate();
    this.preview = mesh;
    mesh.visible = false;
    this.scene.add(mesh);
  }

  showPreview(on) {
    this.invalidate();
    if (on) this.standIn = false; // a live edit: the exact model shown is stale
    if (!this.preview) return;
    this.preview.visible = on;
    if (this.model) this.model.visible = !on;
  }

  // Marks on the surface: polylines of {point, normal}, drawn a hair above
  // it (along the normal) so that the surface does not hide them.
  setMarks(polylines) {
    this.invalidate();
    disposeObject(this.marks);
    this.marks.clear();
    if (!this.surface) return;
    const size = new THREE.Box3().setFromObject(this.surface).getSize(new THREE.Vector3()).length();
    const lift = 0.003 * size;
    const material = this.materials.mark;
    for (const line of polylines) {
      const xyz = line.flatMap((m) => m.point.map((x, i) => x + lift * m.normal[i]));
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.Float32BufferAttribute(xyz, 3));
      const drawn = new THREE.Line(geometry, material);
      drawn.renderOrder = 1;
      this.marks.add(drawn);
    }
  }

  // Bezier control points as draggable handles (an empty list hides them).
  setControlPoints(points) {
    this.invalidate();
    disposeObject(this.handles);
    this.handles.clear();
    if (!points.length) return;
    const box = new THREE.Box3().setFromArray(points.flat());
    const r = 0.015 * box.getSize(new THREE.Vector3()).length();
    const geometry = new THREE.SphereGeometry(r, 12, 8);
    if (this.selected >= points.length) this.selected = -1;
    points.forEach((p, k) => {
      const s = new THREE.Mesh(geometry, this.handleMaterial(k));
      s.position.set(...p);
      s.userData.index = k;
      this.handles.add(s);
    });
  }

  // The deformed model (a three.js object from the GLB the server sent);
  // with distortion, coloured by its _DISTORTION attribute.
  setModel(object, { distortion = false, mixer = null } = {}) {
    this.invalidate();
    this.standIn = false; // a new exact model: asked again when the view next moves
    if (this.model && this.model !== object) {
      this.scene.remove(this.model);
      disposeObject(this.model);
    }
    this.model = object;
    if (this.preview) this.preview.visible = false; // the exact result replaces the preview
    this.mixer = mixer; // null stops an animation that was playing
    // The static surface does not move with an animation: hidden meanwhile.
    for (const o of [this.surface, this.handles, this.marks]) if (o) o.visible = !mixer;
    const meshes = meshesOf(object);
    const colour = distortion && meshes.every((o) => o.geometry.getAttribute('_distortion'));
    // One scale for the whole model: its largest |log s|, as the sheet's
    // colours span its largest |log area ratio|.
    let spread = 0.01;
    if (colour) {
      for (const o of meshes) {
        const d = o.geometry.getAttribute('_distortion');
        for (let k = 0; k < d.count; ++k) {
          spread = Math.max(spread, Math.abs(Math.log1p(d.getX(k))), Math.abs(Math.log1p(d.getY(k))));
        }
      }
    }
    for (const o of meshes) {
      if (!o.geometry.getAttribute('normal')) computeNormals(o.geometry);
      if (colour) {
        o.geometry.setAttribute('color', distortionColours(o.geometry.getAttribute('_distortion'), spread));
        o.material = this.materials.distortion;
      } else if (o.material && o.material.map) {
        // textured: the model's own texture
        o.material = new THREE.MeshStandardMaterial({ map: o.material.map, roughness: 0.6, side: THREE.DoubleSide });
      } else {
        o.material = this.materials.model;
      }
    }
    this.distortionSpread = colour ? spread : null;
    this.scene.add(object);
    if (!this.framed) {
      this.frame(object);
      this.framed = true;
    }
  }

  // Frames drawn per second, over the last second or so.
  achievedFps() {
    const t = this.rendered;
    return t.length > 1 ? ((t.length - 1) * 1000) / (t[t.length - 1] - t[0]) : 0;
  }

  // The camera on `object` with the rest of the scene: the surface and the
  // model together (a name a few mm long on a large surface shows the
  // surface round it), from the default side, or, for a model well off the
  // surface's middle (a name round a bottle), from the model's own side, not
  // through the surface from the far one.
  frame(object) {
    this.invalidate();
    const box = new THREE.Box3().setFromObject(object);
    for (const o of [this.surface, this.model]) {
      if (o && o !== object && o.parent) box.union(new THREE.Box3().setFromObject(o));
    }
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    if (!isFinite(sphere.radius) || sphere.radius === 0) return;
    this.controls.target.copy(sphere.center);
    let dir = new THREE.Vector3(0.5, -0.8, 0.6).normalize();
    if (this.model && this.surface && this.model.parent && this.surface.parent) {
      const surface = new THREE.Box3().setFromObject(this.surface);
      const model = new THREE.Box3().setFromObject(this.model);
      const away = model.getCenter(new THREE.Vector3()).sub(surface.getCenter(new THREE.Vector3()));
      const size = surface.getBoundingSphere(new THREE.Sphere()).radius;
      if (away.length() > 0.25 * size) dir = away.normalize().multiplyScalar(2).add(dir).normalize();
    }
    this.camera.position.copy(sphere.center).addScaledVector(dir, sphere.radius * 2.6);
    this.camera.near = sphere.radius / 100;
    this.camera.far = sphere.radius * 100;
    this.camera.updateProjectionMatrix();
  }

  pointer(e) {
    const r = this.renderer.domElement.getBoundingClientRect();
    return new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  }

  down(e) {
    if (!this.handles.children.length) return;
    this.raycaster.setFromCamera(this.pointer(e), this.camera);
    const hit = this.raycaster.intersectObjects(this.handles.children)[0];
    if (!hit) return;
    this.controls.enabled = false;
    this.select(hit.object.userData.index);
    const size = new THREE.Box3().setFromObject(this.handles).getSize(new THREE.Vector3()).length();
    this.drag = { handle: hit.object, y: e.clientY, z: hit.object.position.z, size };
    this.renderer.domElement.setPointerCapture(e.pointerId);
  }

  move(e) {
    if (!this.drag) return;
    const h = this.drag.handle;
    if (e.shiftKey) {
      // sideways: on the horizontal plane through the point
      this.raycaster.setFromCamera(this.pointer(e), this.camera);
      const plane = new THREE.Plane(new THREE.Vector3(0, 0, 1), -h.position.z);
      const p = this.raycaster.ray.intersectPlane(plane, new THREE.Vector3());
      if (p) h.position.set(p.x, p.y, h.position.z);
    } else {
      // up and down
      h.position.z = this.drag.z + ((this.drag.y - e.clientY) / 200) * this.drag.size * 0.25;
    }
    this.invalidate();
    this.onControlPoint(h.userData.index, h.position.toArray(), false);
  }

  handleMaterial(k) {
    return k === this.selected ? this.materials.selected : this.materials.handle;
  }

  // Control point `k` shown as the selected one (-1: none), and onSelect told.
  select(k) {
    this.selected = k;
    for (const h of this.handles.children) h.material = this.handleMaterial(h.userData.index);
    this.invalidate();
    this.onSelect(k);
  }

  up() {
    if (!this.drag) return;
    const h = this.drag.handle;
    this.drag = null;
    this.controls.enabled = true;
    this.onControlPoint(h.userData.index, h.position.toArray(), true);
  }
}
