// The surfaced web client: tabs (views), the shared viewport, stats, errors and downloads.
import { Viewer } from './viewer.js';
import { PatchesView } from './patches.js';
import { SubdivideView } from './subdivide.js';
import { SimplifyView } from './simplify.js';
import { ImplicitView } from './implicit.js';
import { RemeshView } from './remesh.js';
import { CurvesView } from './curves.js';
import { PointCloudView } from './pointcloud.js';
import { call, ProblemError } from './api.js';

const $ = (id) => document.getElementById(id);

class App {
  constructor() {
    this.viewer = new Viewer($('viewport'));
    this.downloads = null;
    this.views = { patches: new PatchesView(this), subdivide: new SubdivideView(this), simplify: new SimplifyView(this) };
    this.current = null;
    for (const tab of document.querySelectorAll('#tabs button'))
      tab.addEventListener('click', () => this.show(tab.dataset.view));
    $('wireframe').addEventListener('change', () => this.viewer.setWireframe($('wireframe').checked));
    $('download-glb').addEventListener('click', () => this.download('glb'));
    $('download-obj').addEventListener('click', () => this.download('obj'));
  }

  /** Views for endpoints the server has (the document lists them): remesh, implicit, curves and point cloud appear when
   *  it serves them. */
  async discover() {
    try {
      const doc = (await call('GET', '/openapi.json')).json;
      if (doc?.paths?.['/remesh']?.post) {
        this.views.remesh = new RemeshView(this);
        document.querySelector('#tabs button[data-view=remesh]').hidden = false;
      }
      const op = doc?.paths?.['/implicit/mesh']?.post;
      if (op) {
        const example = op.requestBody?.content?.['application/json']?.example;
        const ops = doc?.components?.schemas?.ImplicitScene?.properties?.op?.enum ?? [];
        this.views.implicit = new ImplicitView(this, example, { meshNodes: ops.includes('mesh'),
                                                               query: !!doc?.paths?.['/implicit/query']?.post });
        document.querySelector('#tabs button[data-view=implicit]').hidden = false;
      }
      if (doc?.paths?.['/curves']?.post) {
        this.views.curves = new CurvesView(this);
        document.querySelector('#tabs button[data-view=curves]').hidden = false;
      }
      if (doc?.paths?.['/pointcloud']?.post) {
        this.views.pointcloud = new PointCloudView(this, { reconstruct: doc.paths['/reconstruct']?.post ?? null });
        document.querySelector('#tabs button[data-view=pointcloud]').hidden = false;
      }
    } catch (e) {
      this.showError(e, 'Could not read /openapi.json');
    }
  }

  async show(name) {
    if (!this.views[name]) return;
    for (const tab of document.querySelectorAll('#tabs button')) tab.setAttribute('aria-selected', String(tab.dataset.view === name));
    for (const panel of document.querySelectorAll('[data-panel]')) panel.hidden = panel.dataset.panel !== name;
    this.current?.deactivate();
    this.current = this.views[name];
    document.body.dataset.view = name;
    this.clearError();
    this.setStats([]);
    this.setDownloads(null);
    this.viewer.clearOverlay();
    this.viewer.setGeometry(null);
    this.viewer.setSecond(null);
    this.viewer.setLabels([]);
    await this.current.activate();
  }

  /** Stats lines under the panel; `data` goes into data-* attributes (read by the browser tests). */
  setStats(lines, data = {}) {
    const el = $('stats');
    el.textContent = lines.join('\n');
    for (const key of Object.keys(el.dataset)) delete el.dataset[key];
    for (const [k, v] of Object.entries(data)) el.dataset[k] = String(v);
    el.dataset.updates = String((this.statsUpdates = (this.statsUpdates ?? 0) + 1));
  }

  showError(error, context) {
    const el = $('error');
    const message = error instanceof ProblemError ? error.message : String(error.message ?? error);
    el.replaceChildren();
    const close = document.createElement('button');
    close.className = 'close';
    close.textContent = '×';
    close.title = 'dismiss';
    close.addEventListener('click', () => this.clearError());
    el.append(close, (context ? `${context}\n` : '') + message);
    el.hidden = false;
    if (!(error instanceof ProblemError)) console.warn(error);
  }

  clearError() { $('error').hidden = true; }

  setDownloads(d) {
    this.downloads = d;
    $('download-glb').disabled = !d?.glb;
    $('download-obj').disabled = !d?.obj;
  }

  async download(kind) {
    const d = this.downloads;
    if (!d) return;
    try {
      const bytes = kind === 'glb' ? d.glb : await d.obj();
      const url = URL.createObjectURL(new Blob([bytes], { type: kind === 'glb' ? 'model/gltf-binary' : 'model/obj' }));
      const a = document.createElement('a');
      a.href = url;
      a.download = `${d.name ?? 'result'}.${kind}`;
      a.click();
      setTimeout(() => URL.revokeObjectURL(url), 1000);
    } catch (e) {
      this.showError(e);
    }
  }
}

const app = new App();
window.surfaced = app;   // for the console and the browser tests
await app.discover();
await app.show('patches');
document.body.dataset.ready = 'true';
