// pregrasp plan viewer, part 4 of 4 (after math.js, renderer.js, timeline.js). Reads the JSON
// embedded in <script id="pregrasp-data">, draws the world (z up, metres) with a small WebGL
// renderer of its own (no library, no network: the page is one file) and animates the selected
// plan. Exposes `window.pregraspViewer` for tests and the console. Without WebGL the page says
// so and still lists the candidates.

const DATA = JSON.parse(document.getElementById('pregrasp-data').textContent);
const PLAN = DATA.plan;

const COLORS = {
  background: 0xf4f6f8,
  support: 0xd8d4cc,
  grid: 0xb8b4ac,
  part: 0x8a9bb0,
  hull: 0x1f5fff,
  planned: 0xff8800,
  chosen: 0xffd400,
  rejected: 0xb08050,
  other: 0xffb060,
  arms: [0x9fb4d6, 0xd6b49f],
  gripper: 0x3b3b3b,
  skeleton: 0x404858,
  dummy: 0x20c060,
};
const rgb = (hex) => [((hex >> 16) & 255) / 255, ((hex >> 8) & 255) / 255, (hex & 255) / 255];

// ---------- the world: support, part, candidates, arms (pure state, drawn if WebGL is there) ----------

const pInit = poseMatrix(PLAN.object.initial_pose);
const sceneBox = { lo: [Infinity, Infinity, Infinity], hi: [-Infinity, -Infinity, -Infinity] };
for (const p of [m4.position(pInit), ...PLAN.robots.map((r) => r.base.xyz)]) {
  for (let k = 0; k < 3; k++) {
    sceneBox.lo[k] = Math.min(sceneBox.lo[k], p[k] - 0.6);
    sceneBox.hi[k] = Math.max(sceneBox.hi[k], p[k] + 0.6);
  }
}
const sceneCentre = v3.scale(v3.add(sceneBox.lo, sceneBox.hi), 0.5);
const sceneSize = v3.sub(sceneBox.hi, sceneBox.lo);

const part = { matrix: pInit };
const show = { hull: true, candidates: true, dummies: true };

function candidateColor(c) {
  if (c.outcome === 'planned') return COLORS.planned;
  if (c.outcome.startsWith('rejected')) return COLORS.rejected;
  return COLORS.other;
}

/** One arm: base pose, DH frames in world, the gripper it shows. */
class Arm {
  constructor(robotJson, model) {
    this.json = robotJson;
    this.model = model;
    this.base = poseMatrix(robotJson.base);
    const g = model.gripper;
    this.gripperSets = { open: g.open, precision: g.closed_precision || g.closed, power: g.closed_power || g.closed };
    this.setState(robotJson.start, 'open');
  }

  /** Joints q; grip 'open', 'precision' (holding the support grasp) or 'power'. */
  setState(q, grip) {
    this.q = q.slice();
    this.grip = grip;
    this.world = fkFrames(this.model, q).map((f) => m4.mul(this.base, f));
  }

  /** World position of the flange (DH frame 6). */
  tip() { return m4.position(this.world[6]); }
}

const arms = PLAN.robots.map((r, i) => {
  const model = DATA.robots[i];
  if (!model || !model.known) {
    console.warn(`robot ${r.name}: model ${r.model} unknown to the viewer, arm not drawn`);
    return null;
  }
  return new Arm(r, model);
});
const robotIndex = new Map(PLAN.robots.map((r, i) => [r.name, i]));

/** Flange poses of the translucent power-grasp dummies: P_obj · G_p,i · power_point⁻¹. */
function dummyPoses(plan) {
  if (!plan) return [];
  const goal = poseMatrix(plan.object_goal_pose);
  return PLAN.robots.map((r, i) => (arms[i]
    ? m4.mul(m4.mul(goal, poseMatrix(PLAN.grasps.power[i])), m4.invRigid(poseMatrix(r.power_point)))
    : null));
}

// ---------- camera: orbit (left drag), pan (right or shift drag), zoom (wheel) ----------

const camera = {
  target: [0, 0, 0], distance: 3, azimuth: 0, elevation: 0.5, fovy: (45 * Math.PI) / 180,
  eye: [0, 0, 0], viewProj: m4.identity(),
  update(aspect) {
    const ce = Math.cos(this.elevation);
    this.eye = v3.add(this.target, v3.scale([ce * Math.cos(this.azimuth), ce * Math.sin(this.azimuth), Math.sin(this.elevation)], this.distance));
    this.viewProj = m4.mul(m4.perspective(this.fovy, aspect, 0.01, 100), m4.lookAt(this.eye, this.target, [0, 0, 1]));
  },
  /** Screen position (CSS px) of world point p, or null behind the eye. */
  project(p, width, height) {
    const m = this.viewProj;
    const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12], y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    return w > 1e-6 ? [(x / w + 1) * width / 2, (1 - y / w) * height / 2] : null;
  },
};

