// POST /curves: evaluate a cubic Bezier curve and its length with a guaranteed error bound.
import { client, check } from './_common.mjs';

const r = (await client.curves({ points: [[0, 0], [1, 2], [3, 2], [4, 0]], evaluate: [0, 0.5, 1], length: { tolerance: 1e-6 } })).json;
const [x, y] = r.evaluate[1];   // B(1/2) = (P0 + 3 P1 + 3 P2 + P3) / 8 = (2, 1.5)
check(Math.abs(x - 2) < 1e-12 && Math.abs(y - 1.5) < 1e-12, `B(0.5) = (${x}, ${y})`);
check(r.length.error_bound <= 1e-6 && r.length.length > 4 && r.length.length < 6.5, `length ${r.length.length.toFixed(9)}`);
