// GET /healthz, /livez, /readyz, /metrics and /openapi.json; the server's API version against the client's.
import { API_VERSION, isCompatible } from '../surfaced.mjs';
import { client, check } from './_common.mjs';

check((await client.healthz()).status === 'ok', 'healthz ok');
check((await client.livez()).status === 'ok' && (await client.readyz()).status === 'ready', 'livez ok, readyz ready');
check((await client.metrics()).includes('surfaced_http_requests_total'), 'metrics: Prometheus text');
const doc = await client.openapi();
check(doc.openapi.startsWith('3.1') && '/subdivide' in doc.paths, `${Object.keys(doc.paths).length} paths documented`);
const version = await client.checkServerVersion();
check(isCompatible(version, API_VERSION), `server implements API ${version}; client made for ${API_VERSION}`);
check(!isCompatible('1.0.0', '0.1.0') && isCompatible('1.3.0', '1.2.5'), 'semantic-version compatibility');
