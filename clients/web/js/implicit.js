// Implicit view: an editable scene JSON sent to POST /implicit/mesh, the mesh shown as a preview. The tab appears
// only when the server's /openapi.json lists /implicit/mesh; the initial scene is that document's example.
// Uploaded meshes (repaired by POST /repair) become {"op": "mesh"} nodes of the scene: the editor shows them as
// {"ref_upload": label} and the real positions and faces are put in their place when a request is sent. The probe
// asks POST /implicit/query about the point under the pointer.
import * as THREE from 'three';
import { call, headerStats, meshMediaType, repairStats } from './api.js';

const $ = (id) => document.getElementById(id);

/** The member of a mesh node's "mesh" that names an upload in the editor text (the client's own; never sent). */
const UPLOAD_KEY = 'ref_upload';

/** A BufferGeometry from the service's JSON mesh {positions, faces} (polygons fanned into triangles). */
export function geometryFromJsonMesh(mesh) {
  const index = [];
  for (const f of mesh.faces) for (let k = 1; k + 1 < f.length; ++k) index.push(f[0], f[k], f[k + 1]);
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(mesh.positions.flat(), 3));
  g.setIndex(index);
  g.computeVertexNormals();
  return g;
}

/** JSON on one line with a space after each comma and colon. */
function oneLine(value) {
  if (value === null || typeof value !== 'object') return JSON.stringify(value) ?? 'null';
  if (Array.isArray(value)) return `[${value.map(oneLine).join(', ')}]`;
  return `{${Object.entries(value).filter(([, v]) => v !== undefined).map(([k, v]) => `${JSON.stringify(k)}: ${oneLine(v)}`).join(', ')}}`;
}

/** Indented JSON where arrays of numbers ([1, 1, 1]) and objects or arrays of at most 44 characters stay on one
 *  line, so that a short node such as {"op": "sphere", "radius": 0.5} reads as one. */
function compactJson(value, indent = '') {
  const flat = oneLine(value);
  if (value === null || typeof value !== 'object' || flat.length <= 44 ||
      (Array.isArray(value) && value.every((v) => typeof v === 'number'))) return flat;
  const inner = `${indent}  `;
  const items = Array.isArray(value) ? value.map((v) => inner + compactJson(v, inner))
    : Object.entries(value).filter(([, v]) => v !== undefined).map(([k, v]) => `${inner}${JSON.stringify(k)}: ${compactJson(v, inner)}`);
  return Array.isArray(value) ? `[\n${items.join(',\n')}\n${indent}]` : `{\n${items.join(',\n')}\n${indent}}`;
}

/** A box with a spherical bite, when the server's document has no example. */
const DEFAULT_REQUEST = {
  scene: { op: 'difference', args: [{ op: 'box', half_size: [1, 1, 1] },
                                    { op: 'translate', offset: [0, 0, 1], arg: { op: 'sphere', radius: 0.8 } }] },
  bounds: [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]],
  resolution: 48,
};

const isNode = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
const isUploadNode = (v) => isNode(v) && v.op === 'mesh' && isNode(v.mesh) && UPLOAD_KEY in v.mesh;

/** Replaces, in place, the mesh of every upload node under `node` with the uploaded mesh; `path` names `node` in
 *  errors ("scene.args[1]"). Arrays of numbers (level sets, vectors) are not walked. */
function substituteUploads(node, uploads, path) {
  if (Array.isArray(node)) {
    if (node.length && typeof node[0] === 'object') node.forEach((n, i) => substituteUploads(n, uploads, `${path}[${i}]`));
    return;
  }
  if (!isNode(node)) return;
  if (isUploadNode(node)) {
    const label = node.mesh[UPLOAD_KEY];
    const upload = uploads.get(label);
    if (!upload) {
      const known = [...uploads.keys()].map((k) => JSON.stringify(k)).join(', ') || 'none';
      throw new Error(`${path}.mesh.${UPLOAD_KEY}: no uploaded mesh ${JSON.stringify(label)} (uploaded: ${known})`);
    }
    node.mesh = upload.mesh;
    return;
  }
  for (const [key, value] of Object.entries(node))
    if (value !== null && typeof value === 'object') substituteUploads(value, uploads, `${path}.${key}`);
}

