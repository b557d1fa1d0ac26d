// The 3D viewport: renderer, camera, OrbitControls, lights, GLB loading (Draco through the vendored decoder), and an
// optional second mesh drawn beside the result (two halves, one camera) or instead of it.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';

export class Viewer {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(0x1b1d22);
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
    this.camera.position.set(3, 2, 4);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => this.render());

    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x444455, 1.6));
    const key = new THREE.DirectionalLight(0xffffff, 1.8);
    key.position.set(3, 5, 4);
    this.camera.add(key);
    this.scene.add(this.camera);

    this.material = new THREE.MeshStandardMaterial({ color: 0x9fb7d6, roughness: 0.55, metalness: 0.05,
                                                     side: THREE.DoubleSide, flatShading: false });
    this.root = new THREE.Group();      // the model, in the model's own frame (see setUpAxis)
    this.scene.add(this.root);
    this.result = null;                 // the mesh from the service
    this.overlay = new THREE.Group();   // control net / cage, in the same frame as the result
    this.root.add(this.overlay);
    this.second = null;                 // a second mesh to compare with the result (see setSecond)
    this.secondMaterial = this.material.clone();
    this.secondMaterial.color.set(0xd6bf9f);
    this.layout = 'split';              // with a second mesh: 'split' (result left, second right), 'first', 'second'
    this.labels = document.createElement('div');
    this.labels.className = 'view-labels';
    this.labels.hidden = true;
    container.appendChild(this.labels);

    const draco = new DRACOLoader();
    draco.setDecoderPath(new URL('../vendor/draco/', import.meta.url).href);
    this.loader = new GLTFLoader();
    this.loader.setDRACOLoader(draco);

    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  resize() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.updateAspect();
    this.render();
  }

  split() { return this.second !== null && this.layout === 'split'; }

  /** The camera's aspect: the canvas's, or a half's when split. */
  updateAspect() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    const aspect = this.split() ? Math.floor(w / 2) / h : w / h;
    if (this.camera.aspect !== aspect) {
      this.camera.aspect = aspect;
      this.camera.updateProjectionMatrix();
    }
  }

  /** Draws at the next animation frame; several calls in one frame draw once (dragging must not queue renders). */
  render() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.draw();
    });
  }

  draw() {
    const r = this.renderer;
    this.updateAspect();
    const show = (first, second) => {
      if (this.result) this.result.visible = first;
      if (this.second) this.second.visible = second;
    };
    if (!this.split()) {
      show(!this.second || this.layout !== 'second', this.layout === 'second');
      r.render(this.scene, this.camera);
      return;
    }
    // one camera, two halves of the canvas (viewport and scissor in CSS pixels)
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    const half = Math.floor(w / 2);
    r.setScissorTest(true);
    show(true, false);
    r.setViewport(0, 0, half, h);
    r.setScissor(0, 0, half, h);
    r.render(this.scene, this.camera);
    show(false, true);
    r.setViewport(half, 0, w - half, h);
    r.setScissor(half, 0, w - half, h);
    r.render(this.scene, this.camera);
    r.setScissorTest(false);
    r.setViewport(0, 0, w, h);
    show(true, true);
  }

  /** Z-up data (the teapot) is shown Y-up. */
  setUpAxis(zUp) {
    this.root.rotation.set(zUp ? -Math.PI / 2 : 0, 0, 0);
    this.root.updateMatrixWorld(true);
  }

  /** Parses GLB bytes into one BufferGeometry (the service returns a single mesh primitive). */
  async parseGlb(bytes) {
    const gltf = await this.loader.parseAsync(bytes, '');
    let geometry = null;
    gltf.scene.traverse((o) => { if (!geometry && o.isMesh) geometry = o.geometry; });
    if (!geometry) throw new Error('the GLB has no mesh');
    if (!geometry.attributes.normal) geometry.computeVertexNormals();
    return geometry;
  }

  /** Shows `geometry` as the result, replacing the previous one. */
  setGeometry(geometry, { fit = false } = {}) {
    if (this.result) {
      this.root.remove(this.result);
      this.result.geometry.dispose();
    }
    this.result = geometry ? new THREE.Mesh(geometry, this.material) : null;
    if (this.result) this.root.add(this.result);
    if (fit) this.fit();
    this.render();
  }

  /** Shows `geometry` as the second mesh (null: none), drawn as setLayout says, in its own colour. */
  setSecond(geometry) {
    if (this.second) {
      this.root.remove(this.second);
      this.second.geometry.dispose();
    }
    this.second = geometry ? new THREE.Mesh(geometry, this.secondMaterial) : null;
    if (this.second) this.root.add(this.second);
    this.showLabels();
    this.render();
  }

  /** With a second mesh: 'split' (the result on the left, the second on the right), 'first' or 'second' alone. */
  setLayout(layout) {
    this.layout = layout;
    this.showLabels();
    this.render();
  }

  /** Captions for the result and the second mesh, shown over their halves (or over the one shown). */
  setLabels(texts) {
    this.labelTexts = texts;
    this.showLabels();
  }

  showLabels() {
    const texts = this.labelTexts ?? [];
    const shown = !this.second ? texts.slice(0, 1) : this.layout === 'split' ? texts
      : this.layout === 'first' ? texts.slice(0, 1) : texts.slice(1, 2);
    this.labels.replaceChildren(...shown.filter((t) => t).map((t, i) => {
      const el = document.createElement('span');
      el.textContent = t;
      el.className = shown.length > 1 && i === 1 ? 'right' : 'left';
      return el;
    }));
    this.labels.classList.toggle('split', this.split());
    this.labels.hidden = this.labels.children.length === 0;
  }

  setWireframe(on) {
    this.material.wireframe = on;
    this.secondMaterial.wireframe = on;
    this.render();
  }

  clearOverlay() {
    for (const child of [...this.overlay.children]) {
      this.overlay.remove(child);
      child.geometry?.dispose();
    }
  }

  /** Frames whatever is in root (further away when the view is narrower than tall, as a split half can be). */
  fit() {
    this.root.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(this.root);
    if (box.isEmpty()) return;
    this.updateAspect();
    const size = box.getSize(new THREE.Vector3()).length() * Math.max(1, 0.8 / this.camera.aspect);
    const center = box.getCenter(new THREE.Vector3());
    this.controls.target.copy(center);
    this.camera.near = size / 100;
    this.camera.far = size * 100;
    this.camera.position.copy(center).add(new THREE.Vector3(0.6, 0.45, 0.8).multiplyScalar(size * 1.3));
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.render();
  }
}
