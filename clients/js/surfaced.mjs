// A client for the surfaced HTTP service: an ES module on fetch (Node 18+ or a browser), no dependencies. The package
// `surfaced-client` (package.json); types in surfaced.d.ts.
//
// One method per endpoint. Mesh operations take a JSON mesh ({positions: [[x, y, z], ...], faces: [[i, j, k, ...]]})
// or the bytes of a mesh file (OBJ, OFF, PLY, STL, GLB, glTF) with its media type; options are named as in the API.
// The output options come as `output: {...}` or flattened (format, compression, quantize_position, normals): a JSON
// request gets them in `output`, a file upload every option as a query parameter. Operations resolve to a Result:
// {status, contentType, headers, body (Uint8Array), json (parsed JSON answers), text()}. Error answers (RFC 9457
// problem+json) throw SurfacedError with .status, .problem, .field, .line and .hint.
//
//   import { Client, API_VERSION } from 'surfaced-client';
//   const c = new Client('http://127.0.0.1:8080');
//   await c.checkServerVersion();   // throws IncompatibleServerError for a server of another API version
//   const r = await c.subdivide({ mesh: cube, levels: 2, format: 'json' });
//   console.log(r.json.stats.output_faces);

/** The OpenAPI info.version of the surfaced API this client was made for (api/openapi.json). */
export const API_VERSION = '0.1.0';

export const MESH_MEDIA_TYPES = { obj: 'model/obj', off: 'model/off', ply: 'application/ply', stl: 'model/stl', glb: 'model/gltf-binary', gltf: 'model/gltf+json' };

export class SurfacedError extends Error {
  constructor(status, problem) {
    let text = `${problem.status ?? status} ${problem.title ?? 'error'}: ${problem.detail ?? ''}`;
    if (problem.field) text += ` (field ${problem.field})`;
    if (problem.line) text += ` (line ${problem.line})`;
    if (problem.hint) text += ` (hint: ${problem.hint})`;
    super(text);
    this.status = status;
    this.problem = problem;
    this.code = problem.code;
    this.field = problem.field;
    this.line = problem.line;
    this.hint = problem.hint;
  }
}

export class IncompatibleServerError extends Error {
  constructor(serverVersion, apiVersion = API_VERSION) {
    super(`the server implements API ${serverVersion}; this client was made for ${apiVersion}`);
    this.serverVersion = serverVersion;
    this.apiVersion = apiVersion;
  }
}

function versionParts(version) {
  const m = /^\s*v?(\d+)(?:\.(\d+))?(?:\.(\d+))?/.exec(String(version));
  if (!m) throw new TypeError(`not a version: ${version}`);
  return [Number(m[1]), Number(m[2] ?? 0), Number(m[3] ?? 0)];
}

/** Whether a server implementing API `serverVersion` serves a client made for `clientVersion`, by semantic
 *  versioning: the same major version and a minor version at least the client's; before 1.0, the same minor. */
export function isCompatible(serverVersion, clientVersion = API_VERSION) {
  const [smaj, smin] = versionParts(serverVersion);
  const [cmaj, cmin] = versionParts(clientVersion);
  if (smaj !== cmaj) return false;
  return smaj === 0 ? smin === cmin : smin >= cmin;
}

const queryValue = (v) => (typeof v === 'boolean' ? (v ? 'true' : 'false') : String(v));   // [0, 5] -> "0,5"
const OUTPUT_KEYS = ['format', 'compression', 'quantize_position', 'normals'];

// Splits the flattened output options off `options` and merges them into a copy of `output`.
function takeOutput(options, output) {
  const rest = { ...options };
  const merged = { ...(output ?? {}) };
  for (const key of OUTPUT_KEYS) {
    if (rest[key] === undefined) continue;
    if (merged[key] !== undefined && merged[key] !== rest[key]) {
      throw new TypeError(`${key}: ${JSON.stringify(rest[key])} disagrees with output.${key}: ${JSON.stringify(merged[key])}`);
    }
    merged[key] = rest[key];
    delete rest[key];
  }
  return [rest, merged];
}

function jsonBody(fields, output) {
  const body = {};
  for (const [k, v] of Object.entries(fields)) if (v !== undefined) body[k] = v;
  if (Object.keys(output).length) body.output = output;
  return body;
}

function queryOf(options, output) {
  for (const [k, v] of Object.entries(options)) {
    if (v !== null && typeof v === 'object' && !(Array.isArray(v) && v.every((x) => typeof x !== 'object'))) {
      throw new TypeError(`${k} can only be sent in a JSON request, not with a file upload`);
    }
  }
  return { ...options, ...output };
}

