// Simplify view: a target slider; each position is simplified on the server (POST /simplify) and shown with the
// measured error (report_error: Hausdorff and RMS distances to the input). "Keep volume" sends restore_volume 0.5.
import { call, meshMediaType, headerStats, repairStats } from './api.js';
import { builtins } from './meshes.js';

const $ = (id) => document.getElementById(id);

export class SimplifyView {
  constructor(app) {
    this.app = app;
    this.viewer = app.viewer;
    this.source = null;   // {json: mesh} or {bytes, type}
    this.busy = false;
    this.dirty = false;
    $('simp-source').addEventListener('change', () => this.setSource({ json: builtins[$('simp-source').value]() }, $('simp-source').value));
    $('simp-file').addEventListener('change', async (e) => {
      const file = e.target.files[0];
      if (file) this.setSource({ bytes: await file.arrayBuffer(), type: meshMediaType(file.name) }, file.name.replace(/\.[^.]*$/, ''));
    });
    // while sliding: quick results with the quadric error estimate; on release: the measured Hausdorff/RMS too
    $('simp-ratio').addEventListener('input', () => { this.showRatio(); this.run(false); });
    $('simp-ratio').addEventListener('change', () => this.run(true));
    $('simp-lock').addEventListener('change', () => this.run(true));
    $('simp-volume').addEventListener('change', () => this.run(true));
    this.showRatio();
  }

  showRatio() { $('simp-ratio-out').textContent = `${$('simp-ratio').value} %`; }

  async activate() {
    this.active = true;
    this.viewer.setUpAxis(false);
    this.viewer.clearOverlay();
    if (!this.source) this.setSource({ json: builtins[$('simp-source').value]() }, $('simp-source').value);
    else { this.fitNext = true; this.run(true); }
  }

  deactivate() { this.active = false; }

  setSource(source, name) {
    this.source = source;
    this.name = name;
    this.fitNext = true;
    this.viewer.setGeometry(null);
    this.run(true);
  }

  options(report) {
    const o = { ratio: Number($('simp-ratio').value) / 100, lock_border: $('simp-lock').checked, report_error: report };
    if ($('simp-volume').checked) o.restore_volume = 0.5;   // the README's value for the lowest RMS; 0 (off) is the default: not sent
    return o;
  }

  send(format, report = this.report) {
    const o = this.options(report);
    if (this.source.json) return call('POST', '/simplify', { body: { mesh: this.source.json, ...o, output: { format } } });
    const q = new URLSearchParams({ ratio: String(o.ratio), lock_border: String(o.lock_border), report_error: String(report), format });
    if (o.restore_volume) q.set('restore_volume', String(o.restore_volume));
    return call('POST', `/simplify?${q}`, { body: this.source.bytes, contentType: this.source.type });
  }

  /** Latest wins: while a request is out, slider moves only mark the state dirty. `report`: measure the error. */
  async run(report) {
    if (!this.source || !this.active) return;
    this.report = report;
    if (this.busy) { this.dirty = true; return; }
    this.busy = true;
    this.app.clearError();
    try {
      do {
        this.dirty = false;
        const result = await this.send('glb');
        const geometry = await this.viewer.parseGlb(result.bytes);
        if (!this.active) return;
        this.viewer.setGeometry(geometry, { fit: this.fitNext });
        this.fitNext = false;
        this.app.setStats([
          ...headerStats(result.headers, [['X-Input-Faces', 'input faces'], ['X-Output-Faces', 'output faces'],
                                          ['X-Triangulated', 'triangulated'], ['X-Hausdorff', 'Hausdorff (measured)'],
                                          ['X-RMS', 'RMS (measured)'], ['X-Achieved-Error', 'quadric error estimate'],
                                          ['X-Relative-Error', 'relative to diagonal'],
                                          ['X-Elapsed-Ms', 'server ms']]),
          ...repairStats(result.headers),
          `round trip: ${result.roundTripMs.toFixed(1)} ms`,
        ], { outputFaces: Number(result.headers.get('X-Output-Faces')) });
        this.app.setDownloads({ glb: result.bytes, obj: async () => (await this.send('obj', false)).bytes, name: `${this.name}-simplified` });
      } while (this.dirty);
    } catch (e) {
      this.app.showError(e);
    } finally {
      this.busy = false;
    }
  }
}
