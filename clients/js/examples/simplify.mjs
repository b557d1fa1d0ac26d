// POST /simplify: a finely tessellated teapot to 10 %, with the measured error.
import { client, check } from './_common.mjs';

const teapot = await client.patchSample('teapot', { segments: 16, format: 'obj', normals: false });
const r = await client.simplify({ data: teapot.body, contentType: 'model/obj', ratio: 0.1, report_error: true, output: { format: 'obj' } });
const nIn = Number(r.headers.get('x-input-faces')), nOut = Number(r.headers.get('x-output-faces'));
const hausdorff = Number(r.headers.get('x-hausdorff'));
check(nOut < 0.15 * nIn, `${nIn} -> ${nOut} triangles (ratio 0.1)`);
check(hausdorff > 0 && hausdorff < 0.5, `measured Hausdorff distance ${hausdorff.toPrecision(4)}`);
