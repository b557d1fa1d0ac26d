// Curve arithmetic done in the page, for interaction only: de Casteljau and de Boor with their intermediate polygons,
// the Bernstein and B-spline basis, knot vectors. The server stays the reference: the Curves view shows its
// `evaluate` next to these values and the browser test checks that they agree.
// Points are 2D [x, y]; rational curves (weights) run on homogeneous coordinates [w x, w y, w].

/** The homogeneous form of points with optional weights (absent: all 1). */
function lift(points, weights) {
  return points.map((p, i) => {
    const w = weights ? weights[i] : 1;
    return [p[0] * w, p[1] * w, w];
  });
}

const project = (h) => [h[0] / h[2], h[1] / h[2]];
const lerp = (a, b, t) => a.map((x, k) => (1 - t) * x + t * b[k]);

/**
 * de Casteljau at t in [0, 1]: `levels[0]` is the control polygon, each next level the points of the previous one's
 * segments at ratio t, and the last level the point on the curve (`point`). Levels are returned projected.
 */
export function deCasteljau(points, weights, t) {
  let level = lift(points, weights);
  const levels = [level];
  while (level.length > 1) {
    const next = [];
    for (let i = 0; i + 1 < level.length; ++i) next.push(lerp(level[i], level[i + 1], t));
    levels.push((level = next));
  }
  return { levels: levels.map((l) => l.map(project)), point: project(level[0]) };
}

/** The n + 1 Bernstein polynomials B_{i,n}(t), built up degree by degree (B_{i,k} = (1-t) B_{i,k-1} + t B_{i-1,k-1}). */
export function bernstein(n, t) {
  const b = [1];
  for (let k = 1; k <= n; ++k)
    for (let i = k; i >= 0; --i) b[i] = (i < k ? (1 - t) * b[i] : 0) + (i > 0 ? t * b[i - 1] : 0);
  return b;
}

/**
 * The weights that make the curve's point an affine combination of the control points: the basis itself for
 * a polynomial curve, w_i B_i / sum_j w_j B_j for a rational one. They sum to 1 either way.
 */
export function rationalWeights(basis, weights) {
  if (!weights) return basis;
  const scaled = basis.map((b, i) => b * weights[i]);
  const sum = scaled.reduce((a, b) => a + b, 0);
  return scaled.map((b) => b / sum);
}

/** A clamped uniform knot vector for n points of degree p: p + 1 zeros, n - p - 1 evenly spaced knots, p + 1 ones. */
export function clampedKnots(n, p) {
  const spans = n - p;
  const knots = [];
  for (let i = 0; i <= p; ++i) knots.push(0);
  for (let j = 1; j < spans; ++j) knots.push(j / spans);
  for (let i = 0; i <= p; ++i) knots.push(1);
  return knots;
}

/** The parameter domain [U[p], U[n]] of n points of degree p. */
export function domain(knots, n, p) { return [knots[p], knots[n]]; }

/** The knot span k (U[k] <= u < U[k+1], p <= k < n) holding u; the domain's end belongs to the last non-empty span. */
export function findSpan(knots, n, p, u) {
  let k = n - 1;
  while (k > p && (knots[k] > u || knots[k] === knots[k + 1])) --k;
  return k;
}

/** The p + 1 non-zero B-spline basis functions N_{k-p..k, p}(u) of span k (Cox-de Boor, triangular form). */
export function bsplineBasisInSpan(knots, p, k, u) {
  const N = [1], left = [], right = [];
  for (let j = 1; j <= p; ++j) {
    left[j] = u - knots[k + 1 - j];
    right[j] = knots[k + j] - u;
    let saved = 0;
    for (let r = 0; r < j; ++r) {
      const temp = N[r] / (right[r + 1] + left[j - r]);
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
  return N;
}

/** All n basis functions N_{i,p}(u), zero outside the span's p + 1. */
export function bsplineBasis(knots, n, p, u) {
  const k = findSpan(knots, n, p, u);
  const all = new Array(n).fill(0);
  bsplineBasisInSpan(knots, p, k, u).forEach((v, r) => { all[k - p + r] = v; });
  return all;
}

/**
 * de Boor at u: `levels[0]` is the p + 1 control points that act on u's span, each next level the corner cutting
 * with ratios (u - U[j]) / (U[j+p+1-r] - U[j]), the last the point on the curve. Levels are returned projected.
 */
export function deBoor(points, weights, knots, p, u) {
  const n = points.length;
  const k = findSpan(knots, n, p, u);
  const h = lift(points, weights);
  let level = h.slice(k - p, k + 1);
  const levels = [level];
  for (let r = 1; r <= p; ++r) {
    const next = [];
    for (let j = k - p + r; j <= k; ++j) {
      const i = j - (k - p + r);   // index of d_{j-1} in `level`, which starts at k - p + r - 1
      const alpha = (u - knots[j]) / (knots[j + p + 1 - r] - knots[j]);
      next.push(lerp(level[i], level[i + 1], alpha));
    }
    levels.push((level = next));
  }
  return { levels: levels.map((l) => l.map(project)), point: project(level[0]), span: k };
}
