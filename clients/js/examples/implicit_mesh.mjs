// POST /implicit/mesh: a unit sphere meshed at resolution 32: closed (every edge in two triangles), vertices on it.
import { client, check } from './_common.mjs';

const r = await client.implicitMesh({ scene: { op: 'sphere', radius: 1 }, bounds: [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]],
                                      resolution: 32, output: { format: 'json' } });
const { positions, faces } = r.json.mesh;
const off = Math.max(...positions.map((p) => Math.abs(Math.hypot(...p) - 1)));
const edges = new Map();
for (const f of faces)
  for (let i = 0; i < f.length; ++i) {
    const a = f[i], b = f[(i + 1) % f.length], k = a < b ? `${a},${b}` : `${b},${a}`;
    edges.set(k, (edges.get(k) ?? 0) + 1);
  }
check(faces.length > 500, `${faces.length} triangles, grid ${r.headers.get('x-grid')}`);
check(off < 0.02, `vertices on the sphere: max | |p| - 1 | = ${off.toExponential(2)} (cell size 0.094)`);
check([...edges.values()].every((n) => n === 2), 'closed: every edge is shared by exactly two triangles');
