// Curves view: a 2D editor for POST /curves. One Bézier curve, chains of Bézier pieces (also from pasted SVG path
// data) or a B-spline/NURBS, drawn in an <svg> over the viewport. Control points are dragged in the page; the curve
// itself, its length, the joints' continuity and the point at the slider's parameter come from the server, and the
// page draws de Casteljau's (or de Boor's) construction and the basis weights at that parameter, computed locally,
// next to the server's answer.
import { call, ProblemError } from './api.js';
import { deCasteljau, bernstein, rationalWeights, clampedKnots, domain, deBoor, bsplineBasis } from './curvemath.js';

const $ = (id) => document.getElementById(id);
const SVG_NS = 'http://www.w3.org/2000/svg';
// the length's error bound relative to the control points' extent: a millionth keeps a drag's round trip at
// about a millisecond (the cost grows quickly below that)
const RELATIVE_LENGTH_TOLERANCE = 1e-6;

// Starting shapes, in SVG's convention (y grows downwards), so that pasted path data looks as it does in a browser.
const DEFAULT_BEZIER = [[0, 8], [2, 0], [6, 0], [8, 8]];
const DEFAULT_CHAIN = [
  { points: [[0, 5], [1, 1], [3, 1], [4, 5]] },
  { points: [[4, 5], [5, 8], [7, 9], [8, 4]] },
  { points: [[8, 4], [9, 1], [11, 2], [12, 5]] },
];
const DEFAULT_BSPLINE = [[0, 6], [2, 1], [4, 7], [6, 1], [8, 7], [10, 2]];
// a construction level's colour: the control polygon grey, then warmer towards the point
const LEVEL_COLOURS = ['#8a8f99', '#4fb3f5', '#5fd38d', '#e7c94a', '#f08a4b', '#e0559a', '#b57cf0'];

const clone = (x) => JSON.parse(JSON.stringify(x));
const fmt = (x, digits = 6) => (Number.isFinite(x) ? Number(x.toPrecision(digits)).toString() : String(x));
const fmtPoint = (p) => `(${p.map((x) => fmt(x, 12)).join(', ')})`;

/** An SVG element with attributes, appended to `parent`. */
function svgEl(parent, name, attrs = {}, text) {
  const el = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, String(v));
  if (text !== undefined) el.textContent = text;
  parent.append(el);
  return el;
}

/** The path data around a byte offset, the offset marked: "… C 10 ▶x 30". */
function markOffset(text, offset) {
  const bytes = new TextEncoder().encode(text);
  const decode = (a, b) => new TextDecoder().decode(bytes.slice(a, b));
  const from = Math.max(0, offset - 24);
  return `${from > 0 ? '…' : ''}${decode(from, offset)}▶${decode(offset, offset + 24)}${offset + 24 < bytes.length ? '…' : ''}`;
}

/** A comma- or space-separated list of numbers; null if any entry is not a number. */
function parseNumbers(text) {
  const items = text.split(/[\s,]+/).filter(Boolean).map(Number);
  return items.every(Number.isFinite) ? items : null;
}

export class CurvesView {
  constructor(app) {
    this.app = app;
    this.mode = 'bezier';
    this.bezier = { points: clone(DEFAULT_BEZIER) };
    this.chains = [{ pieces: clone(DEFAULT_CHAIN), closed: false }];   // SVG path data replaces these (one per subpath)
    this.bspline = { degree: 3, points: clone(DEFAULT_BSPLINE), knots: clampedKnots(DEFAULT_BSPLINE.length, 3), weights: null };
    this.activeChain = 0;          // the chain the slider's parameter runs over
    this.selectedJoint = null;     // {chain, joint}
    this.answers = null;           // the server's latest answers, for the state they were asked about
    this.busy = false;             // one round of requests at a time...
    this.dirty = false;            // ...and the latest edit is sent when it returns
    this.roundTrips = 0;
    this.chainAnswers = new Map();  // the last round's answer per chain request (JSON text), see askChain
    this.drag = null;
    this.levelsShown = Infinity;   // intermediate construction levels drawn (all)
    this.stage = $('curves-stage');
    this.bindControls();
    this.bindStage();
    new ResizeObserver(() => { if (this.active) { this.fit(); this.draw(); } }).observe(this.stage);
  }

  // ---- panel -------------------------------------------------------------------------------------------------------

