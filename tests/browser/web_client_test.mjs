// Browser tests of the web client: Playwright (playwright-core) driving Debian's Chromium headless against a real
// `surfaced serve` on loopback. Usage:
//   node tests/browser/web_client_test.mjs SURFACED_BINARY WEB_ROOT ARTIFACT_DIR
// Exit 0 pass, 1 fail, 77 skipped (no Chromium; said loudly).
import { existsSync, mkdirSync } from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { startServer } from './serve.mjs';
import { checkCurvesView } from './curves_checks.mjs';
import { checkPointCloudView } from './pointcloud_checks.mjs';

const [binary, webRoot, artifacts] = process.argv.slice(2);
if (!binary || !webRoot || !artifacts) {
  console.error('usage: web_client_test.mjs SURFACED_BINARY WEB_ROOT ARTIFACT_DIR');
  process.exit(2);
}
const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';
if (!existsSync(chromiumPath)) {
  console.error(`\n*** SKIPPED: browser tests need Chromium at ${chromiumPath} (apt-get install chromium; ` +
                'scripts/install-deps.sh installs it). The web client was NOT tested. ***\n');
  process.exit(77);
}
if (!existsSync(path.join(webRoot, 'vendor/three/three.module.js'))) {
  console.error(`${webRoot}/vendor is missing (it is committed; scripts/vendor-web.sh restores it from npm)`);
  process.exit(1);
}
const require = createRequire(import.meta.url);
const { chromium } = require('playwright-core');
mkdirSync(artifacts, { recursive: true });