/** `scene` without the upload node `label`: a combination left with one argument becomes that argument, a node left
 *  with none (or a transform of the upload, or a {"ref"} to a removed id) goes too. Null when nothing is left. */
function removeUpload(scene, label) {
  let removedIds = new Set();
  for (;;) {   // ids found on removed nodes remove the refs to them, which may be met before the id: repeat until stable
    const ids = new Set(removedIds);
    const strip = (node) => {
      if (!isNode(node)) return node;
      const gone = () => { if (typeof node.id === 'string') ids.add(node.id); return null; };
      if (isUploadNode(node) && node.mesh[UPLOAD_KEY] === label) return gone();
      if (typeof node.ref === 'string' && removedIds.has(node.ref)) return null;
      const out = { ...node };
      if (isNode(node.arg)) {
        out.arg = strip(node.arg);
        if (out.arg === null) return gone();
      }
      if (Array.isArray(node.args)) {
        out.args = node.args.map(strip).filter((a) => a !== null);
        if (out.args.length === 0) return gone();
        if (out.args.length === 1 && node.args.length > 1) {
          const only = out.args[0];
          // the node's id moves to what replaces it, so that refs to it still resolve
          if (typeof node.id === 'string' && isNode(only) && only.id === undefined && only.ref === undefined)
            return { id: node.id, ...only };
          if (typeof node.id === 'string') ids.add(node.id);
          return only;
        }
      }
      return out;
    };
    const result = strip(scene);
    if (ids.size === removedIds.size) return result;
    removedIds = ids;
  }
}

/** [[min], [max]] of positions. */
function boxOf(positions) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const p of positions)
    for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], p[k]); hi[k] = Math.max(hi[k], p[k]); }
  return [lo, hi];
}

const validBounds = (b) => Array.isArray(b) && b.length === 2 &&
  b.every((c) => Array.isArray(c) && c.length === 3 && c.every(Number.isFinite)) && [0, 1, 2].every((k) => b[0][k] < b[1][k]);

/** `node` (with box `box`) scaled uniformly and moved so that its box is centred in `bounds` with its longest side
 *  three quarters of theirs (4 significant digits); the transformed node and its box. */
function fitted(node, box, bounds) {
  const longest = (b) => Math.max(...[0, 1, 2].map((k) => b[1][k] - b[0][k]));
  const round = (v) => Number(v.toPrecision(4));
  const factor = round(0.75 * longest(bounds) / Math.max(longest(box), 1e-12));
  const offset = [0, 1, 2].map((k) => round((bounds[0][k] + bounds[1][k]) / 2 - factor * (box[0][k] + box[1][k]) / 2));
  return { node: { op: 'translate', offset, arg: { op: 'scale', factor, arg: node } },
           box: box.map((corner) => corner.map((v, k) => factor * v + offset[k])) };
}

/** `bounds` grown to hold `box` with a margin of a tenth of the box's longest side, rounded outward to 3 digits. */
function growBounds(bounds, box) {
  const extent = Math.max(...[0, 1, 2].map((k) => box[1][k] - box[0][k]), 1e-9);
  const margin = 0.1 * extent;
  const step = 10 ** (Math.floor(Math.log10(extent)) - 2);
  const round = (v, dir) => Number(((dir < 0 ? Math.floor(v / step) : Math.ceil(v / step)) * step).toPrecision(12));
  const lo = [0, 1, 2].map((k) => round(box[0][k] - margin, -1)), hi = [0, 1, 2].map((k) => round(box[1][k] + margin, 1));
  if (!validBounds(bounds)) return [lo, hi];
  return [lo.map((v, k) => Math.min(v, bounds[0][k])), hi.map((v, k) => Math.max(v, bounds[1][k]))];
}

