// GET /patches/teapot (GLB, ETag/304, control points) and POST /tessellate with an edited control point.
import { client, check } from './_common.mjs';

const glb = await client.patchSample('teapot', { tolerance: 0.01 });
check(glb.contentType === 'model/gltf-binary', `teapot within 0.01: error bound ${glb.headers.get('x-error-bound')}`);
const again = await client.patchSample('teapot', { tolerance: 0.01, etag: glb.headers.get('etag') });
check(again.status === 304, 'unchanged sample answers 304 Not Modified');

const net = (await client.patchSample('teapot', { format: 'patches' })).json;
check(net.patches.length === 32, 'teapot control points: 32 bicubic patches');
const original = await client.patchSample('teapot', { segments: 4, format: 'obj' });
net.patches[0].points[5][2] += 0.5;
const t0 = performance.now();
const r = await client.tessellate({ patches: net.patches, segments: 4, output: { format: 'obj' } });
const ms = performance.now() - t0;
check(r.headers.get('x-output-faces') === original.headers.get('x-output-faces') && r.text() !== original.text(),
      `edited patches tessellated: ${r.headers.get('x-output-faces')} triangles, round trip ${ms.toFixed(1)} ms`);

const flat = await client.tessellate({ bez: 'BEZ113\n0 0 0  1 0 0\n0 1 0  1 1 1\n', segments: 2, format: 'obj' });
check(flat.headers.get('x-output-faces') === '8', 'a BEZ bilinear patch at 2 segments: 8 triangles');
