// Point data for the point cloud view: the PLY the service answers with (read here) and the demo clouds' sources.
import { bumpySphere } from './meshes.js';

const PLY_TYPES = {
  char: ['getInt8', 1], int8: ['getInt8', 1], uchar: ['getUint8', 1], uint8: ['getUint8', 1],
  short: ['getInt16', 2], int16: ['getInt16', 2], ushort: ['getUint16', 2], uint16: ['getUint16', 2],
  int: ['getInt32', 4], int32: ['getInt32', 4], uint: ['getUint32', 4], uint32: ['getUint32', 4],
  float: ['getFloat32', 4], float32: ['getFloat32', 4], double: ['getFloat64', 8], float64: ['getFloat64', 8],
};

/**
 * The vertices of a PLY file (ASCII or binary; `vertex` must be the first element and have no list properties, as
 * the service writes it): {count, positions, normals (null when absent)}, Float32Arrays of 3 per point.
 */
export function readPlyPoints(buffer) {
  const bytes = new Uint8Array(buffer);
  const head = new TextDecoder().decode(bytes.subarray(0, Math.min(bytes.length, 4096)));
  const end = head.indexOf('end_header');
  if (!head.startsWith('ply') || end < 0) throw new Error('not a PLY file (no "ply" ... "end_header")');
  const lines = head.slice(0, end).split(/\r?\n/).map((l) => l.trim().split(/\s+/));
  let format = null, count = -1;
  const props = [];
  let inVertex = false, first = true;
  for (const [key, ...rest] of lines) {
    if (key === 'format') format = rest[0];
    else if (key === 'element') {
      inVertex = rest[0] === 'vertex' && first;
      if (inVertex) count = Number(rest[1]);
      first = false;
    } else if (key === 'property' && inVertex) {
      if (rest[0] === 'list') throw new Error('PLY: list properties in "vertex" are not read here');
      if (!PLY_TYPES[rest[0]]) throw new Error(`PLY: unknown property type ${rest[0]}`);
      props.push({ type: rest[0], name: rest[1] });
    }
  }
  if (count < 0) throw new Error('PLY: no "vertex" element first');
  const col = (name) => props.findIndex((p) => p.name === name);
  const [ix, iy, iz, inx, iny, inz] = ['x', 'y', 'z', 'nx', 'ny', 'nz'].map(col);
  if (ix < 0 || iy < 0 || iz < 0) throw new Error('PLY: the vertices have no x, y, z');
  const hasNormals = inx >= 0 && iny >= 0 && inz >= 0;
  const positions = new Float32Array(3 * count), normals = hasNormals ? new Float32Array(3 * count) : null;
  // the header ends with "end_header" and one newline
  let offset = end + 'end_header'.length;
  if (bytes[offset] === 13) ++offset;
  ++offset;
  const values = new Float64Array(props.length);
  const store = (i) => {
    positions[3 * i] = values[ix]; positions[3 * i + 1] = values[iy]; positions[3 * i + 2] = values[iz];
    if (normals) { normals[3 * i] = values[inx]; normals[3 * i + 1] = values[iny]; normals[3 * i + 2] = values[inz]; }
  };
  if (format === 'ascii') {
    const rows = new TextDecoder().decode(bytes.subarray(offset)).split('\n');
    for (let i = 0, r = 0; i < count; ++r) {
      if (r >= rows.length) throw new Error(`PLY: ${count} vertices announced, ${i} found`);
      const f = rows[r].trim();
      if (!f) continue;
      const parts = f.split(/\s+/);
      for (let k = 0; k < props.length; ++k) values[k] = Number(parts[k]);
      store(i++);
    }
  } else if (format === 'binary_little_endian' || format === 'binary_big_endian') {
    const little = format === 'binary_little_endian';
    const stride = props.reduce((s, p) => s + PLY_TYPES[p.type][1], 0);
    if (offset + stride * count > bytes.length) throw new Error('PLY: the file is shorter than its header says');
    const view = new DataView(buffer, bytes.byteOffset + offset);
    const readers = props.map((p) => PLY_TYPES[p.type]);
    for (let i = 0, at = 0; i < count; ++i) {
      for (let k = 0; k < readers.length; ++k) {
        values[k] = view[readers[k][0]](at, little);
        at += readers[k][1];
      }
      store(i);
    }
  } else {
    throw new Error(`PLY: unknown format ${format}`);
  }
  return { count, positions, normals };
}

