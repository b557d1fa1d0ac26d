// The Curves view's part of the browser test (web_client_test.mjs runs it): dragging a control point changes the
// server's tessellation, which lies on the dragged curve; de Casteljau / de Boor in the page agree with the server's
// evaluate at the slider's parameter within 1e-9; the basis weights sum to 1; joints made C1 and G1 are reported so;
// SVG path data is drawn as its pieces and a syntax error names its byte offset; B-spline knots are drawn as ticks.

const TOLERANCE = 1e-9;
const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

/**
 * `check(condition, message)` records a result, `shot(name)` saves a screenshot and returns its path,
 * `expectRejection(on)` tells the console listener that a 4xx answer is deliberate.
 */
export async function checkCurvesView(page, { check, shot, expectRejection }) {
  // the answer describes the current state: nothing in flight, nothing waiting to be sent
  const settled = () => page.waitForFunction(() => {
    const v = window.surfaced.views.curves;
    return !v.busy && !v.dirty && v.current() !== null;
  });
  const readout = () => page.$eval('#crv-readout', (el) => ({
    t: Number(el.dataset.t), local: el.dataset.local && JSON.parse(el.dataset.local),
    server: el.dataset.server && JSON.parse(el.dataset.server), text: el.textContent,
  }));
  const basis = () => page.$eval('#crv-basis-values', (el) => ({
    sum: Number(el.dataset.sum), values: [...el.children].map((li) => Number(li.dataset.value)),
  }));
  const setParameter = async (value) => {
    await page.fill('#crv-t', String(value));
    await page.dispatchEvent('#crv-t', 'input');
    await settled();
    return readout();
  };
  // the local point at the slider equals the server's evaluate there, and the basis weights sum to 1
  const checkParameter = async (value, what) => {
    const r = await setParameter(value);
    const b = await basis();
    check(r.t === value && r.local && r.server && distance(r.local, r.server) < TOLERANCE,
          `${what} at ${value}: local ${JSON.stringify(r.local)} = server evaluate ${JSON.stringify(r.server)} ` +
          `(|difference| ${r.local && r.server ? distance(r.local, r.server).toExponential(1) : '-'})`);
    check(b.values.length > 1 && Math.abs(b.sum - 1) < 1e-12 && b.values.every((v) => v >= 0),
          `${b.values.length} basis weights at ${value} sum to 1 (${b.sum})`);
  };

  // 1. one Bézier curve: drag a control point; the server's tessellation changes and lies on the dragged curve
  await page.click('#tabs button[data-view=curves]');
  await settled();
  const before = await page.evaluate(() => JSON.stringify(window.surfaced.views.curves.current().curves[0].tessellate));
  const handle = await page.$eval('#curves-stage circle[data-list="0"][data-index="1"]', (c) => {
    const r = c.getBoundingClientRect();
    return { x: r.left + r.width / 2, y: r.top + r.height / 2 };
  });
  const tripsBefore = await page.evaluate(() => window.surfaced.views.curves.roundTrips);
  await page.mouse.move(handle.x, handle.y);
  await page.mouse.down();
  for (let k = 1; k <= 8; ++k) {
    await page.mouse.move(handle.x + 10 * k, handle.y + 12 * k);
    await page.waitForTimeout(30);
  }
  await page.mouse.up();
  await settled();
  const dragged = await page.evaluate(async () => {
    const v = window.surfaced.views.curves;
    const { deCasteljau } = await import(new URL('js/curvemath.js', location.href).href);
    const a = v.current();
    const tess = a.curves[0].tessellate;
    // every tessellation vertex is the dragged curve's point at its parameter
    const off = Math.max(...tess.params.map((t, i) => Math.hypot(...deCasteljau(v.bezier.points, null, t).point.map((x, k) => x - tess.points[i][k]))));
    return { tess: JSON.stringify(tess), point: v.bezier.points[1], sameState: JSON.stringify(a.state.bezier.points) === JSON.stringify(v.bezier.points),
             off, trips: v.roundTrips };
  });
  check(dragged.tess !== before && dragged.sameState && dragged.off < TOLERANCE && dragged.trips > tripsBefore,
        `dragged control point 1 to ${JSON.stringify(dragged.point.map((x) => Number(x.toFixed(3))))}: the server's ` +
        `tessellation changed and its vertices lie on the dragged curve (max off ${dragged.off.toExponential(1)}), ` +
        `${dragged.trips - tripsBefore} round trips (${await shot('08-curves-bezier-dragged')})`);
  await checkParameter(0.37, 'de Casteljau on the Bézier curve');
  await checkParameter(0.8125, 'de Casteljau on the Bézier curve');
  // a fifth point: degree 4, five Bernstein weights, still the server's point
  await page.click('#crv-add-point');
  await page.waitForFunction(() => window.surfaced.views.curves.current()?.state.bezier.points.length === 5);
  await settled();
  check(/^degree 4 /.test(await page.textContent('#crv-degree')), `"Add point" makes it ${await page.textContent('#crv-degree')}`);
  await checkParameter(0.6, 'de Casteljau on the quartic');
  await page.click('#crv-remove-point');
  await page.waitForFunction(() => window.surfaced.views.curves.current()?.state.bezier.points.length === 4);
  await settled();
  // the construction, level by level: all intermediate polygons (3 and 2 points on a cubic), then only the first
  const levels = () => page.$$eval('#curves-stage polyline.construction', (ls) => ls.map((l) => l.getAttribute('points').split(' ').length));
  const allLevels = await levels();
  await page.fill('#crv-levels', '1');
  await page.dispatchEvent('#crv-levels', 'input');
  const firstLevel = await levels();
  await page.fill('#crv-levels', '2');
  await page.dispatchEvent('#crv-levels', 'input');
  check(JSON.stringify(allLevels) === '[3,2]' && JSON.stringify(firstLevel) === '[3]' && JSON.stringify(await levels()) === '[3,2]',
        `de Casteljau's intermediate polygons drawn level by level: ${JSON.stringify(allLevels)} points, 1 level: ${JSON.stringify(firstLevel)}`);
  const length = await page.$eval('#crv-readout', (el) => el.textContent);
  check(/length: [0-9.]+ \(± /.test(length), `the length is shown: ${JSON.stringify(length.split('\n').at(-1))}`);
  // a finer tolerance: more segments, the server's bound within it
  const tessellation = () => page.evaluate(() => window.surfaced.views.curves.current().curves[0].tessellate);
  const coarse = await tessellation();
  await page.fill('#crv-tolerance', '0.001');
  await page.dispatchEvent('#crv-tolerance', 'change');
  await page.waitForFunction(() => window.surfaced.views.curves.current()?.state.tolerance === 0.001);
  await settled();
  const fine = await tessellation();
  check(fine.segments > coarse.segments && fine.bound <= 0.001 && coarse.bound <= 0.01,
        `tolerance 0.01 -> 0.001: ${coarse.segments} -> ${fine.segments} segments, bound ${fine.bound.toExponential(2)}`);

  // 2. a chain: de Casteljau on the piece under s; the first joint is C0, made C1 by the server's enforce_c1
  await page.selectOption('#crv-mode', 'chain');
  await settled();
  await checkParameter(1.37, 'de Casteljau on piece 1 of the chain');
  const jointClass = () => page.$eval('#crv-joints li[data-chain="0"][data-joint="0"]', (li) => li.dataset.class);
  const classBefore = await jointClass();
  await page.check('#crv-joints li[data-chain="0"][data-joint="0"] input');
  await page.click('#crv-make-c1');
  await page.waitForFunction(() => document.querySelector('#crv-joints li[data-chain="0"][data-joint="0"]')?.dataset.class === 'C1');
  await settled();
  const classAfter = await jointClass();
  const labels = await page.$$eval('#curves-stage text.joint-label', (ts) => ts.map((t) => t.textContent));
  check(classBefore === 'C0' && classAfter === 'C1' && labels[0] === 'C1',
        `joint 0 made C1: class ${classBefore} -> ${classAfter} in the list and on the joint (${await shot('08b-curves-chain-c1')})`);
  await checkParameter(0.9, 'de Casteljau on the chain after enforce_c1');
  // joint 1 made G1 (both handles turned to the bisecting direction): each handle keeps its length
  const handles = () => page.evaluate(() => {
    const pieces = window.surfaced.views.curves.chains[0].pieces;
    const [b, c] = [pieces[1].points, pieces[2].points];
    return { left: Math.hypot(b[3][0] - b[2][0], b[3][1] - b[2][1]), right: Math.hypot(c[1][0] - c[0][0], c[1][1] - c[0][1]) };
  });
  const lengthsBefore = await handles();
  await page.check('#crv-joints li[data-chain="0"][data-joint="1"] input');
  await page.click('#crv-make-g1');
  await page.waitForFunction(() => document.querySelector('#crv-joints li[data-chain="0"][data-joint="1"]')?.dataset.class === 'G1');
  await settled();
  const lengthsAfter = await handles();
  check(Math.abs(lengthsAfter.left - lengthsBefore.left) < TOLERANCE && Math.abs(lengthsAfter.right - lengthsBefore.right) < TOLERANCE,
        `joint 1 made G1, the handles keep their lengths ${lengthsBefore.left.toFixed(6)} and ${lengthsBefore.right.toFixed(6)}`);

  // 3. SVG path data: two subpaths, 2 + 2 pieces, drawn as chains
  await page.fill('#crv-svg', 'M 0 0 C 10 20 30 20 40 0 S 70 -20 80 0 M 0 40 Q 20 60 40 40 T 80 40');
  await page.click('#crv-svg-load');
  await page.waitForFunction(() => window.surfaced.views.curves.chains.length === 2);
  await settled();
  const drawn = await page.evaluate(() => ({
    polygons: document.querySelectorAll('#curves-stage polyline.polygon').length,
    curves: document.querySelectorAll('#curves-stage polyline.curve').length,
    joints: [...document.querySelectorAll('#crv-joints li')].map((li) => li.dataset.class),
    pieces: window.surfaced.views.curves.chains.map((c) => c.pieces.map((p) => p.points.length)),
  }));
  check(drawn.polygons === 4 && drawn.curves === 2 && JSON.stringify(drawn.pieces) === '[[4,4],[3,3]]' &&
        JSON.stringify(drawn.joints) === '["C1","C1"]',
        `SVG path drawn as 2 chains: pieces ${JSON.stringify(drawn.pieces)}, ${drawn.polygons} control polygons, ` +
        `${drawn.curves} tessellated curves, joints ${drawn.joints.join(' ')} (${await shot('08c-curves-svg')})`);
  await checkParameter(1.5, 'de Casteljau on the SVG path\'s second piece');

  // 4. malformed path data: the server's 422 is shown next to the box with the byte offset of the bad token
  expectRejection(true);
  await page.fill('#crv-svg', 'M 0 0 C 10 x 30');
  await page.click('#crv-svg-load');
  await page.waitForSelector('#crv-svg-error:not([hidden])');
  const svgError = await page.$eval('#crv-svg-error', (el) => ({ text: el.textContent, offset: el.dataset.offset }));
  expectRejection(false);
  check(svgError.offset === '11' && /offset 11\b/.test(svgError.text),
        `bad SVG path data: ${JSON.stringify(svgError.text)} (${await shot('08d-curves-svg-error')})`);

  // 5. a B-spline: ticks at its distinct knots; de Boor agrees with the server, then as a NURBS with weights
  await page.selectOption('#crv-mode', 'bspline');
  await settled();
  const ticks = await page.$$eval('#curves-stage line.knot-tick', (ls) => ls.map((l) => Number(l.dataset.u)));
  const knots = await page.inputValue('#crv-knots');
  check(ticks.length === 4 && ticks[0] === 0 && ticks[3] === 1,
        `B-spline knots [${knots}] shown as ${ticks.length} ticks on the curve at ${ticks.map((u) => u.toFixed(3)).join(', ')}`);
  await checkParameter(0.41, 'de Boor on the B-spline');
  await page.fill('#crv-bs-weights', '1, 3, 0.5, 1, 2, 1');
  await page.dispatchEvent('#crv-bs-weights', 'change');
  await settled();
  await checkParameter(0.58, 'de Boor on the NURBS');
  // one more point: the knots become uniform clamped for 7 points, the new point weighs 1
  await page.click('#crv-bs-add');
  await page.waitForFunction(() => window.surfaced.views.curves.current()?.state.bspline.points.length === 7);
  await settled();
  const grown = await page.evaluate(() => ({
    knots: window.surfaced.views.curves.bspline.knots, weights: document.getElementById('crv-bs-weights').value,
    ticks: document.querySelectorAll('#curves-stage line.knot-tick').length, error: !document.getElementById('error').hidden,
  }));
  check(grown.knots.length === 11 && grown.ticks === 5 && grown.weights === '1, 3, 0.5, 1, 2, 1, 1' && !grown.error,
        `a point added to the NURBS: ${grown.knots.length} knots, ${grown.ticks} ticks, weights ${grown.weights}`);
  await checkParameter(0.58, 'de Boor on the NURBS of 7 points');
  await shot('08e-curves-nurbs');
}
