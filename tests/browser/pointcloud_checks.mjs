// The Point cloud view's part of the browser test (web_client_test.mjs runs it): the demo cloud is sampled and drawn;
// an uploaded PLY without normals gets estimated, outward normals from POST /pointcloud; when the server has
// POST /reconstruct, the cloud is reconstructed, closed and trimmed, both drawn side by side with their reports.
// The uploaded cloud is made here: points on the unit sphere below z = 0.5 (open, as a scan is; the hole faces the
// camera), so the closed reconstruction caps the hole and trimming removes the cap.

const RADIUS = 1, CUT = 0.5, COUNT = 1500;

/** COUNT points of a Fibonacci spiral on the sphere's part below z = CUT, as an ASCII PLY without normals. */
function capPly() {
  const lines = ['ply', 'format ascii 1.0', 'comment points on the unit sphere below z = 0.5 (browser test)',
                 `element vertex ${COUNT}`, 'property float x', 'property float y', 'property float z', 'end_header'];
  const golden = Math.PI * (3 - Math.sqrt(5));
  for (let i = 0; i < COUNT; ++i) {
    const z = -1 + (i + 0.5) / COUNT * (CUT + 1);   // uniform in z over [-1, CUT]: uniform in area
    const r = Math.sqrt(1 - z * z);
    lines.push([r * Math.cos(golden * i), r * Math.sin(golden * i), z].map((v) => (RADIUS * v).toFixed(6)).join(' '));
  }
  return lines.join('\n') + '\n';
}

/**
 * `check(condition, message)` records a result, `shot(name)` saves a screenshot and returns its path,
 * `canvasPixels(region)` counts the canvas's non-background pixels (region: 'left' or 'right' half, or all).
 */