/** Looks at the part from beyond it, away from the arms' bases, from above and a little aside. */
function fitCamera() {
  const radius = Math.max(sceneSize[0], sceneSize[1], 1.0) * 0.75;
  const target = m4.position(pInit);
  target[2] = PLAN.support_height + 0.2;
  let bases = [0, 0, 0];
  for (const r of PLAN.robots) bases = v3.add(bases, v3.scale(r.base.xyz, 1 / PLAN.robots.length));
  let dir = [target[0] - bases[0], target[1] - bases[1]];
  if (Math.hypot(dir[0], dir[1]) < 1e-3) dir = [1, -1];
  camera.target = target;
  camera.azimuth = Math.atan2(dir[1], dir[0]) + 0.6;
  camera.elevation = Math.atan2(1.1, 1.5);
  camera.distance = Math.hypot(1.5, 1.1) * radius;
}

// ---------- UI ----------

const ui = {
  view: document.getElementById('view'),
  status: document.getElementById('status'),
  planSelect: document.getElementById('plan-select'),
  play: document.getElementById('play'),
  slider: document.getElementById('timeline'),
  speed: document.getElementById('speed'),
  time: document.getElementById('time'),
  segment: document.getElementById('segment'),
  gripForces: document.getElementById('grip-forces'),
  candidates: document.getElementById('candidates'),
  tooltip: document.getElementById('tooltip'),
  showHull: document.getElementById('show-hull'),
  showCandidates: document.getElementById('show-candidates'),
  showDummies: document.getElementById('show-dummies'),
};

let currentPlanIndex = -1;
let currentPlan = null;
let timeline = buildTimeline(null);
let time = 0;
let playing = false;
let framesRendered = 0;
let dirty = true; // the view changed since the last frame
let hovered = -1; // candidate id under the mouse or the table row
let dummies = [];

const fmt = (x, d = 3) => (x === null || x === undefined ? '—' : Number(x).toFixed(d));
const deg = (x) => (x === null || x === undefined ? '—' : (x * 180 / Math.PI).toFixed(1) + '°');

function candidateText(c) {
  return `#${c.id} ${c.direction}  length ${fmt(c.length)} m  θ_max ${deg(c.theta_max)}  score ${fmt(c.score)}  θ_goal ${deg(c.theta_goal)}  ${c.outcome}`;
}

function highlightCandidates(hoverId) {
  hovered = hoverId;
  dirty = true;
  const chosen = currentPlan ? currentPlan.candidate : -1;
  for (const row of ui.candidates.querySelectorAll('tr[data-id]')) {
    const id = Number(row.dataset.id);
    row.classList.toggle('chosen', id === chosen);
    row.classList.toggle('hover', id === hoverId);
  }
}

function fillCandidateTable() {
  const body = ui.candidates.querySelector('tbody');
  for (const c of PLAN.candidates) {
    const tr = document.createElement('tr');
    tr.dataset.id = c.id;
    const cells = [c.id, c.direction, fmt(c.length), deg(c.theta_max), fmt(c.score), deg(c.theta_goal), c.outcome];
    for (const v of cells) {
      const td = document.createElement('td');
      td.textContent = String(v);
      tr.appendChild(td);
    }
    tr.title = candidateText(c);
    tr.addEventListener('mouseenter', () => highlightCandidates(c.id));
    tr.addEventListener('mouseleave', () => highlightCandidates(-1));
    tr.addEventListener('click', () => {
      const k = PLAN.plans.findIndex((p) => p.candidate === c.id);
      if (k >= 0) selectPlan(k);
    });
    body.appendChild(tr);
  }
}

function applyTime(t) {
  time = Math.min(Math.max(t, 0), timeline.total);
  dirty = true;
  const st = stateAt(currentPlan, timeline, time);
  arms.forEach((arm, i) => arm && arm.setState(st.q[i], st.grip[i]));
  part.matrix = st.object;
  ui.slider.value = timeline.total > 0 ? String(Math.round(1000 * time / timeline.total)) : '0';
  ui.time.textContent = `${time.toFixed(2)} / ${timeline.total.toFixed(2)} s`;
  ui.segment.textContent = currentPlan ? st.segment : '—';
  return st;
}

