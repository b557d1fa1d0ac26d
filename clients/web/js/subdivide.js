// Subdivision view: a built-in or uploaded cage, edges picked for crease sharpness, POST /subdivide.
import * as THREE from 'three';
import { call, meshMediaType, headerStats } from './api.js';
import { builtins } from './meshes.js';
import { nearestLimitPoint, limitMarker } from './limit_probe.js';

const $ = (id) => document.getElementById(id);

/**
 * Any mesh file the service reads, as the service's JSON mesh: POST /subdivide with levels=0, format=json and
 * normals=false parses
 * it on the server (errors name the file line) and returns it unchanged.
 */
export async function uploadToJsonMesh(file) {
  const bytes = await file.arrayBuffer();
  const result = await call('POST', '/subdivide?levels=0&format=json&normals=false', { body: bytes, contentType: meshMediaType(file.name) });
  return result.json.mesh;
}

export class SubdivideView {
  constructor(app) {
    this.app = app;
    this.viewer = app.viewer;
    this.mesh = null;
    this.picked = new Set();   // "a,b" with a < b
    $('sub-source').addEventListener('change', () => this.setMesh(builtins[$('sub-source').value]()));
    $('sub-file').addEventListener('change', (e) => this.upload(e.target.files[0]));
    $('sub-levels').addEventListener('input', () => { $('sub-levels-out').textContent = $('sub-levels').value; });
    for (const id of ['sub-levels', 'sub-scheme', 'sub-boundary', 'sub-limit', 'sub-sharpness', 'sub-by-tolerance', 'sub-tolerance', 'sub-straddle', 'sub-threads'])
      $(id).addEventListener('change', () => this.run());
    $('sub-run').addEventListener('click', () => this.run());
    $('sub-patches').addEventListener('click', () => this.showPatches());
    $('sub-clear').addEventListener('click', () => { this.picked.clear(); this.drawCage(); this.run(); });
    const canvas = this.viewer.renderer.domElement;
    canvas.addEventListener('pointerdown', (e) => { this.down = [e.clientX, e.clientY]; });
    canvas.addEventListener('click', (e) => ($('sub-probe').checked ? this.probe(e) : this.onClick(e)));
    $('sub-probe').addEventListener('change', () => { if (!$('sub-probe').checked) this.clearProbe(); });
    this.raycaster = new THREE.Raycaster();
  }

  async activate() {
    this.active = true;
    this.viewer.setUpAxis(false);
    if (!this.mesh) this.setMesh(builtins[$('sub-source').value]());
    else { this.drawCage(); await this.run(); }
  }

  deactivate() { this.active = false; }

  async upload(file) {
    if (!file) return;
    this.app.clearError();
    try {
      const mesh = await uploadToJsonMesh(file);
      this.name = file.name.replace(/\.[^.]*$/, '');
      this.setMesh(mesh, { keepName: true });
    } catch (e) {
      this.app.showError(e, `Upload of ${file.name} failed`);
    }
  }

  setMesh(mesh, { keepName = false } = {}) {
    this.mesh = mesh;
    this.clearProbe();
    if (!keepName) this.name = $('sub-source').value;
    this.picked.clear();
    this.edges = [];
    const seen = new Set();
    for (const f of mesh.faces)
      for (let k = 0; k < f.length; ++k) {
        const a = Math.min(f[k], f[(k + 1) % f.length]), b = Math.max(f[k], f[(k + 1) % f.length]);
        if (!seen.has(`${a},${b}`)) { seen.add(`${a},${b}`); this.edges.push([a, b]); }
      }
    this.drawCage();
    this.viewer.setGeometry(null);
    this.run(true);
  }

