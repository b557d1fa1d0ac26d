// Point cloud view: a scan (PLY, XYZ, OBJ, or the points of a GLB or glTF) or a sampled demo cloud, drawn as points with their
// normals, and its screened Poisson reconstruction. POST /pointcloud reads the file (or samples the demo) and
// estimates and orients normals when the cloud has none; its PLY answer is drawn and is what POST /reconstruct is
// sent. The reconstruction is shown twice, closed and trimmed, side by side (or one of them), with the server's report.
// The tab appears when /openapi.json lists POST /pointcloud; reconstruction when it lists POST /reconstruct.
import * as THREE from 'three';
import { call } from './api.js';
import { readPlyPoints, demoClouds, typicalDensity } from './pointdata.js';

const $ = (id) => document.getElementById(id);

/** The media type POST /pointcloud expects for a point file, from its extension (the service sniffs the rest). */
function pointMediaType(fileName) {
  const ext = fileName.toLowerCase().split('.').pop();
  return { ply: 'application/ply', obj: 'model/obj', xyz: 'text/x-xyz', glb: 'model/gltf-binary',
           gltf: 'model/gltf+json' }[ext] ?? 'application/octet-stream';
}

/** The report of an answer as lines ("iso value: 0.49"): its X- headers but the request id, the triangle count first
 *  and the time last (the rest in name order, as fetch lists headers). */
function reportLines(headers) {
  const labels = { 'x-output-faces': 'triangles', 'x-elapsed-ms': 'server ms' };
  const rank = (name) => (name === 'x-output-faces' ? 0 : name === 'x-elapsed-ms' ? 2 : 1);
  return [...headers].filter(([name]) => name.startsWith('x-') && name !== 'x-request-id')
    .sort((a, b) => rank(a[0]) - rank(b[0]))
    .map(([name, value]) => `${labels[name] ?? name.slice(2).replace(/-/g, ' ')}: ${value}`);
}

const triangleCount = (g) => (g.index ? g.index.count : g.attributes.position.count) / 3;

export class PointCloudView {
  /** `reconstruct`: the POST /reconstruct operation of /openapi.json, or null when the server has none. */
  constructor(app, { reconstruct }) {
    this.app = app;
    this.viewer = app.viewer;
    this.canReconstruct = !!reconstruct;
    this.cloud = null;     // {count, positions, normals, ply (the bytes sent to /reconstruct), estimated, k, name, ...}
    this.results = null;   // {options, full, trimmed}: the answers of /reconstruct ({bytes, headers, roundTripMs, triangles})
    this.loads = 0;        // latest wins, for clouds and for reconstructions
    this.runs = 0;
    this.busy = false;
    this.pointMaterial = new THREE.PointsMaterial({ size: 3, sizeAttenuation: false, vertexColors: true });
    this.normalMaterial = new THREE.LineBasicMaterial({ color: 0xffd84a, transparent: true, opacity: 0.4 });

    // the option ranges are the server's, when /openapi.json gives them; no trim control unless it lists trim
    const parameter = (name) => reconstruct?.parameters?.find((p) => p.name === name && p.in === 'query');
    for (const [id, name] of [['pc-depth', 'depth'], ['pc-point-weight', 'point_weight'], ['pc-trim', 'trim']]) {
      const schema = parameter(name)?.schema;
      if (schema?.minimum !== undefined) $(id).min = String(schema.minimum);
      if (schema?.maximum !== undefined) $(id).max = String(schema.maximum);
    }
    this.canTrim = !!parameter('trim');
    this.canFit = !!parameter('fit_to_samples');
    $('pc-fit').disabled = !this.canFit;
    $('pc-run').disabled = !this.canReconstruct;
    $('pc-trim').disabled = !this.canTrim;
    $('pc-layout').disabled = !this.canTrim;
    $('pc-no-recon').hidden = this.canReconstruct;
    $('pc-no-trim').hidden = !this.canReconstruct || this.canTrim;

    $('pc-file').addEventListener('change', async (e) => {
      const file = e.target.files[0];
      if (!file) return;
      const name = file.name.replace(/\.[^.]*$/, '');
      try {
        const bytes = await file.arrayBuffer();
        await this.load({ bytes, type: pointMediaType(file.name) }, name);
      } catch (err) {
        this.app.showError(err, `Could not read ${file.name}`);
      }
    });
    $('pc-sample').addEventListener('click', () => this.sampleDemo());
    for (const id of ['pc-estimate', 'pc-k'])
      $(id).addEventListener('change', () => { if (this.source) this.load(this.source, this.cloud?.name ?? 'cloud'); });
    $('pc-show-points').addEventListener('change', () => this.showOverlay());
    $('pc-show-normals').addEventListener('change', () => this.showOverlay());
    $('pc-run').addEventListener('click', () => this.reconstruct());
    for (const id of ['pc-depth', 'pc-point-weight', 'pc-trim'])
      $(id).addEventListener('keydown', (e) => { if (e.key === 'Enter') this.reconstruct(); });
    $('pc-layout').addEventListener('change', () => this.viewer.setLayout($('pc-layout').value));
  }

