// POST /pointcloud: 200 points sampled on a unit sphere (an implicit scene) with estimated normals: on the sphere,
// normals radial (up to orientation); then an XYZ text upload.
import { client, check } from './_common.mjs';

const r = await client.pointcloud({ sample: { scene: { op: 'sphere', radius: 1 }, bounds: [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]], count: 200, seed: 3 },
                                    estimate_normals: { k: 12 }, output: { format: 'json' } });
const { points, normals } = r.json;
const off = Math.max(...points.map((p) => Math.abs(Math.hypot(...p) - 1)));
const radial = Math.min(...points.map((p, i) => {
  const n = normals[i];
  return Math.abs(n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / (Math.hypot(...n) * Math.hypot(...p));
}));
check(points.length === 200 && normals.length === 200, `${points.length} points with normals`);
check(off < 1e-3, `on the sphere: max | |p| - 1 | = ${off.toExponential(2)}`);
check(radial > 0.9, `estimated normals radial: min |cos| = ${radial.toFixed(4)}`);

const xyz = await client.pointcloud({ data: '0 0 0\n1 0 0\n0 1 0\n1 1 0.1\n', contentType: 'text/x-xyz', format: 'ply' });
check(xyz.headers.get('x-output-points') === '4' && xyz.text().startsWith('ply'), 'XYZ upload -> PLY with 4 points');