/** Each closing segment of `plan` with its grip force (N): its own, else sup1's falls back to
 * the pinch's recommended force; '—' when the plan gives none. */
function gripForcesText(plan) {
  if (!plan) return '';
  const pinch = plan.physics ? plan.physics.grip_force_recommended : null;
  const items = plan.segments.filter((s) => s.kind === 'reach' || s.kind === 'regrasp').map((s) => {
    const f = s.grip_force ?? (s.grasp === 'support' ? pinch : null);
    return `${s.name} ${s.robot} ${f === null || f === undefined ? '—' : `${fmt(f, 1)} N`}`;
  });
  return `grip force: ${items.join(' · ')}`;
}

function selectPlan(k) {
  if (PLAN.plans.length === 0) {
    currentPlanIndex = -1;
    currentPlan = null;
  } else {
    currentPlanIndex = Math.min(Math.max(k, 0), PLAN.plans.length - 1);
    currentPlan = PLAN.plans[currentPlanIndex];
    ui.planSelect.value = String(currentPlanIndex);
  }
  timeline = buildTimeline(currentPlan);
  ui.gripForces.textContent = gripForcesText(currentPlan);
  dummies = dummyPoses(currentPlan);
  highlightCandidates(-1);
  applyTime(0);
  render();
}

function setPlaying(p) {
  playing = p && timeline.total > 0;
  ui.play.textContent = playing ? 'Pause' : 'Play';
}

function setupUi() {
  if (PLAN.status === 'planned' && PLAN.plans.length > 0) {
    ui.status.textContent = `planned — ${PLAN.plans.length} plan(s), ${PLAN.candidates.length} candidate(s)`;
  } else {
    ui.status.textContent = `no plan: ${PLAN.reason || 'no reason given'}`;
    ui.status.classList.add('no-plan');
    document.body.classList.add('no-plan');
  }
  PLAN.plans.forEach((p, k) => {
    const o = document.createElement('option');
    o.value = String(k);
    o.textContent = `plan ${k + 1}: candidate #${p.candidate}, score ${fmt(p.score)}, master ${p.master}`;
    ui.planSelect.appendChild(o);
  });
  ui.planSelect.addEventListener('change', () => selectPlan(Number(ui.planSelect.value)));
  ui.play.addEventListener('click', () => {
    if (!playing && time >= timeline.total) applyTime(0);
    setPlaying(!playing);
  });
  ui.slider.addEventListener('input', () => {
    setPlaying(false);
    applyTime(timeline.total * Number(ui.slider.value) / 1000);
  });
  ui.speed.value = String(DATA.options.speed);
  if (ui.speed.value === '') ui.speed.value = '1';
  const toggle = (el, key) => el.addEventListener('change', () => { show[key] = el.checked; dirty = true; });
  toggle(ui.showHull, 'hull');
  toggle(ui.showCandidates, 'candidates');
  toggle(ui.showDummies, 'dummies');
  fillCandidateTable();
}

// ---------- drawing (only with WebGL) ----------

let renderer = null;
try {
  renderer = new Renderer(ui.view);
} catch (e) {
  const note = document.createElement('div');
  note.className = 'no-webgl';
  note.setAttribute('role', 'alert');
  note.innerHTML = '<p><b>The 3D view needs WebGL, and this browser does not provide it.</b></p>'
    + '<p>WebGL may be switched off in the browser settings or unsupported by the graphics driver. '
    + 'The candidate table and the plan are listed on the right; open this file in a browser '
    + 'with WebGL to see the part and both arms move.</p>';
  const detail = document.createElement('p');
  detail.className = 'detail';
  detail.textContent = `(${e.message})`;
  note.appendChild(detail);
  ui.view.appendChild(note);
}

/** Number of candidate axes drawn. */
let candidateRods = 0;