  async activate() {
    this.active = true;
    this.viewer.setUpAxis(false);
    this.viewer.setLayout($('pc-layout').value);
    if (!this.cloud) return this.sampleDemo();
    this.drawCloud();
    if (this.results) await this.showResults();
    else this.showStats();
    this.viewer.fit();
  }

  deactivate() { this.active = false; }

  sampleDemo() {
    const demo = $('pc-demo').value;
    const count = Math.max(1, Math.round(Number($('pc-count').value) || 5000));
    return this.load({ json: { sample: demoClouds[demo](count) } }, `${demo}-${count}`);
  }

  /** POST /pointcloud for the PLY of `source` ({bytes, type}: a file; {json}: points or a sample), normals estimated
   *  with k neighbours when `k` is set. */
  requestCloud(source, k) {
    if (source.json) {
      const body = { ...source.json, output: { format: 'ply' } };
      if (k) body.estimate_normals = { k };
      return call('POST', '/pointcloud', { body });
    }
    const q = new URLSearchParams({ format: 'ply' });
    if (k) {
      q.set('estimate_normals', 'true');
      q.set('k', String(k));
    }
    return call('POST', `/pointcloud?${q}`, { body: source.bytes, contentType: source.type });
  }

  /** Reads a cloud through the server: as it is, then (when it has no normals, or asked to) with estimated ones. */
  async load(source, name) {
    const seq = ++this.loads;
    this.app.clearError();
    const k = Number($('pc-k').value);
    try {
      const force = $('pc-estimate').checked;
      let answer = await this.requestCloud(source, force ? k : null);
      let estimated = force;
      const first = answer;
      if (answer.headers.get('X-Normals') !== 'true') {
        answer = await this.requestCloud(source, k);
        estimated = true;
      }
      const points = readPlyPoints(answer.bytes);
      if (seq !== this.loads) return;
      this.source = source;
      this.cloud = { ...points, ply: answer.bytes, estimated, k, name, headers: answer.headers,
                     roundTripMs: answer.roundTripMs + (first === answer ? 0 : first.roundTripMs) };
      this.results = null;
      this.fitResults = true;
      this.runs++;   // a reconstruction still running is of the previous cloud: its answer is dropped
      this.busy = false;
      if (!this.active) return;
      this.viewer.setGeometry(null);
      this.viewer.setSecond(null);
      this.viewer.setLabels([]);
      this.app.setDownloads(null);
      this.drawCloud();
      this.viewer.fit();
      this.suggestTrim();
      this.showStats();
    } catch (e) {
      if (seq === this.loads) this.app.showError(e, `Could not read ${name}`);
    }
  }

  /** Fills in a trim half a level below the cloud's typical sampling density (estimated here on the server's scale):
   *  that cuts within a cell or two of where the samples end (docs/reconstruction.md, "Trimming"). */
  suggestTrim() {
    const c = this.cloud;
    c.density = typicalDensity(c.positions, c.count);
    if (!this.canTrim || !Number.isFinite(c.density)) return;
    $('pc-trim').value = String(Math.max(0, Math.round((c.density - 0.5) * 10) / 10));
    $('pc-density').textContent = `This cloud's sampling density is about ${c.density.toFixed(2)} (the server reports it ` +
      'as sample density): a trim 0.3 to 1 below it cuts where the samples end.';
    $('pc-density').hidden = false;
  }

  /** The points, coloured by their normal (grey without), and a line along each normal (at most 20,000 drawn). */
  drawCloud() {
    this.viewer.clearOverlay();
    const c = this.cloud;
    const points = new THREE.BufferGeometry();
    points.setAttribute('position', new THREE.BufferAttribute(c.positions, 3));
    const colors = new Float32Array(3 * c.count);
    for (let i = 0; i < colors.length; ++i) colors[i] = c.normals ? 0.5 + 0.5 * c.normals[i] : 0.8;
    points.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    points.computeBoundingBox();
    this.points = new THREE.Points(points, this.pointMaterial);
    this.viewer.overlay.add(this.points);
    this.normals = null;
    if (c.normals) {
      const length = 0.025 * points.boundingBox.getSize(new THREE.Vector3()).length();
      const stride = Math.max(1, Math.ceil(c.count / 20000));
      const ends = new Float32Array(6 * Math.ceil(c.count / stride));
      for (let i = 0, j = 0; i < c.count; i += stride, j += 6)
        for (let k = 0; k < 3; ++k) {
          ends[j + k] = c.positions[3 * i + k];
          ends[j + 3 + k] = c.positions[3 * i + k] + length * c.normals[3 * i + k];
        }
      const lines = new THREE.BufferGeometry();
      lines.setAttribute('position', new THREE.BufferAttribute(ends, 3));
      this.normals = new THREE.LineSegments(lines, this.normalMaterial);
      this.viewer.overlay.add(this.normals);
    }
    this.showOverlay();
  }

