// POST /implicit/query: a unit sphere classified at points and hit by a ray (exact signed distance).
import { client, check } from './_common.mjs';

const { json: r } = await client.implicitQuery({ scene: { op: 'sphere', radius: 1 }, points: [[0, 0, 0], [2, 0, 0], [0, 0.6, 0.8]],
                                       rays: [{ origin: [-5, 0, 0], direction: [1, 0, 0] }] });
const classes = r.points.map((p) => p.class);
check(JSON.stringify(classes) === '["inside","outside","on"]', `classes ${classes}`);
check(Math.abs(r.points[0].value + 1) < 1e-9 && Math.abs(r.points[1].value - 1) < 1e-9, 'signed distances -1 and 1');
check(r.rays[0].hit && Math.abs(r.rays[0].t - 4) < 1e-3, `ray from x = -5 hits the sphere at t = ${r.rays[0].t}`);