function buildScene(r) {
  const color = (hex, alpha = 1) => [...rgb(hex), alpha];
  const z0 = PLAN.support_height;
  // Support: a plane and a 0.1 m grid, both a shade below the support so parts rest on it.
  const plane = new Geometry();
  const [lx, ly, hx, hy] = [sceneBox.lo[0], sceneBox.lo[1], sceneBox.hi[0], sceneBox.hi[1]];
  plane.tri([lx, ly, z0 - 0.0008], [hx, ly, z0 - 0.0008], [hx, hy, z0 - 0.0008], [0, 0, 1]);
  plane.tri([lx, ly, z0 - 0.0008], [hx, hy, z0 - 0.0008], [lx, hy, z0 - 0.0008], [0, 0, 1]);
  r.add(plane, { color: color(COLORS.support) });
  const grid = new Geometry(true);
  for (let x = Math.ceil(lx * 10) / 10; x <= hx; x += 0.1) grid.segment([x, ly, z0 - 0.0004], [x, hy, z0 - 0.0004]);
  for (let y = Math.ceil(ly * 10) / 10; y <= hy; y += 0.1) grid.segment([lx, y, z0 - 0.0004], [hx, y, z0 - 0.0004]);
  r.add(grid, { color: color(COLORS.grid) });

  // The part and its hull's feature edges, in the object frame.
  r.add(meshGeometry(DATA.mesh), { color: color(COLORS.part), matrix: () => part.matrix, behindLines: true });
  const hull = new Geometry(true);
  for (const e of DATA.hull_edges) hull.segment(e.slice(0, 3), e.slice(3, 6));
  r.add(hull, { color: color(COLORS.hull), matrix: () => part.matrix, visible: () => show.hull });

  // Candidate axes: a unit rod (radius 1, z from 0 to 1) scaled onto each axis. The chosen
  // and the hovered axis are thicker and show through the part (an axis lies on its edge).
  const rod = cylinder(new Geometry(), [0, 0, 0], [0, 0, 1], 1);
  for (const c of PLAN.candidates) {
    const a = c.axis[0], d = v3.sub(c.axis[1], c.axis[0]), len = v3.len(d);
    const u = len > 0 ? v3.scale(d, 1 / len) : [0, 0, 1], [e1, e2] = basis(u);
    const rodMatrix = (radius) => m4.frame(v3.scale(e1, radius), v3.scale(e2, radius), v3.scale(u, Math.max(len, 1e-6)), a);
    const thin = rodMatrix(0.004), chosenRod = rodMatrix(0.0088), hoverRod = rodMatrix(0.0072);
    const isChosen = () => currentPlan !== null && currentPlan.candidate === c.id;
    r.add(rod, {
      color: () => (isChosen() ? color(COLORS.chosen) : color(candidateColor(c), hovered === c.id ? 1 : 0.85)),
      depthTest: () => !(isChosen() || hovered === c.id),
      matrix: () => (isChosen() ? chosenRod : hovered === c.id ? hoverRod : thin),
      visible: () => show.candidates,
    });
    candidateRods++;
  }

  // The chosen axis's rotation sense: a cone along the signed axis (right-hand rule: "ccw" is
  // positive about axis[1] − axis[0]) at the end it points to.
  const unitCone = cone(new Geometry(), [0, 0, 0], [0, 0, 1], 0.3);
  const arrowMatrix = new Map();
  for (const c of PLAN.candidates) {
    const d = v3.sub(c.axis[1], c.axis[0]);
    if (v3.len(d) === 0) continue;
    const u = v3.scale(v3.norm(d), c.direction === 'ccw' ? 1 : -1), [e1, e2] = basis(u);
    const tip = c.direction === 'ccw' ? c.axis[1] : c.axis[0];
    arrowMatrix.set(c.id, m4.frame(v3.scale(e1, 0.05), v3.scale(e2, 0.05), v3.scale(u, 0.05), tip));
  }
  r.add(unitCone, {
    color: color(COLORS.chosen), depthTest: false, order: 1,
    matrix: () => arrowMatrix.get(currentPlan.candidate),
    visible: () => show.candidates && currentPlan !== null && arrowMatrix.has(currentPlan.candidate),
  });

  // Arms: per DH frame one merged geometry of its link shapes; the gripper's three sets on
  // the flange; a kinematic skeleton when a model brings no link shapes.
  arms.forEach((arm, index) => {
    if (!arm) return;
    const linkColor = color(COLORS.arms[index % 2]);
    for (let f = 0; f <= 6; f++) {
      const g = new Geometry();
      for (const s of arm.model.links) if (s.frame === f) shapeGeometry(g, s);
      if (g.count > 0) r.add(g, { color: linkColor, matrix: () => arm.world[f] });
    }
    for (const [grip, shapes] of Object.entries(arm.gripperSets)) {
      const byFrame = new Map();
      for (const s of shapes || []) {
        if (!byFrame.has(s.frame)) byFrame.set(s.frame, new Geometry());
        shapeGeometry(byFrame.get(s.frame), s);
      }
      for (const [f, g] of byFrame) {
        r.add(g, { color: color(COLORS.gripper), matrix: () => arm.world[f], visible: () => arm.grip === grip });
      }
    }
    if (arm.model.links.length === 0) {
      // A kinematic skeleton instead: a unit segment mapped onto each pair of DH frame origins.
      const unit = new Geometry(true);
      unit.segment([0, 0, 0], [0, 0, 1]);
      for (let f = 0; f < 6; f++) {
        r.add(unit, {
          color: color(COLORS.skeleton),
          matrix: () => {
            const a = m4.position(arm.world[f]), d = v3.sub(m4.position(arm.world[f + 1]), a);
            const [e1, e2] = basis(v3.norm(d));
            return m4.frame(e1, e2, d, a);
          },
        });
      }
    }
    // The power-grasp dummy: the open gripper, translucent, on the part at P_obj.
    const dummy = new Geometry();
    for (const s of arm.model.gripper.open) shapeGeometry(dummy, s);
    r.add(dummy, {
      color: color(COLORS.dummy, 0.35),
      matrix: () => dummies[index],
      visible: () => show.dummies && Boolean(dummies[index]),
    });
  });
}