  showOverlay() {
    if (this.points) this.points.visible = $('pc-show-points').checked;
    if (this.normals) this.normals.visible = $('pc-show-normals').checked;
    this.viewer.render();
  }

  options() {
    return { depth: Number($('pc-depth').value), point_weight: Number($('pc-point-weight').value),
             trim: this.canTrim ? Number($('pc-trim').value) : 0, fit: $('pc-fit').checked };
  }

  /** POST /reconstruct with the cloud's PLY; `trimmed`: with the trim option (otherwise the closed surface). */
  send(o, trimmed, format) {
    const q = new URLSearchParams({ depth: String(o.depth), point_weight: String(o.point_weight), format });
    if (trimmed) q.set('trim', String(o.trim));
    if (this.canFit && !o.fit) q.set('fit_to_samples', 'false');
    return call('POST', `/reconstruct?${q}`, { body: this.cloud.ply, contentType: 'application/ply' });
  }

  /** The closed and (with trim > 0) the trimmed reconstruction, one after the other; the latest press wins. */
  async reconstruct() {
    if (!this.cloud || !this.canReconstruct) return;
    const seq = ++this.runs;
    const o = this.options();
    this.app.clearError();
    this.busy = true;
    try {
      const full = await this.send(o, false, 'glb');
      const trimmed = o.trim > 0 && seq === this.runs ? await this.send(o, true, 'glb') : null;
      if (seq !== this.runs) return;
      const answer = (r) => r && { bytes: r.bytes, headers: r.headers, roundTripMs: r.roundTripMs };
      this.results = { options: o, full: answer(full), trimmed: answer(trimmed) };
      if (this.active) await this.showResults();
    } catch (e) {
      if (seq === this.runs) this.app.showError(e, 'Reconstruction failed');
    } finally {
      if (seq === this.runs) this.busy = false;
    }
  }

  /** Draws the results (parsed again from their GLB: switching views disposes the meshes), labels and report. */
  async showResults() {
    const { full, trimmed, options } = this.results;
    const results = this.results;
    const first = await this.viewer.parseGlb(full.bytes);
    const second = trimmed ? await this.viewer.parseGlb(trimmed.bytes) : null;
    if (results !== this.results || !this.active) return;
    full.triangles = triangleCount(first);
    if (trimmed) trimmed.triangles = triangleCount(second);
    this.viewer.setGeometry(first);
    this.viewer.setSecond(second);
    if (this.fitResults) this.viewer.fit();   // the first results of a cloud: framed for the halves
    this.fitResults = false;
    this.viewer.setLabels([`reconstructed: ${full.triangles} triangles`,
                           trimmed ? `trimmed (trim ${options.trim}): ${trimmed.triangles} triangles` : '']);
    this.showStats();
    const shown = trimmed ?? full;
    const name = `${this.cloud.name}-${trimmed ? 'trimmed' : 'reconstructed'}`;
    this.app.setDownloads({ glb: shown.bytes, obj: async () => (await this.send(options, !!trimmed, 'obj')).bytes, name });
  }

  showStats() {
    const c = this.cloud;
    const lines = [`points: ${c.count}`,
                   c.normals ? `normals: ${c.estimated ? `estimated and oriented (k = ${c.k})` : 'from the cloud'}` : 'normals: none',
                   `POST /pointcloud round trip: ${c.roundTripMs.toFixed(1)} ms`];
    const data = { points: c.count, normals: !c.normals ? 'none' : c.estimated ? 'estimated' : 'given' };
    const r = this.results;
    if (r) {
      lines.push('', `reconstructed (depth ${r.options.depth}, point weight ${r.options.point_weight}):`,
                 ...reportLines(r.full.headers).map((l) => `  ${l}`),
                 `  round trip: ${r.full.roundTripMs.toFixed(1)} ms`);
      data.triangles = r.full.triangles;
      data.outputFaces = r.full.triangles;
      if (r.trimmed) {
        lines.push(`trimmed (trim ${r.options.trim}):`, ...reportLines(r.trimmed.headers).map((l) => `  ${l}`),
                   `  round trip: ${r.trimmed.roundTripMs.toFixed(1)} ms`);
        data.trimmedTriangles = r.trimmed.triangles;
      }
    }
    this.app.setStats(lines, data);
  }
}