  drawCage() {
    this.viewer.clearOverlay();
    if (!this.mesh) return;
    const positions = this.mesh.positions.flat();
    const plain = [], sharp = [];
    for (const [a, b] of this.edges) (this.picked.has(`${a},${b}`) ? sharp : plain).push(a, b);
    for (const [list, colour] of [[plain, 0xdddddd], [sharp, 0xff4040]]) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
      g.setIndex(list);
      const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: colour, depthTest: false, transparent: true, opacity: 0.8 }));
      lines.renderOrder = 1;
      this.viewer.overlay.add(lines);
    }
    this.viewer.overlay.visible = true;
    $('sub-picked').textContent = `${this.picked.size} edge${this.picked.size === 1 ? '' : 's'} picked`;
    this.viewer.render();
  }

  /** Toggles the cage edge within 6 px of a click (not the end of a camera drag). */
  onClick(event) {
    if (!this.active || !this.mesh || !this.isClick(event)) return;
    const rect = this.viewer.renderer.domElement.getBoundingClientRect();
    const px = event.clientX - rect.left, py = event.clientY - rect.top;
    const screen = this.mesh.positions.map((p) => {
      const v = new THREE.Vector3(...p).applyMatrix4(this.viewer.overlay.matrixWorld).project(this.viewer.camera);
      return [(v.x + 1) / 2 * rect.width, (1 - v.y) / 2 * rect.height, v.z];
    });
    let best = null, bestD = 6;
    for (const [a, b] of this.edges) {
      const [ax, ay] = screen[a], [bx, by] = screen[b];
      const dx = bx - ax, dy = by - ay;
      const t = Math.max(0, Math.min(1, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy || 1)));
      const d = Math.hypot(ax + t * dx - px, ay + t * dy - py);
      if (d < bestD) { bestD = d; best = `${a},${b}`; }
    }
    if (!best) return;
    if (this.picked.has(best)) this.picked.delete(best); else this.picked.add(best);
    this.drawCage();
    this.run();
  }

  /** True when a click is a click, not the end of a camera drag. */
  isClick(event) {
    return this.down && Math.hypot(event.clientX - this.down[0], event.clientY - this.down[1]) <= 4;
  }

  /**
   * The limit point under a click on the drawn surface (limit_probe.js): its base face, (u, v), position and normal,
   * and how far the drawn surface is from it there.
   */
  async probe(event) {
    if (!this.active || !this.mesh || !this.viewer.result || !this.isClick(event)) return;
    const rect = this.viewer.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2((event.clientX - rect.left) / rect.width * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.viewer.camera);
    const hit = this.raycaster.intersectObject(this.viewer.result, false)[0];
    const readout = $('sub-probe-readout');
    if (!hit) { readout.textContent = 'limit point: click on the surface'; return; }
    const target = this.viewer.root.worldToLocal(hit.point.clone()).toArray();
    const { mesh, scheme, boundary, creases } = this.request();
    this.app.clearError();
    try {
      const p = await nearestLimitPoint(mesh, { scheme, boundary, creases }, target);
      this.clearProbe();
      const size = new THREE.Box3().setFromArray(mesh.positions.flat()).getSize(new THREE.Vector3()).length();
      this.marker = limitMarker(p.position, p.normal, 0.15 * size);
      this.viewer.root.add(this.marker);
      this.viewer.render();
      const f = (v) => v.map((x) => x.toFixed(5)).join(', ');
      readout.textContent = `limit point: face ${p.face}, uv (${f(p.uv)})\nposition (${f(p.position)})\n` +
                            `normal (${f(p.normal)})\ndistance to the drawn surface: ${p.distance.toExponential(3)}`;
      readout.dataset.face = p.face;
      readout.dataset.distance = p.distance;
      readout.dataset.position = JSON.stringify(p.position);
      readout.dataset.normal = JSON.stringify(p.normal);
    } catch (e) {
      this.app.showError(e);
    }
  }

  clearProbe() {
    if (this.marker) {
      this.viewer.root.remove(this.marker);
      for (const o of this.marker.children) { o.geometry.dispose(); o.material.dispose(); }
      this.marker = null;
      this.viewer.render();
    }
    const readout = $('sub-probe-readout');
    readout.textContent = '';
    delete readout.dataset.face;
  }

  request(format = 'glb') {
    const sharpness = Number($('sub-sharpness').value);
    const body = {
      mesh: this.mesh,
      scheme: $('sub-scheme').value,
      boundary: $('sub-boundary').value,
      creases: [...this.picked].map((k) => ({ edge: k.split(',').map(Number), sharpness })),
      output: format === 'glb' ? { format: 'glb', normals: true } : { format },
      threads: Number($('sub-threads').value),   // the same answer either way
    };
    // to a tolerance: the limit surface tessellated adaptively (Catmull-Clark; levels and limit_surface do not apply)
    if ($('sub-by-tolerance').checked) {
      const straddle = Number($('sub-straddle').value);   // vertices off the surface by straddle x tolerance
      return { ...body, tolerance: Number($('sub-tolerance').value), straddle };
    }
    return { ...body, levels: Number($('sub-levels').value), limit_surface: $('sub-limit').checked };
  }

  /**
   * POST /subdivide format=patches: the limit surface as Bézier patches (the isolation level chosen by the server),
   * handed to the Patches view, which tessellates and shows them with their control net.
   */
  async showPatches() {
    if (!this.mesh) return;
    this.app.clearError();
    try {
      const { mesh, scheme, boundary, creases } = this.request();
      const result = await call('POST', '/subdivide', { body: { mesh, scheme, boundary, creases, output: { format: 'patches' } } });
      const h = result.headers;
      this.app.views.patches.usePatchSet(result.json, {
        name: `${this.name}-limit`,
        info: `limit patches of ${this.name}: isolation level ${h.get('X-Isolation-Level')}, ` +
              `${h.get('X-Approximate-Patches')} approximate (error at most ${Number(h.get('X-Max-Error')).toPrecision(3)})`,
      });
      await this.app.show('patches');
    } catch (e) {
      this.app.showError(e);
    }
  }

  async run(fit = false) {
    if (!this.mesh || !this.active) return;
    this.app.clearError();
    this.clearProbe();   // the surface may change
    const seq = (this.seq = (this.seq ?? 0) + 1);
    try {
      const result = await call('POST', '/subdivide', { body: this.request() });
      const geometry = await this.viewer.parseGlb(result.bytes);
      if (seq !== this.seq || !this.active) return;   // a newer request was made meanwhile
      this.viewer.setGeometry(geometry, { fit });
      this.app.setStats([
        ...headerStats(result.headers, [['X-Input-Vertices', 'input vertices'], ['X-Input-Faces', 'input faces'],
                                        ['X-Output-Vertices', 'output vertices'], ['X-Output-Faces', 'output faces'],
                                        ['X-Tolerance', 'tolerance'], ['X-Achieved-Tolerance', 'max distance to the limit surface'],
                                        ['X-Elapsed-Ms', 'server ms']]),
        `round trip: ${result.roundTripMs.toFixed(1)} ms`,
      ], { outputFaces: Number(result.headers.get('X-Output-Faces')), request: seq });
      this.app.setDownloads({
        glb: result.bytes,
        obj: async () => (await call('POST', '/subdivide', { body: this.request('obj') })).bytes,
        name: `${this.name}-subdivided`,
      });
    } catch (e) {
      if (seq === this.seq) this.app.showError(e);
    }
  }
}
