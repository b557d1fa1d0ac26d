// Contract test: walks every operation of the OpenAPI document served by a live `surfaced serve` and holds each
// response to that document.
//
// Usage: node contract_test.mjs SURFACED_BINARY [OPENAPI_JSON]
//   OPENAPI_JSON: hold the server to this document instead of the one it serves (an edited api/openapi.json before
//   the binary that embeds it is rebuilt)
//
// The cases come from the document: every query parameter (in the query string of a file upload, or of a GET) and
// every option of the JSON body (the scalar members of the body and of its objects of options such as `output`),
// read from their schemas (type, minimum/maximum, exclusiveMinimum/exclusiveMaximum, enum, deprecated):
//   * a valid value, the boundary values just inside the range and every enum value are accepted;
//   * values just outside the range, a wrong enum value and a wrong type are 400 with a problem `field` naming the
//     parameter (`levels`, or `output.quantize_position` in JSON); an undocumented parameter or member is 400 too;
//   * a maximum marked `x-maximum-is-limit` is a server limit: just above it is 422 budget_exceeded naming it;
//   * an item outside a JSON list's item range is refused naming the item; a JSON request with a query parameter
//     is refused naming it.
// Every documented upload media type is accepted (a tiny file of each, below; multipart/form-data with the file as
// its binary part); an unknown media type is 415, broken JSON 400 invalid_json with its offset, an Accept nothing
// matches 406 where documented; a path parameter's values answer and another is 404; If-None-Match gives 304; an
// undocumented method is 405 with Allow, an unknown path 404. With a bearer token configured (a second server),
// operations with security [] answer without it and the others are 401 without it.
// Every response, success or error, must have a status and content type the operation lists; JSON answers
// (application/json, application/problem+json, model/gltf+json) validate against the documented schema (Ajv,
// JSON Schema 2020-12); a GLB answer starts with the glTF magic; the documented response headers are present and
// match their schemas (a header whose description says it is sent "only" in some cases may be absent); a problem's
// status and type agree with the response; each `format` answers with its media type.
// The JSON bodies are the document's own request examples. Cases the server cannot satisfy as written are listed in
// `knownGaps` with the reason and the answer they get instead; they are sent, checked, printed and counted.
import { strict as assert } from 'node:assert';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import Ajv2020 from 'ajv/dist/2020.js';
import addFormats from 'ajv-formats';
import { startServer } from '../browser/serve.mjs';

const [binary, documentFile] = process.argv.slice(2);
if (!binary) {
  console.error('usage: node contract_test.mjs SURFACED_BINARY [OPENAPI_JSON]');
  process.exit(2);
}

// ---- tables: the only per-operation knowledge the test has ---------------------------------------------------------

// Tiny valid files for the upload media types (the document lists the media types, not sample files). Every
// documented upload type with a sample is sent once; the first one listed carries the query-parameter cases.
const tetraPositions = [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]];
const tetraFaces = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];  // closed, outward, triangles (Loop subdivision)

// The tetrahedron as glTF: one triangle primitive, float positions, 16-bit indices; `binary` gives a GLB.
function tetraGltf(binary) {
  const bin = Buffer.alloc(48 + 24);
  tetraPositions.flat().forEach((v, i) => bin.writeFloatLE(v, 4 * i));
  tetraFaces.flat().forEach((v, i) => bin.writeUInt16LE(v, 48 + 2 * i));
  const gltf = {
    asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1, mode: 4 }] }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 4, type: 'VEC3', min: [-1, -1, -1], max: [1, 1, 1] },
      { bufferView: 1, componentType: 5123, count: 12, type: 'SCALAR' },
    ],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: 48 }, { buffer: 0, byteOffset: 48, byteLength: 24 }],
    buffers: [{ byteLength: bin.length }],
  };
  if (!binary) {
    gltf.buffers[0].uri = `data:application/octet-stream;base64,${bin.toString('base64')}`;
    return JSON.stringify(gltf);
  }
  let json = Buffer.from(JSON.stringify(gltf));
  json = Buffer.concat([json, Buffer.alloc((4 - (json.length % 4)) % 4, 0x20)]);
  const chunk = (type, data) => {
    const head = Buffer.alloc(8);
    head.writeUInt32LE(data.length, 0);
    head.write(type, 4, 'latin1');
    return Buffer.concat([head, data]);
  };
  const body = Buffer.concat([chunk('JSON', json), chunk('BIN\0', bin)]);
  const head = Buffer.alloc(12);
  head.write('glTF', 0, 'latin1');
  head.writeUInt32LE(2, 4);
  head.writeUInt32LE(12 + body.length, 8);
  return Buffer.concat([head, body]);
}

const tetraObj = tetraPositions.map((p) => `v ${p.join(' ')}\n`).join('') +
  tetraFaces.map((f) => `f ${f.map((i) => i + 1).join(' ')}\n`).join('');
const tetraPly = 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n' +
  'element face 4\nproperty list uchar int vertex_indices\nend_header\n' +
  tetraPositions.map((p) => `${p.join(' ')}\n`).join('') + tetraFaces.map((f) => `3 ${f.join(' ')}\n`).join('');
