// POST /limit/evaluate: the limit surface of a flat 2 x 2 grid with sharp corners is its own plane.
import { client, check } from './_common.mjs';

const xy = [];
for (let y = 0; y < 3; ++y) for (let x = 0; x < 3; ++x) xy.push([x / 2, y / 2]);
const faces = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
const grid = { positions: xy.map(([x, y]) => [x, y, 0]), faces, uvs: xy, uv_faces: faces };
const { json: r } = await client.limitEvaluate({
  mesh: grid, points: [{ face: 0, uv: [0.5, 0.5] }, { face: 3, uv: [1, 1] }],
  boundary: 'edge-and-corner', uv_interpolation: 'all', derivatives: 2,
});
const near = (a, b) => a.every((v, i) => Math.abs(v - b[i]) < 1e-12);
const [p, corner] = r.points;
check(near(p.position, [0.25, 0.25, 0]), `position ${p.position}`);
check(near(corner.position, [1, 1, 0]), 'the sharp corner is interpolated');
check(near(p.normal, [0, 0, 1]), `normal ${p.normal}`);
check(near(p.uv, [0.25, 0.25]), `uv ${p.uv}`);
check(p.duu.every((c) => Math.abs(c) < 1e-12), 'a plane has no second derivatives');
