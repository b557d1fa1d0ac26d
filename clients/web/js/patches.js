// Patches view: a Bézier patch set (the teapot from GET /patches/teapot, or an uploaded JSON/BEZ set) or NURBS
// surfaces (the trimmed NURBS sphere, or a JSON upload) tessellated by the service, its control net, control points
// dragged with a server round trip per update, a picked point's weight edited, and trimming loops drawn.
import * as THREE from 'three';
import { call } from './api.js';
import { netSize, trimLoops3d, trimmedSphere } from './nurbs.js';

const $ = (id) => document.getElementById(id);

/** Minimal geomview BEZ/BBP reader (Nd = 3) for the control net; the server is the judge of validity. */
export function parseBez(text) {
  const tokens = text.replace(/#[^\n]*/g, ' ').split(/\s+/).filter(Boolean);
  const patches = [];
  let du = 3, dv = 3, st = false, colour = false;
  for (let i = 0; i < tokens.length;) {
    const t = tokens[i];
    const m = /^(ST)?BBP$/.exec(t) || /^(C)?BEZ(\d)(\d)(\d)(_ST)?$/.exec(t);
    if (m) {
      if (t.endsWith('BBP')) { du = 3; dv = 3; st = !!m[1]; colour = false; }
      else { colour = !!m[1]; du = +m[2]; dv = +m[3]; st = !!m[5]; if (+m[4] !== 3) return null; }
      ++i;
      continue;
    }
    const n = (du + 1) * (dv + 1);
    if (i + 3 * n > tokens.length) return null;
    const points = [];
    for (let k = 0; k < n; ++k, i += 3) points.push([+tokens[i], +tokens[i + 1], +tokens[i + 2]]);
    if (points.flat().some((x) => !Number.isFinite(x))) return null;
    if (st) i += 8;
    if (colour) i += 16;
    patches.push({ degree: [du, dv], points });
  }
  return patches.length ? { patches } : null;
}

export class PatchesView {
  constructor(app) {
    this.app = app;
    this.viewer = app.viewer;
    this.patches = null;        // {patches: [{degree, points}], surfaces: [...]}, edited in place while dragging
    this.original = null;       // JSON text of the set as loaded, for "reset"
    this.zUp = true;
    this.busy = false;          // one tessellation request at a time...
    this.dirty = false;         // ...and the latest edit is sent when it returns
    this.roundTrips = [];
    this.drag = null;
    this.pointColour = new THREE.Color(0xffd84a);

    $('patch-segments').addEventListener('change', () => this.retessellate());
    $('patch-tolerance').addEventListener('change', () => this.retessellate());
    for (const r of document.querySelectorAll('input[name=patch-mode]')) r.addEventListener('change', () => this.retessellate());
    $('patch-net').addEventListener('change', () => { this.viewer.overlay.visible = $('patch-net').checked; this.viewer.render(); });
    $('patch-reset').addEventListener('click', () => {
      if (!this.original) return;
      this.setPatches(JSON.parse(this.original));
      this.retessellate();
    });
    $('patch-source').addEventListener('change', () => this.loadSample($('patch-source').value));
    $('patch-file').addEventListener('change', (e) => this.loadFile(e.target.files[0]));
    $('patch-weight').addEventListener('change', () => this.setWeight(Number($('patch-weight').value)));

    const canvas = this.viewer.renderer.domElement;
    // capture phase: runs before OrbitControls' own listener, which is disabled while a point is dragged
    canvas.addEventListener('pointerdown', (e) => this.onPointerDown(e), { capture: true });
    canvas.addEventListener('pointermove', (e) => this.onPointerMove(e));
    canvas.addEventListener('pointerup', (e) => this.onPointerUp(e));
    canvas.addEventListener('pointercancel', (e) => this.onPointerUp(e));
  }

  async activate() {
    this.active = true;
    if (this.pending) {
      const { set, info, name } = this.pending;
      this.pending = null;
      await this.loadPatchSet(set, { info, name });
      return;
    }
    this.viewer.setUpAxis(this.zUp);
    if (!this.patches) await this.loadSample('teapot');
    else this.show();
  }

  /** A patch set from another view ({patches: [...]}, e.g. a subdivision surface's limit patches), shown on activation. */
  usePatchSet(set, { info, name }) { this.pending = { set, info, name }; }

  /** Tessellates a patch set (y up, as mesh files are) and shows it with its net; `info` is an extra stats line. */
  async loadPatchSet(set, { info, name } = {}) {
    this.app.clearError();
    // trimmed surfaces are tessellated to a tolerance only (their trims need it)
    if (set.surfaces?.some((surface) => surface.trim)) document.querySelector('input[name=patch-mode][value=tolerance]').checked = true;
    try {
      const result = await call('POST', '/tessellate', { body: { ...set, ...this.tessellationQuery(), output: { compression: 'none' } } });
      this.info = info;
      this.name = name;
      const editable = { ...(set.patches ? { patches: set.patches } : {}), ...(set.surfaces ? { surfaces: set.surfaces } : {}) };
      this.setPatches(editable);
      this.original = JSON.stringify(editable);
      this.zUp = false;
      this.viewer.setUpAxis(false);
      await this.showResult(result, { fit: true });
    } catch (e) {
      this.app.showError(e);
    }
  }

  deactivate() {
    this.active = false;
    this.onPointerUp();
    if (this.trimLines) this.viewer.root.remove(this.trimLines);   // setPatches puts them back
  }

  tessellationQuery() {
    const mode = document.querySelector('input[name=patch-mode]:checked').value;
    return mode === 'tolerance' ? { tolerance: Number($('patch-tolerance').value) }
                                : { segments: Math.round(Number($('patch-segments').value)) };
  }

  /** GET /patches/{name}: the tessellated sample (Draco GLB) and its control points (format=patches). */
  async loadSample(name) {
    this.app.clearError();
    if (name === 'nurbs-sphere')
      return this.loadPatchSet(trimmedSphere(), { name: 'nurbs-sphere', info: 'NURBS sphere (9 × 5 rational net), trimmed by a circle' });
    try {
      const q = new URLSearchParams(Object.entries(this.tessellationQuery()).map(([k, v]) => [k, String(v)]));
      const [mesh, net] = await Promise.all([
        call('GET', `/patches/${encodeURIComponent(name)}?${q}`),
        call('GET', `/patches/${encodeURIComponent(name)}?format=patches`),
      ]);
      this.zUp = true;
      this.viewer.setUpAxis(true);
      this.info = undefined;
      this.name = undefined;
      this.setPatches(net.json);
      this.original = JSON.stringify(net.json);
      await this.showResult(mesh, { fit: true });
    } catch (e) {
      this.app.showError(e);
    }
  }

  async loadFile(file) {
    if (!file) return;
    this.app.clearError();
    const text = await file.text();
    try {
      let set;
      if (file.name.toLowerCase().endsWith('.json')) {
        try { set = JSON.parse(text); } catch (e) { throw new Error(`${file.name}: not JSON (${e.message})`); }
      } else {
        // the server validates (errors name the line); the net is read here once it has accepted the file
        await call('POST', '/tessellate?segments=1&compression=none', { body: text, contentType: 'application/x-geomview-bez' });
        set = parseBez(text);
        if (!set) throw new Error(`${file.name}: the control net could not be read here (rational or unusual BEZ)`);
      }
      await this.loadPatchSet(set);
    } catch (e) {
      this.app.showError(e);
    }
  }

  /**
   * Builds the unique control points (shared points of neighbouring patches or surfaces are one, when their weights
   * agree too) and the net lines.
   */
  setPatches(set) {
    this.patches = set;
    const key = (p, w) => `${p.join(',')};${w}`;
    const index = new Map();
    this.refs = [];           // unique point -> [[item, i], ...], item a patch or a surface of the set
    this.selected = -1;
    $('patch-weight-row').hidden = true;
    const positions = [];
    const lines = [];
    const items = [...(set.patches ?? []).map((patch) => [patch, [patch.degree[0] + 1, patch.degree[1] + 1]]),
                   ...(set.surfaces ?? []).map((surface) => [surface, netSize(surface)])];
    for (const [item, [nu, nv]] of items) {
      const ids = item.points.map((p, i) => {
        const k = key(p, item.weights?.[i] ?? 1);
        let id = index.get(k);
        if (id === undefined) {
          id = this.refs.length;
          index.set(k, id);
          this.refs.push([]);
          positions.push(p[0], p[1], p[2]);
        }
        this.refs[id].push([item, i]);
        return id;
      });
      for (let j = 0; j < nv; ++j)
        for (let i = 0; i < nu; ++i) {
          const a = ids[j * nu + i];
          if (i + 1 < nu) lines.push(a, ids[j * nu + i + 1]);
          if (j + 1 < nv) lines.push(a, ids[(j + 1) * nu + i]);
        }
    }
    this.positions = new THREE.Float32BufferAttribute(positions, 3);
    this.viewer.clearOverlay();
    const pointsGeometry = new THREE.BufferGeometry();
    pointsGeometry.setAttribute('position', this.positions);
    const lineGeometry = new THREE.BufferGeometry();
    lineGeometry.setAttribute('position', this.positions);
    lineGeometry.setIndex(lines);
    this.netLines = new THREE.LineSegments(lineGeometry, new THREE.LineBasicMaterial({ color: 0x8a7a3a }));
    this.netPoints = new THREE.Points(pointsGeometry, new THREE.PointsMaterial({ color: this.pointColour, size: 5, sizeAttenuation: false }));
    this.netPoints.renderOrder = 1;
    this.netPoints.material.depthTest = false;
    this.viewer.overlay.add(this.netLines, this.netPoints);
    this.trimLines = new THREE.Group();
    this.viewer.root.remove(this.viewer.root.getObjectByName('trim-loops') ?? new THREE.Group());
    this.trimLines.name = 'trim-loops';
    this.viewer.root.add(this.trimLines);
    this.viewer.overlay.visible = $('patch-net').checked;
    this.viewer.render();
  }

  show() {
    if (this.patches) this.setPatches(this.patches);
    if (this.lastResult) this.showResult(this.lastResult);
  }

  async showResult(result, { fit = false, t0 } = {}) {
    const geometry = await this.viewer.parseGlb(result.bytes);
    if (!this.active) return;
    this.lastResult = result;
    this.viewer.setGeometry(geometry, { fit });
    await this.drawTrimLoops();
    const h = result.headers;
    const server = h.get('X-Elapsed-Ms');
    const wire = result.networkMs ?? result.roundTripMs;
    const shown = t0 === undefined ? undefined : performance.now() - t0;
    if (this.drag && t0 !== undefined) this.roundTrips.push({ wire, shown });
    const trips = this.roundTrips;
    this.app.setStats([
      ...(this.info ? [this.info] : []),
      ...(this.patches?.surfaces?.length ? [`surfaces: ${this.patches.surfaces.length}` +
                                            `${this.trimCount ? `, ${this.trimCount} trimming loops` : ''}`] : []),
      `patches: ${this.patches?.patches?.length ?? h.get('X-Patches')}`,
      `triangles: ${h.get('X-Output-Faces') ?? geometry.index?.count / 3}`,
      `error bound: ${h.get('X-Error-Bound')}`,
      `round trip: ${wire.toFixed(1)} ms` + (server ? ` (server ${server} ms)` : '') +
        (shown !== undefined ? `, shown after ${shown.toFixed(1)} ms` : ''),
      ...(trips.length ? [`drag: ${trips.length} round trips, median ${median(trips.map((t) => t.wire)).toFixed(1)} ms` +
                          ` (shown after ${median(trips.map((t) => t.shown)).toFixed(1)} ms)`] : []),
    ], { roundTripMs: wire });
    const body = () => ({ ...this.patches, ...this.tessellationQuery() });
    this.app.setDownloads({
      glb: result.bytes,
      obj: async () => (await call('POST', '/tessellate', { body: { ...body(), output: { format: 'obj' } } })).bytes,
      name: this.name ?? 'patches',
    });
  }

  /** POST /tessellate with the current control points; while one is in flight, the latest edit waits for it. */
  async retessellate() {
    if (!this.patches) return;
    if (this.busy) { this.dirty = true; return; }
    this.busy = true;
    this.app.clearError();
    try {
      do {
        this.dirty = false;
        const t0 = performance.now();
        const result = await call('POST', '/tessellate',
                                  { body: { ...this.patches, ...this.tessellationQuery(), output: { compression: 'none' } } });
        await this.showResult(result, { t0 });
      } while (this.dirty);
    } catch (e) {
      this.app.showError(e);
    } finally {
      this.busy = false;
    }
  }

  /** The unique control point within 10 px of the pointer, nearest the camera. */
  pick(event) {
    if (!this.positions || !this.viewer.overlay.visible) return -1;
    const rect = this.viewer.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3();
    const world = this.viewer.overlay.matrixWorld;
    let best = -1, bestDepth = Infinity;
    for (let i = 0; i < this.positions.count; ++i) {
      v.fromBufferAttribute(this.positions, i).applyMatrix4(world).project(this.viewer.camera);
      if (v.z > 1) continue;
      const x = (v.x + 1) / 2 * rect.width, y = (1 - v.y) / 2 * rect.height;
      const d = Math.hypot(x - (event.clientX - rect.left), y - (event.clientY - rect.top));
      if (d <= 10 && v.z < bestDepth) { best = i; bestDepth = v.z; }
    }
    return best;
  }

  onPointerDown(event) {
    if (!this.active || event.button !== 0) return;
    const id = this.pick(event);
    if (id < 0) return;
    this.viewer.controls.enabled = false;
    this.lastDragged = id;
    const world = new THREE.Vector3().fromBufferAttribute(this.positions, id).applyMatrix4(this.viewer.overlay.matrixWorld);
    const normal = this.viewer.camera.getWorldDirection(new THREE.Vector3());
    this.drag = { id, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, world), pointer: event.pointerId, moved: false };
    this.select(id);
    this.viewer.renderer.domElement.setPointerCapture(event.pointerId);
    event.preventDefault();
  }

  onPointerMove(event) {
    if (!this.drag) return;
    const rect = this.viewer.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2((event.clientX - rect.left) / rect.width * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.viewer.camera);
    const hit = ray.ray.intersectPlane(this.drag.plane, new THREE.Vector3());
    if (!hit) return;
    const local = this.viewer.overlay.worldToLocal(hit);
    this.positions.setXYZ(this.drag.id, local.x, local.y, local.z);
    this.positions.needsUpdate = true;
    for (const [item, i] of this.refs[this.drag.id]) item.points[i] = [local.x, local.y, local.z];
    this.viewer.render();
    this.retessellate();
  }

  onPointerUp() {
    if (!this.drag) return;
    this.drag = null;
    this.viewer.controls.enabled = true;
  }

  /** Picks control point `id` for the weight field (its weight in the first patch or surface that uses it). */
  select(id) {
    this.selected = id;
    const [item, i] = this.refs[id][0];
    $('patch-weight').value = String(item.weights?.[i] ?? 1);
    $('patch-weight-index').textContent = `point ${id}`;
    $('patch-weight-row').hidden = false;
  }

  /** Sets the picked control point's weight in every patch or surface that uses it (a set without weights gets 1s). */
  setWeight(w) {
    if (this.selected < 0 || !(w > 0)) return;
    for (const [item, i] of this.refs[this.selected]) {
      if (!item.weights) item.weights = item.points.map(() => 1);
      item.weights[i] = w;
    }
    this.retessellate();
  }

  /** The set's trimming loops on the surface, lifted slightly along the normal so they show over the shading. */
  async drawTrimLoops() {
    if (!this.trimLines) return;
    for (const child of [...this.trimLines.children]) { this.trimLines.remove(child); child.geometry.dispose(); }
    this.trimCount = 0;
    if (!this.patches?.surfaces?.some((s) => s.trim)) return;
    const box = new THREE.Box3().setFromBufferAttribute(this.positions);
    const loops = await trimLoops3d(this.patches, 0.003 * box.getSize(new THREE.Vector3()).length());
    const material = new THREE.LineBasicMaterial({ color: 0xff5a5a });
    for (const loop of loops) {
      const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(loop.map((p) => new THREE.Vector3(...p))), material);
      line.renderOrder = 1;
      this.trimLines.add(line);
    }
    this.trimCount = loops.length;
    this.viewer.render();
  }
}

function median(values) {
  const s = [...values].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}
