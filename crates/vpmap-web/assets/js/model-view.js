// The 3D view: the glTF model from /api/build in three.js, with orbit controls, and the
// planned paths on its floor. three.js is loaded on first use (it is large), from the copy
// vendored in assets/vendor/three/ through the page's import map. The scene is rendered on
// demand (after a change or an orbit step), not in a loop.
//
// glTF is +Y up; vpmap stores map point (x, y, z) as (x, z, -y) (docs/map-format.md).

import { cameraGroup } from './model-cameras.js';

let three = null;

async function loadThree() {
  if (!three) {
    three = Promise.all([
      import('three'),
      import('three/addons/loaders/GLTFLoader.js'),
      import('three/addons/controls/OrbitControls.js'),
    ]).then(([THREE, { GLTFLoader }, { OrbitControls }]) => ({ THREE, GLTFLoader, OrbitControls }));
  }
  return three;
}

export class ModelView {
  constructor(host) {
    this.host = host;
    this.ready = null;
    this.model = null;
    this.paths = null;
    // The view is framed on the model until the user orbits, zooms or pans it; and again
    // whenever the model gains its first object or floor (from the camera alone to a room).
    this.userMoved = false;
    this.content = 0;
    this.loads = 0;
    this.pending = 0;
    this.failed = false;
    this.loadSeq = 0;
  }

  async init() {
    if (this.ready) return this.ready;
    this.ready = (async () => {
      const { THREE, OrbitControls } = await loadThree();
      this.THREE = THREE;
      let renderer;
      try {
        renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
      } catch (err) {
        this.failed = true;
        throw new Error(`the 3D view needs WebGL, which this browser cannot provide (${err.message})`);
      }
      renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
      renderer.outputColorSpace = THREE.SRGBColorSpace;
      const canvas = renderer.domElement;
      canvas.setAttribute('aria-label', '3D model of the room');
      canvas.setAttribute('role', 'img');
      canvas.tabIndex = 0;
      this.host.replaceChildren(canvas);
      const scene = new THREE.Scene();
      scene.background = new THREE.Color(0xeef1f4);
      scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 2.2));
      const sun = new THREE.DirectionalLight(0xffffff, 1.6);
      sun.position.set(4, 9, 6);
      scene.add(sun);
      const camera = new THREE.PerspectiveCamera(50, 1, 0.02, 500);
      camera.position.set(0, 4, 6);
      const controls = new OrbitControls(camera, canvas);
      controls.addEventListener('change', () => this.render());
      controls.addEventListener('start', () => {
        this.userMoved = true;
      });
      controls.listenToKeyEvents(canvas);
      controls.maxPolarAngle = Math.PI * 0.495;
      Object.assign(this, { renderer, scene, camera, controls, canvas });
      new ResizeObserver(() => this.resize()).observe(this.host);
      this.resize();
    })();
    return this.ready;
  }

  resize() {
    if (!this.renderer) return;
    const w = Math.max(1, this.host.clientWidth);
    const hgt = Math.max(1, this.host.clientHeight);
    this.renderer.setSize(w, hgt);
    this.camera.aspect = w / hgt;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    if (this.renderer) this.renderer.render(this.scene, this.camera);
  }

  /**
   * Show the model in `glb` (bytes); `content` counts what it shows besides the camera (objects
   * and floor). Frames it while the user has not moved the view and its content changed, or
   * when it changes from empty (the camera only) to something; else keeps the user's viewpoint.
   */
  async setModel(glb, { content = 0 } = {}) {
    const seq = ++this.loadSeq;
    await this.init();
    const { GLTFLoader } = await loadThree();
    const gltf = await new Promise((resolve, reject) => {
      new GLTFLoader().parse(glb.buffer.slice(glb.byteOffset, glb.byteOffset + glb.byteLength), '', resolve, reject);
    });
    if (seq !== this.loadSeq) return; // a newer model arrived meanwhile
    const { THREE } = this;
    if (this.model) {
      this.scene.remove(this.model);
      dispose(this.model);
    }
    this.model = gltf.scene;
    let meshes = 0;
    this.model.traverse((o) => {
      if (o.isMesh) {
        meshes++;
        // Double-sided, so that a floor seen from below or an open prism still shows.
        for (const m of Array.isArray(o.material) ? o.material : [o.material]) m.side = THREE.DoubleSide;
      }
    });
    this.scene.add(this.model);
    this.host.dataset.meshes = String(meshes);
    // A 1-unit grid under the model, a little larger than it.
    const box = new THREE.Box3().setFromObject(this.model);
    if (!box.isEmpty()) {
      const c = box.getCenter(new THREE.Vector3());
      const size = box.getSize(new THREE.Vector3());
      const n = Math.max(2, Math.min(200, 2 * Math.ceil((0.7 * Math.max(size.x, size.z)) + 1)));
      if (this.grid) {
        this.scene.remove(this.grid);
        dispose(this.grid);
      }
      this.grid = new THREE.GridHelper(n, n, 0xb4bcc5, 0xd5dae0);
      this.grid.position.set(Math.round(c.x), -0.003, Math.round(c.z));
      this.scene.add(this.grid);
    }
    const first = this.loads === 0;
    const grew = this.content === 0 && content > 0;
    if (first || grew || (!this.userMoved && content !== this.content)) this.resetView();
    this.content = content;
    this.loads++;
    this.render();
  }

  /** Where the model's bounding box lands in the view: its 8 corners in normalised device coordinates (x, y in -1..1 and z < 1 when in view). */
  framing() {
    if (!this.model) return null;
    const { THREE } = this;
    const box = new THREE.Box3().setFromObject(this.model);
    const corners = [];
    for (const x of [box.min.x, box.max.x]) {
      for (const y of [box.min.y, box.max.y]) {
        for (const z of [box.min.z, box.max.z]) {
          const v = new THREE.Vector3(x, y, z).project(this.camera);
          corners.push([v.x, v.y, v.z]);
        }
      }
    }
    return { loads: this.loads, content: this.content, userMoved: this.userMoved, corners };
  }

  /** Frame the model from behind and above the camera's station point. */
  resetView() {
    this.userMoved = false;
    if (!this.model) return;
    const { THREE } = this;
    const box = new THREE.Box3().setFromObject(this.model);
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    const r = Math.max(size.x, size.z, size.y, 1e-3);
    // Map +y (forward) is glTF -z: stand behind the room (at +z) and look down on it.
    this.camera.position.set(centre.x, centre.y + 0.9 * r, centre.z + 1.05 * r);
    this.camera.near = r / 500;
    this.camera.far = r * 50;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.render();
  }

  /**
   * Draw paths on the floor: `paths` is a list of `{points: [[x, y]...] (map), colour, dashed}`;
   * `markers` a list of `{p: [x, y], colour}`.
   */
  setPaths(paths, markers) {
    if (!this.renderer) return;
    const { THREE } = this;
    if (this.paths) {
      this.scene.remove(this.paths);
      dispose(this.paths);
    }
    const g = new THREE.Group();
    const scale = this.model ? Math.max(new THREE.Box3().setFromObject(this.model).getSize(new THREE.Vector3()).length(), 1) : 10;
    paths.forEach((path, i) => {
      // WebGL draws lines one pixel wide: draw each path as a flat ribbon on the floor instead.
      const geom = ribbon(THREE, path.points, scale * (path.dashed ? 0.0035 : 0.005), 0.006 + 0.002 * i);
      if (geom) g.add(new THREE.Mesh(geom, new THREE.MeshBasicMaterial({ color: path.colour, side: THREE.DoubleSide })));
    });
    for (const m of markers) {
      if (!m.p) continue;
      const r = scale * 0.01;
      const ball = new THREE.Mesh(new THREE.SphereGeometry(r, 16, 12), new THREE.MeshStandardMaterial({ color: m.colour }));
      ball.position.set(m.p[0], r, -m.p[1]);
      g.add(ball);
    }
    this.paths = g;
    this.scene.add(g);
    this.render();
  }

  /**
   * Draw the room's cameras (map.json `cameras`; none for a single photo, whose camera the
   * model itself shows), the camera of photo `active` highlighted.
   */
  setCameras(cameras, active) {
    this.cameraList = cameras;
    this.activeCamera = active;
    if (!this.renderer) return;
    if (this.cameras) {
      this.scene.remove(this.cameras);
      // Not the sprites' geometry: three.js shares one among all sprites.
      this.cameras.traverse((o) => {
        if (!o.isSprite) o.geometry?.dispose?.();
        o.material?.map?.dispose?.();
        o.material?.dispose?.();
      });
      this.cameras = null;
    }
    if (!cameras.length) {
      this.render();
      return;
    }
    const { THREE } = this;
    const size = this.model ? new THREE.Box3().setFromObject(this.model).getSize(new THREE.Vector3()) : null;
    const depth = Math.max(0.15, 0.08 * (size ? Math.max(size.x, size.z) : 4));
    this.cameras = cameraGroup(THREE, cameras, active, depth);
    this.scene.add(this.cameras);
    this.host.dataset.cameras = String(this.cameras.children.filter((o) => o.isLineSegments).length);
    this.render();
  }

  markStale(stale) {
    this.host.classList.toggle('stale', stale);
  }
}

