// GET /healthz and GET /openapi.json
import { client, check } from './_common.mjs';

check((await client.healthz()).status === 'ok', 'healthz ok');
const doc = await client.openapi();
check(doc.openapi.startsWith('3.1') && '/subdivide' in doc.paths, `${Object.keys(doc.paths).length} paths documented`);
