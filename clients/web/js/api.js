// Requests to the surfaced service: timing, the progress indicator, and problem+json errors turned into readable text.

/** An error response (RFC 9457 problem+json) or a network failure, with a readable message. */
export class ProblemError extends Error {
  constructor(status, problem) {
    super(formatProblem(status, problem));
    this.status = status;
    this.problem = problem;
  }
}

export function formatProblem(status, p) {
  if (!p || typeof p !== 'object') return `HTTP ${status}`;
  let text = `${p.status ?? status} ${p.title ?? 'Error'}`;
  if (p.detail) text += `: ${p.detail}`;
  const where = [];
  if (p.field) where.push(`field ${p.field}`);
  if (p.line) where.push(`line ${p.line}`);
  if (where.length) text += `\n(at ${where.join(', ')})`;
  if (p.code) text += `\n[${p.code}]`;
  return text;
}

let inFlight = 0;
let progressTimer = null;

function progressStart() {
  if (inFlight++ === 0) {
    // only requests that take more than a moment show the bar (dragging must not flicker)
    progressTimer = setTimeout(() => { document.getElementById('progress').hidden = false; }, 150);
  }
}

function progressEnd() {
  if (--inFlight === 0) {
    clearTimeout(progressTimer);
    document.getElementById('progress').hidden = true;
  }
}

/**
 * fetch() with the progress indicator. Resolves to {bytes, json, headers, status, roundTripMs, networkMs}; rejects with a
 * ProblemError for any non-2xx answer.
 */
export async function call(method, path, { body, contentType, signal } = {}) {
  const headers = {};
  if (body !== undefined) {
    if (contentType) headers['Content-Type'] = contentType;
    else if (typeof body === 'object' && !(body instanceof ArrayBuffer) && !ArrayBuffer.isView(body)) {
      headers['Content-Type'] = 'application/json';
      body = JSON.stringify(body);
    }
  }
  progressStart();
  const t0 = performance.now();
  try {
    let res;
    try {
      res = await fetch(path, { method, headers, body, signal });
    } catch (e) {
      if (e.name === 'AbortError') throw e;
      throw new ProblemError(0, { title: 'Network error', detail: `${method} ${path}: ${e.message} (is the server running?)` });
    }
    const type = res.headers.get('Content-Type') || '';
    const bytes = await res.arrayBuffer();
    const roundTripMs = performance.now() - t0;
    if (!res.ok) {
      let problem = null;
      try { problem = JSON.parse(new TextDecoder().decode(bytes)); } catch { /* not JSON */ }
      throw new ProblemError(res.status, problem ?? { title: res.statusText, detail: new TextDecoder().decode(bytes).slice(0, 300) });
    }
    const json = type.startsWith('application/json') ? JSON.parse(new TextDecoder().decode(bytes)) : undefined;
    return { bytes, json, headers: res.headers, status: res.status, type, roundTripMs, networkMs: networkTime(res.url, t0) };
  } finally {
    progressEnd();
  }
}

/**
 * The request's own time on the wire (request start to last response byte) from the Resource Timing entry: unlike
 * the promise round trip it leaves out time the page's main thread was busy (drawing) before it saw the answer.
 */
function networkTime(url, t0) {
  const entries = performance.getEntriesByName(url, 'resource');
  for (let i = entries.length - 1; i >= 0; --i)
    if (entries[i].startTime >= t0 - 1) {
      const ms = entries[i].responseEnd - entries[i].startTime;
      if (performance.getEntriesByType('resource').length > 200) performance.clearResourceTimings();  // buffer holds 250
      return ms;
    }
  return undefined;
}

/** The media type the service expects for an uploaded mesh file, from its extension. */
export function meshMediaType(fileName) {
  const ext = fileName.toLowerCase().split('.').pop();
  return { obj: 'model/obj', off: 'model/off', ply: 'application/ply', stl: 'model/stl', glb: 'model/gltf-binary',
           gltf: 'model/gltf+json' }[ext]
    ?? 'application/octet-stream';
}

/** The repair report of X-Repairs (simplify and remesh repair uploads first) as one summary line: the counts that are
 *  not zero ("repaired: welded 12, flipped 3"), "repair: none needed", or nothing when the header is absent. */
export function repairStats(headers) {
  const value = headers.get('X-Repairs');
  if (value === null) return [];
  const done = value.split(';').map((item) => item.trim().split('='))
    .filter(([name, count]) => name !== 'components' && Number(count) > 0)
    .map(([name, count]) => `${name.replace('_', ' ')} ${count}`);
  return [done.length ? `repaired: ${done.join(', ')}` : 'repair: none needed'];
}

/** "X-Output-Faces: 1234"-style summary lines for the headers that are present. */
export function headerStats(headers, names) {
  const lines = [];
  for (const [name, label] of names) {
    const v = headers.get(name);
    if (v !== null) lines.push(`${label}: ${v}`);
  }
  return lines;
}
