// POST /repair: a bow-tie (two triangles meeting at one vertex), a duplicated triangle and a flipped one, repaired.
import { client, check } from './_common.mjs';

const mesh = {
  positions: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [1, 1, 0]],
  faces: [[0, 1, 2], [0, 3, 4], [0, 1, 2], [2, 5, 1]],
};
const r = await client.repair({ mesh, format: 'json' });
const { repairs } = r.json.stats;
check(repairs.duplicate === 1, `one duplicate face dropped (${r.headers.get('x-repairs')})`);
check(repairs.nonmanifold_split === 1, 'the pinched vertex cut apart into two');
check(r.json.mesh.faces.length === 3, '3 faces left of 4');