  bindControls() {
    $('crv-mode').addEventListener('change', () => this.setMode($('crv-mode').value));
    $('crv-add-point').addEventListener('click', () => { this.addPoint(this.bezier.points); this.afterEdit(); });
    $('crv-remove-point').addEventListener('click', () => { this.removePoint(this.bezier.points, 2); this.afterEdit(); });
    $('crv-add-piece').addEventListener('click', () => this.addPiece());
    $('crv-remove-piece').addEventListener('click', () => this.removePiece());
    $('crv-make-c1').addEventListener('click', () => this.enforceJoint('C1'));
    $('crv-make-g1').addEventListener('click', () => this.enforceJoint('G1'));
    $('crv-svg-load').addEventListener('click', () => this.loadSvg($('crv-svg').value));
    $('crv-bs-degree').addEventListener('change', () => this.setDegree(Math.round(Number($('crv-bs-degree').value))));
    // a B-spline's knot vector follows its point count: back to uniform clamped
    $('crv-bs-add').addEventListener('click', () => { this.addPoint(this.bspline.points); this.resetKnots(); this.afterEdit(); });
    $('crv-bs-remove').addEventListener('click', () => {
      this.removePoint(this.bspline.points, this.bspline.degree + 1);
      this.resetKnots();
      this.afterEdit();
    });
    $('crv-knots').addEventListener('change', () => this.editKnots());
    $('crv-knots-uniform').addEventListener('click', () => { this.resetKnots(); this.afterEdit(); });
    $('crv-bs-weights').addEventListener('change', () => this.editWeights());
    $('crv-t').addEventListener('input', () => { this.draw(); this.schedule(); });
    $('crv-tolerance').addEventListener('change', () => this.schedule());
    $('crv-construction').addEventListener('change', () => this.draw());
    $('crv-levels').addEventListener('input', () => {
      const slider = $('crv-levels');
      this.levelsShown = slider.value === slider.max ? Infinity : Number(slider.value);
      this.draw();
    });
    $('crv-fit').addEventListener('click', () => { this.fit(); this.draw(); });
  }

  async activate() {
    this.active = true;
    this.setMode(this.mode);
  }

  deactivate() { this.active = false; this.drag = null; }

  setMode(mode) {
    this.mode = mode;
    $('crv-mode').value = mode;
    for (const m of ['bezier', 'chain', 'bspline']) $(`crv-${m}-controls`).hidden = m !== mode;
    $('crv-construction-name').textContent = mode === 'bspline' ? 'de Boor' : 'de Casteljau';
    this.answers = null;
    this.updateSlider();
    this.showPanelValues();
    this.fit();
    this.draw();
    this.schedule();
  }

  /** The slider's range: [0, 1] for one curve, [0, pieces] for a chain (the chain parameter s), the B-spline's domain. */
  updateSlider() {
    const slider = $('crv-t');
    let [lo, hi] = [0, 1];
    if (this.mode === 'chain') hi = this.chains[this.activeChain].pieces.length;
    if (this.mode === 'bspline') {
      const [a, b] = domain(this.bspline.knots, this.bspline.points.length, this.bspline.degree);
      if (a < b) [lo, hi] = [a, b];   // else the knots are wrong, and the server's answer says how
    }
    const value = Math.min(Math.max(Number(slider.value), lo), hi);
    slider.min = String(lo);
    slider.max = String(hi);
    slider.step = 'any';   // the parameter is sent as it is: no snapping to a grid
    slider.value = String(value);
    $('crv-t-label').textContent = { bezier: 't', chain: 's', bspline: 'u' }[this.mode];
  }

  parameter() { return Number($('crv-t').value); }

  /** Appends a point continuing the last segment (degree + 1 for a Bézier curve). */
  addPoint(points) {
    const [a, b] = [points.at(-2), points.at(-1)];
    points.push([b[0] + (b[0] - a[0]) / 2 + 0.5, b[1] + (b[1] - a[1]) / 2]);
  }

  removePoint(points, minimum) {
    if (points.length > minimum) points.pop();
  }

  /** Appends a cubic to the active chain, leaving its last end with the mirrored handle (a C1 joint). */
  addPiece() {
    const chain = this.chains[this.activeChain];
    const last = chain.pieces.at(-1).points;
    const [a, b] = [last.at(-2), last.at(-1)];
    const d = [b[0] - a[0], b[1] - a[1]];
    const c1 = [b[0] + d[0], b[1] + d[1]];
    chain.pieces.push({ points: [[...b], c1, [c1[0] + 2, c1[1] - d[1]], [c1[0] + 3, b[1]]] });
    this.afterEdit();
  }

