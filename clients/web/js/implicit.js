// Implicit view: an editable scene JSON sent to POST /implicit/mesh, the mesh shown as a preview. The tab appears
// only when the server's /openapi.json lists /implicit/mesh; the initial scene is that document's example.
import * as THREE from 'three';
import { call, headerStats } from './api.js';

const $ = (id) => document.getElementById(id);

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

/** Indented JSON with arrays of numbers kept on one line ([1, 1, 1]). */
function compactJson(value) {
  return JSON.stringify(value, null, 2)
    .replace(/\[\s*(-?[\d.eE+-]+(?:,\s*-?[\d.eE+-]+)*)\s*\]/g, (_, inner) => `[${inner.split(/,\s*/).join(', ')}]`);
}

/** A box with a spherical bite, when the server's document has no example. */
const DEFAULT_REQUEST = {
  scene: { op: 'difference', args: [{ op: 'box', half_size: [1, 1, 1] },
                                    { op: 'translate', offset: [0, 0, 1], arg: { op: 'sphere', radius: 0.8 } }] },
  bounds: [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]],
  resolution: 48,
};

export class ImplicitView {
  constructor(app, example) {
    this.app = app;
    this.viewer = app.viewer;
    const initial = { ...(example ?? DEFAULT_REQUEST) };
    delete initial.output;   // the preview asks for GLB itself
    $('imp-scene').value = compactJson(initial);
    $('imp-run').addEventListener('click', () => this.run(false));
    $('imp-scene').addEventListener('keydown', (e) => { if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) this.run(false); });
  }

  async activate() {
    this.active = true;
    this.viewer.setUpAxis(false);
    this.viewer.clearOverlay();
    await this.run(true);
  }

  deactivate() { this.active = false; }

  async run(fit) {
    this.app.clearError();
    let scene;
    try {
      scene = JSON.parse($('imp-scene').value);
    } catch (e) {
      this.app.showError(e, 'The scene is not valid JSON');
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
    } catch (e) {
      this.app.showError(e);
    }
  }
}
