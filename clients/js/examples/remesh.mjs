// POST /remesh: an octahedron remeshed to edge length 0.25; the new vertices stay on its surface (|x|+|y|+|z| = 1).
import { client, check } from './_common.mjs';

const octahedron = {
  positions: [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
  faces: [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]],
};
const r = await client.remesh({ mesh: octahedron, edge_length: 0.25, iterations: 5, format: 'json' });
const { positions, faces } = r.json.mesh;
const offSurface = Math.max(...positions.map(([x, y, z]) => Math.abs(Math.abs(x) + Math.abs(y) + Math.abs(z) - 1)));
check(faces.length > 80, `8 -> ${faces.length} triangles (min angle ${r.headers.get('x-min-angle-after')})`);
check(offSurface < 1e-6, `every vertex on the octahedron: max | |x|+|y|+|z| - 1 | = ${offSurface.toExponential(2)}`);