  removePiece() {
    const chain = this.chains[this.activeChain];
    if (chain.pieces.length > 1) chain.pieces.pop();
    this.selectedJoint = null;
    this.afterEdit();
  }

  afterEdit() {
    this.updateSlider();
    this.showPanelValues();
    this.draw();
    this.schedule();
  }

  // ---- B-spline knots and weights ----------------------------------------------------------------------------------

  setDegree(p) {
    const b = this.bspline;
    if (!(p >= 1 && p <= 32)) return;
    b.degree = p;
    while (b.points.length < p + 1) this.addPoint(b.points);
    this.resetKnots();
    this.afterEdit();
  }

  /** Uniform clamped knots for the current points and degree (the default; edits to the list replace them). */
  resetKnots() {
    const b = this.bspline;
    b.knots = clampedKnots(b.points.length, b.degree);
    if (b.weights && b.weights.length !== b.points.length)
      b.weights = b.points.map((_, i) => b.weights[i] ?? 1);   // new points weigh 1
  }

  /** The panel's fields from the model: the Bézier curve's degree, the B-spline's degree, knots and weights. */
  showPanelValues() {
    const b = this.bspline;
    $('crv-knots').value = b.knots.join(', ');
    $('crv-bs-weights').value = b.weights ? b.weights.join(', ') : '';
    $('crv-bs-degree').value = String(b.degree);
    $('crv-degree').textContent = `degree ${this.bezier.points.length - 1} (${this.bezier.points.length} points)`;
  }

  /** The edited knot list, sent as it is: the server says what is wrong with it (count, order). */
  editKnots() {
    const knots = parseNumbers($('crv-knots').value);
    if (!knots) return this.app.showError(new Error('knots: a list of numbers, e.g. 0, 0, 0, 0, 0.5, 1, 1, 1, 1'));
    this.bspline.knots = knots;
    this.afterEdit();
  }

  /** Weights for a NURBS: one per control point, or none (empty) for a polynomial B-spline. */
  editWeights() {
    const text = $('crv-bs-weights').value.trim();
    const weights = text === '' ? null : parseNumbers(text);
    if (text !== '' && !weights) return this.app.showError(new Error('weights: a list of positive numbers, one per point'));
    this.bspline.weights = weights;
    this.afterEdit();
  }

  // ---- requests ----------------------------------------------------------------------------------------------------

  /** Asks the server about the current state: one round in flight, the latest state sent when it returns. */
  async schedule() {
    if (!this.active) return;
    if (this.busy) { this.dirty = true; return; }
    this.busy = true;
    try {
      do {
        this.dirty = false;
        const state = this.snapshot();
        try {
          const previous = this.chainAnswers;
          this.chainAnswers = new Map();   // this round's, looked up in the previous round's first
          const answers = await this.ask(state, previous);
          if (!this.active) break;
          this.answers = { state, ...answers };
          this.roundTrips++;
          this.app.clearError();
        } catch (e) {
          if (!(e instanceof ProblemError)) throw e;
          this.answers = null;
          this.app.showError(e, 'POST /curves');
        }
        this.draw();
      } while (this.dirty && this.active);
    } finally {
      this.busy = false;
    }
  }

  /** What a request is about: the mode, the curve(s) and the parameter, copied (dragging edits the originals). */
  snapshot() {
    return { mode: this.mode, t: this.parameter(), tolerance: Number($('crv-tolerance').value), activeChain: this.activeChain,
             bezier: clone(this.bezier), chains: clone(this.chains), bspline: clone(this.bspline) };
  }

  /** The answers about `state`; `previous` holds the last round's chain answers by request. */
  async ask(state, previous) {
    const t0 = performance.now();
    const tessellate = { tolerance: state.tolerance };
    const length = { tolerance: RELATIVE_LENGTH_TOLERANCE * this.extent(state) };
    let out;
    if (state.mode === 'bezier') {
      const r = await call('POST', '/curves', { body: { points: state.bezier.points, evaluate: [state.t], length, tessellate } });
      out = { curves: [r.json] };
    } else if (state.mode === 'chain') {
      // one request per chain (a request holds one curve); only the active chain is evaluated
      out = { curves: await Promise.all(state.chains.map((chain, i) => this.askChain({
        chain, continuity: true, length, tessellate, ...(i === state.activeChain ? { evaluate: [state.t] } : {}),
      }, previous))) };
    } else {
      out = await this.askBspline(state, tessellate, length);
    }
    out.roundTripMs = performance.now() - t0;
    return out;
  }

