// The limit point under a click in the subdivision view: the clicked point of the drawn surface is mapped to the
// base face and (u, v) whose limit point is nearest it, by POST /limit/evaluate and Gauss-Newton steps, and that
// limit point is drawn with its normal.
//
// (face, u, v) is OpenSubdiv Bfr's parameterization (docs/subdivision.md, "What (face, u, v) means"): a quad is the
// unit square, a Loop triangle the unit triangle, any other face under Catmull-Clark a row of half-size quad tiles,
// tile i spanning corner i, the midpoint of edge i, the centre and the midpoint of edge i - 1.
import * as THREE from 'three';
import { call } from './api.js';

const NEWTON_STEPS = 4;   // requests after the first; each halves the digits of the error or stops at the domain's edge
const CANDIDATES = 3;     // domain pieces nearest the clicked point that are followed to the limit surface

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const lerp3 = (a, b, t) => [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t];
const mid = (a, b) => lerp3(a, b, 0.5);

/**
 * The pieces of face `f`'s domain, each a map from local (s, t) in [0, 1]^2 (or the unit triangle) to the cage
 * (bilinear) and to the face's (u, v) (affine): {face, triangle, corners: [c00, c10, c11, c01], uv(s, t)}.
 */
export function domainPieces(mesh, f, scheme) {
  const ids = mesh.faces[f];
  const p = ids.map((i) => mesh.positions[i]);
  const n = p.length;
  if (scheme === 'loop')
    return n === 3 ? [{ face: f, triangle: true, corners: [p[0], p[1], p[2]], uv: (s, t) => [s, t] }] : [];
  if (n === 4) return [{ face: f, triangle: false, corners: [p[0], p[1], p[2], p[3]], uv: (s, t) => [s, t] }];
  const centre = p.reduce((acc, q) => [acc[0] + q[0] / n, acc[1] + q[1] / n, acc[2] + q[2] / n], [0, 0, 0]);
  const perRow = n === 3 ? 2 : n < 10 ? 3 : 1 + Math.floor(Math.sqrt(n - 1));
  return p.map((corner, i) => {
    const x = i % perRow, y = Math.floor(i / perRow);
    return {
      face: f, triangle: false,
      corners: [corner, mid(corner, p[(i + 1) % n]), centre, mid(corner, p[(i + n - 1) % n])],
      uv: (s, t) => [x + s / 2, y + t / 2],
      clampUv: ([u, v]) => [Math.min(x + 0.5, Math.max(x, u)), Math.min(y + 0.5, Math.max(y, v))],
    };
  });
}

/** The piece's point at (s, t) and its two partial derivatives. */
function pieceFrame(piece, s, t) {
  const [a, b, c, d] = piece.corners;
  if (piece.triangle) {
    const ds = sub(b, a), dt = sub(c, a);
    return { point: [a[0] + s * ds[0] + t * dt[0], a[1] + s * ds[1] + t * dt[1], a[2] + s * ds[2] + t * dt[2]], ds, dt };
  }
  const bottom = lerp3(a, b, s), top = lerp3(d, c, s);
  return { point: lerp3(bottom, top, t), ds: lerp3(sub(b, a), sub(c, d), t), dt: sub(top, bottom) };
}

/** Clamps local (s, t) into the piece: the unit square, or the unit triangle for a Loop face. */
function clampLocal(piece, s, t) {
  s = Math.min(1, Math.max(0, s));
  t = Math.min(1, Math.max(0, t));
  if (piece.triangle && s + t > 1) { const e = (s + t - 1) / 2; s -= e; t -= e; }
  return [Math.max(0, s), Math.max(0, t)];
}

/** The least-squares step of a Gauss-Newton iteration: J^T J delta = J^T r with J = [a b]; zero if singular. */
function step(a, b, r) {
  const aa = dot(a, a), ab = dot(a, b), bb = dot(b, b), det = aa * bb - ab * ab;
  if (!(Math.abs(det) > 1e-30)) return [0, 0];
  const ar = dot(a, r), br = dot(b, r);
  return [(bb * ar - ab * br) / det, (aa * br - ab * ar) / det];
}

/** The point of the cage piece nearest `target`: local (s, t) and its distance. */
function nearestOnPiece(piece, target) {
  let [s, t] = piece.triangle ? [1 / 3, 1 / 3] : [0.5, 0.5];
  for (let k = 0; k < 8; ++k) {
    const { point, ds, dt } = pieceFrame(piece, s, t);
    const [es, et] = step(ds, dt, sub(target, point));
    [s, t] = clampLocal(piece, s + es, t + et);
  }
  const r = sub(target, pieceFrame(piece, s, t).point);
  return { s, t, distance: Math.sqrt(dot(r, r)) };
}

/** Clamps (u, v) into the piece's part of the face's domain. */
function clampUv(piece, [u, v]) {
  if (piece.clampUv) return piece.clampUv([u, v]);
  return clampLocal(piece, u, v);
}

/**
 * The limit point nearest `target` (a point of the drawn surface, in the mesh's frame): the nearest cage pieces are
 * followed to the limit surface by Gauss-Newton steps on (u, v) with the limit derivatives /limit/evaluate answers.
 * `options` are the subdivide options the surface is drawn with (scheme, boundary, creases).
 */
export async function nearestLimitPoint(mesh, options, target) {
  const pieces = [];
  for (let f = 0; f < mesh.faces.length; ++f)
    for (const piece of domainPieces(mesh, f, options.scheme)) pieces.push({ piece, ...nearestOnPiece(piece, target) });
  pieces.sort((a, b) => a.distance - b.distance);
  const candidates = pieces.slice(0, CANDIDATES).map(({ piece, s, t }) => ({ piece, uv: piece.uv(s, t) }));
  if (!candidates.length) throw new Error(`no face of this mesh has a ${options.scheme} limit surface to probe`);
  let answers = null;
  for (let k = 0; k <= NEWTON_STEPS; ++k) {
    const body = { mesh, ...options, points: candidates.map((c) => ({ face: c.piece.face, uv: c.uv })) };
    answers = (await call('POST', '/limit/evaluate', { body })).json.points;
    if (k === NEWTON_STEPS) break;
    candidates.forEach((c, i) => {
      const [du, dv] = step(answers[i].du, answers[i].dv, sub(target, answers[i].position));
      c.uv = clampUv(c.piece, [c.uv[0] + du, c.uv[1] + dv]);
    });
  }
  let best = 0, bestDistance = Infinity;
  answers.forEach((a, i) => {
    const r = sub(target, a.position);
    const d = Math.sqrt(dot(r, r));
    if (d < bestDistance) { bestDistance = d; best = i; }
  });
  return { face: candidates[best].piece.face, uv: candidates[best].uv, ...answers[best], distance: bestDistance };
}

/** A marker for the limit point: a dot and its normal as a line `length` long, drawn over the surface. */
export function limitMarker(point, normal, length) {
  const group = new THREE.Group();
  const from = new THREE.Vector3(...point), to = from.clone().addScaledVector(new THREE.Vector3(...normal), length);
  const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([from, to]),
                              new THREE.LineBasicMaterial({ color: 0xffd060, depthTest: false }));
  const dot3 = new THREE.Points(new THREE.BufferGeometry().setFromPoints([from]),
                                new THREE.PointsMaterial({ color: 0xffd060, size: 8, sizeAttenuation: false, depthTest: false }));
  for (const o of [line, dot3]) { o.renderOrder = 2; group.add(o); }
  return group;
}