/** The part of the bumpy sphere above y = -0.45, vertices renumbered: an open surface, as a scan of a bowl is. */
function bumpyBowl() {
  const sphere = bumpySphere(3);
  const faces = sphere.faces.filter((f) => f.every((i) => sphere.positions[i][1] > -0.45));
  const index = new Map(), positions = [];
  const renumbered = faces.map((f) => f.map((i) => {
    if (!index.has(i)) { index.set(i, positions.length); positions.push(sphere.positions[i]); }
    return index.get(i);
  }));
  return { positions, faces: renumbered };
}

/** The `sample` member of a POST /pointcloud request for each demo cloud (`count` points, a fixed seed). */
export const demoClouds = {
  // mesh sampling gives the faces' (outward) normals; the open rim is where trimming shows
  bowl: (count) => ({ mesh: bumpyBowl(), count, seed: 7 }),
  // scene sampling gives the gradient's normals; a closed shape with a thin neck
  blob: (count) => ({
    scene: { op: 'smooth_union', k: 0.2, args: [{ op: 'sphere', radius: 0.7 },
                                                { op: 'torus', major_radius: 1.1, minor_radius: 0.25 }] },
    bounds: [[-1.6, -1.6, -1.0], [1.6, 1.6, 1.0]], count, seed: 7,
  }),
};

/**
 * The cloud's typical sampling density on the octree-depth scale, as POST /reconstruct measures it for trimming
 * (X-Sample-Density; docs/reconstruction.md, "Trimming"): the median over samples of log2(cube / h), h the side of a
 * square holding `samplesPerNode` samples at the density k / (pi r^2) given by the distance r to the k-th nearest
 * sample, cube the bounding box's largest side times `scale`. Estimated from at most 200 samples against at most
 * 100,000 others (k scaled down with them), by brute force: a trim suggestion before any reconstruction.
 */
export function typicalDensity(positions, count, { k = 32, samplesPerNode = 1.5, scale = 1.1 } = {}) {
  if (count < 2) return NaN;
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < count; ++i)
    for (let c = 0; c < 3; ++c) {
      lo[c] = Math.min(lo[c], positions[3 * i + c]);
      hi[c] = Math.max(hi[c], positions[3 * i + c]);
    }
  const cube = scale * Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  const stride = Math.max(1, Math.ceil(count / 100000));
  const kk = Math.min(Math.max(1, Math.round(k / stride)), Math.ceil(count / stride));
  const nearest = new Float64Array(kk);   // the kk smallest squared distances, ascending
  const values = [];
  const probeStride = Math.max(1, Math.floor(count / 200));
  for (let p = 0; p < count; p += probeStride) {
    nearest.fill(Infinity);
    const [x, y, z] = [positions[3 * p], positions[3 * p + 1], positions[3 * p + 2]];
    for (let i = 0; i < count; i += stride) {
      const dx = positions[3 * i] - x, dy = positions[3 * i + 1] - y, dz = positions[3 * i + 2] - z;
      const d = dx * dx + dy * dy + dz * dz;
      if (d >= nearest[kk - 1]) continue;
      let j = kk - 1;
      for (; j > 0 && nearest[j - 1] > d; --j) nearest[j] = nearest[j - 1];
      nearest[j] = d;
    }
    const h = Math.sqrt(samplesPerNode * Math.PI * nearest[kk - 1] / (stride * kk));
    if (h > 0) values.push(Math.log2(cube / h));
  }
  values.sort((a, b) => a - b);
  return values.length ? values[Math.floor(values.length / 2)] : NaN;
}
