// POST /subdivide: a cube as JSON (counts), a GLB file with a crease, an OBJ upload with Loop, and a refused request.
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { client, check, out } from './_common.mjs';
import { SurfacedError } from '../surfaced.mjs';

const cube = {
  positions: [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]],
  faces: [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
};
const r = await client.subdivide({ mesh: cube, scheme: 'catmull-clark', levels: 2, output: { format: 'json' } });
check(r.json.stats.output_faces === 6 * 16, `cube, 2 levels: ${r.json.stats.output_faces} faces`);

const glb = await client.subdivide({ mesh: cube, levels: 3, creases: [{ edge: [0, 1], sharpness: 2 }] });
const file = path.join(out, 'cube-l3.glb');
writeFileSync(file, glb.body);
check(new TextDecoder().decode(glb.body.slice(0, 4)) === 'glTF', `GLB written to ${file} (${glb.headers.get('x-output-faces')} faces)`);

const tetra = 'v 1 1 1\nv -1 -1 1\nv -1 1 -1\nv 1 -1 -1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n';
const obj = await client.subdivide({ data: tetra, contentType: 'model/obj', scheme: 'loop', levels: 2, output: { format: 'obj' } });
const faces = obj.text().split('\n').filter((l) => l.startsWith('f ')).length;
check(faces === 4 * 16, `OBJ upload, Loop 2 levels: ${faces} faces`);

try {
  await client.subdivide({ mesh: { positions: cube.positions, faces: [[0, 1, 99]] }, levels: 1 });
  check(false, 'a face index out of range must be refused');
} catch (e) {
  check(e instanceof SurfacedError && e.status >= 400 && e.status < 500 && /mesh\.faces\[0\]/.test(e.field ?? ''), `refused: ${e.message}`);
}
