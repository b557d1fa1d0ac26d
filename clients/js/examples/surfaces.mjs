// POST /surfaces: the closest point on a NURBS cylinder is the radial projection; elevating its degree keeps it.
import { client, check } from './_common.mjs';

const h = Math.SQRT1_2;
// the 9-point rational quadratic circle of radius 1 (u), swept linearly from z = 0 to z = 2 (v)
const circle = [[1, 0, 1], [1, 1, h], [0, 1, 1], [-1, 1, h], [-1, 0, 1], [-1, -1, h], [0, -1, 1], [1, -1, h], [1, 0, 1]];
const cylinder = {
  degree: [2, 1], knots_u: [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1], knots_v: [0, 0, 1, 1],
  points: [0, 2].flatMap((z) => circle.map(([x, y]) => [x, y, z])), weights: [0, 2].flatMap(() => circle.map((p) => p[2])),
};
const r = (await client.surfaces({ surface: cylinder, closest: [[3, 4, 1]], elevate: { direction: 'v', times: 2 }, evaluate: [[0.1, 0.5]] })).json;
const c = r.closest[0];
check(Math.abs(c.distance - 4) < 1e-9, `distance ${c.distance}`);   // |(3, 4)| - 1
check(c.point.every((x, i) => Math.abs(x - [0.6, 0.8, 1][i]) < 1e-6), `closest point ${c.point}`);
const again = (await client.surfaces({ surface: r.elevate, evaluate: [[0.1, 0.5]] })).json;
check(r.elevate.degree[1] === 3, `elevated degree ${r.elevate.degree}`);
check(again.evaluate[0].position.every((x, i) => Math.abs(x - r.evaluate[0].position[i]) < 1e-12), 'the elevated surface is the same surface');
