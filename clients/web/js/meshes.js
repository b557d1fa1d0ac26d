// Built-in meshes for the subdivision and simplify views, in the service's JSON mesh form {positions, faces}.

export function cube() {
  return {
    positions: [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]],
    faces: [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
  };
}

export function tetra() {
  return { positions: [[1, 1, 1], [-1, -1, 1], [-1, 1, -1], [1, -1, -1]], faces: [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]] };
}

/** An open n×n grid of quads in the xz plane, with a raised centre. */
export function grid(n = 3) {
  const positions = [], faces = [];
  for (let j = 0; j <= n; ++j)
    for (let i = 0; i <= n; ++i) {
      const x = i / n * 2 - 1, z = j / n * 2 - 1;
      positions.push([x, (i > 0 && i < n && j > 0 && j < n) ? 0.5 : 0, z]);
    }
  for (let j = 0; j < n; ++j)
    for (let i = 0; i < n; ++i) {
      const a = j * (n + 1) + i;
      faces.push([a, a + n + 1, a + n + 2, a + 1]);
    }
  return { positions, faces };
}

export function torus(nu = 12, nv = 6, R = 1, r = 0.4) {
  const positions = [], faces = [];
  for (let i = 0; i < nu; ++i)
    for (let j = 0; j < nv; ++j) {
      const u = i / nu * 2 * Math.PI, v = j / nv * 2 * Math.PI;
      positions.push([(R + r * Math.cos(v)) * Math.cos(u), r * Math.sin(v), (R + r * Math.cos(v)) * Math.sin(u)]);
    }
  for (let i = 0; i < nu; ++i)
    for (let j = 0; j < nv; ++j) {
      const a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
      faces.push([a, d, c, b]);
    }
  return { positions, faces };
}

/** An icosphere (levels of 1:4 splits) with a deterministic bumpy radius: a triangle mesh worth simplifying. */
export function bumpySphere(levels = 4) {
  const t = (1 + Math.sqrt(5)) / 2;
  let positions = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                   [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]];
  let faces = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
               [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
               [8, 6, 7], [9, 8, 1]];
  for (let l = 0; l < levels; ++l) {
    const mid = new Map();
    const midpoint = (a, b) => {
      const k = a < b ? `${a},${b}` : `${b},${a}`;
      if (!mid.has(k)) {
        mid.set(k, positions.length);
        positions.push(positions[a].map((x, i) => (x + positions[b][i]) / 2));
      }
      return mid.get(k);
    };
    const next = [];
    for (const [a, b, c] of faces) {
      const ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.push([a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]);
    }
    faces = next;
  }
  positions = positions.map(([x, y, z]) => {
    const len = Math.hypot(x, y, z);
    const [nx, ny, nz] = [x / len, y / len, z / len];
    const r = 1 + 0.08 * Math.sin(5 * nx) * Math.sin(6 * ny) * Math.sin(7 * nz) + 0.04 * Math.sin(13 * ny);
    return [nx * r, ny * r, nz * r].map((c) => Math.round(c * 1e6) / 1e6);
  });
  return { positions, faces };
}

export const builtins = { cube, tetra, grid: () => grid(3), torus: () => torus(12, 6), torus64: () => torus(64, 32), bumpy: () => bumpySphere(4), bumpy3: () => bumpySphere(3) };
