// POST /implicit/grid: a tetrahedron as a narrow-band signed distance grid, sent back as a scene and queried.
import { client, check } from './_common.mjs';

const tet = { positions: [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]],
              faces: [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]] };
const { json: grid } = await client.implicitGrid({ mesh: tet, voxel_size: 0.25, band: 2 });
check(grid.op === 'level_set' && grid.values.length === grid.dims[0] * grid.dims[1] * grid.dims[2],
      `a level_set node of ${grid.dims} nodes`);
check(Math.max(...grid.values.map(Math.abs)) <= 0.5 + 1e-12, 'values clamped to the band, 2 * 0.25');
const { json: r } = await client.implicitQuery({ scene: grid, points: [[0, 0, 0], [3, 0, 0]] });
const classes = r.points.map((p) => p.class);
check(JSON.stringify(classes) === '["inside","outside"]', `classes ${classes}`);