/** A flat strip of width `w` along a map polyline, `lift` above the floor (glTF frame). */
function ribbon(THREE, points, w, lift) {
  const pts = points.filter((p) => Number.isFinite(p[0]) && Number.isFinite(p[1]));
  if (pts.length < 2) return null;
  const pos = [];
  for (let i = 0; i + 1 < pts.length; i++) {
    const [x0, y0] = pts[i], [x1, y1] = pts[i + 1];
    const len = Math.hypot(x1 - x0, y1 - y0);
    if (!(len > 0)) continue;
    // Perpendicular in the map plane, half width; extend each piece by half a width to close joints.
    const nx = (-(y1 - y0) / len) * (w / 2), ny = ((x1 - x0) / len) * (w / 2);
    const ex = ((x1 - x0) / len) * (w / 2), ey = ((y1 - y0) / len) * (w / 2);
    const a = [x0 - ex + nx, y0 - ey + ny], b = [x0 - ex - nx, y0 - ey - ny];
    const c = [x1 + ex + nx, y1 + ey + ny], d = [x1 + ex - nx, y1 + ey - ny];
    for (const p of [a, b, c, c, b, d]) pos.push(p[0], lift, -p[1]);
  }
  if (!pos.length) return null;
  const geom = new THREE.BufferGeometry();
  geom.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  return geom;
}

function dispose(obj) {
  obj.traverse((o) => {
    o.geometry?.dispose?.();
    const mats = Array.isArray(o.material) ? o.material : o.material ? [o.material] : [];
    for (const m of mats) {
      for (const v of Object.values(m)) if (v && v.isTexture) v.dispose();
      m.dispose();
    }
  });
}