let failures = 0;
function check(condition, message) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${message}`);
  if (!condition) failures++;
}

const server = await startServer(binary, webRoot);
const browser = await chromium.launch({
  executablePath: chromiumPath,
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const consoleErrors = [];
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 700 } });
  // Chromium logs every 4xx answer as "Failed to load resource"; only the deliberately invalid upload may cause one
  let expectRejection = false;
  page.on('console', (m) => {
    if (m.type() !== 'error') return;
    if (expectRejection && /Failed to load resource: .*status of 4\d\d/.test(m.text())) return;
    consoleErrors.push(m.text());
  });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
  page.setDefaultTimeout(20000);

  const shot = async (name) => {
    const file = path.join(artifacts, `${name}.png`);
    await page.screenshot({ path: file });
    return file;
  };
  // Pixels of the WebGL canvas that differ from the background colour (the renderer keeps its drawing buffer).
  // The viewer draws at the next animation frame after a change: wait for two frames, so that a frame asked for
  // before this call has been drawn (the stats can be set before the first frame of a new result). `region`: 'left'
  // or 'right' half (a split view), else the whole canvas.
  const canvasPixels = (region) => page.evaluate(async (region) => {
    await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
    const src = document.querySelector('#viewport canvas');
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    const half = Math.floor(c.width / 2);
    const [x0, width] = region === 'left' ? [0, half] : region === 'right' ? [half, c.width - half] : [0, c.width];
    const d = ctx.getImageData(x0, 0, width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4)
      if (Math.abs(d[i] - 0x1b) + Math.abs(d[i + 1] - 0x1d) + Math.abs(d[i + 2] - 0x22) > 24) n++;
    return { n, total: width * c.height, webgl: !!src.getContext('webgl2') || !!src.getContext('webgl') };
  }, region);
  const statsUpdates = () => page.$eval('#stats', (el) => Number(el.dataset.updates ?? 0));
  const meshSignature = () => page.evaluate(() => {
    const r = window.surfaced.viewer.result;
    if (!r) return null;
    const p = r.geometry.attributes.position.array;
    let s = 0;
    for (let i = 0; i < p.length; ++i) s += p[i] * ((i % 7) + 1);
    return `${p.length}:${s.toFixed(4)}`;
  });

  // 1. the page loads, the teapot appears
  const loadStart = Date.now();
  // generous: cpp-httplib (Debian's, built with brotli) compresses the 2 MB of three.js at brotli's slowest setting
  await page.goto(`${server.url}/`, { timeout: 90000 });
  await page.waitForSelector('body[data-ready=true]', { timeout: 90000 });
  console.log(`     page loaded and teapot requested in ${Date.now() - loadStart} ms`);
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.updates ?? 0) > 0);
  const teapot = await canvasPixels();
  const teapotShot = await shot('01-teapot');
  check(teapot.n > 0.05 * teapot.total, `teapot drawn: ${teapot.n} of ${teapot.total} canvas pixels are not background (${teapotShot})`);
  const patchCount = await page.evaluate(() => window.surfaced.views.patches.patches.patches.length);
  check(patchCount === 32, `control net of the teapot has 32 patches (got ${patchCount})`);

  // 2. drag a control point: the geometry changes, through POST /tessellate round trips
  const before = await meshSignature();
  const target = await page.evaluate(() => {
    const v = window.surfaced.views.patches;
    const canvas = window.surfaced.viewer.renderer.domElement.getBoundingClientRect();
    // the control point furthest right on screen (a point of the spout tip, not hidden behind others)
    let best = null;
    for (let i = 0; i < v.positions.count; ++i) {
      const p = new (window.surfaced.viewer.camera.position.constructor)().fromBufferAttribute(v.positions, i)
        .applyMatrix4(window.surfaced.viewer.overlay.matrixWorld).project(window.surfaced.viewer.camera);
      const x = canvas.left + (p.x + 1) / 2 * canvas.width, y = canvas.top + (1 - p.y) / 2 * canvas.height;
      if (!best || x > best.x) best = { x, y, id: i };
    }
    return best;
  });
  const originalSet = await page.evaluate(() => JSON.stringify(window.surfaced.views.patches.patches));
  const updatesBefore = await statsUpdates();
  await page.mouse.move(target.x, target.y);
  await page.mouse.down();
  for (let k = 1; k <= 12; ++k) {
    await page.mouse.move(target.x - 6 * k, target.y - 8 * k);
    await page.waitForTimeout(30);
  }
  await page.mouse.up();
  await page.waitForFunction(() => !window.surfaced.views.patches.busy);
  const after = await meshSignature();
  const { movedPoint, originalPoint } = await page.evaluate((original) => {
    const v = window.surfaced.views.patches;
    const before = JSON.parse(original);
    const refs = v.lastDragged === undefined ? [] : v.refs[v.lastDragged];
    // refs: [patch object, point index] for each copy of the point in the patches sharing it
    return { movedPoint: refs.map(([patch, i]) => patch.points[i]),
             originalPoint: refs.map(([patch, i]) => before.patches[v.patches.patches.indexOf(patch)].points[i]) };
  }, originalSet);
  const dragShot = await shot('02-teapot-dragged');
  const trips = await page.evaluate(() => window.surfaced.views.patches.roundTrips);
  check(movedPoint.length > 0 && JSON.stringify(movedPoint) !== JSON.stringify(originalPoint) && new Set(movedPoint.map(String)).size === 1,
        `dragged control point moved (all ${movedPoint.length} copies shared by neighbouring patches together)`);
  check(before !== after && after !== null, `tessellated geometry changed after the drag (${dragShot})`);
  check((await statsUpdates()) > updatesBefore && trips.length >= 2,
        `view updated while dragging: ${trips.length} POST /tessellate round trips during the drag`);
  const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
  const wire = median(trips.map((t) => t.wire)), shown = median(trips.map((t) => t.shown));
  console.log(`     drag round trips (ms, request sent -> response received): ${trips.map((t) => t.wire.toFixed(1)).join(' ')}`);
  console.log(`     until drawn (ms, incl. GLB parse on this GPU-less software renderer): ${trips.map((t) => t.shown.toFixed(1)).join(' ')}`);
  // measured and printed, not asserted (no timing assertions in tests; the README quotes the number)
  console.log(`     teapot drag round trip: median ${wire?.toFixed(1)} ms (request sent -> response received); shown after ${shown?.toFixed(1)} ms`);

  // 2b. an uploaded JSON patch set: one bicubic saddle, 8 segments -> 8 x 8 x 2 triangles, with its 16-point net
  const saddle = { patches: [{ degree: [3, 3], points: [] }] };
  for (let j = 0; j < 4; ++j) for (let i = 0; i < 4; ++i) saddle.patches[0].points.push([i, j, (i - 1.5) * (j - 1.5) / 2]);
  const updatesBeforeUpload = await statsUpdates();
  await page.setInputFiles('#patch-file', { name: 'saddle.json', mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(saddle)) });
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n, updatesBeforeUpload);
  const saddleStats = await page.$eval('#stats', (el) => el.textContent);
  const saddleNet = await page.evaluate(() => window.surfaced.views.patches.positions.count);
  check(/patches: 1\n/.test(saddleStats) && /triangles: 128\n/.test(saddleStats) && saddleNet === 16,
        `uploaded JSON patch set tessellated: 1 patch, 128 triangles, 16 control points (${await shot('02b-saddle')})`);

  // 2c. the trimmed NURBS sphere: tessellated by the server with its hole, the trimming loop drawn on the surface
  // (points of the exact sphere, lifted by 0.3% of the net's diagonal), then a picked control point's weight edited
  const updatesBeforeNurbs = await statsUpdates();
  await page.selectOption('#patch-source', 'nurbs-sphere');
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n &&
                             /trimming loops/.test(document.getElementById('stats').textContent), updatesBeforeNurbs);
  const nurbsStats = await page.$eval('#stats', (el) => el.textContent);
  const nurbsTriangles = Number(/triangles: (\d+)/.exec(nurbsStats)?.[1]);
  const loop = await page.evaluate(() => {
    const lines = window.surfaced.views.patches.trimLines.children;
    const radii = lines.length ? Array.from({ length: lines[0].geometry.attributes.position.count }, (_, i) => {
      const a = lines[0].geometry.attributes.position;
      return Math.hypot(a.getX(i), a.getY(i), a.getZ(i));
    }) : [];
    return { loops: lines.length, points: radii.length, min: Math.min(...radii), max: Math.max(...radii) };
  });
  check(/surfaces: 1, 1 trimming loops/.test(nurbsStats) && nurbsTriangles > 0 && loop.loops === 1 && loop.points > 50 &&
        loop.min > 0.999 && loop.max < 1.02,
        `trimmed NURBS sphere: ${nurbsTriangles} triangles, its hole's loop drawn on the sphere (${loop.points} points, ` +
        `radius ${loop.min.toFixed(4)}-${loop.max.toFixed(4)}) (${await shot('02c-nurbs-sphere')})`);
  const sphereSignature = await meshSignature();
  // a click on an equator control point picks it; a weight of 1.2 pulls the surface towards it
  const equator = await page.evaluate(() => {
    const v = window.surfaced.views.patches, rect = window.surfaced.viewer.renderer.domElement.getBoundingClientRect();
    const P = window.surfaced.viewer.camera.position.constructor;
    let best = null;
    for (let i = 0; i < v.positions.count; ++i) {
      const p = new P().fromBufferAttribute(v.positions, i);
      if (Math.abs(p.z) > 1e-9) continue;   // the net's middle row (z = 0 in the surface's frame)
      const q = p.clone().applyMatrix4(window.surfaced.viewer.overlay.matrixWorld).project(window.surfaced.viewer.camera);
      if (!best || q.z < best.depth) best = { depth: q.z, x: rect.left + (q.x + 1) / 2 * rect.width, y: rect.top + (1 - q.y) / 2 * rect.height };
    }
    return best;
  });
  await page.mouse.click(equator.x, equator.y);
  await page.waitForSelector('#patch-weight-row:not([hidden])');
  const weightBefore = Number(await page.inputValue('#patch-weight'));
  const updatesBeforeWeight = await statsUpdates();
  await page.fill('#patch-weight', '1.2');
  await page.dispatchEvent('#patch-weight', 'change');
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n, updatesBeforeWeight);
  const weighted = await meshSignature();
  check(weightBefore > 0 && weighted !== sphereSignature,
        `editing a control point's weight (${weightBefore} -> 1.2) changes the NURBS surface (${await shot('02d-nurbs-weight')})`);

  // 3. subdivision through the UI: the cube at level 2 (96 faces), then a picked edge made sharp
  await page.click('#tabs button[data-view=subdivide]');
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) > 0);
  const cubeFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));
  check(cubeFaces === 96, `Catmull-Clark cube, 2 levels: 96 faces (got ${cubeFaces})`);
  await page.fill('#sub-levels', '3');
  await page.dispatchEvent('#sub-levels', 'input');
  await page.click('#sub-run');
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) === 384);
  const smooth = await meshSignature();
  const sub = await canvasPixels();
  check(sub.n > 0.03 * sub.total, `subdivided cube rendered: ${sub.n} pixels (${await shot('03-subdivided')})`);
  const edge = await page.evaluate(() => {
    const v = window.surfaced.views.subdivide;
    const rect = window.surfaced.viewer.renderer.domElement.getBoundingClientRect();
    const V = window.surfaced.viewer.camera.position.constructor;
    const screen = (i) => {
      const p = new V(...v.mesh.positions[i]).applyMatrix4(window.surfaced.viewer.overlay.matrixWorld).project(window.surfaced.viewer.camera);
      return [rect.left + (p.x + 1) / 2 * rect.width, rect.top + (1 - p.y) / 2 * rect.height];
    };
    // the longest edge on screen: the least likely to be near another one
    let best = null;
    for (const [a, b] of v.edges) {
      const [pa, pb] = [screen(a), screen(b)];
      const len = Math.hypot(pa[0] - pb[0], pa[1] - pb[1]);
      if (!best || len > best.len) best = { len, x: (pa[0] + pb[0]) / 2, y: (pa[1] + pb[1]) / 2 };
    }
    return best;
  });
  const updatesBeforeCrease = await statsUpdates();
  await page.mouse.click(edge.x, edge.y);
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n, updatesBeforeCrease);
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) === 384);
  const picked = await page.textContent('#sub-picked');
  const creased = await meshSignature();
  check(picked.startsWith('1 edge'), `clicking a cage edge picks it (${picked})`);
  check(creased !== smooth, `a sharp edge changes the subdivided surface (${await shot('04-crease')})`);

  // 3a. the creased cube's limit surface as patches, handed to the Patches view: 6 x 4^L patches at the isolation
  // level the server chose, tessellated and drawn with their net
  await page.click('#sub-patches');
  await page.waitForFunction(() => document.body.dataset.view === 'patches' &&
                             /isolation level/.test(document.getElementById('stats').textContent));
  const limitStats = await page.$eval('#stats', (el) => el.textContent);
  const level = Number(/isolation level (\d+)/.exec(limitStats)?.[1]);
  const limitPatches = Number(/patches: (\d+)\n/.exec(limitStats)?.[1]);
  const limitPixels = await canvasPixels();
  check(level >= 1 && limitPatches === 6 * 4 ** level && limitPixels.n > 0.03 * limitPixels.total,
        `limit patches of the creased cube in the Patches view: level ${level}, ${limitPatches} patches, ` +
        `${limitPixels.n} pixels (${await shot('04a-limit-patches')})`);
  const netPoints = await page.evaluate(() => window.surfaced.views.patches.positions.count);
  // shared boundary control points are bit-identical, so the net has one point per distinct control point:
  // (3 * 2^L)^2 per face's 4x4 grids joined along edges, 6 faces sharing edges and corners -> 6 * (3 * 2^L - 1)^2 + 12 * (3 * 2^L - 1) + 8
  const m = 3 * 2 ** level - 1;
  check(netPoints === 6 * m * m + 12 * m + 8, `limit patches share their edges' control points: ${netPoints} net points`);
  await page.click('#tabs button[data-view=subdivide]');
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) === 384);

  // 3a'. the same creased cube to a tolerance: the server's bound on the distance to the limit surface is shown and
  // within the tolerance asked for
  await page.fill('#sub-tolerance', '0.01');
  await page.check('#sub-by-tolerance');
  await page.waitForFunction(() => /max distance to the limit surface: /.test(document.getElementById('stats').textContent));
  const tolStats = await page.$eval('#stats', (el) => el.textContent);
  const achieved = Number(/max distance to the limit surface: ([0-9.e+-]+)/.exec(tolStats)?.[1]);
  const tolFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));
  check(achieved > 0 && achieved <= 0.01 && tolFaces > 0,
        `creased cube to tolerance 0.01: ${tolFaces} triangles within ${achieved} of the limit surface (${await shot('04c-tolerance')})`);
  // straddle 0 (every vertex on the surface): more triangles than the default 0.45, still within the tolerance
  await page.fill('#sub-straddle', '0');
  await page.dispatchEvent('#sub-straddle', 'change');
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.outputFaces) !== n, tolFaces);
  const surfaceStats = await page.$eval('#stats', (el) => el.textContent);
  const surfaceAchieved = Number(/max distance to the limit surface: ([0-9.e+-]+)/.exec(surfaceStats)?.[1]);
  const surfaceFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));
  check(surfaceFaces > tolFaces && surfaceAchieved > 0 && surfaceAchieved <= 0.01,
        `straddle 0: ${surfaceFaces} triangles (straddled: ${tolFaces}) within ${surfaceAchieved}`);
  // two threads: the same triangles (the planning of half of the faces on a second thread)
  const request = await page.$eval('#stats', (el) => el.dataset.request);
  await page.selectOption('#sub-threads', '2');
  await page.waitForFunction((r) => document.getElementById('stats').dataset.request !== r, request);
  const threadFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));
  check(threadFaces === surfaceFaces, `threads 2: ${threadFaces} triangles (one thread: ${surfaceFaces})`);
  await page.selectOption('#sub-threads', '1');
  await page.fill('#sub-straddle', '0.45');
  await page.dispatchEvent('#sub-straddle', 'change');
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.outputFaces) === n, tolFaces);
  await page.uncheck('#sub-by-tolerance');
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) === 384);

  // 3a''. a click on the surface shows the limit point there: the base face and (u, v) whose exact limit point
  // (POST /limit/evaluate) is nearest the clicked point of the drawn level-3 mesh, with its unit normal, outward
  await page.check('#sub-probe');
  const box = await page.$eval('#viewport canvas', (c) => { const r = c.getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; });
  await page.mouse.click(box[0] + box[2] / 2, box[1] + box[3] / 2);
  await page.waitForFunction(() => document.getElementById('sub-probe-readout').dataset.face !== undefined);
  const probe = await page.$eval('#sub-probe-readout', (el) => ({ face: Number(el.dataset.face), distance: Number(el.dataset.distance),
                                                                   position: JSON.parse(el.dataset.position), normal: JSON.parse(el.dataset.normal) }));
  const normalLength = Math.hypot(...probe.normal);
  const outward = probe.normal.reduce((acc, x, k) => acc + x * probe.position[k], 0);
  check(probe.face >= 0 && probe.face < 6 && probe.distance < 0.05 && Math.abs(normalLength - 1) < 1e-9 && outward > 0,
        `clicking the surface shows its limit point: face ${probe.face}, ${probe.distance.toExponential(2)} from the drawn ` +
        `level-3 surface, unit outward normal (${await shot('04d-limit-point')})`);
  await page.uncheck('#sub-probe');

  // 3b. a valid upload: a tetrahedron OBJ, read by the server, Catmull-Clark level 3: 4 x 3 x 4^2 = 192 quads
  await page.setInputFiles('#sub-file', { name: 'tetra.obj', mimeType: 'model/obj',
                                          buffer: Buffer.from('v 1 1 1\nv -1 -1 1\nv -1 1 -1\nv 1 -1 -1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n') });
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) === 192);
  const tetraCage = await page.evaluate(() => window.surfaced.views.subdivide.edges.length);
  check(tetraCage === 6, `uploaded OBJ subdivided: 192 faces, cage of 6 edges (${await shot('04b-upload')})`);

  // 4. an invalid upload shows the service's error, naming the line
  expectRejection = true;
  await page.setInputFiles('#sub-file', { name: 'bad.obj', mimeType: 'model/obj',
                                          buffer: Buffer.from('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n') });
  await page.waitForSelector('#error:not([hidden])');
  const errorText = await page.textContent('#error');
  await shot('05-invalid-upload');
  expectRejection = false;
  check(/bad\.obj/.test(errorText) && /\b(400|422)\b/.test(errorText) && /line 4/.test(errorText),
        `invalid upload shows the problem: ${JSON.stringify(errorText.replace(/\s+/g, ' ').slice(0, 160))}`);

  // 5. simplify: the slider gives a live result with its measured error
  await page.click('#tabs button[data-view=simplify]');
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) > 0);
  await page.fill('#simp-ratio', '5');
  await page.dispatchEvent('#simp-ratio', 'input');
  await page.dispatchEvent('#simp-ratio', 'change');
  await page.waitForFunction(() => !window.surfaced.views.simplify.busy && /Hausdorff/.test(document.getElementById('stats').textContent)
                                   && Number(document.getElementById('stats').dataset.outputFaces) <= 0.05 * 5120 + 2);
  const simplified = await page.$eval('#stats', (el) => el.textContent);
  check(/Hausdorff \(measured\): [0-9.e+-]+/.test(simplified), `simplified to 5 % with the measured error shown (${await shot('06-simplified')})`);
  console.log(simplified.split('\n').map((l) => `     ${l}`).join('\n'));

  // 5b. "Keep volume", toggled from the keyboard: the next POST /simplify carries restore_volume 0.5 and its result
  // (different vertex positions, the measured error) is shown; turned off again, none is sent and the plain result is back
  const simplifyRequests = [];
  const onSimplify = (req) => {
    if (req.method() !== 'POST' || new URL(req.url()).pathname !== '/simplify') return;
    const body = req.postData();
    const query = new URL(req.url()).searchParams.get('restore_volume');
    simplifyRequests.push(query !== null ? Number(query) : body?.startsWith('{') ? JSON.parse(body).restore_volume : undefined);
  };
  page.on('request', onSimplify);
  const toggleVolume = async () => {
    const n = await statsUpdates();
    simplifyRequests.length = 0;
    await page.getByLabel('Keep volume (restore_volume 0.5)').focus();
    await page.keyboard.press('Space');
    await page.waitForFunction((m) => Number(document.getElementById('stats').dataset.updates) > m &&
                                      !window.surfaced.views.simplify.busy, n);
    return { sent: [...simplifyRequests], stats: await page.$eval('#stats', (el) => el.textContent),
             faces: await page.$eval('#stats', (el) => Number(el.dataset.outputFaces)), mesh: await meshSignature() };
  };
  const plainMesh = await meshSignature();
  const kept = await toggleVolume();
  check(kept.sent.length > 0 && kept.sent.every((v) => v === 0.5) && await page.isChecked('#simp-volume'),
        `Keep volume on: POST /simplify sent restore_volume 0.5 (${JSON.stringify(kept.sent)})`);
  check(kept.faces > 0 && kept.faces <= 0.05 * 5120 + 2 && /RMS \(measured\): [0-9.e+-]+/.test(kept.stats) &&
        kept.mesh !== null && kept.mesh !== plainMesh && !(await page.isVisible('#error')),
        `Keep volume on: a different result shown, ${kept.faces} faces with its measured error (${await shot('06a-keep-volume')})`);
  const plain = await toggleVolume();
  check(plain.sent.length > 0 && plain.sent.every((v) => v === undefined) && !(await page.isChecked('#simp-volume')),
        `Keep volume off: POST /simplify sent no restore_volume (${plain.sent.length} request(s))`);
  check(plain.mesh === plainMesh && /RMS \(measured\)/.test(plain.stats), 'Keep volume off: the plain result is shown again');
  page.off('request', onSimplify);

  // 6. downloads: OBJ of the current result (asked of the service again), GLB as received
  const [objDownload] = await Promise.all([page.waitForEvent('download'), page.click('#download-obj')]);
  const objPath = path.join(artifacts, objDownload.suggestedFilename());
  await objDownload.saveAs(objPath);
  const objText = (await import('node:fs')).readFileSync(objPath, 'utf8');
  const objFaces = objText.split('\n').filter((l) => l.startsWith('f ')).length;
  const shownFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));
  check(objFaces === shownFaces, `Download OBJ: ${objPath} has the ${shownFaces} faces shown`);
  const [glbDownload] = await Promise.all([page.waitForEvent('download'), page.click('#download-glb')]);
  const glbPath = path.join(artifacts, glbDownload.suggestedFilename());
  await glbDownload.saveAs(glbPath);
  check((await import('node:fs')).readFileSync(glbPath).subarray(0, 4).toString() === 'glTF', `Download GLB: ${glbPath}`);

  // 6a. a broken upload is repaired before simplifying, and the view says what was fixed: an octahedron as a soup (every
  // triangle with its own corners, welded: 24 - 6 = 18) with one face repeated back to back (a duplicate)
  const octa = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]];
  const octaFaces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
  const soupLines = [];
  octaFaces.forEach((f, i) => {
    for (const v of f) soupLines.push(`v ${octa[v].join(' ')}`);
    soupLines.push(`f ${3 * i + 1} ${3 * i + 2} ${3 * i + 3}`);
  });
  soupLines.push('f 3 2 1');  // the first face again, reversed
  const updatesBeforeSoup = await statsUpdates();
  await page.setInputFiles('#simp-file', { name: 'soup.obj', mimeType: 'model/obj', buffer: Buffer.from(soupLines.join('\n') + '\n') });
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n &&
                                    !window.surfaced.views.simplify.busy, updatesBeforeSoup, { timeout: 60000 });
  const soupStats = await page.$eval('#stats', (el) => el.textContent);
  check(!(await page.isVisible('#error')) && /repaired: .*welded 18/.test(soupStats) && /duplicate 1/.test(soupStats),
        `broken upload repaired and reported: ${JSON.stringify(soupStats.split('\n').find((l) => /repair/.test(l)))} (${await shot('06r-repaired-upload')})`);

  // 6b. remeshing, when this server has it: the bumpy sphere remeshed, the quality report shown
  if (await page.isVisible('#tabs button[data-view=remesh]')) {
    await page.click('#tabs button[data-view=remesh]');
    await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) > 0 ||
                                     !document.getElementById('error').hidden, null, { timeout: 60000 });
    const errorShown = await page.isVisible('#error');
    const remeshStats = await page.$eval('#stats', (el) => el.textContent);
    const remeshed = await canvasPixels();
    check(!errorShown && /min angle after: [0-9.]+/.test(remeshStats) && remeshed.n > 0.02 * remeshed.total,
          `remeshed and drawn: ${remeshStats.replace(/\n/g, ', ')} (${await shot('06b-remesh')})`);
  } else {
    console.log('     (this server does not document POST /remesh: no remesh view to test)');
  }

  // 7. implicit surfaces, when this server has them: the example scene from /openapi.json meshed and drawn
  if (await page.isVisible('#tabs button[data-view=implicit]')) {
    await page.click('#tabs button[data-view=implicit]');
    await page.waitForFunction(() => Number(document.getElementById('stats').dataset.outputFaces) > 0 ||
                                     !document.getElementById('error').hidden, null, { timeout: 60000 });
    const errorShown = await page.isVisible('#error');
    const implicit = await canvasPixels();
    check(!errorShown && implicit.n > 0.02 * implicit.total,
          `implicit scene meshed and drawn: ${implicit.n} pixels (${await shot('07-implicit')})`);
    // an edit with a mistake: the error names the field path inside the scene
    const updatesBeforeEdit = await statsUpdates();
    expectRejection = true;
    await page.fill('#imp-scene', JSON.stringify({ scene: { op: 'sphere', radius: -1 }, bounds: [[-2, -2, -2], [2, 2, 2]] }));
    await page.click('#imp-run');
    await page.waitForSelector('#error:not([hidden])');
    const sceneError = await page.textContent('#error');
    expectRejection = false;
    check(/scene\.radius/.test(sceneError), `a bad scene shows the field: ${JSON.stringify(sceneError.replace(/\s+/g, ' ').slice(0, 140))}`);
    // and a valid edit re-meshes
    await page.fill('#imp-scene', JSON.stringify({ scene: { op: 'sphere', radius: 1 }, bounds: [[-2, -2, -2], [2, 2, 2]], resolution: 24 }));
    await page.click('#imp-run');
    await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n, updatesBeforeEdit, { timeout: 60000 });
    check(!(await page.isVisible('#error')), `edited scene re-meshed (${await shot('07b-implicit-edited')})`);
    const sphereFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));

    // 7c. the probe over the unit sphere (an exact distance): f is |p| - 1 at the queried point, the class agrees with
    // its sign, the marker is at the point and the closest point lies on the sphere
    const canvasBox = await page.$eval('#viewport canvas', (c) => {
      const r = c.getBoundingClientRect();
      return { x: r.left, y: r.top, w: r.width, h: r.height };
    });
    const probeAt = async (fx, fy) => {
      const n = await page.$eval('#imp-probe-readout', (el) => Number(el.dataset.queries ?? 0));
      await page.mouse.move(canvasBox.x + fx * canvasBox.w, canvasBox.y + fy * canvasBox.h, { steps: 4 });
      await page.waitForFunction((m) => {
        const v = window.surfaced.views.implicit;
        return Number(document.getElementById('imp-probe-readout').dataset.queries ?? 0) > m && !v.probeBusy && !v.probePending;
      }, n);
      return page.evaluate(() => {
        const el = document.getElementById('imp-probe-readout');
        const v = window.surfaced.views.implicit;
        return { text: el.textContent, cls: el.dataset.class, value: Number(el.dataset.value), point: JSON.parse(el.dataset.point),
                 closest: el.dataset.closest ? JSON.parse(el.dataset.closest) : null,
                 marker: v.probeGroup.visible && v.probeGroup.parent !== null && v.probeMarker.visible,
                 markerAt: v.probeMarker.position.toArray(), lineShown: v.probeLine.visible };
      });
    };
    const norm = (p) => Math.hypot(...p);
    if (await page.isVisible('#imp-probe')) {
      await page.click('#imp-probe');
      const onSphere = await probeAt(0.5, 0.5);       // the ray meets the drawn sphere: the point is just inside
      const offSphere = await probeAt(0.08, 0.1);     // the ray misses it: the point is on the plane, outside
      await shot('07c-probe');
      for (const [name, r, cls] of [['over the sphere', onSphere, 'inside'], ['beside the sphere', offSphere, 'outside']]) {
        const expected = norm(r.point) - 1;
        check(r.cls === cls && r.value * (cls === 'inside' ? -1 : 1) > 0 && Math.abs(r.value - expected) < 1e-9 &&
              new RegExp(`^${cls} f = -?[0-9]`).test(r.text),
              `probe ${name}: ${JSON.stringify(r.text.split('\n')[0])}, f = |p| - 1 = ${expected.toFixed(6)}`);
        check(r.marker && r.lineShown && r.closest !== null && Math.abs(norm(r.closest) - 1) < 1e-9 &&
              r.markerAt.every((x, k) => Math.abs(x - r.point[k]) < 1e-6),
              `probe ${name}: marker at the point, closest point on the sphere (|c| = ${r.closest && norm(r.closest).toFixed(9)})`);
      }
    } else {
      console.log('     (this server does not document POST /implicit/query: no probe to test)');
    }

    // 7d. a mesh added to the scene: a cube OBJ uploaded (repaired by POST /repair), subtracted from the sphere, the
    // bounds grown to hold it, the editor showing a label instead of coordinates; then removed again
    const served = await (await fetch(`${server.url}/openapi.json`)).json();
    if (!(served.components?.schemas?.ImplicitScene?.properties?.op?.enum ?? []).includes('mesh')) {
      console.log('     SKIPPED: the mesh scene node (this server\'s ImplicitScene schema has no "mesh" op): ' +
                  '"Add mesh…" was NOT tested');
    } else {
      const [c0, c1] = [0.3, 2.5];   // the cube [0.3, 2.5]^3: a corner bite out of the sphere, beyond the bounds (2)
      const cubeObj = [];
      for (let i = 0; i < 8; ++i) cubeObj.push(`v ${i & 1 ? c1 : c0} ${i & 2 ? c1 : c0} ${i & 4 ? c1 : c0}`);
      for (const f of [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]]) cubeObj.push(`f ${f.join(' ')}`);
      const meshRequests = [];
      const onMesh = (req) => {
        if (req.method() === 'POST' && new URL(req.url()).pathname === '/implicit/mesh') meshRequests.push(req.postData());
      };
      page.on('request', onMesh);
      await page.selectOption('#imp-combine', 'difference');
      const n = await statsUpdates();
      await page.setInputFiles('#imp-mesh-file', { name: 'cube.obj', mimeType: 'model/obj', buffer: Buffer.from(cubeObj.join('\n') + '\n') });
      await page.waitForFunction((m) => Number(document.getElementById('stats').dataset.updates) > m ||
                                        !document.getElementById('error').hidden, n, { timeout: 60000 });
      const errorShown = await page.isVisible('#error');
      const editor = await page.inputValue('#imp-scene');
      const edited = JSON.parse(editor);
      const bitten = await canvasPixels();
      const bittenFaces = await page.$eval('#stats', (el) => Number(el.dataset.outputFaces));
      check(!errorShown && bitten.n > 0.02 * bitten.total && bittenFaces > 0 && bittenFaces !== sphereFaces,
            `sphere minus an uploaded cube meshed and drawn: ${bittenFaces} triangles, ${bitten.n} pixels` +
            `${errorShown ? ', error: ' + (await page.textContent('#error')).replace(/\s+/g, ' ') : ''} (${await shot('07d-mesh-difference')})`);
      check(edited.scene.op === 'difference' && edited.scene.args[0].op === 'sphere' &&
            edited.scene.args[1].mesh?.ref_upload === 'cube.obj (12 triangles)' && editor.length < 2000 &&
            edited.bounds[1].every((v) => v >= c1 + 0.2) && edited.bounds[0].every((v) => v <= -2) && edited.mode === 'adaptive',
            `the editor shows the mesh as a label, bounds grown to ${JSON.stringify(edited.bounds)}, mode ${edited.mode}`);
      const sent = meshRequests.length ? JSON.parse(meshRequests.at(-1)) : null;
      check(sent?.scene?.args?.[1]?.mesh?.positions?.length === 8 && sent.scene.args[1].mesh.faces.length >= 6 &&
            !JSON.stringify(sent).includes('ref_upload'),
            'POST /implicit/mesh was sent the repaired cube\'s positions and faces in place of the label');
      // no vertex inside the cube by more than a cell, and vertices on the bite's flat faces inside the sphere
      const cell = Math.max(...edited.bounds[1].map((v, k) => v - edited.bounds[0][k])) / edited.resolution;
      const bite = await page.evaluate(({ c0, cell }) => {
        const p = window.surfaced.viewer.result.geometry.attributes.position;
        let inside = 0, onFaces = 0;
        for (let i = 0; i < p.count; ++i) {
          const m = Math.min(p.getX(i), p.getY(i), p.getZ(i));
          if (m > c0 + cell) ++inside;
          if (Math.abs(m - c0) < 1e-3 && Math.hypot(p.getX(i), p.getY(i), p.getZ(i)) < 1 - cell) ++onFaces;
        }
        return { inside, onFaces };
      }, { c0, cell });
      check(bite.inside === 0 && bite.onFaces >= 3,
            `the bite: no vertex inside the cube, ${bite.onFaces} vertices on its faces within 1e-3 (cell ${cell.toFixed(3)})`);
      if (await page.isVisible('#imp-probe')) {
        const overBite = await probeAt(0.5, 0.5);
        check(/^(inside|outside) f = -?[0-9]/.test(overBite.text) && overBite.marker &&
              (overBite.cls === 'inside') === (overBite.value < 0),
              `probe over the mesh scene: ${JSON.stringify(overBite.text.split('\n').slice(0, 3).join('; '))} (${await shot('07e-mesh-probe')})`);
      }
      // the mesh alone is an exact distance: the probe's f and closest point are the cube's, analytically
      if (await page.isVisible('#imp-probe')) {
        const combined = await page.inputValue('#imp-scene');
        const k0 = await statsUpdates();
        await page.fill('#imp-scene', JSON.stringify({ ...edited, scene: edited.scene.args[1] }));
        await page.click('#imp-run');
        await page.waitForFunction((k) => Number(document.getElementById('stats').dataset.updates) > k, k0, { timeout: 60000 });
        const classes = new Set();
        for (const [fx, fy] of [[0.5, 0.5], [0.9, 0.15], [0.02, 0.95]]) {   // the last one misses the cube
          const r = await probeAt(fx, fy);
          const p = r.point;
          const inside = p.every((v) => v > c0 && v < c1);
          classes.add(r.cls);
          let f, q;
          if (inside) {   // the nearest face
            let best = null;
            for (let k = 0; k < 3; ++k)
              for (const face of [c0, c1]) if (!best || Math.abs(p[k] - face) < best.d) best = { d: Math.abs(p[k] - face), k, face };
            f = -best.d;
            q = p.map((v, k) => (k === best.k ? best.face : v));
          } else {
            q = p.map((v) => Math.min(Math.max(v, c0), c1));
            f = Math.hypot(...p.map((v, k) => v - q[k]));
          }
          check(r.cls === (inside ? 'inside' : 'outside') && Math.abs(r.value - f) < 1e-9 && r.closest !== null &&
                r.closest.every((v, k) => Math.abs(v - q[k]) < 1e-9) && /exact_distance/.test(r.text),
                `probe on the cube mesh alone at ${JSON.stringify(p.map((v) => Number(v.toFixed(3))))}: ${r.cls}, ` +
                `f = ${r.value.toFixed(6)} (analytic ${f.toFixed(6)}), closest point on the cube's ${inside ? 'nearest face' : 'surface'}`);
        }
        check(classes.has('inside') && classes.has('outside'), `the cube was probed inside and outside (${await shot('07e-mesh-alone-probe')})`);
        const k1 = await statsUpdates();
        await page.fill('#imp-scene', combined);
        await page.click('#imp-run');
        await page.waitForFunction((k) => Number(document.getElementById('stats').dataset.updates) > k, k1, { timeout: 60000 });
      }
      const m = await statsUpdates();
      await page.click('#imp-meshes button');
      await page.waitForFunction((k) => Number(document.getElementById('stats').dataset.updates) > k, m, { timeout: 60000 });
      const restored = JSON.parse(await page.inputValue('#imp-scene'));
      check(restored.scene.op === 'sphere' && JSON.stringify(restored.bounds) === JSON.stringify([[-2, -2, -2], [2, 2, 2]]) &&
            !(await page.isVisible('#error')) &&
            (await page.$$('#imp-meshes li')).length === 0, `"remove" takes the mesh out of the scene and the bounds back (${await shot('07f-mesh-removed')})`);
      page.off('request', onMesh);
    }
  } else {
    console.log('     (this server does not document POST /implicit/mesh: no implicit view to test)');
  }

  // 8. curves: the 2D editor on POST /curves (its checks are in curves_checks.mjs)
  if (await page.isVisible('#tabs button[data-view=curves]'))
    await checkCurvesView(page, { check, shot, expectRejection: (on) => { expectRejection = on; } });
  else
    console.log('     (this server does not document POST /curves: no curves view to test)');

  // 9. point clouds: sampled and uploaded clouds with their normals, reconstructed (pointcloud_checks.mjs)
  if (await page.isVisible('#tabs button[data-view=pointcloud]'))
    await checkPointCloudView(page, { check, shot, canvasPixels });
  else
    console.log('     (this server does not document POST /pointcloud: no point cloud view to test)');

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} catch (e) {
  console.error(e);
  failures++;
} finally {
  await browser.close();
  await server.stop();
}
console.log(`screenshots: ${path.resolve(artifacts)}`);
console.log(failures ? `${failures} check(s) FAILED` : 'all browser checks passed');
process.exit(failures ? 1 : 0);