function viewSize() {
  const dpr = window.devicePixelRatio || 1;
  return { css: [ui.view.clientWidth, Math.max(ui.view.clientHeight, 1)], px: [Math.round(ui.view.clientWidth * dpr), Math.round(Math.max(ui.view.clientHeight, 1) * dpr)] };
}

function render() {
  if (!renderer) return;
  const { css, px } = viewSize();
  if (renderer.canvas.width !== px[0] || renderer.canvas.height !== px[1]) {
    renderer.canvas.width = px[0];
    renderer.canvas.height = px[1];
  }
  camera.update(css[0] / css[1]);
  renderer.draw(camera, px[0], px[1], rgb(COLORS.background));
  framesRendered++;
}

/** The candidate whose axis passes within 6 px of the mouse (nearest), or undefined. */
function pickCandidate(x, y) {
  const { css } = viewSize();
  let best, bestD = 6;
  for (const c of PLAN.candidates) {
    const a = camera.project(c.axis[0], css[0], css[1]), b = camera.project(c.axis[1], css[0], css[1]);
    if (!a || !b) continue;
    const ab = [b[0] - a[0], b[1] - a[1]], l2 = ab[0] * ab[0] + ab[1] * ab[1];
    const s = l2 > 0 ? Math.min(Math.max(((x - a[0]) * ab[0] + (y - a[1]) * ab[1]) / l2, 0), 1) : 0;
    const d = Math.hypot(a[0] + s * ab[0] - x, a[1] + s * ab[1] - y);
    if (d < bestD) { bestD = d; best = c; }
  }
  return best;
}

function setupMouse(canvas) {
  let drag = null;
  canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());
  canvas.addEventListener('pointerdown', (ev) => {
    drag = { x: ev.clientX, y: ev.clientY, pan: ev.button !== 0 || ev.shiftKey };
    canvas.setPointerCapture(ev.pointerId);
  });
  canvas.addEventListener('pointerup', (ev) => { drag = null; canvas.releasePointerCapture(ev.pointerId); });
  canvas.addEventListener('pointermove', (ev) => {
    if (drag) {
      const dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
      drag.x = ev.clientX;
      drag.y = ev.clientY;
      if (drag.pan) {
        const forward = v3.norm(v3.sub(camera.target, camera.eye));
        const right = v3.norm(v3.cross(forward, [0, 0, 1])), up = v3.cross(right, forward);
        const k = (camera.distance * 2 * Math.tan(camera.fovy / 2)) / Math.max(canvas.clientHeight, 1);
        camera.target = v3.add(camera.target, v3.add(v3.scale(right, -dx * k), v3.scale(up, dy * k)));
      } else {
        camera.azimuth -= dx * 0.008;
        camera.elevation = Math.min(Math.max(camera.elevation + dy * 0.008, -1.5), 1.5);
      }
      dirty = true;
      return;
    }
    const r = canvas.getBoundingClientRect();
    const c = show.candidates ? pickCandidate(ev.clientX - r.left, ev.clientY - r.top) : undefined;
    if (c) {
      const same = PLAN.candidates.filter((o) => o.axis[0].join() === c.axis[0].join() && o.axis[1].join() === c.axis[1].join());
      ui.tooltip.textContent = same.map(candidateText).join('\n');
      ui.tooltip.style.left = `${ev.clientX + 12}px`;
      ui.tooltip.style.top = `${ev.clientY + 12}px`;
      ui.tooltip.hidden = false;
      if (hovered !== c.id) highlightCandidates(c.id);
    } else if (!ui.tooltip.hidden) {
      ui.tooltip.hidden = true;
      highlightCandidates(-1);
    }
  });
  canvas.addEventListener('wheel', (ev) => {
    ev.preventDefault();
    camera.distance = Math.min(Math.max(camera.distance * Math.exp(ev.deltaY * 0.001), 0.1), 50);
    dirty = true;
  }, { passive: false });
  canvas.addEventListener('dblclick', () => { fitCamera(); dirty = true; });
}