export async function checkPointCloudView(page, { check, shot, canvasPixels }) {
  const stats = () => page.$eval('#stats', (el) => ({ text: el.textContent, ...el.dataset }));
  const updates = () => page.$eval('#stats', (el) => Number(el.dataset.updates ?? 0));

  // 1. the tab opens with the demo cloud sampled on the server (mesh sampling gives normals)
  await page.click('#tabs button[data-view=pointcloud]');
  await page.waitForFunction(() => Number(document.getElementById('stats').dataset.points) > 0 ||
                                   !document.getElementById('error').hidden, null, { timeout: 60000 });
  const demo = await stats();
  const demoCount = await page.inputValue('#pc-count');
  const demoPixels = await canvasPixels();
  check(!(await page.isVisible('#error')) && demo.points === demoCount && demo.normals === 'given' &&
        demoPixels.n > 0.005 * demoPixels.total,
        `demo cloud sampled and drawn: ${demo.points} points, normals ${demo.normals}, ${demoPixels.n} pixels (${await shot('09-pointcloud-demo')})`);

  // 1b. a GLB of points (Draco-compressed POINTS, as POST /pointcloud writes them) is sent as it is: the service reads it
  const glb = await page.evaluate(async () => {
    const tetra = { positions: [[1, 1, 1], [-1, -1, 1], [-1, 1, -1], [1, -1, -1]], faces: [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]] };
    const r = await fetch('/pointcloud', { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                           body: JSON.stringify({ sample: { mesh: tetra, count: 300, seed: 3 } }) });
    return [...new Uint8Array(await r.arrayBuffer())];
  });
  const beforeGlb = await updates();
  await page.setInputFiles('#pc-file', { name: 'tetra.glb', mimeType: 'model/gltf-binary', buffer: Buffer.from(glb) });
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n ||
                                    !document.getElementById('error').hidden, beforeGlb, { timeout: 60000 });
  const fromGlb = await stats();
  check(!(await page.isVisible('#error')) && fromGlb.points === '300' && fromGlb.normals === 'given',
        `uploaded GLB of 300 Draco points read by the service: ${fromGlb.points} points, normals ${fromGlb.normals}`);

  // 2. an uploaded PLY without normals: the server estimates and orients them; on the sphere they point outward
  const before = await updates();
  await page.setInputFiles('#pc-file', { name: 'cap.ply', mimeType: 'application/ply', buffer: Buffer.from(capPly()) });
  await page.waitForFunction((n) => Number(document.getElementById('stats').dataset.updates) > n ||
                                    !document.getElementById('error').hidden, before, { timeout: 60000 });
  const cap = await stats();
  const orientation = await page.evaluate(() => {
    const v = window.surfaced.views.pointcloud;
    const { positions: p, normals: n, count } = v.cloud;
    let outward = 0, worst = 1;
    for (let i = 0; i < count; ++i) {
      const len = Math.hypot(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
      const cos = (p[3 * i] * n[3 * i] + p[3 * i + 1] * n[3 * i + 1] + p[3 * i + 2] * n[3 * i + 2]) / len;
      if (cos > 0) ++outward;
      worst = Math.min(worst, cos);
    }
    return { outward, worstDegrees: Math.acos(worst) * 180 / Math.PI,
             lines: v.normals ? v.normals.geometry.attributes.position.count / 2 : 0 };
  });
  check(!(await page.isVisible('#error')) && Number(cap.points) === COUNT && cap.normals === 'estimated' &&
        /normals: estimated and oriented \(k = 16\)/.test(cap.text),
        `uploaded PLY without normals: ${cap.points} points, normals ${cap.normals}`);
  check(orientation.outward === COUNT && orientation.worstDegrees < 10 && orientation.lines === COUNT,
        `estimated normals all point outward (${orientation.outward} of ${COUNT}, worst ${orientation.worstDegrees.toFixed(2)}° ` +
        `from the sphere's normal), ${orientation.lines} normal lines drawn (${await shot('09b-pointcloud-upload')})`);

  // 3. reconstruction, closed and trimmed, side by side
  if (!(await page.isEnabled('#pc-run'))) {
    console.log('     SKIPPED: this server does not document POST /reconstruct: reconstruction was NOT tested');
    return;
  }
  await page.fill('#pc-depth', '6');
  const n = await updates();
  await page.click('#pc-run');
  await page.waitForFunction((m) => (Number(document.getElementById('stats').dataset.updates) > m &&
                                     document.getElementById('stats').dataset.triangles !== undefined) ||
                                    !document.getElementById('error').hidden, n, { timeout: 60000 });
  const recon = await stats();
  const errorText = (await page.isVisible('#error')) ? await page.textContent('#error') : '';
  const full = Number(recon.triangles), trimmed = Number(recon.trimmedTriangles);
  const trimming = await page.isEnabled('#pc-trim');
  check(!errorText && full > 0 && /triangles: \d+/.test(recon.text) && /iso value: /.test(recon.text) &&
        (!trimming || (trimmed > 0 && trimmed < full)),
        `reconstructed: ${full} triangles${trimming ? `, trimmed: ${trimmed}` : ''}` +
        `${errorText ? `, error: ${errorText.replace(/\s+/g, ' ')}` : ''}`);
  console.log(`     report: ${recon.text.split('\n').filter((l) => l.startsWith('  ')).map((l) => l.trim()).join('; ')}`);
  // the closed mesh follows the sphere where it was sampled and caps the hole above z = 0.5; the trimmed one keeps
  // the sampled part only
  const measure = (which) => page.evaluate(({ which, cut }) => {
    const p = window.surfaced.viewer[which].geometry.attributes.position;
    let highest = -Infinity, offSphere = 0;
    for (let i = 0; i < p.count; ++i) {
      highest = Math.max(highest, p.getZ(i));
      if (p.getZ(i) < cut - 0.25) offSphere = Math.max(offSphere, Math.abs(Math.hypot(p.getX(i), p.getY(i), p.getZ(i)) - 1));
    }
    return { highest, offSphere };
  }, { which, cut: CUT });
  const closed = await measure('result');
  const cell = 2.2 / 64;   // depth 6 over the bounding cube (1.1 times the cloud's extent)
  check(closed.highest > CUT + 2 * cell && closed.offSphere < cell,
        `the closed mesh reaches z = ${closed.highest.toFixed(3)} above the cut at ${CUT}, and below z = ${CUT - 0.25} ` +
        `lies within ${closed.offSphere.toFixed(4)} of the sphere (cell ${cell.toFixed(4)})`);
  // the iso-surface as meshed, without the fit of its vertices to the points: farther from the sphere
  if (await page.isEnabled('#pc-fit')) {
    await page.uncheck('#pc-fit');
    const m = await updates();
    await page.click('#pc-run');
    await page.waitForFunction((k) => Number(document.getElementById('stats').dataset.updates) > k ||
                                      !document.getElementById('error').hidden, m, { timeout: 60000 });
    const meshed = await measure('result');
    check(!(await page.isVisible('#error')) && meshed.offSphere > closed.offSphere,
          `without the fit to the points the mesh lies within ${meshed.offSphere.toFixed(4)} of the sphere, with it ` +
          `${closed.offSphere.toFixed(4)}`);
    await page.check('#pc-fit');
    const k = await updates();
    await page.click('#pc-run');
    await page.waitForFunction((j) => Number(document.getElementById('stats').dataset.updates) > j ||
                                      !document.getElementById('error').hidden, k, { timeout: 60000 });
  }
  if (!trimming) {
    const pixels = await canvasPixels();
    check(pixels.n > 0.03 * pixels.total, `the closed mesh drawn: ${pixels.n} pixels (${await shot('09c-reconstructed')})`);
    console.log('     SKIPPED: this server\'s POST /reconstruct has no trim option: trimming was NOT tested');
    return;
  }
  // the trim suggested (half a level below the density estimated in the page) against the server's measure
  const suggested = await page.evaluate(() => window.surfaced.views.pointcloud.cloud.density);
  const served = Number(/sample density: ([0-9.]+)/.exec(recon.text)?.[1]);
  check(Math.abs(suggested - served) < 0.25 && Number(await page.inputValue('#pc-trim')) === Math.round((suggested - 0.5) * 10) / 10,
        `trim ${await page.inputValue('#pc-trim')} suggested from the page's density estimate ${suggested.toFixed(3)}; ` +
        `the server's X-Sample-Density ${served}`);
  const cut = await measure('second');
  check(cut.highest < CUT + 2 * cell && cut.offSphere < cell,
        `the trimmed mesh stops at z = ${cut.highest.toFixed(3)}, within two cells of the cut at ${CUT}`);
  const left = await canvasPixels('left'), right = await canvasPixels('right');
  const labels = await page.$$eval('.view-labels span', (spans) => spans.map((s) => s.textContent));
  check(left.n > 0.02 * left.total && right.n > 0.02 * right.total && labels.length === 2 &&
        labels[0] === `reconstructed: ${full} triangles` && labels[1].endsWith(`: ${trimmed} triangles`),
        `both drawn side by side: ${left.n} and ${right.n} pixels, labelled ${JSON.stringify(labels)} (${await shot('09c-reconstructed')})`);
  // one of them alone, in the whole canvas
  await page.selectOption('#pc-layout', 'second');
  const alone = await canvasPixels();
  const aloneLabels = await page.$$eval('.view-labels span', (spans) => spans.map((s) => s.textContent));
  check(alone.n > 0.03 * alone.total && aloneLabels.length === 1 && aloneLabels[0].startsWith('trimmed'),
        `the trimmed mesh alone: ${alone.n} pixels (${await shot('09d-trimmed-alone')})`);
  await page.selectOption('#pc-layout', 'split');
}
