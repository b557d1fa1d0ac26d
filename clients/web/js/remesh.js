// Remesh view: isotropic remeshing (POST /remesh) of a built-in or uploaded mesh towards one edge length, with the
// triangle quality the service reports before and after. The tab appears when /openapi.json lists /remesh.
import { call, meshMediaType, headerStats, repairStats } from './api.js';
import { builtins } from './meshes.js';

const $ = (id) => document.getElementById(id);

export class RemeshView {
  constructor(app) {
    this.app = app;
    this.viewer = app.viewer;
    this.source = null;
    $('rem-source').addEventListener('change', () => this.setSource({ json: builtins[$('rem-source').value]() }, $('rem-source').value));
    $('rem-file').addEventListener('change', async (e) => {
      const file = e.target.files[0];
      if (file) this.setSource({ bytes: await file.arrayBuffer(), type: meshMediaType(file.name) }, file.name.replace(/\.[^.]*$/, ''));
    });
    for (const id of ['rem-edge', 'rem-iterations', 'rem-feature']) $(id).addEventListener('change', () => this.run());
    $('rem-run').addEventListener('click', () => this.run());
  }

  async activate() {
    this.active = true;
    this.viewer.setUpAxis(false);
    this.viewer.clearOverlay();
    this.fitNext = true;
    if (!this.source) this.setSource({ json: builtins[$('rem-source').value]() }, $('rem-source').value);
    else await this.run();
  }

  deactivate() { this.active = false; }

  setSource(source, name) {
    this.source = source;
    this.name = name;
    this.fitNext = true;
    this.viewer.setGeometry(null);
    this.run();
  }

  options() {
    const o = { iterations: Number($('rem-iterations').value), feature_angle: Number($('rem-feature').value) };
    if ($('rem-edge').value !== '') o.edge_length = Number($('rem-edge').value);
    return o;
  }

  send(format) {
    const o = this.options();
    if (this.source.json) return call('POST', '/remesh', { body: { mesh: this.source.json, ...o, output: { format } } });
    const q = new URLSearchParams(Object.entries({ ...o, format }).map(([k, v]) => [k, String(v)]));
    return call('POST', `/remesh?${q}`, { body: this.source.bytes, contentType: this.source.type });
  }

  async run() {
    if (!this.source || !this.active) return;
    this.app.clearError();
    const seq = (this.seq = (this.seq ?? 0) + 1);
    try {
      const result = await this.send('glb');
      const geometry = await this.viewer.parseGlb(result.bytes);
      if (seq !== this.seq || !this.active) return;
      this.viewer.setGeometry(geometry, { fit: this.fitNext });
      this.fitNext = false;
      this.app.setStats([
        ...headerStats(result.headers, [['X-Input-Faces', 'input faces'], ['X-Output-Faces', 'output faces'],
                                        ['X-Edge-Length', 'target edge length'], ['X-Mean-Edge-Length-After', 'mean edge after'],
                                        ['X-Min-Angle-Before', 'min angle before'], ['X-Min-Angle-After', 'min angle after'],
                                        ['X-Below-30-Before', 'angles < 30° before'], ['X-Below-30-After', 'angles < 30° after'],
                                        ['X-Feature-Edges', 'feature edges'], ['X-Hausdorff', 'Hausdorff'],
                                        ['X-Elapsed-Ms', 'server ms']]),
        ...repairStats(result.headers),
        `round trip: ${result.roundTripMs.toFixed(1)} ms`,
      ], { outputFaces: Number(result.headers.get('X-Output-Faces')) });
      this.app.setDownloads({ glb: result.bytes, obj: async () => (await this.send('obj')).bytes, name: `${this.name}-remeshed` });
    } catch (e) {
      if (seq === this.seq) this.app.showError(e);
    }
  }
}
