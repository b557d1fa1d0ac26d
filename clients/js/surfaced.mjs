// A client for the surfaced HTTP service: an ES module on fetch (Node 18+ or a browser), no dependencies.
//
// One function per endpoint. Mesh endpoints take a JSON mesh ({positions: [[x, y, z], ...], faces: [[i, j, k, ...]]})
// or the bytes of a mesh file (OBJ, OFF, PLY, STL, GLB) with its media type; options are named as in the API.
// Results: {status, contentType, headers, body (Uint8Array), json (parsed JSON answers), text()}. Error answers
// (RFC 9457 problem+json) throw SurfacedError with .status, .problem, .field and .line.
//
//   import { Client } from './surfaced.mjs';
//   const c = new Client('http://127.0.0.1:8080');
//   const r = await c.subdivide({ mesh: cube, levels: 2, output: { format: 'json' } });
//   console.log(r.json.stats.output_faces);

export const MESH_MEDIA_TYPES = { obj: 'model/obj', off: 'model/off', ply: 'application/ply', stl: 'model/stl', glb: 'model/gltf-binary' };

export class SurfacedError extends Error {
  constructor(status, problem) {
    let text = `${problem.status ?? status} ${problem.title ?? 'error'}: ${problem.detail ?? ''}`;
    if (problem.field) text += ` (field ${problem.field})`;
    if (problem.line) text += ` (line ${problem.line})`;
    super(text);
    this.status = status;
    this.problem = problem;
    this.code = problem.code;
    this.field = problem.field;
    this.line = problem.line;
  }
}

const queryValue = (v) => (typeof v === 'boolean' ? (v ? 'true' : 'false') : String(v));

export class Client {
  constructor(baseUrl = 'http://127.0.0.1:8080', { timeoutMs = 60000 } = {}) {
    this.baseUrl = baseUrl.replace(/\/+$/, '');
    this.timeoutMs = timeoutMs;
  }

  /** Any request; `json` is sent as application/json, `data` (bytes or text) with `contentType`. */
  async request(method, path, { json, data, contentType, query, headers = {} } = {}) {
    let url = this.baseUrl + path;
    if (query) {
      const q = new URLSearchParams();
      for (const [k, v] of Object.entries(query)) if (v !== undefined && v !== null) q.set(k, queryValue(v));
      if ([...q].length) url += `?${q}`;
    }
    const h = { ...headers };
    let body = data;
    if (json !== undefined) { body = JSON.stringify(json); h['Content-Type'] = 'application/json'; }
    else if (contentType) h['Content-Type'] = contentType;
    let res;
    try {
      res = await fetch(url, { method, headers: h, body, signal: AbortSignal.timeout(this.timeoutMs) });
    } catch (e) {
      throw new SurfacedError(0, { title: 'connection failed', detail: `${url}: ${e.cause?.message ?? e.message}` });
    }
    const bytes = new Uint8Array(await res.arrayBuffer());
    const type = res.headers.get('content-type') ?? '';
    if (!res.ok && res.status !== 304) {
      let problem;
      try { problem = JSON.parse(new TextDecoder().decode(bytes)); } catch { problem = { title: res.statusText, detail: new TextDecoder().decode(bytes).slice(0, 300) }; }
      throw new SurfacedError(res.status, problem);
    }
    return {
      status: res.status,
      contentType: type,
      headers: res.headers,
      body: bytes,
      json: type.startsWith('application/json') ? JSON.parse(new TextDecoder().decode(bytes)) : undefined,
      text: () => new TextDecoder().decode(bytes),
    };
  }

  meshOperation(path, { mesh, data, contentType, ...options }) {
    if ((mesh === undefined) === (data === undefined)) throw new TypeError('give either mesh (JSON) or data (file bytes)');
    if (mesh !== undefined) return this.request('POST', path, { json: { mesh, ...options } });
    const { output = {}, ...rest } = options;   // raw file: options in the query, output options flattened
    return this.request('POST', path, { data, contentType: contentType ?? 'application/octet-stream', query: { ...rest, ...output } });
  }

  /** GET /healthz */
  async healthz() { return (await this.request('GET', '/healthz')).json; }

  /** GET /openapi.json */
  async openapi() { return (await this.request('GET', '/openapi.json')).json; }

  /** POST /subdivide: {mesh | data + contentType, scheme, levels, boundary, creases, limit_surface, ..., output} */
  subdivide(args) { return this.meshOperation('/subdivide', args); }

  /** POST /simplify: {mesh | data + contentType, target_faces | ratio | max_error, lock_border, restore_volume,
   *  threads, locked_vertices, report_error, repair ('auto' | 'none'), output}; what repair did: X-Repairs */
  simplify(args) { return this.meshOperation('/simplify', args); }

  /** POST /repair: {mesh | data + contentType, weld_tolerance, orient, min_component_faces, max_hole_edges, output};
   *  the report in X-Repairs and, in JSON output, stats.repairs */
  repair(args) { return this.meshOperation('/repair', args); }

  /** POST /tessellate: {patches, tolerance | segments, output} or {bez: text, tolerance | segments, format, ...} */
  tessellate({ patches, bez, ...options }) {
    if ((patches === undefined) === (bez === undefined)) throw new TypeError('give either patches or bez');
    if (patches !== undefined) return this.request('POST', '/tessellate', { json: { patches, ...options } });
    const { output = {}, ...rest } = options;
    return this.request('POST', '/tessellate', { data: bez, contentType: 'application/x-geomview-bez', query: { ...rest, ...output } });
  }

  /** GET /patches/{name}: tessellated (tolerance | segments, format, ...), or format 'json' for the control points.
   *  With etag, an unchanged answer has status 304. */
  patchSample(name = 'teapot', { etag, ...query } = {}) {
    return this.request('GET', `/patches/${encodeURIComponent(name)}`, { query, headers: etag ? { 'If-None-Match': etag } : {} });
  }

  /** POST /remesh: {mesh | data + contentType, edge_length, iterations, feature_angle, keep_boundary, smoothing,
   *  repair ('auto' | 'none'), output} */
  remesh(args) { return this.meshOperation('/remesh', args); }

  /** POST /implicit/query: {scene, points, rays, tolerance, max_distance, max_steps} */
  async implicitQuery(request) { return (await this.request('POST', '/implicit/query', { json: request })).json; }

  /** POST /implicit/mesh: {scene, bounds, resolution | cell_size, mode, simplify_tolerance, output} -> a closed mesh */
  implicitMesh(request) { return this.request('POST', '/implicit/mesh', { json: request }); }

  /** POST /pointcloud: {points, normals, colors} | {sample: {mesh | scene + bounds, count, seed}} | {data, contentType}
   *  (PLY/OBJ/XYZ), with estimate_normals (true or {k}) and output (glb, ply, json) */
  pointcloud({ data, contentType, ...options }) {
    if (data === undefined) return this.request('POST', '/pointcloud', { json: options });
    const { output = {}, ...rest } = options;
    return this.request('POST', '/pointcloud', { data, contentType: contentType ?? 'application/octet-stream', query: { ...rest, ...output } });
  }

  /** POST /curves: {points, evaluate, derivatives, curvature, split, elevate, bounding_box, length, closest, tessellate} */
  async curves(request) { return (await this.request('POST', '/curves', { json: request })).json; }
}