function tetraStl() {
  const facet = (f) => {
    const [a, b, c] = f.map((i) => tetraPositions[i]);
    const u = b.map((x, k) => x - a[k]);
    const v = c.map((x, k) => x - a[k]);
    const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    return `facet normal ${n.join(' ')}\nouter loop\n${[a, b, c].map((p) => `vertex ${p.join(' ')}\n`).join('')}` +
      'endloop\nendfacet\n';
  };
  return `solid tetra\n${tetraFaces.map(facet).join('')}endsolid tetra\n`;
}
const meshUploads = {
  'model/obj': tetraObj,
  'model/off': `OFF\n4 4 0\n${tetraPositions.map((p) => `${p.join(' ')}\n`).join('')}${
    tetraFaces.map((f) => `3 ${f.join(' ')}\n`).join('')}`,
  'application/ply': tetraPly,
  'model/stl': tetraStl(),
  'model/gltf-binary': tetraGltf(true),
  'model/gltf+json': tetraGltf(false),
  'application/octet-stream': tetraGltf(true),  // the format is detected from the content
};
const xyz = '0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 0\n1 0 1\n0 1 1\n1 1 1\n';
const pointUploads = {
  'text/x-xyz': xyz, 'application/ply': tetraPly, 'model/obj': tetraObj, 'text/plain': xyz,
  'application/octet-stream': xyz,
};
const bez = 'BEZ113\n0 0 0\n1 0 0\n0 1 0\n1 1 1\n';  // one bilinear patch
const patchUploads = {
  'application/x-geomview-bez': bez, 'text/plain': bez, 'application/octet-stream': bez,
  'model/obj': 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\ncstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nend\n',
};
// /reconstruct's query cases: the cube's corners with outward normals and colours (x y z nx ny nz r g b), so that
// estimate_normals never and vertex_colors true apply
const cornersXyz = [0, 1].flatMap((x) => [0, 1].flatMap((y) => [0, 1].map((z) => [x, y, z])))
  .map(([x, y, z]) => `${x} ${y} ${z} ${x - 0.5} ${y - 0.5} ${z - 0.5} ${x} ${y} ${z}\n`).join('');
const reconstructUploads = { ...pointUploads, 'text/x-xyz': cornersXyz };
const uploadsFor = { '/pointcloud': pointUploads, '/reconstruct': reconstructUploads, '/tessellate': patchUploads };
// The upload that carries the query-parameter cases, when it is not the first documented type with a sample.
const queryUpload = {
  '/pointcloud': 'text/x-xyz', '/reconstruct': 'text/x-xyz', '/tessellate': 'application/x-geomview-bez',
};

// The media type each output format answers with.
const formatMedia = {
  glb: 'model/gltf-binary', gltf: 'model/gltf+json', obj: 'model/obj', ply: 'application/ply', json: 'application/json',
  stl: 'model/stl', off: 'model/off',
};

// Options that exclude each other are read from the document ("Excludes cell_size." in a description): testing
// one removes the other from the base request.
const excludes = new Map();  // name -> names it excludes

// Options that apply only together with another option's value (a 400 naming them otherwise): testing one sets
// the other, in the same object (JSON) or the query string, to the first value listed.
// These dependencies are stated in the descriptions (the Output schema's, the operations'), in prose.
const requires = {
  compression: { format: ['glb', 'gltf'] },                                   // Draco is for glTF output only
  quantize_position: { format: ['glb', 'gltf'], compression: ['draco'] },     // a Draco setting
  normals: { format: ['glb', 'gltf', 'obj', 'ply'] },                         // json output has no normals
  // the neighbour count of the normal estimate: /pointcloud's estimate_normals=true, /reconstruct's auto or always
  k: { estimate_normals: ['true', 'auto', 'always'] },
  vertex_colors: { format: ['ply', 'obj', 'json'] },  // colours go into these formats only (/reconstruct)
  straddle: { tolerance: [0.05] },  // /subdivide: vertices off the surface in tolerance tessellation only
};

// "Just inside" an exclusive minimum is bound + 1e-6, except where that small a value means heavy work (which the
// server refuses as a budget): there a cheap value still above the bound.
const cheapInside = {
  'tolerance': 0.05,   // a chord tolerance of 1e-6 needs more segments than the server allows
  'edge_length': 0.5,  // a target edge of 1e-6 on a unit mesh is millions of faces
  'cell_size': 0.25,   // likewise a grid of 1e-6 cells
  'voxel_size': 0.25,  // and a distance grid of 1e-6 voxels
};

// Cases whose documented expectation the server does not meet as written, each with its reason and the answer it
// gives instead (checked, so a change shows); printed and counted.
const knownGaps = [
  {
    op: 'POST /implicit/mesh', option: 'resolution', kind: 'max', status: 422, code: 'budget_exceeded',
    reason: 'the range maximum 65536 passes the range check, but 65536^3 grid cells are over the grid-cell budget ' +
      '(422 budget_exceeded, as the operation describes)',
  },
  {
    op: 'POST /subdivide', option: 'scheme', kind: 'enum loop', transport: 'json',
    status: 422, code: 'not_triangle_mesh',
    reason: 'the JSON example is one quad and Loop needs triangles (422 not_triangle_mesh); the query walk ' +
      'subdivides the tetrahedron with loop',
  },
  {
    op: 'POST /limit/evaluate', option: 'scheme', kind: 'enum loop', transport: 'json',
    status: 422, code: 'not_triangle_mesh',
    reason: 'the JSON example is a cube of quads and Loop needs triangles (422 not_triangle_mesh naming the face)',
  },
  {
    op: 'POST /pointcloud', option: 'sample.count', kind: 'min', transport: 'json',
    status: 422, code: 'invalid_argument',
    reason: 'sample.count 1 is in range, but the example also estimates normals, which needs at least 3 points',
  },
  {
    op: 'POST /curves', option: 'weights[]', kind: 'exclusive min', transport: 'json',
    status: 400, code: 'invalid_field',
    reason: 'weights holds one weight per control point: a list of one is refused for its length (naming weights) ' +
      'before its item is read',
  },
  {
    op: 'POST /reconstruct', option: 'depth', kind: 'max', status: 422, code: 'budget_exceeded',
    reason: 'the range maximum 10 passes the range check and the depth limit, but its mesher grid of 1024^3 cells ' +
      'is over the grid-cell budget (422 budget_exceeded naming depth, as the operation describes)',
  },
  {
    op: 'GET /patches/{name}', option: 'segments', kind: 'max', status: 422, code: 'budget_exceeded',
    reason: 'the teapot sample has 32 patches: 256 segments predict 4.2M triangles, over the output-face budget (422)',
  },
];