/** The new scene node for "Combine as". */
function combine(scene, meshNode, how, k) {
  switch (how) {
    case 'difference-reverse': return { op: 'difference', args: [meshNode, scene] };
    case 'smooth_union': return { op: 'smooth_union', args: [scene, meshNode], k };
    default: return { op: how, args: [scene, meshNode] };
  }
}

/** A number for the probe's readout: 4 decimals, or exponent notation when tiny. */
function num(x) {
  if (x === null || x === undefined) return 'null';
  return x !== 0 && Math.abs(x) < 1e-3 ? x.toExponential(2) : x.toFixed(4);
}
const vec = (v) => `(${[...v].map(num).join(', ')})`;

const PROBE_COLOURS = { inside: 0xe5533d, outside: 0x3fbf6f, on: 0xffd54a, undefined: 0x999999 };

export class ImplicitView {
  /** `features`: {meshNodes: the server's scenes have the "mesh" op, query: it serves POST /implicit/query}. */
  constructor(app, example, features = {}) {
    this.app = app;
    this.viewer = app.viewer;
    // label in the editor -> {mesh: {positions, faces}, box, triangles, repair: [lines], boundsBefore, boundsAfter}
    this.uploads = new Map();
    const initial = { ...(example ?? DEFAULT_REQUEST) };
    delete initial.output;   // the preview asks for GLB itself
    $('imp-scene').value = compactJson(initial);
    $('imp-run').addEventListener('click', () => this.run(false));
    $('imp-scene').addEventListener('keydown', (e) => { if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) this.run(false); });

    $('imp-mesh-controls').hidden = !features.meshNodes;
    $('imp-mesh-file').addEventListener('change', () => {
      const file = $('imp-mesh-file').files[0];
      if (file) this.addMesh(file);
    });
    const showRadius = () => { $('imp-smooth-k').parentElement.hidden = $('imp-combine').value !== 'smooth_union'; };
    $('imp-combine').addEventListener('change', showRadius);
    showRadius();