  /**
   * One chain's answer; a chain whose request is the same as last time (of many subpaths, all but the dragged one)
   * is answered from the previous round instead of the server.
   */
  async askChain(body, previous) {
    const key = JSON.stringify(body);
    const json = previous?.get(key) ?? (await call('POST', '/curves', { body })).json;
    this.chainAnswers.set(key, json);
    return json;
  }

  /**
   * The B-spline: the point at u, points and tangents at its distinct knots (the ticks), its Bézier pieces and the
   * tessellation; then its length, measured on those pieces as a chain (the B-spline form has no length query).
   */
  async askBspline(state, tessellate, length) {
    const b = state.bspline;
    const ticks = this.knotTicks(b);
    const curve = { degree: b.degree, points: b.points, knots: b.knots, ...(b.weights ? { weights: b.weights } : {}) };
    const r = await call('POST', '/curves', {
      body: { bspline: curve, evaluate: [state.t, ...ticks], derivatives: { t: ticks, order: 1 }, to_bezier: true, tessellate },
    });
    const pieces = await call('POST', '/curves', { body: { chain: { pieces: r.json.to_bezier.pieces }, length } });
    return { curves: [{ ...r.json, length: pieces.json.length }], ticks };
  }

  /** The diagonal of the control points' bounding box (1 if they all coincide). */
  extent(state) {
    const pts = state.mode === 'bezier' ? state.bezier.points
      : state.mode === 'bspline' ? state.bspline.points : state.chains.flatMap((c) => c.pieces.flatMap((p) => p.points));
    const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
    return Math.hypot(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)) || 1;
  }

  /** The distinct knots inside the domain. */
  knotTicks(b) {
    const [lo, hi] = domain(b.knots, b.points.length, b.degree);
    return [...new Set(b.knots.filter((k) => k >= lo && k <= hi))];
  }

  // ---- SVG path data -----------------------------------------------------------------------------------------------

  /** Path data → chains (one per subpath) through the server's to_bezier; a syntax error is shown with its offset. */
  async loadSvg(text) {
    const note = $('crv-svg-error');
    note.hidden = true;
    try {
      const r = await call('POST', '/curves', { body: { svg: text, to_bezier: true } });
      this.chains = r.json.subpaths.map((s) => s.to_bezier);
      this.activeChain = 0;
      this.selectedJoint = null;
      $('crv-svg-status').textContent = `${this.chains.length} subpath(s), ` +
        `${this.chains.reduce((n, c) => n + c.pieces.length, 0)} pieces`;
      this.setMode('chain');
    } catch (e) {
      if (!(e instanceof ProblemError)) throw e;
      const p = e.problem ?? {};
      $('crv-svg-status').textContent = '';
      note.textContent = p.offset !== undefined ? `${p.detail}\n${markOffset(text, p.offset)}` : e.message;
      note.dataset.offset = p.offset ?? '';
      note.hidden = false;
    }
  }

  // ---- joints ------------------------------------------------------------------------------------------------------

  /** The selected joint made C1 or G1 by the server's enforce_c1 (the mirror rule on that joint only). */
  async enforceJoint(mode) {
    const sel = this.selectedJoint;
    if (!sel) return this.app.showError(new Error('Select a joint first (in the list or by clicking its point).'));
    try {
      const r = await call('POST', '/curves', {
        body: { chain: this.chains[sel.chain], enforce_c1: { mode, side: $('crv-side').value, joints: [sel.joint] } },
      });
      this.chains[sel.chain] = r.json.enforce_c1.chain;
      this.afterEdit();
    } catch (e) {
      if (!(e instanceof ProblemError)) throw e;
      this.app.showError(e, `enforce_c1 ${mode}`);
    }
  }

  selectJoint(chain, joint) {
    this.selectedJoint = { chain, joint };
    this.setActiveChain(chain);
    this.draw();
  }

  /** The chain (of several, from SVG path data) that the slider runs over. */
  setActiveChain(chain) {
    if (chain === this.activeChain) return;
    this.activeChain = chain;
    this.updateSlider();
    this.draw();
    this.schedule();
  }

  /** The latest answers if they are about the current mode (an answer for the previous mode may still arrive). */
  current() { return this.answers?.state.mode === this.mode ? this.answers : null; }

  /** The joint list: each joint's class and measures from the server's continuity report, selectable. */
  showJoints() {
    const list = $('crv-joints');
    list.replaceChildren();
    const answers = this.mode === 'chain' ? this.current() : null;
    if (!answers) return;
    answers.curves.forEach((answer, c) => {
      for (const [j, joint] of (answer.continuity?.joints ?? []).entries()) {
        const li = document.createElement('li');
        li.dataset.chain = c;
        li.dataset.joint = j;
        li.dataset.class = joint.continuity;
        const selected = this.selectedJoint?.chain === c && this.selectedJoint?.joint === j;
        li.className = selected ? 'selected' : '';
        const where = this.chains.length > 1 ? `path ${c + 1} ` : '';
        li.innerHTML = `<label><input type="radio" name="crv-joint" ${selected ? 'checked' : ''}>` +
          `${where}joint ${j} (pieces ${joint.left}→${joint.right}): <b class="class-${joint.continuity}">${joint.continuity}</b></label>` +
          `<span class="measures">gap ${fmt(joint.gap, 3)} · Δderivative ${fmt(joint.derivative_mismatch, 3)} · ` +
          `angle ${fmt(joint.angle * 180 / Math.PI, 3)}°</span>`;
        li.querySelector('input').addEventListener('change', () => this.selectJoint(c, j));
        list.append(li);
      }
    });
    if (!list.children.length) list.innerHTML = '<li class="hint">no joints (one piece)</li>';
  }

  // ---- the stage: view transform and dragging ----------------------------------------------------------------------

  /** The editable point lists of the mode, each with the group its coincident points move together in. */
  pointLists() {
    if (this.mode === 'bezier') return [{ points: this.bezier.points, group: 0 }];
    if (this.mode === 'bspline') return [{ points: this.bspline.points, group: 0 }];
    return this.chains.flatMap((chain, c) => chain.pieces.map((piece, p) => ({ points: piece.points, group: c, chain: c, piece: p })));
  }

  /** Scale and offset that fit every control point in the stage with a margin, y as in SVG (downwards). */
  fit() {
    const pts = this.pointLists().flatMap((l) => l.points);
    const rect = this.stage.getBoundingClientRect();
    if (!pts.length || rect.width === 0) return;
    const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
    const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
    const s = 0.8 * Math.min(rect.width / Math.max(x1 - x0, 1e-9), rect.height / Math.max(y1 - y0, 1e-9));
    this.view = { s, ox: rect.width / 2 - s * (x0 + x1) / 2, oy: rect.height / 2 - s * (y0 + y1) / 2 };
  }

  toScreen(p) { return [this.view.ox + this.view.s * p[0], this.view.oy + this.view.s * p[1]]; }

  toWorld(x, y) { return [(x - this.view.ox) / this.view.s, (y - this.view.oy) / this.view.s]; }

  bindStage() {
    this.stage.addEventListener('pointerdown', (e) => this.onPointerDown(e));
    this.stage.addEventListener('pointermove', (e) => this.onPointerMove(e));
    this.stage.addEventListener('pointerup', () => { this.drag = null; });
    this.stage.addEventListener('pointercancel', () => { this.drag = null; });
  }

  /** Grabs a control point and every point of its chain at the same place (a joint's two ends move together). */
  onPointerDown(e) {
    const handle = e.target.closest?.('[data-list]');
    if (!handle) return;
    const lists = this.pointLists();
    const grabbed = lists[Number(handle.dataset.list)];
    const p = grabbed.points[Number(handle.dataset.index)];
    const refs = [];
    for (const l of lists) {
      if (l.group !== grabbed.group) continue;
      l.points.forEach((q, i) => { if (q[0] === p[0] && q[1] === p[1]) refs.push([l.points, i]); });
    }
    this.drag = { refs };
    if (handle.dataset.joint !== undefined) this.selectJoint(Number(handle.dataset.chain), Number(handle.dataset.joint));
    else if (grabbed.chain !== undefined) this.setActiveChain(grabbed.chain);
    this.stage.setPointerCapture(e.pointerId);
    e.preventDefault();
  }

  onPointerMove(e) {
    if (!this.drag) return;
    const rect = this.stage.getBoundingClientRect();
    const w = this.toWorld(e.clientX - rect.left, e.clientY - rect.top);
    for (const [points, i] of this.drag.refs) points[i] = [...w];
    this.draw();
    this.schedule();
  }

  // ---- drawing -----------------------------------------------------------------------------------------------------

  /** Redraws the stage and the panel's readouts from the current state and the latest answers. */
  draw() {
    if (!this.active) return;
    if (!this.view) this.fit();
    if (!this.view) return;
    this.stage.replaceChildren();
    this.drawCurves();
    this.drawControlPolygons();
    if (this.mode === 'bspline') this.drawKnotTicks();
    const local = this.localConstruction();
    if (local && $('crv-construction').checked) this.drawConstruction(local);
    this.drawControlPoints();
    this.drawEvaluation(local);
    this.drawBasis(local);
    this.showJoints();
    this.showReadout(local);
  }

  /** The curves as the server tessellated them (nothing until the first answer). */
  drawCurves() {
    for (const answer of this.current()?.curves ?? []) {
      const pts = answer.tessellate?.points;
      if (!pts) continue;
      svgEl(this.stage, 'polyline', { class: 'curve', points: pts.map((p) => this.toScreen(p).join(',')).join(' ') });
    }
  }

  drawControlPolygons() {
    for (const l of this.pointLists())
      svgEl(this.stage, 'polyline', { class: 'polygon', points: l.points.map((p) => this.toScreen(p).join(',')).join(' ') });
  }

  /** Control points; in a chain, joint points carry their joint (first point of every piece after the first). */
  drawControlPoints() {
    this.pointLists().forEach((l, li) => {
      l.points.forEach((p, i) => {
        const [x, y] = this.toScreen(p);
        const attrs = { class: 'handle', cx: x, cy: y, r: 6, 'data-list': li, 'data-index': i };
        const joint = this.jointAt(l, i);
        if (joint !== null) {
          Object.assign(attrs, { class: 'handle joint', r: 7, 'data-chain': l.chain, 'data-joint': joint });
          if (this.selectedJoint?.chain === l.chain && this.selectedJoint?.joint === joint) attrs.class += ' selected';
        }
        svgEl(this.stage, 'circle', attrs);
      });
    });
    this.drawJointLabels();
  }

  /** The joint index a chain's control point sits on (the start of piece k > 0 is joint k - 1), or null. */
  jointAt(list, i) {
    if (list.chain === undefined) return null;
    const chain = this.chains[list.chain];
    if (i === 0 && list.piece > 0) return list.piece - 1;
    if (i === 0 && list.piece === 0 && chain.closed) return chain.pieces.length - 1;
    return null;
  }

  /** Each joint's class (from the server's continuity report) written next to it. */
  drawJointLabels() {
    const answers = this.mode === 'chain' ? this.current() : null;
    if (!answers) return;
    answers.curves.forEach((answer, c) => {
      for (const joint of answer.continuity?.joints ?? []) {
        const p = answers.state.chains[c].pieces[joint.right].points[0];
        const [x, y] = this.toScreen(p);
        svgEl(this.stage, 'text', { class: `joint-label class-${joint.continuity}`, x: x + 10, y: y - 10 }, joint.continuity);
      }
    });
  }

  /** Ticks across the B-spline at its distinct knots (positions and tangents from the server), labelled with u. */
  drawKnotTicks() {
    const a = this.current();
    if (!a?.curves[0].derivatives) return;
    const { evaluate, derivatives } = a.curves[0];
    a.ticks.forEach((u, i) => {
      const p = this.toScreen(evaluate[i + 1]);
      const d = derivatives[i];
      const len = Math.hypot(d[0], d[1]) || 1;
      const n = [-d[1] / len * 9, d[0] / len * 9];
      svgEl(this.stage, 'line', { class: 'knot-tick', 'data-u': u, x1: p[0] - n[0], y1: p[1] - n[1], x2: p[0] + n[0], y2: p[1] + n[1] });
      svgEl(this.stage, 'text', { class: 'knot-label', x: p[0] + n[0] * 1.6, y: p[1] + n[1] * 1.6 + 4 }, fmt(u, 3));
    });
  }

  /**
   * The local construction at the slider's parameter: for a Bézier curve de Casteljau, for a chain de Casteljau on
   * the piece under s (piece floor(s) at t = s - floor(s), the last piece at s = pieces, as the server does), for a
   * B-spline de Boor. With the basis weights at that parameter and the control points they weigh.
   */
  localConstruction() {
    const s = this.parameter();
    if (this.mode === 'bezier') return this.bezierConstruction(this.bezier.points, null, s, { t: s });
    if (this.mode === 'chain') {
      const pieces = this.chains[this.activeChain].pieces;
      const piece = Math.min(Math.floor(s), pieces.length - 1);
      const t = s - piece;
      return this.bezierConstruction(pieces[piece].points, pieces[piece].weights, t, { s, piece, t });
    }
    const b = this.bspline;
    const n = b.points.length;
    if (b.knots.length !== n + b.degree + 1 || (b.weights && b.weights.length !== n)) return null;  // the server says why
    const { levels, point, span } = deBoor(b.points, b.weights, b.knots, b.degree, s);
    const basis = rationalWeights(bsplineBasis(b.knots, n, b.degree, s), b.weights);
    return { levels, point, basis, where: { u: s, span }, kind: 'B-spline' };
  }

  bezierConstruction(points, weights, t, where) {
    const { levels, point } = deCasteljau(points, weights, t);
    const basis = rationalWeights(bernstein(points.length - 1, t), weights);
    return { levels, point, basis, where, kind: 'Bernstein', n: points.length - 1, weights };
  }

  /** The intermediate polygons, level by level, and their points. */
  drawConstruction(local) {
    const shown = this.showLevelsControl(local.levels.length - 2);
    local.levels.forEach((level, k) => {
      // the control polygon and the point are drawn apart; the levels control stops the construction early
      if (k === 0 || k === local.levels.length - 1 || k > shown) return;
      const colour = LEVEL_COLOURS[k % LEVEL_COLOURS.length];
      const pts = level.map((p) => this.toScreen(p));
      svgEl(this.stage, 'polyline', { class: 'construction', stroke: colour, 'data-level': k, points: pts.map((p) => p.join(',')).join(' ') });
      for (const [x, y] of pts) svgEl(this.stage, 'circle', { class: 'construction-point', fill: colour, cx: x, cy: y, r: 3 });
    });
  }

  /**
   * The levels control's range (the intermediate levels there are: the degree less one) and how many it shows:
   * all of them while it is at its end, also when the degree changes.
   */
  showLevelsControl(count) {
    const slider = $('crv-levels');
    slider.max = String(Math.max(count, 1));
    slider.value = String(Math.min(this.levelsShown, count));
    slider.disabled = count < 1;
    const shown = Math.min(this.levelsShown, count);
    $('crv-levels-out').textContent = `${shown} of ${count}`;
    return shown;
  }

  /** The local point (filled) and the server's evaluate at the same parameter (ring): they coincide. */
  drawEvaluation(local) {
    if (local) {
      const [x, y] = this.toScreen(local.point);
      svgEl(this.stage, 'circle', { class: 'local-point', cx: x, cy: y, r: 5 });
    }
    const server = this.serverPoint();
    if (server) {
      const [x, y] = this.toScreen(server);
      svgEl(this.stage, 'circle', { class: 'server-point', cx: x, cy: y, r: 9 });
    }
  }

  /** The server's evaluate at the slider's parameter, when the latest answer is about the current state. */
  serverPoint() {
    const a = this.current();
    if (!a || a.state.t !== this.parameter()) return null;
    const curve = this.mode === 'chain' ? a.curves[a.state.activeChain] : a.curves[0];
    return curve?.evaluate?.[0] ?? null;
  }

  /** The basis functions over the parameter range, a line at the slider, and each weight's value at it. */
  drawBasis(local) {
    const plot = $('crv-basis');
    plot.replaceChildren();
    const list = $('crv-basis-values');
    list.replaceChildren();
    if (!local) return;
    const [W, H, pad] = [260, 100, 6];
    const samples = this.basisSamples(local, 80);
    const sx = (t) => pad + (W - 2 * pad) * t, sy = (v) => H - pad - (H - 2 * pad) * v;
    samples.curves.forEach((values, i) => {
      const colour = LEVEL_COLOURS[1 + (i % (LEVEL_COLOURS.length - 1))];
      svgEl(plot, 'polyline', { class: 'basis', stroke: colour,
                                points: values.map((v, k) => `${sx(k / (values.length - 1))},${sy(v)}`).join(' ') });
      svgEl(plot, 'circle', { cx: sx(samples.at), cy: sy(local.basis[i]), r: 3, fill: colour });
    });
    svgEl(plot, 'line', { class: 'basis-cursor', x1: sx(samples.at), x2: sx(samples.at), y1: pad, y2: H - pad });
    const name = this.basisName(local);
    local.basis.forEach((v, i) => {
      const li = document.createElement('li');
      li.dataset.value = String(v);
      li.textContent = `${name(i)} = ${v.toFixed(6)}`;
      li.style.color = LEVEL_COLOURS[1 + (i % (LEVEL_COLOURS.length - 1))];
      list.append(li);
    });
    list.dataset.sum = String(local.basis.reduce((a, b) => a + b, 0));
  }

  /** The weights' names, and the caption saying what they are. */
  basisName(local) {
    const rational = local.kind === 'B-spline' ? !!this.bspline.weights : !!local.weights;
    const [letter, order] = local.kind === 'B-spline' ? ['N', this.bspline.degree] : ['B', local.n];
    $('crv-basis-caption').textContent = `${local.kind === 'B-spline' ? 'B-spline basis' : 'Bernstein basis'} at ` +
      `${local.kind === 'B-spline' ? 'u' : 't'}${rational ? ', times the weights and normalised (rational)' : ''}:`;
    return (i) => `${rational ? 'R' : letter}${i},${order}`;
  }

  /** Each basis weight sampled over its range ([0, 1] or the B-spline's domain), and where the slider is in it (0..1). */
  basisSamples(local, count) {
    const curves = local.basis.map(() => []);
    const b = this.bspline;
    const [lo, hi] = this.mode === 'bspline' ? domain(b.knots, b.points.length, b.degree) : [0, 1];
    for (let k = 0; k <= count; ++k) {
      const u = lo + (hi - lo) * (k / count);
      const values = this.mode === 'bspline' ? rationalWeights(bsplineBasis(b.knots, b.points.length, b.degree, u), b.weights)
                                             : rationalWeights(bernstein(local.n, u), local.weights);
      values.forEach((v, i) => curves[i].push(v));
    }
    const at = this.mode === 'bspline' ? (local.where.u - lo) / (hi - lo) : local.where.t;
    return { curves, at };
  }

  /** The parameter, the local and the server's point and their difference, the length and the tessellation. */
  showReadout(local) {
    const el = $('crv-readout');
    const lines = [];
    const server = this.serverPoint();
    const w = local?.where ?? {};
    if (this.mode === 'chain' && local) lines.push(`s = ${fmt(w.s, 6)}: piece ${w.piece} at t = ${fmt(w.t, 6)}`);
    else lines.push(`${this.mode === 'bspline' ? 'u' : 't'} = ${fmt(this.parameter(), 6)}`);
    for (const key of Object.keys(el.dataset)) delete el.dataset[key];
    el.dataset.t = String(this.parameter());
    if (local) {
      lines.push(`${this.mode === 'bspline' ? 'de Boor' : 'de Casteljau'}: ${fmtPoint(local.point)}`);
      el.dataset.local = JSON.stringify(local.point);
    }
    if (server) {
      lines.push(`server evaluate: ${fmtPoint(server)}`);
      el.dataset.server = JSON.stringify(server);
      if (local) lines.push(`difference: ${Math.hypot(local.point[0] - server[0], local.point[1] - server[1]).toExponential(2)}`);
    }
    const curves = this.current()?.curves ?? [];
    if (curves.length && curves.every((c) => c.length)) {
      const length = curves.reduce((a, c) => a + c.length.length, 0);
      const bound = curves.reduce((a, c) => a + c.length.error_bound, 0);
      // as many digits as the error bound allows
      const digits = bound > 0 ? Math.min(15, Math.max(3, Math.ceil(Math.log10(length / bound)) + 1)) : 15;
      lines.push(`length: ${fmt(length, digits)} (± ${fmt(bound, 2)})`);
      el.dataset.length = String(length);
    }
    el.textContent = lines.join('\n');
    // the same lines in the stage's corner, where the eye is while dragging
    lines.forEach((line, i) => svgEl(this.stage, 'text', { class: 'stage-readout', x: 12, y: 22 + 17 * i }, line));
    this.showStats(curves);
  }

  showStats(curves) {
    if (!this.current()) return;
    const segments = curves.reduce((a, c) => a + (c.tessellate?.segments ?? 0), 0);
    const bound = Math.max(0, ...curves.map((c) => c.tessellate?.bound ?? 0));
    const pieces = this.mode === 'chain' ? this.chains.reduce((a, c) => a + c.pieces.length, 0) : curves[0]?.to_bezier?.pieces.length;
    this.app.setStats([
      ...(pieces !== undefined ? [`Bézier pieces: ${pieces}`] : []),
      `polyline segments: ${segments}`,
      `deviation bound: ${fmt(bound, 3)} (tolerance ${this.answers.state.tolerance})`,
      `round trip: ${this.answers.roundTripMs.toFixed(1)} ms (${curves.length} curve${curves.length === 1 ? '' : 's'})`,
    ], { segments, pieces: pieces ?? '', roundTrips: this.roundTrips });
  }
}