export class Client {
  /** `token` is sent as Authorization: Bearer; `headers` go with every request. */
  constructor(baseUrl = 'http://127.0.0.1:8080', { timeoutMs = 60000, token, headers = {} } = {}) {
    this.baseUrl = baseUrl.replace(/\/+$/, '');
    this.timeoutMs = timeoutMs;
    this.headers = { ...headers };
    if (token) this.headers.Authorization = `Bearer ${token}`;
  }

  /** Any request; `json` is sent as application/json, `data` (bytes or text) with `contentType`. */
  async request(method, path, { json, data, contentType, query, headers = {} } = {}) {
    let url = this.baseUrl + path;
    if (query) {
      const q = new URLSearchParams();
      for (const [k, v] of Object.entries(query)) if (v !== undefined && v !== null) q.set(k, queryValue(v));
      if ([...q].length) url += `?${q}`;
    }
    const h = { ...this.headers, ...headers };
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

  // A JSON request {[payload]: ..., options, output} or, with `data`, a file with the options in the query.
  operation(path, payload, { data, contentType, output, ...options }) {
    const [rest, out] = takeOutput(options, output);
    // payload: the member (or members, of which the JSON form needs one) that carries the input
    const payloads = Array.isArray(payload) ? payload : [payload];
    const names = payloads.join(' or ');
    const given = payloads.some((name) => rest[name] !== undefined);
    if (data === undefined) {
      if (!given) throw new TypeError(`give either ${names} (JSON) or data (file bytes) with contentType`);
      return this.request('POST', path, { json: jsonBody(rest, out) });
    }
    if (given) throw new TypeError(`give either ${names} (JSON) or data (file bytes), not both`);
    for (const name of payloads) delete rest[name];
    return this.request('POST', path, { data, contentType: contentType ?? 'application/octet-stream', query: queryOf(rest, out) });
  }

  /** The API version the server implements: info.version of its /openapi.json (no probe or header reports one). */
  async serverVersion() { return String((await this.openapi()).info.version); }

  /** The server's API version; throws IncompatibleServerError when this client was not made for it. */
  async checkServerVersion() {
    const version = await this.serverVersion();
    if (!isCompatible(version, API_VERSION)) throw new IncompatibleServerError(version, API_VERSION);
    return version;
  }

  /** GET /healthz: {status: 'ok'} (an alias of /livez) */
  async healthz() { return (await this.request('GET', '/healthz')).json; }

  /** GET /livez: {status: 'ok'} while the process answers */
  async livez() { return (await this.request('GET', '/livez')).json; }

  /** GET /readyz: {status: 'ready'}; a draining server throws SurfacedError 503 (code 'draining') */
  async readyz() { return (await this.request('GET', '/readyz')).json; }

  /** GET /metrics: Prometheus text */
  async metrics() { return (await this.request('GET', '/metrics')).text(); }

  /** GET /openapi.json */
  async openapi() { return (await this.request('GET', '/openapi.json')).json; }

  /** POST /subdivide: {mesh | data + contentType, scheme, levels | tolerance, target_faces, boundary, crease_method, triangle_rule,
   *  uv_interpolation, loop_weights, limit_surface, creases, corners, holes, output | format, compression, ...} */
  subdivide(options) { return this.operation('/subdivide', 'mesh', options); }

  /** POST /simplify: {mesh | data + contentType, target_faces | ratio | max_error, lock_border, restore_volume,
   *  threads, locked_vertices, report_error, repair ('auto' | 'none'), output}; what repair did: X-Repairs */
  simplify(options) { return this.operation('/simplify', 'mesh', options); }

  /** POST /remesh: {mesh | data + contentType, edge_length, iterations, feature_angle, lock_border, smoothing,
   *  repair ('auto' | 'none'), output} */
  remesh(options) { return this.operation('/remesh', 'mesh', options); }

  /** POST /repair: {mesh | data + contentType, weld_tolerance, orient, min_component_faces, max_hole_edges, output};
   *  the report in X-Repairs and, in JSON output, stats.repairs */
  repair(options) { return this.operation('/repair', 'mesh', options); }

  /** POST /tessellate: {patches and/or surfaces | bez (BEZ text) | data + contentType, tolerance | segments, output} */
  tessellate({ bez, ...options }) {
    if (bez !== undefined) {
      if (options.data !== undefined) throw new TypeError('give either bez (text) or data (bytes)');
      return this.operation('/tessellate', ['patches', 'surfaces'], { ...options, data: bez, contentType: 'application/x-geomview-bez' });
    }
    return this.operation('/tessellate', ['patches', 'surfaces'], options);
  }

  /** GET /patches/{name}: tessellated (tolerance | segments, format, ...), or format 'patches' for the control points.
   *  With etag, an unchanged answer has status 304. */
  patchSample(name = 'teapot', { etag, ...query } = {}) {
    return this.request('GET', `/patches/${encodeURIComponent(name)}`, { query, headers: etag ? { 'If-None-Match': etag } : {} });
  }

  /** POST /curves: {points | chain | svg | bspline, queries..., output}; the answer's document in .json */
  curves(request) { return this.request('POST', '/curves', { json: request }); }

  /** POST /surfaces: {surface, evaluate, derivatives, closest, insert_knot, elevate, to_bezier, bounding_box}; the
   *  answer's document in .json */
  surfaces(request) { return this.request('POST', '/surfaces', { json: request }); }

  /** POST /implicit/query: {scene, points, rays, tolerance, max_distance, max_steps}; the answer's document in .json */
  implicitQuery(request) { return this.request('POST', '/implicit/query', { json: request }); }

  /** POST /mesh/query: {mesh, points, rays, want, winding}; the answer's document in .json */
  meshQuery(request) { return this.request('POST', '/mesh/query', { json: request }); }

  /** POST /limit/evaluate: {mesh, points: [{face, uv: [u, v]}], scheme, boundary, crease_method, triangle_rule,
   *  uv_interpolation, creases, corners, holes, derivatives, encoding}; the limit points in .json */
  limitEvaluate(request) { return this.request('POST', '/limit/evaluate', { json: request }); }

  /** POST /implicit/grid: {mesh | scene, voxel_size, band, bounds}; a level_set scene node in .json */
  implicitGrid(request) { return this.request('POST', '/implicit/grid', { json: request }); }

  /** POST /implicit/mesh: {scene, bounds, resolution | cell_size, mode, simplify_tolerance, crease_angle, output}
   *  -> a closed mesh */
  implicitMesh(request) { return this.request('POST', '/implicit/mesh', { json: request }); }

  /** POST /reconstruct: {points, normals (an array), colors} | {data, contentType} (PLY/OBJ/XYZ), with depth,
   *  point_weight, samples_per_node, boundary, scale, fit_to_samples, confidence, estimate_normals ('auto' | 'always' |
   *  'never'), k, trim, island_area, threads and output -> a closed mesh (open where trimmed); a boolean `normals` is
   *  the output option. */
  reconstruct({ normals, output, ...options }) {
    const out = { ...(output ?? {}) };
    if (typeof normals === 'boolean') {
      if (out.normals !== undefined && out.normals !== normals) throw new TypeError('normals disagrees with output.normals');
      out.normals = normals;
      normals = undefined;
    }
    return this.operation('/reconstruct', ['points', 'normals', 'colors'], { ...options, normals, output: out });
  }

  /** POST /pointcloud: {points, normals (an array), colors} | {sample: {mesh | scene + bounds, count, seed}} |
   *  {data, contentType} (PLY/OBJ/XYZ), with estimate_normals (true or {k}), k, and output (glb, gltf, ply, json); a
   *  boolean `normals` is the output option. */
  pointcloud({ data, contentType, normals, k, output, ...options }) {
    let out = { ...(output ?? {}) };
    if (typeof normals === 'boolean') {
      if (out.normals !== undefined && out.normals !== normals) throw new TypeError('normals disagrees with output.normals');
      out.normals = normals;
      normals = undefined;
    }
    if (data === undefined) {
      if (options.points === undefined && options.sample === undefined) throw new TypeError('give points, sample or data (file bytes)');
      const fields = { ...options };
      if (k !== undefined) {
        if (!fields.estimate_normals) throw new TypeError('k needs estimate_normals');
        fields.estimate_normals = { ...(typeof fields.estimate_normals === 'object' ? fields.estimate_normals : {}), k };
      }
      const [rest, merged] = takeOutput(fields, out);
      return this.request('POST', '/pointcloud', { json: jsonBody({ ...rest, normals }, merged) });
    }
    if (options.points !== undefined || options.sample !== undefined || normals !== undefined || options.colors !== undefined) {
      throw new TypeError('a file upload (data) takes no points, sample, normals array or colors');
    }
    const query = { ...options, k };
    if (typeof query.estimate_normals === 'object' && query.estimate_normals !== null) {
      query.k = query.estimate_normals.k ?? k;
      query.estimate_normals = true;
    }
    const [rest, merged] = takeOutput(query, out);
    for (const key of Object.keys(rest)) if (rest[key] === undefined) delete rest[key];
    return this.request('POST', '/pointcloud', { data, contentType: contentType ?? 'application/octet-stream', query: queryOf(rest, merged) });
  }
}