// ---- the document and its schemas -------------------------------------------------------------------------------

let doc;
function resolve(node) {
  while (node && typeof node === 'object' && typeof node.$ref === 'string') {
    assert.ok(node.$ref.startsWith('#/'), `external $ref ${node.$ref}`);
    node = node.$ref.slice(2).split('/').map((p) => p.replace(/~1/g, '/').replace(/~0/g, '~'))
      .reduce((at, key) => at?.[key], doc);
    assert.ok(node !== undefined, 'dangling $ref');
  }
  return node;
}

const ajv = new Ajv2020({ strict: false, allErrors: true, validateFormats: true });
addFormats(ajv);
const compiled = new Map();
// A validator for one schema of the document; its "#/components/schemas/X" refs point at the registered components.
function validatorFor(schema) {
  const text = JSON.stringify(schema);
  if (!compiled.has(text)) {
    const rewritten = JSON.parse(text.replace(/"#\/components\/schemas\//g, '"surfaced-components#/$defs/'));
    compiled.set(text, ajv.compile(rewritten));
  }
  return compiled.get(text);
}

// ---- bookkeeping ------------------------------------------------------------------------------------------------

let checks = 0;
let requests = 0;
const perOperation = new Map();
const failures = [];
const skipped = [];
function check(ok, what) {
  checks += 1;
  if (!ok) failures.push(what);
  return ok;
}

// ---- one request and the checks every response gets ------------------------------------------------------------

let base;
async function send(op, { query = {}, body, contentType, headers = {}, pathValues = {}, note = '' }) {
  let path = op.path.replace(/\{(\w+)\}/g, (_, name) => encodeURIComponent(pathValues[name]));
  const qs = new URLSearchParams(query).toString();
  if (qs) path += `?${qs}`;
  const init = { method: op.method.toUpperCase(), headers: { ...headers } };
  if (body !== undefined) {
    init.body = body;
    if (contentType) init.headers['Content-Type'] = contentType;
  }
  requests += 1;
  perOperation.set(op.label, (perOperation.get(op.label) ?? 0) + 1);
  const res = await fetch(base + path, init);
  const bytes = Buffer.from(await res.arrayBuffer());
  const label = `${op.label}${qs ? '?' + qs : ''}${contentType ? ` [${contentType}]` : ''}${note ? ' ' + note : ''}`;
  const out = { status: res.status, headers: res.headers, bytes, label, json: undefined };
  checkResponse(op, out);
  return out;
}

const jsonTypes = /^application\/(.+\+)?json$|^model\/gltf\+json$/;

function checkHeaderValue(name, value, schema, where) {
  schema = resolve(schema ?? {});
  let parsed = value;
  if (schema.type === 'boolean') parsed = value === 'true' ? true : value === 'false' ? false : value;
  if (schema.type === 'integer' || schema.type === 'number') {
    parsed = Number(value);
    const number = value.trim() !== '' && Number.isFinite(parsed);
    if (!check(number, `${where}: header ${name} "${value}" is not a number`)) return;
  }
  const validate = validatorFor(schema);
  check(validate(parsed), `${where}: header ${name} "${value}": ${ajv.errorsText(validate.errors)}`);
}

function checkResponse(op, out) {
  const where = `${out.label} -> ${out.status}`;
  const documented = op.responses[String(out.status)] ?? op.responses.default;
  if (!check(documented !== undefined,
    `${where}: status ${out.status} is not among the documented ${Object.keys(op.responses).join(', ')}`)) return;
  const response = resolve(documented);
  const type = (out.headers.get('content-type') ?? '').split(';')[0].trim().toLowerCase();
  if (!response.content) {
    check(out.bytes.length === 0, `${where}: documented without content, got ${out.bytes.length} bytes of ${type}`);
  } else if (check(type in response.content,
    `${where}: Content-Type "${type}" is not among the documented ${Object.keys(response.content).join(', ')}`)) {
    const schema = response.content[type].schema;
    if (jsonTypes.test(type)) {
      try {
        out.json = JSON.parse(out.bytes.toString('utf8'));
      } catch (e) {
        check(false, `${where}: ${type} body does not parse: ${e.message}`);
      }
      if (out.json !== undefined && schema) {
        const validate = validatorFor(schema);
        check(validate(out.json), `${where}: body against the ${type} schema: ${ajv.errorsText(validate.errors)}`);
      }
      if (type === 'application/problem+json' && out.json) {
        // RFC 9457: the member status is the response's; the type is the code's problem page
        check(out.json.status === out.status, `${where}: problem status ${out.json.status}`);
        check(out.json.type === `/problems/${out.json.code}`,
          `${where}: problem type ${out.json.type} for ${out.json.code}`);
      }
    } else if (type === 'model/gltf-binary') {
      check(out.bytes.subarray(0, 4).toString('latin1') === 'glTF', `${where}: GLB without the glTF magic`);
    } else {
      check(out.bytes.length > 0, `${where}: empty ${type} body`);
    }
  }
  for (const [name, header] of Object.entries(response.headers ?? {})) {
    const h = resolve(header);
    const value = out.headers.get(name);
    const conditional = /\bonly\b/i.test(h.description ?? '') && !h.required;
    if (value === null) {
      check(conditional, `${where}: documented header ${name} is missing`);
      continue;
    }
    checkHeaderValue(name, value, h.schema, where);
  }
}

// A refusal: the documented status, a problem naming `field`.
function expectRefused(out, status, field, code) {
  const where = `${out.label} -> ${out.status}`;
  if (!check(out.status === status, `${where}: expected ${status} naming ${field}, got ${shown(out)}`)) return;
  const named = out.json?.field === field || String(out.json?.field).startsWith(`${field}[`);  // or an item of it
  check(named, `${where}: problem field ${JSON.stringify(out.json?.field)}, expected "${field}"`);
  if (code) check(out.json?.code === code, `${where}: problem code ${out.json?.code}, expected ${code}`);
}
function expectRefusedCode(out, status, code) {
  if (!check(out.status === status, `${out.label} -> ${out.status}: expected ${status}, got ${shown(out)}`)) return;
  if (code)
    check(out.json?.code === code, `${out.label} -> ${out.status}: problem code ${out.json?.code}, expected ${code}`);
}
// A known gap is still sent: the answer must be the one its reason names (so a change shows), and it is counted.
function knownGap(out, gap, what) {
  skipped.push(`${what}: ${gap.reason}`);
  check(out.status === gap.status && out.json?.code === gap.code,
    `${out.label} -> ${out.status}: known gap expected ${gap.status} ${gap.code}, got ${out.json?.code ?? ''}`);
}
function shown(out) {
  const type = out.headers.get('content-type') ?? '';
  return /json|text/.test(type) ? out.bytes.toString('utf8').slice(0, 300) : `(${out.bytes.length} bytes of ${type})`;
}
// `option`, `value`: the option the case set; a `format` must answer with its media type.
function expectAccepted(out, option, value) {
  if (!check(out.status >= 200 && out.status < 300,
    `${out.label} -> ${out.status}: expected success, got ${shown(out)}`)) return;
  if (option !== 'format' || !(value in formatMedia)) return;  // a format the table does not know: listed type only
  const type = (out.headers.get('content-type') ?? '').split(';')[0].trim();
  check(formatMedia[value] === type, `${out.label}: format ${value} answered as ${type}, not ${formatMedia[value]}`);
}

// ---- cases from a schema ----------------------------------------------------------------------------------------

// The values to try for one option: {value, expect: 'ok'|'bad'|'budget', kind}. `query`: as query-string text;
// `current`: the option's value in the request example, if it has one.
function casesFor(schema, query, name, current) {
  schema = resolve(schema);
  const cases = [];
  const text = (v) => (query ? String(v) : v);
  const ok = (v, kind) => cases.push({ value: text(v), expect: 'ok', kind });
  const bad = (v, kind) => cases.push({ value: query ? String(v) : v, expect: 'bad', kind });
  if (schema.enum) {
    for (const v of schema.enum) ok(v, `enum ${v}`);
    bad(typeof schema.enum[0] === 'string' ? 'not-a-documented-value' : -12345, 'wrong enum');
    return cases;
  }
  if (schema.type === 'boolean') {
    ok(true, 'true');
    ok(false, 'false');
    bad(query ? 'maybe' : 'true', 'wrong type');
    return cases;
  }
  if (schema.type === 'integer' || schema.type === 'number') {
    const int = schema.type === 'integer';
    const step = int ? 1 : 1e-6;
    if (schema.minimum !== undefined) {
      ok(schema.minimum, 'min');
      bad(schema.minimum - (int ? 1 : 1e-3), 'below min');
    }
    if (schema.exclusiveMinimum !== undefined) {
      bad(schema.exclusiveMinimum, 'exclusive min');
      ok(cheapInside[name] ?? schema.exclusiveMinimum + step, 'above exclusive min');
    }
    if (schema.maximum !== undefined) {
      ok(schema.maximum, 'max');
      cases.push({
        value: text(schema.maximum + (int ? 1 : 1e-3)),
        expect: schema['x-maximum-is-limit'] ? 'budget' : 'bad', kind: 'above max',
      });
    }
    if (schema.exclusiveMaximum !== undefined) {
      bad(schema.exclusiveMaximum, 'exclusive max');
      ok(schema.exclusiveMaximum - step, 'below exclusive max');
    }
    if (schema.default !== undefined) ok(schema.default, 'default');
    // no bound and no default: the example's value, else 1
    if (!cases.some((c) => c.expect === 'ok')) ok(current ?? 1, 'a value');
    if (int) bad(query ? '1.5' : 1.5, 'fraction');
    bad(query ? 'abc' : '1', 'wrong type');
    return cases;
  }
  if (schema.type === 'string' && schema.pattern && query) {
    bad('not a match!', 'pattern');
    return cases;
  }
  if (schema.type === 'string' && !query) {
    bad(12, 'wrong type');
  }
  return cases;
}

function isScalar(schema) {
  schema = resolve(schema);
  return schema.enum !== undefined || ['integer', 'number', 'boolean', 'string'].includes(schema.type);
}
function objectOf(schema) {
  schema = resolve(schema);
  if (schema.type === 'object' && schema.properties) return schema;
  for (const alt of schema.oneOf ?? []) {
    const a = resolve(alt);
    if (a.type === 'object' && a.properties) return a;
  }
  return null;
}
// An object whose scalar members are options: all its members are scalars (`output`) and it needs none or the example
// has it; or it is a closed object (additionalProperties false) the example has and whose required members are
// scalars (`sample`: count and seed beside the mesh). A scene node is neither (its members depend on its op), nor is
// the object alternative of a member the example gives in another form.
function optionsObject(object, inExample) {
  const present = typeof inExample === 'object' && inExample !== null && !Array.isArray(inExample);
  // the example took another alternative of a oneOf (points as arrays, not the packed object): not options
  if (inExample !== undefined && !present) return false;
  if (Object.values(object.properties).every(isScalar)) return present || !(object.required ?? []).length;
  // an object that requires a non-scalar member is an input (bspline: degree and points), not options
  const requiresInput = (object.required ?? []).some((name) => !isScalar(object.properties[name] ?? {}));
  return present && object.additionalProperties === false && !requiresInput;
}

// The scalar options of a JSON body schema: its scalar members (and scalar alternatives of a oneOf) and the scalar
// members of its objects of options (optionsObject). Returns [{path: ['output', 'format'], schema, container,
// example}]: `container` is the schema of the object holding the option.
// Each option comes with the example it is tried in: the first that has its top-level member (a member of some
// inputs only, like the curves' `continuity` for chains, gets an example of that input), else the first.
function jsonOptions(bodySchema, examples) {
  const found = [];
  const root = resolve(bodySchema);
  for (const [name, member] of Object.entries(root.properties ?? {})) {
    const example = examples.find((e) => e[name] !== undefined) ?? examples[0];
    const m = resolve(member);
    if (isScalar(m)) found.push({ path: [name], schema: m, container: root, example });
    for (const alt of m.oneOf ?? [])
      if (isScalar(alt)) found.push({ path: [name], schema: resolve(alt), container: root, example });
    const object = objectOf(m);
    if (!object || !optionsObject(object, example[name])) continue;
    for (const [inner, s] of Object.entries(object.properties))
      if (isScalar(s)) found.push({ path: [name, inner], schema: resolve(s), container: object, example });
  }
  return found;
}

// `example` with the option at `path` set to `value`, the options it excludes removed and the ones it needs set.
function withValue(example, path, value, container) {
  const body = structuredClone(example);
  let at = body;
  for (const key of path.slice(0, -1)) {
    if (typeof at[key] !== 'object' || at[key] === null) at[key] = {};
    at = at[key];
  }
  const name = path[path.length - 1];
  at[name] = value;
  for (const other of excludes.get(name) ?? []) delete at[other];
  for (const [other, allowed] of Object.entries(requires[name] ?? {})) {
    const sibling = container.properties?.[other];
    if (sibling && !allowed.includes(at[other] ?? resolve(sibling).default)) {
      at[other] = allowed[0];
      for (const excluded of excludes.get(other) ?? []) if (excluded !== name) delete at[excluded];
    }
  }
  return body;
}

function gap(op, option, kind, transport) {
  return knownGaps.find((g) => g.op === op.label && g.option === option && g.kind === kind &&
    (!g.transport || g.transport === transport));
}

// "Excludes segments." in the description of a property or parameter `tolerance`: either, not both.
function collectExclusions(node) {
  if (Array.isArray(node)) return node.forEach(collectExclusions);
  if (!node || typeof node !== 'object') return;
  const note = (name, description) => {
    const m = /\bExcludes ([\w, ]+?)\./i.exec(description ?? '');
    if (!m) return;
    for (const other of m[1].split(/,\s*|\s+and\s+|\s+or\s+/)) {
      if (!excludes.has(name)) excludes.set(name, new Set());
      excludes.get(name).add(other.trim());
      if (!excludes.has(other.trim())) excludes.set(other.trim(), new Set());
      excludes.get(other.trim()).add(name);
    }
  };
  if (node.properties && typeof node.properties === 'object')
    for (const [name, s] of Object.entries(node.properties)) note(name, s?.description);
  if (typeof node.name === 'string' && typeof node.in === 'string')
    note(node.name, node.description ?? node.schema?.description);
  for (const value of Object.values(node)) collectExclusions(value);
}

// A multipart/form-data upload: the file in the schema's binary member (format binary, or a contentMediaType), the
// part's Content-Type from the encoding object when it names one, the options as query parameters.
async function sendMultipart(op, media, upload, query, pathValues) {
  const schema = resolve(media.schema ?? {});
  const fileMember = Object.entries(schema.properties ?? {}).find(([, s]) => {
    const m = resolve(s);
    return m.type === 'string' && (m.format === 'binary' || m.contentMediaType || m.contentEncoding);
  })?.[0];
  if (!fileMember) {
    skipped.push(`${op.label}: multipart/form-data: the schema has no binary member to put the file in`);
    return;
  }
  const form = new FormData();
  form.append(fileMember, new Blob([upload.body], { type: upload.type }), `upload.${upload.type.split('/')[1]}`);
  // fetch sets the multipart Content-Type with its boundary from the FormData body
  expectAccepted(await send(op, { query, body: form, pathValues, note: `multipart ${fileMember}` }));
}

// ---- the walk ---------------------------------------------------------------------------------------------------

function operations() {
  const ops = [];
  for (const [path, item] of Object.entries(doc.paths)) {
    for (const method of ['get', 'post', 'put', 'patch', 'delete']) {
      if (!item[method]) continue;
      const op = item[method];
      ops.push({
        path, method, label: `${method.toUpperCase()} ${path}`, responses: op.responses,
        parameters: [...(item.parameters ?? []), ...(op.parameters ?? [])].map(resolve),
        requestBody: op.requestBody ? resolve(op.requestBody) : undefined,
      });
    }
  }
  return ops;
}

function examplesOf(media) {
  if (!media) return [];
  if (media.example !== undefined) return [media.example];
  return Object.values(media.examples ?? {}).map((e) => resolve(e).value).filter((v) => v !== undefined);
}

async function walk(op) {
  const content = op.requestBody?.content ?? {};
  const jsonMedia = content['application/json'];
  const examples = examplesOf(jsonMedia);
  const pathParams = op.parameters.filter((p) => p.in === 'path');
  const pathValues = Object.fromEntries(
    pathParams.map((p) => [p.name, resolve(p.schema).enum?.[0] ?? resolve(p.schema).example]));
  const queryParams = op.parameters.filter((p) => p.in === 'query');

  // every path parameter value (an enum) answers, a value outside it is refused with the documented 404
  for (const p of pathParams) {
    const schema = resolve(p.schema);
    for (const v of schema.enum ?? []) expectAccepted(await send(op, { pathValues: { ...pathValues, [p.name]: v } }));
    if (schema.enum && op.responses['404'])
      check((await send(op, { pathValues: { ...pathValues, [p.name]: 'no-such-name' } })).status === 404,
        `${op.label}: an unknown ${p.name} is not 404`);
  }

  // the JSON examples are accepted, and refused with a query parameter (options go in the body); the probes without
  // parameters or body (healthz, livez, readyz, metrics, openapi.json) ignore a query string, which is not checked
  for (const example of examples)
    expectAccepted(await send(op, { body: JSON.stringify(example), contentType: 'application/json', pathValues }));
  if (examples.length) {
    const documented = op.parameters.find((p) => p.in === 'query');
    const name = documented?.name ?? 'contract_undocumented';
    const value = String((documented && resolve(documented.schema).default) ?? '1');
    expectRefused(await send(op, { query: { [name]: value }, body: JSON.stringify(examples[0]),
      contentType: 'application/json', pathValues }), 400, name, 'unknown_parameter');
  }
  if (!op.requestBody) {
    const out = await send(op, { pathValues });
    // readiness may be 503 and metrics 401 by design (both documented); the rest answer
    if (op.path !== '/readyz' && op.path !== '/metrics') expectAccepted(out);
    // a conditional GET with the ETag the answer carried: 304 when documented
    const etag = out.headers.get('etag');
    if (etag && op.responses['304'] && op.parameters.some((p) => p.in === 'header' && /^if-none-match$/i.test(p.name)))
      check((await send(op, { pathValues, headers: { 'If-None-Match': etag } })).status === 304,
        `${op.label}: If-None-Match with its own ETag is not 304`);
  }

  // a body of a media type the operation does not read is 415; JSON that does not parse is 400 with its offset; an
  // Accept header naming nothing the operation answers with is 406, when the operation documents 406
  if (op.requestBody && op.responses['415'])
    expectRefusedCode(await send(op, { body: 'x', contentType: 'application/x-contract-unknown', pathValues }), 415,
      'unsupported_media_type');
  if (jsonMedia && op.responses['400']) {
    const out = await send(op, { body: '{"a": ', contentType: 'application/json', pathValues });
    expectRefusedCode(out, 400, 'invalid_json');
    check(Number.isInteger(out.json?.offset), `${out.label}: invalid_json without a byte offset`);
  }
  if (op.responses['406']) {
    // Accept only picks the format when the request names none: the example without its output.format
    let example = examples[0];
    if (example?.output?.format !== undefined) {
      const { format, ...output } = example.output;
      example = { ...example, output };
    }
    const body = example !== undefined ? JSON.stringify(example) : undefined;
    expectRefusedCode(await send(op, { body, contentType: body && 'application/json', pathValues,
      headers: { Accept: 'application/x-contract-nothing' }, note: 'Accept: application/x-contract-nothing' }), 406);
  }

  // the upload used with query parameters
  let upload;
  const uploads = uploadsFor[op.path] ?? meshUploads;
  if (op.requestBody && queryParams.length) {
    const type = queryUpload[op.path] ?? Object.keys(content).find((t) => t in uploads);
    if (!type || !(type in content)) {
      skipped.push(`${op.label}: query parameters: no sample file for any of ${Object.keys(content).join(', ')}`);
    } else {
      upload = { type, body: uploads[type] };
    }
  }
  // the base query: the example's top-level options that are also query parameters (e.g. simplify's ratio)
  const baseQuery = {};
  if (examples[0]) {
    for (const p of queryParams)
      if (examples[0][p.name] !== undefined && typeof examples[0][p.name] !== 'object')
        baseQuery[p.name] = String(examples[0][p.name]);
  }
  const sendQuery = (query) => (upload
    ? send(op, { query, body: upload.body, contentType: upload.type, pathValues })
    : send(op, { query, pathValues }));

  // every documented upload media type (multipart/form-data: the file as its one binary part)
  if (upload) {
    for (const [type, media] of Object.entries(content)) {
      if (type === 'application/json') continue;
      if (type === 'multipart/form-data') {
        await sendMultipart(op, media, upload, baseQuery, pathValues);
        continue;
      }
      if (!(type in uploads)) {
        skipped.push(`${op.label}: upload ${type}: the test has no sample file of this type`);
        continue;
      }
      expectAccepted(await send(op, { query: baseQuery, body: uploads[type], contentType: type, pathValues }));
    }
  }

  if (queryParams.length && (upload || !op.requestBody)) {
    expectAccepted(await sendQuery(baseQuery));
    for (const p of queryParams) {
      for (const c of casesFor(p.schema, true, p.name, baseQuery[p.name])) {
        const g = gap(op, p.name, c.kind, 'query');
        const query = { ...baseQuery, [p.name]: c.value };
        for (const other of excludes.get(p.name) ?? []) delete query[other];
        for (const [other, allowed] of Object.entries(requires[p.name] ?? {})) {
          const sibling = queryParams.find((q) => q.name === other);
          if (sibling && !allowed.includes(query[other] ?? String(resolve(sibling.schema).default))) {
            query[other] = allowed[0];
            for (const excluded of excludes.get(other) ?? []) if (excluded !== p.name) delete query[excluded];
          }
        }
        const out = await sendQuery(query);
        if (g) {
          knownGap(out, g, `${op.label} query ${p.name}=${c.value} (${c.kind})`);
          continue;
        }
        const tag = `${p.deprecated ? 'deprecated ' : ''}query ${p.name}`;
        if (c.expect === 'ok') expectAccepted(out, p.name, c.value);
        else if (c.expect === 'budget') {
          check(op.responses['422'] !== undefined, `${op.label}: ${tag} has a limit but 422 is not documented`);
          expectRefused(out, 422, p.name, 'budget_exceeded');
        } else {
          check(op.responses['400'] !== undefined, `${op.label}: ${tag} can be refused but 400 is not documented`);
          expectRefused(out, 400, p.name);
        }
      }
    }
    // an undocumented query parameter
    expectRefused(await sendQuery({ ...baseQuery, contract_undocumented: '1' }), 400, 'contract_undocumented');
  }

  // JSON body options, each set in an example
  if (jsonMedia && examples[0] && typeof examples[0] === 'object') {
    const example = examples[0];
    for (const { path, schema, container, example: into } of jsonOptions(jsonMedia.schema, examples)) {
      const field = path.join('.');
      for (const c of casesFor(schema, false, path.at(-1), path.reduce((at, key) => at?.[key], into))) {
        const g = gap(op, field, c.kind, 'json');
        const body = JSON.stringify(withValue(into, path, c.value, container));
        const note = `JSON ${field}=${JSON.stringify(c.value)}`;
        const out = await send(op, { body, contentType: 'application/json', pathValues, note });
        if (g) {
          knownGap(out, g, `${op.label} JSON ${field}=${JSON.stringify(c.value)} (${c.kind})`);
          continue;
        }
        if (c.expect === 'ok') expectAccepted(out, path.at(-1), c.value);
        else if (c.expect === 'budget') expectRefused(out, 422, field, 'budget_exceeded');
        else expectRefused(out, 400, field);
      }
    }
    // lists of bounded numbers (locked_vertices, holes, curvature): an item outside the items' range is refused
    // naming the item
    for (const [name, member] of Object.entries(resolve(jsonMedia.schema).properties ?? {})) {
      const m = resolve(member);
      const items = m.type === 'array' ? resolve(m.items ?? {}) : {};
      if (!['integer', 'number'].includes(items.type) || (m.minItems ?? 0) > 1) continue;
      const into = examples.find((e) => e[name] !== undefined) ?? examples[0];
      for (const c of casesFor(items, false, name)) {
        if (c.expect !== 'bad' || !/min|max/.test(c.kind)) continue;
        const body = JSON.stringify({ ...into, [name]: [c.value] });
        const note = `JSON ${name}=[${c.value}]`;
        const out = await send(op, { body, contentType: 'application/json', pathValues, note });
        const g = gap(op, `${name}[]`, c.kind, 'json');
        if (g) knownGap(out, g, `${op.label} JSON ${name}=[${c.value}] (${c.kind})`);
        else expectRefused(out, 400, `${name}[0]`);
      }
    }

    // undocumented members, at the top and inside each object of options
    const root = resolve(jsonMedia.schema);
    if (root.additionalProperties === false)
        expectRefused(await send(op, { body: JSON.stringify({ ...example, contract_undocumented: 1 }),
        contentType: 'application/json', pathValues, note: 'JSON contract_undocumented' }),
      400, 'contract_undocumented');
    for (const [name, member] of Object.entries(root.properties ?? {})) {
      const object = objectOf(member);
      const into = examples.find((e) => typeof e[name] === 'object' && e[name] !== null && !Array.isArray(e[name]));
      if (!object || object.additionalProperties !== false || !into || !optionsObject(object, into[name])) continue;
      const body = structuredClone(into);
      body[name].contract_undocumented = 1;
      expectRefused(await send(op, { body: JSON.stringify(body), contentType: 'application/json', pathValues,
        note: `JSON ${name}.contract_undocumented` }), 400, `${name}.contract_undocumented`);
    }
  }
}

// The statuses the document gives every endpoint (info.description): a method a path does not document is 405 with
// Allow naming the documented ones, an unknown path 404; both problems validate against the Problem schema.
async function sharedStatuses() {
  const problem = validatorFor({ $ref: '#/components/schemas/Problem' });
  const expectProblem = (res, json, status, code, where) => {
    if (!check(res.status === status, `${where}: expected ${status}, got ${res.status}`)) return;
    check(problem(json), `${where}: problem against the Problem schema: ${ajv.errorsText(problem.errors)}`);
    check(json?.code === code, `${where}: problem code ${json?.code}, expected ${code}`);
  };
  const parse = async (res) => {
    try {
      return JSON.parse(await res.text());
    } catch {
      return undefined;
    }
  };
  for (const [path, item] of Object.entries(doc.paths)) {
    const documented = ['get', 'post', 'put', 'patch', 'delete'].filter((m) => item[m]);
    const other = ['put', 'delete', 'patch', 'post'].find((m) => !item[m]);
    const concrete = path.replace(/\{(\w+)\}/g, (_, name) => {
      const p = [...(item.parameters ?? []), ...documented.flatMap((m) => item[m].parameters ?? [])]
        .map(resolve).find((q) => q.in === 'path' && q.name === name);
      return encodeURIComponent(resolve(p?.schema ?? {}).enum?.[0] ?? 'x');
    });
    requests += 1;
    const res = await fetch(base + concrete, { method: other.toUpperCase() });
    const where = `${other.toUpperCase()} ${concrete}`;
    expectProblem(res, await parse(res), 405, 'method_not_allowed', where);
    const allow = (res.headers.get('allow') ?? '').split(',').map((m) => m.trim().toLowerCase());
    for (const m of documented) check(allow.includes(m), `${where}: Allow "${res.headers.get('allow')}" lacks ${m}`);
  }
  requests += 1;
  const res = await fetch(`${base}/contract-no-such-path`);
  expectProblem(res, await parse(res), 404, 'not_found', 'GET /contract-no-such-path');
}

// Bearer authentication (components.securitySchemes, http bearer): a second server runs with a token. An operation
// whose security is [] answers without it; any other is 401 `unauthorized` with WWW-Authenticate without the token
// (a status it must document) and answers with it.
async function authentication() {
  const scheme = Object.entries(doc.components?.securitySchemes ?? {})
    .find(([, s]) => s.type === 'http' && s.scheme === 'bearer')?.[0];
  if (!scheme) return;
  const dir = mkdtempSync(join(tmpdir(), 'surfaced-contract-'));
  const tokenFile = join(dir, 'token');
  const token = 'contract-test-token';
  writeFileSync(tokenFile, `${token}\n`);
  const secured = await startServer(binary, undefined, ['--access-log', 'off', '--auth-token-file', tokenFile]);
  const plain = base;
  base = secured.url;
  try {
    for (const op of operations()) {
      const item = doc.paths[op.path][op.method];
      const requirements = item.security ?? doc.security ?? [];
      const open = requirements.every((r) => Object.keys(r).length === 0);  // security [] (or only {})
      const media = op.requestBody?.content?.['application/json'];
      const example = examplesOf(media)[0];
      const pathValues = Object.fromEntries(op.parameters.filter((p) => p.in === 'path')
        .map((p) => [p.name, resolve(p.schema).enum?.[0] ?? 'x']));
      const request = (headers) => send(op, {
        body: example === undefined ? undefined : JSON.stringify(example),
        contentType: example === undefined ? undefined : 'application/json', pathValues, headers,
        note: headers.Authorization ? '(with the token)' : '(no token)',
      });
      if (op.requestBody && example === undefined) continue;  // nothing to send
      const without = await request({});
      if (open) {
        check(without.status !== 401, `${without.label}: security [] but 401 without a token`);
        continue;
      }
      if (check(without.status === 401, `${without.label} -> ${without.status}: expected 401 without the token`)) {
        check(without.json?.code === 'unauthorized', `${without.label}: problem code ${without.json?.code}`);
        check(/^Bearer/i.test(without.headers.get('www-authenticate') ?? ''),
          `${without.label}: 401 without WWW-Authenticate: Bearer`);
      }
      const withToken = await request({ Authorization: `Bearer ${token}` });
      if (op.path !== '/readyz' && op.path !== '/metrics') expectAccepted(withToken);
      else check(withToken.status !== 401, `${withToken.label}: 401 with the token`);
    }
  } finally {
    base = plain;
    await secured.stop();
    rmSync(dir, { recursive: true, force: true });
  }
}

// ---- main -------------------------------------------------------------------------------------------------------

const started = Date.now();
const server = await startServer(binary, undefined, ['--access-log', 'off']);  // a failure prints its request
base = server.url;
try {
  doc = documentFile
    ? JSON.parse(readFileSync(documentFile, 'utf8'))
    : await (await fetch(`${base}/openapi.json`)).json();
  collectExclusions(doc);
  ajv.addSchema(JSON.parse(JSON.stringify({ $id: 'surfaced-components', $defs: doc.components?.schemas ?? {} })
    .replace(/"#\/components\/schemas\//g, '"#/$defs/')));
  for (const op of operations()) await walk(op);
  await sharedStatuses();
  await authentication();
} finally {
  await server.stop();
}

for (const [label, n] of perOperation) console.log(`${label}: ${n} requests`);
for (const s of skipped) console.log(`SKIPPED (known gap) ${s}`);
for (const f of failures) console.log(`FAIL ${f}`);
console.log(`contract: ${requests} requests, ${checks} checks, ${failures.length} failed, ` +
  `${skipped.length} skipped as known gaps, ` +
  `${((Date.now() - started) / 1000).toFixed(1)} s`);
process.exit(failures.length ? 1 : 0);