// ---------- loop ----------

let lastFrame = performance.now();
function tick(now) {
  const dt = Math.min((now - lastFrame) / 1000, 0.1);
  lastFrame = now;
  if (playing) {
    const next = time + dt * Number(ui.speed.value || 1);
    applyTime(next);
    if (next >= timeline.total) setPlaying(false);
  }
  if (dirty) {
    render();
    dirty = false;
  }
  requestAnimationFrame(tick);
}

/** Largest distance (m) between the JS FK flange pose and Rust's FK for the embedded checks. */
function fkError() {
  let worst = 0;
  DATA.robots.forEach((model) => {
    if (!model || !model.known) return;
    for (const c of model.fk_check) {
      const f = fkFrames(model, c.q)[6];
      const expected = poseMatrix(c.flange);
      worst = Math.max(worst, v3.dist(m4.position(f), m4.position(expected)));
      // Rotation: compare the x and z axes as unit vectors.
      for (const col of [0, 2]) worst = Math.max(worst, v3.dist(m4.column(f, col), m4.column(expected, col)));
    }
  });
  return worst;
}

setupUi();
fitCamera();
if (renderer) {
  buildScene(renderer);
  setupMouse(renderer.canvas);
  window.addEventListener('resize', () => { dirty = true; });
}
selectPlan(Math.min(DATA.options.initial_plan, Math.max(PLAN.plans.length - 1, 0)));
setPlaying(Boolean(DATA.options.autoplay) && renderer !== null);

window.pregraspViewer = {
  get framesRendered() { return framesRendered; },
  /** Whether the page got a WebGL context (false: it shows a message instead of the view). */
  webgl: renderer !== null,
  duration: () => timeline.total,
  time: () => time,
  /** Jump to time t (s), pause, and render at once. Returns the segment name there. */
  setTime(t) { setPlaying(false); const st = applyTime(t); render(); return st.segment; },
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  selectPlan: (k) => selectPlan(k),
  planIndex: () => currentPlanIndex,
  /** Index of the robot that moves in the current plan's first segment (-1: none). */
  movingArm: () => (timeline.items.length ? timeline.items[0].robot : -1),
  /** Timeline time (s) at which the named segment of the current plan ends (NaN: absent). */
  segmentEnd: (name) => { const it = timeline.items.find((i) => i.seg.name === name); return it ? it.t1 : NaN; },
  /** World position [x, y, z] of arm i's flange (DH frame 6). */
  armTip: (i) => (arms[i] ? arms[i].tip() : null),
  /** World position of arm i's DH frame f (0 = base … 6 = flange). */
  armFrame: (i, f) => (arms[i] ? m4.position(arms[i].world[f]) : null),
  /** Canvas position (CSS px from its top left) of world point p, null if behind the eye. */
  project: (p) => { const { css } = viewSize(); return camera.project(p, css[0], css[1]); },
  /** Current joint vector of arm i. */
  armJoints: (i) => (arms[i] ? arms[i].q.slice() : null),
  /** Gripper shown on arm i: 'open', 'precision' (closed on the support grasp) or 'power'. */
  gripper: (i) => (arms[i] ? arms[i].grip : null),
  /** The panel's line of each closing's grip force for the current plan. */
  gripForces: () => ui.gripForces.textContent,
  /** World position of the part frame. */
  objectPosition: () => m4.position(part.matrix),
  fkError,
  /** Candidate axes drawn in the 3D view. */
  candidateCount: () => candidateRods,
  /** Candidate rows in the table. */
  candidateRows: () => ui.candidates.querySelectorAll('tbody tr').length,
  hullEdgeCount: () => DATA.hull_edges.length,
};
if (renderer) requestAnimationFrame((now) => { lastFrame = now; tick(now); });
