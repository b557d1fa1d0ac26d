// The 3D viewport: renderer, camera, OrbitControls, lights, GLB loading (Draco through the vendored decoder).
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
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /** Draws at the next animation frame; several calls in one frame draw once (dragging must not queue renders). */
  render() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.renderer.render(this.scene, this.camera);
    });
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

  setWireframe(on) { this.material.wireframe = on; this.render(); }

  clearOverlay() {
    for (const child of [...this.overlay.children]) {
      this.overlay.remove(child);
      child.geometry?.dispose();
    }
  }

  /** Frames whatever is in root. */
  fit() {
    this.root.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(this.root);
    if (box.isEmpty()) return;
    const size = box.getSize(new THREE.Vector3()).length();
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