    $('imp-probe').hidden = !features.query;
    $('imp-probe').addEventListener('click', () => this.setProbe(!this.probeOn));
    this.probeOn = false;
    this.probeQueries = 0;
    this.raycaster = new THREE.Raycaster();
    // drawn over the surface (no depth test): the probe point is usually just behind it
    const marker = (colour) => new THREE.Mesh(new THREE.SphereGeometry(1, 16, 12),
                                              new THREE.MeshBasicMaterial({ color: colour, depthTest: false, transparent: true }));
    this.probeMarker = marker(PROBE_COLOURS.outside);
    this.closestMarker = marker(0xffffff);
    this.probeLine = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
                                    new THREE.LineBasicMaterial({ color: 0xffd54a, depthTest: false, transparent: true }));
    this.probeGroup = new THREE.Group();
    this.probeGroup.add(this.probeMarker, this.closestMarker, this.probeLine);
    for (const o of this.probeGroup.children) o.renderOrder = 10;
    this.probeGroup.visible = false;
    const canvas = this.viewer.renderer.domElement;
    canvas.addEventListener('pointermove', (e) => this.onPointerMove(e));
  }

  async activate() {
    this.active = true;
    this.viewer.setUpAxis(false);
    this.viewer.clearOverlay();
    this.viewer.scene.add(this.probeGroup);   // in the scene, not in the model's root: framing ignores it
    await this.run(true);
  }

  deactivate() {
    this.active = false;
    this.setProbe(false);
    this.viewer.scene.remove(this.probeGroup);
  }

  /** The editor's request as an object, upload nodes still named by their label. Throws when it is not JSON. */
  editorRequest() {
    try {
      return JSON.parse($('imp-scene').value);
    } catch (e) {
      throw new Error(`The scene is not valid JSON: ${e.message}`);
    }
  }

  /** The editor's request with the uploaded meshes in place of their labels. */
  requestToSend() {
    const request = this.editorRequest();
    if (isNode(request)) substituteUploads(request.scene, this.uploads, 'scene');
    return request;
  }

  async run(fit) {
    this.app.clearError();
    let scene;
    try {
      scene = this.requestToSend();
    } catch (e) {
      this.app.showError(e);
      return;
    }
    try {
      const result = await call('POST', '/implicit/mesh', { body: { ...scene, output: { ...(scene.output ?? {}), format: 'glb', normals: true } } });
      const geometry = result.json?.mesh ? geometryFromJsonMesh(result.json.mesh) : await this.viewer.parseGlb(result.bytes);
      if (!this.active) return;
      this.viewer.setGeometry(geometry, { fit: fit || !this.shown });
      this.shown = true;
      const faces = geometry.index ? geometry.index.count / 3 : geometry.attributes.position.count / 3;
      this.app.setStats([`triangles: ${faces}`,
                         ...headerStats(result.headers, [['X-Output-Vertices', 'output vertices'], ['X-Grid', 'grid'],
                                                         ['X-Surface-Cells', 'surface cells'],
                                                         ['X-Field-Evaluations', 'field evaluations'], ['X-Elapsed-Ms', 'server ms']]),
                         `round trip: ${result.roundTripMs.toFixed(1)} ms`], { outputFaces: faces });
      const objRequest = { ...scene, output: { ...(scene.output ?? {}), format: 'obj' } };
      this.app.setDownloads({ glb: result.json ? null : result.bytes,
                              obj: async () => (await call('POST', '/implicit/mesh', { body: objRequest })).bytes, name: 'implicit' });
      if (this.probeOn && this.pointer) {   // the probe answers for the scene now shown, at the same pointer position
        this.probePending = true;
        this.probeNext();
      }
    } catch (e) {
      this.app.showError(e);
    }
  }

  /** "Add mesh…": the file repaired and converted by POST /repair, combined with the editor's scene, bounds grown to
   *  hold it, and meshed again. */
  async addMesh(file) {
    this.app.clearError();
    let request;
    try {
      request = this.editorRequest();
      if (!isNode(request) || !isNode(request.scene)) throw new Error('The editor has no "scene" to combine the mesh with');
    } catch (e) {
      this.app.showError(e);
      $('imp-mesh-file').value = '';
      return;
    }
    let upload;
    try {
      const result = await call('POST', '/repair?format=json', { body: await file.arrayBuffer(), contentType: meshMediaType(file.name) });
      const mesh = result.json?.mesh;
      if (!mesh?.faces?.length) throw new Error('the repaired mesh has no faces');
      const triangles = mesh.faces.reduce((n, f) => n + f.length - 2, 0);
      upload = { mesh: { positions: mesh.positions, faces: mesh.faces }, box: boxOf(mesh.positions), triangles,
                 repair: repairStats(result.headers) };
    } catch (e) {
      this.app.showError(e, `${file.name}:`);
      return;
    } finally {
      $('imp-mesh-file').value = '';
    }
    let label = `${file.name} (${upload.triangles.toLocaleString('en-US')} triangles)`;
    for (let n = 2; this.uploads.has(label); ++n) label = `${file.name} #${n} (${upload.triangles.toLocaleString('en-US')} triangles)`;
    this.uploads.set(label, upload);
    let node = { op: 'mesh', mesh: { [UPLOAD_KEY]: label } }, box = upload.box;
    if ($('imp-fit').checked && validBounds(request.bounds)) ({ node, box } = fitted(node, box, request.bounds));
    request.scene = combine(request.scene, node, $('imp-combine').value, Number($('imp-smooth-k').value));
    upload.boundsBefore = request.bounds;
    request.bounds = upload.boundsAfter = growBounds(request.bounds, box);
    // a mesh node costs a BVH descent per evaluation: the octree skips the cells far from the surface
    if (request.mode === undefined) request.mode = 'adaptive';
    $('imp-scene').value = compactJson(request);
    this.listUploads();
    await this.run(true);
  }

  /** "remove": the upload's node taken out of the editor's scene (see removeUpload) and the scene meshed again. */
  async removeMesh(label) {
    this.app.clearError();
    let request;
    try {
      request = this.editorRequest();
    } catch (e) {
      this.app.showError(e);
      return;
    }
    if (isNode(request) && isNode(request.scene)) {
      const scene = removeUpload(request.scene, label);
      if (scene === null) {
        this.app.showError(new Error('The scene is only this mesh: edit the scene first, or it would be empty'));
        return;
      }
      request.scene = scene;
      // the bounds this upload grew go back to what they were, unless they have been edited or grown again since
      const upload = this.uploads.get(label);
      if (upload && upload.boundsBefore !== undefined && JSON.stringify(request.bounds) === JSON.stringify(upload.boundsAfter))
        request.bounds = upload.boundsBefore;
      $('imp-scene').value = compactJson(request);
    }
    this.uploads.delete(label);
    this.listUploads();
    await this.run(false);
  }

  listUploads() {
    const list = $('imp-meshes');
    list.replaceChildren();
    for (const [label, upload] of this.uploads) {
      const item = document.createElement('li');
      const remove = document.createElement('button');
      remove.textContent = 'remove';
      remove.title = `remove ${label} from the scene`;
      remove.addEventListener('click', () => this.removeMesh(label));
      item.append(label, remove);
      if (upload.repair.length) {
        const report = document.createElement('span');
        report.className = 'repair';
        report.textContent = upload.repair.join('; ');
        item.append(report);
      }
      list.append(item);
    }
  }

  setProbe(on) {
    this.probeOn = on;
    $('imp-probe').setAttribute('aria-pressed', String(on));
    $('imp-probe-readout').hidden = !on;
    if (on) $('imp-probe-readout').textContent = 'move the pointer over the view';
    this.probeGroup.visible = false;
    this.viewer.renderer.domElement.style.cursor = on ? 'crosshair' : '';
    this.viewer.render();
  }

  onPointerMove(event) {
    if (!this.active || !this.probeOn) return;
    this.pointer = { x: event.clientX, y: event.clientY };
    this.probePending = true;
    this.probeNext();
  }

  /** The size and centre of what is shown: the drawn mesh's box, else the editor's bounds. */
  extent() {
    const box = new THREE.Box3();
    if (this.viewer.result) box.setFromObject(this.viewer.result);
    else {
      try {
        const b = this.editorRequest().bounds;
        box.set(new THREE.Vector3(...b[0]), new THREE.Vector3(...b[1]));
      } catch { box.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1)); }
    }
    return { size: Math.max(box.getSize(new THREE.Vector3()).length(), 1e-9), centre: box.getCenter(new THREE.Vector3()) };
  }

  /** The meshing cell of the editor's request: its cell_size, else the bounds' longest side / resolution (64 when
   *  not given); from the drawn extent when the request cannot be read. */
  cellSize(extent) {
    try {
      const r = this.editorRequest();
      if (Number(r.cell_size) > 0) return Number(r.cell_size);
      const side = Math.max(...[0, 1, 2].map((k) => r.bounds[1][k] - r.bounds[0][k]));
      if (side > 0) return side / (Number(r.resolution) || 64);
    } catch { /* below */ }
    return extent.size / Math.sqrt(3) / 64;
  }

  /** The probe point under the pointer, in the scene's frame: just past the drawn surface where the ray meets it (a
   *  fraction of a meshing cell, so inside the solid), else on the plane through the centre facing the camera. */
  probePoint(pointer, extent) {
    const rect = this.viewer.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2((pointer.x - rect.left) / rect.width * 2 - 1, -((pointer.y - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.viewer.camera);
    const ray = this.raycaster.ray;
    let point = null, onSurface = false;
    if (this.viewer.result) {
      const hit = this.raycaster.intersectObject(this.viewer.result, false)[0];
      if (hit) {
        point = hit.point.clone().addScaledVector(ray.direction, 0.25 * this.cellSize(extent));
        onSurface = true;
      }
    }
    if (!point) {
      const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(this.viewer.camera.getWorldDirection(new THREE.Vector3()), extent.centre);
      point = ray.intersectPlane(plane, new THREE.Vector3());
    }
    return point && { point: this.viewer.root.worldToLocal(point), onSurface };
  }

  /** One query in flight at most: the latest pointer position is asked when the previous answer is in. */
  async probeNext() {
    if (this.probeBusy || !this.probePending) return;
    this.probePending = false;
    const extent = this.extent();
    const probe = this.probePoint(this.pointer, extent);
    if (!probe) return;
    const readout = $('imp-probe-readout');
    let body;
    try {
      body = this.probeBody(probe.point);
    } catch (e) {
      readout.textContent = `probe: ${e.message}`;
      return;
    }
    this.probeBusy = true;
    try {
      const result = await call('POST', '/implicit/query', { body, contentType: 'application/json' });
      if (this.active && this.probeOn) this.showProbe(probe, result.json, extent, result.roundTripMs);
    } catch (e) {
      readout.textContent = `probe: ${e.message}`;
      delete readout.dataset.class;
    } finally {
      this.probeBusy = false;
    }
    this.probeNext();
  }

  /** The query's body as text; the scene (with its meshes, perhaps large) is serialised once per edit or upload. */
  probeBody(point) {
    const text = $('imp-scene').value;
    if (this.probeScene?.text !== text || this.probeScene.uploads !== this.uploadsKey()) {
      const request = this.requestToSend();
      if (!isNode(request) || request.scene === undefined) throw new Error('the editor has no "scene"');
      this.probeScene = { text, uploads: this.uploadsKey(), json: JSON.stringify(request.scene) };
    }
    return `{"scene":${this.probeScene.json},"points":[${JSON.stringify(point.toArray())}]}`;
  }

  uploadsKey() { return [...this.uploads.keys()].join('\n'); }

  showProbe({ point, onSurface }, answer, extent, ms) {
    const a = answer.points[0];
    const radius = 0.012 * extent.size;
    const world = this.viewer.root.localToWorld(point.clone());
    this.probeMarker.position.copy(world);
    this.probeMarker.scale.setScalar(radius);
    this.probeMarker.material.color.setHex(PROBE_COLOURS[a.class] ?? PROBE_COLOURS.undefined);
    let closest = null;
    const g = a.gradient;
    if (answer.kind === 'exact_distance' && a.value !== null && g) {
      const g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
      if (g2 > 0) closest = point.clone().sub(new THREE.Vector3(...g).multiplyScalar(a.value / g2));
    }
    this.closestMarker.visible = this.probeLine.visible = closest !== null;
    if (closest) {
      const closestWorld = this.viewer.root.localToWorld(closest.clone());
      this.closestMarker.position.copy(closestWorld);
      this.closestMarker.scale.setScalar(0.6 * radius);
      this.probeLine.geometry.setFromPoints([world, closestWorld]);
    }
    this.probeGroup.visible = true;
    this.viewer.render();
    const lines = [`${a.class} f = ${num(a.value)}`,
                   `at ${vec(point.toArray())}${onSurface ? ' (just past the drawn surface)' : ' (on the plane)'}`,
                   closest ? `closest ${vec(closest.toArray())}` : `closest: only for exact distances (scene: ${answer.kind})`,
                   `grad ${g ? vec(g) : 'null'}`,
                   `${answer.kind}, ${ms.toFixed(1)} ms`];
    const readout = $('imp-probe-readout');
    readout.textContent = lines.join('\n');
    readout.dataset.class = a.class;
    readout.dataset.value = String(a.value);
    readout.dataset.point = JSON.stringify(point.toArray());
    readout.dataset.closest = closest ? JSON.stringify(closest.toArray()) : '';
    readout.dataset.queries = String(++this.probeQueries);
  }
}
