// NURBS surfaces in the Patches view: the built-in trimmed NURBS sphere, the control-net layout of a surface, and its
// trimming loops drawn on the surface (the loops sampled in (u, v) here by de Boor, mapped onto the surface by
// POST /surfaces, which evaluates the exact surface).
import { deBoor, domain } from './curvemath.js';
import { call } from './api.js';

const H = Math.SQRT1_2;

/** A rational quadratic full circle of 9 points (4 arcs of 90 degrees) centred on `c` with radius r, in 2D. */
function circle2d(c, r, clockwise) {
  const x = [1, 1, 0, -1, -1, -1, 0, 1, 1], y = [0, 1, 1, 1, 0, -1, -1, -1, 0];
  const points = x.map((xi, i) => [c[0] + r * xi, c[1] + r * (clockwise ? -y[i] : y[i])]);
  return { degree: 2, knots: [0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1], points, weights: [1, H, 1, H, 1, H, 1, H, 1] };
}

/**
 * The unit sphere as the standard 9 x 5 NURBS net (a quarter-circle arc per Bézier piece along u, a half circle from
 * the south pole to the north pole along v), with a circular hole trimmed out of it.
 */
export function trimmedSphere() {
  const circle = circle2d([0, 0], 1, false);
  const profile = [[0, -1], [1, -1], [1, 0], [1, 1], [0, 1]], profileWeights = [1, H, 1, H, 1];
  const points = [], weights = [];
  for (let j = 0; j < 5; ++j)
    for (let i = 0; i < 9; ++i) {
      const [cx, cy] = circle.points[i], [r, z] = profile[j];
      points.push([cx * r, cy * r, z]);
      weights.push(circle.weights[i] * profileWeights[j]);
    }
  return {
    surfaces: [{
      degree: [2, 2], knots_u: circle.knots, knots_v: [0, 0, 0, 0.5, 0.5, 1, 1, 1], points, weights,
      trim: { holes: [[circle2d([0.3, 0.5], 0.12, true)]] },
    }],
  };
}

/** Control points along u and v of a surface ({degree, knots_u, points}). */
export function netSize(surface) {
  const nu = surface.knots_u.length - surface.degree[0] - 1;
  return [nu, surface.points.length / nu];
}

/** (u, v) samples of a trim curve ({degree, knots?, points, weights?}; Bézier without knots), `per` per knot span. */
export function sampleTrimCurve(curve, per = 24) {
  const p = curve.degree, n = curve.points.length;
  const knots = curve.knots ?? [...Array(p + 1).fill(0), ...Array(p + 1).fill(1)];
  const [lo, hi] = domain(knots, n, p);
  const breaks = [...new Set(knots.filter((k) => k >= lo && k <= hi))];
  const out = [];
  for (let b = 0; b + 1 < breaks.length; ++b)
    for (let k = 0; k < per; ++k) out.push(deBoor(curve.points, curve.weights, knots, p, breaks[b] + (breaks[b + 1] - breaks[b]) * k / per).point);
  out.push(deBoor(curve.points, curve.weights, knots, p, hi).point);
  return out;
}

/**
 * The trimming loops of every surface of `set` as 3D polylines on the surfaces, each point lifted off the surface by
 * `lift` along its normal so the line shows over the shading: [[x, y, z], ...] per loop.
 */
export async function trimLoops3d(set, lift) {
  const loops = [];
  for (const surface of set.surfaces ?? []) {
    if (!surface.trim) continue;
    const { trim, ...untrimmed } = surface;
    const loops2d = [...(trim.outer ? [trim.outer] : []), ...(trim.holes ?? [])]
      .map((loop) => loop.flatMap((curve) => sampleTrimCurve(curve)));
    if (!loops2d.length) continue;
    const uvs = loops2d.flat();
    const answer = (await call('POST', '/surfaces', { body: { surface: untrimmed, evaluate: uvs } })).json.evaluate;
    let k = 0;
    for (const loop of loops2d) {
      loops.push(loop.map(() => {
        const { position, normal } = answer[k++];
        return position.map((x, c) => x + lift * normal[c]);
      }));
    }
  }
  return loops;
}
