// pregrasp plan viewer. Reads the JSON embedded in <script id="pregrasp-data">, builds a
// three.js scene (world frame: z up, metres) and animates the selected plan.
// Exposes `window.pregraspViewer` for tests and the console.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const DATA = JSON.parse(document.getElementById('pregrasp-data').textContent);
const PLAN = DATA.plan;

const COLORS = {
  support: 0xd8d4cc,
  part: 0x8a9bb0,
  hull: 0x1f5fff,
  planned: 0xff8800,
  chosen: 0xffd400,
  rejected: 0xb08050,
  other: 0xffb060,
  arms: [0x9fb4d6, 0xd6b49f],
  gripper: 0x3b3b3b,
  dummy: 0x20c060,
};

// ---------- small math helpers ----------

/** A pose JSON `{xyz, quat_xyzw}` as a Matrix4 (parent <- child). */
function poseMatrix(p) {
  const m = new THREE.Matrix4();
  const q = new THREE.Quaternion(p.quat_xyzw[0], p.quat_xyzw[1], p.quat_xyzw[2], p.quat_xyzw[3]).normalize();
  m.compose(new THREE.Vector3(p.xyz[0], p.xyz[1], p.xyz[2]), q, new THREE.Vector3(1, 1, 1));
  return m;
}

/** Standard DH link transform T_i = Rz(θ)·Tz(d)·Tx(a)·Rx(α). */
function dhMatrix(theta, d, a, alpha) {
  const ct = Math.cos(theta), st = Math.sin(theta), ca = Math.cos(alpha), sa = Math.sin(alpha);
  return new THREE.Matrix4().set(
    ct, -st * ca, st * sa, a * ct,
    st, ct * ca, -ct * sa, a * st,
    0, sa, ca, d,
    0, 0, 0, 1);
}

/** DH frames 0..=6 in the arm base frame: [0] = identity, [i] = T_1···T_i, [6] = flange. */
function fkFrames(dh, q) {
  const frames = [new THREE.Matrix4()];
  for (let i = 0; i < 6; i++) {
    frames.push(frames[i].clone().multiply(dhMatrix(q[i], dh.d[i], dh.a[i], dh.alpha[i])));
  }
  return frames;
}

function lerpJoints(q0, q1, s) {
  return q0.map((v, i) => v + (q1[i] - v) * s);
}

// ---------- renderer, scene, camera ----------

const container = document.getElementById('view');
let renderer;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
} catch (e) {
  document.getElementById('status').textContent = 'WebGL is not available: ' + e.message;
  throw e;
}
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setSize(container.clientWidth, container.clientHeight);
container.appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf4f6f8);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8890a0, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(2, -3, 5);
scene.add(sun);

const camera = new THREE.PerspectiveCamera(45, container.clientWidth / container.clientHeight, 0.01, 100);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = false;

// ---------- static content: support, part, hull edges, candidates ----------

const pInit = poseMatrix(PLAN.object.initial_pose);
const sceneBox = new THREE.Box3();
sceneBox.expandByPoint(new THREE.Vector3().setFromMatrixPosition(pInit));
for (const r of PLAN.robots) sceneBox.expandByPoint(new THREE.Vector3(...r.base.xyz));
sceneBox.expandByScalar(0.6);
const sceneCentre = sceneBox.getCenter(new THREE.Vector3());
const sceneSize = sceneBox.getSize(new THREE.Vector3());

{
  const support = new THREE.Mesh(
    new THREE.PlaneGeometry(sceneSize.x, sceneSize.y),
    new THREE.MeshStandardMaterial({ color: COLORS.support, roughness: 0.9, side: THREE.DoubleSide }));
  support.position.set(sceneCentre.x, sceneCentre.y, PLAN.support_height - 0.0005);
  support.name = 'support';
  scene.add(support);
  const grid = new THREE.GridHelper(Math.ceil(Math.max(sceneSize.x, sceneSize.y)), Math.ceil(Math.max(sceneSize.x, sceneSize.y)) * 10, 0xb8b4ac, 0xc8c4bc);
  grid.rotation.x = Math.PI / 2;
  grid.position.set(sceneCentre.x, sceneCentre.y, PLAN.support_height);
  scene.add(grid);
}

const part = new THREE.Group();
part.name = 'part';
part.matrixAutoUpdate = false;
scene.add(part);
{
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(DATA.mesh.positions, 3));
  geometry.setIndex(DATA.mesh.indices);
  geometry.computeVertexNormals();
  part.add(new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({
    color: COLORS.part, flatShading: true, roughness: 0.6, metalness: 0.1, side: THREE.DoubleSide,
  })));
  const edges = new THREE.BufferGeometry();
  edges.setAttribute('position', new THREE.Float32BufferAttribute(DATA.hull_edges.flat(), 3));
  const hullLines = new THREE.LineSegments(edges, new THREE.LineBasicMaterial({ color: COLORS.hull }));
  hullLines.name = 'hull-edges';
  part.add(hullLines);
}

const candidateGroup = new THREE.Group();
scene.add(candidateGroup);
const candidateMeshes = new Map(); // candidate id -> mesh

function candidateColor(c) {
  if (c.outcome === 'planned') return COLORS.planned;
  if (c.outcome.startsWith('rejected')) return COLORS.rejected;
  return COLORS.other;
}

/** A cylinder from a to b (world), radius r. */
function rod(a, b, r, material) {
  const va = new THREE.Vector3(...a), vb = new THREE.Vector3(...b);
  const len = va.distanceTo(vb);
  const mesh = new THREE.Mesh(new THREE.CylinderGeometry(r, r, Math.max(len, 1e-6), 12), material);
  mesh.position.copy(va).add(vb).multiplyScalar(0.5);
  if (len > 0) mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), vb.clone().sub(va).normalize());
  return mesh;
}

for (const c of PLAN.candidates) {
  const material = new THREE.MeshStandardMaterial({ color: candidateColor(c), transparent: true, opacity: 0.85 });
  const mesh = rod(c.axis[0], c.axis[1], 0.004, material);
  mesh.userData.candidate = c;
  candidateMeshes.set(c.id, mesh);
  candidateGroup.add(mesh);
}

// ---------- robots ----------

/** A three.js mesh for one link shape (capsule or cuboid) in its owning frame. */
function shapeMesh(shape, material) {
  if (shape.kind === 'capsule') {
    const a = new THREE.Vector3(...shape.a), b = new THREE.Vector3(...shape.b);
    const len = a.distanceTo(b);
    const mesh = new THREE.Mesh(new THREE.CapsuleGeometry(shape.radius, len, 6, 16), material);
    mesh.position.copy(a).add(b).multiplyScalar(0.5);
    if (len > 0) mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
    return mesh;
  }
  const h = shape.half_extents;
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(2 * h[0], 2 * h[1], 2 * h[2]), material);
  mesh.matrixAutoUpdate = false;
  mesh.matrix.copy(poseMatrix(shape.pose));
  return mesh;
}

/** One arm: a base group at the base pose, 7 DH frame groups, link and gripper meshes. */
class Arm {
  constructor(robotJson, model, index) {
    this.json = robotJson;
    this.model = model;
    this.root = new THREE.Group();
    this.root.name = 'arm-' + robotJson.name;
    this.root.matrixAutoUpdate = false;
    this.root.matrix.copy(poseMatrix(robotJson.base));
    this.frames = [];
    for (let i = 0; i <= 6; i++) {
      const f = new THREE.Group();
      f.matrixAutoUpdate = false;
      this.frames.push(f);
      this.root.add(f);
    }
    const linkMaterial = new THREE.MeshStandardMaterial({ color: COLORS.arms[index % 2], roughness: 0.5 });
    for (const s of model.links) this.frames[s.frame].add(shapeMesh(s, linkMaterial));
    const gripperMaterial = new THREE.MeshStandardMaterial({ color: COLORS.gripper, roughness: 0.7 });
    this.open = new THREE.Group();
    this.closed = new THREE.Group();
    for (const s of model.gripper.open) this.open.add(shapeMesh(s, gripperMaterial));
    for (const s of model.gripper.closed) this.closed.add(shapeMesh(s, gripperMaterial));
    this.frames[6].add(this.open, this.closed);
    // Kinematic skeleton: segments between consecutive DH frame origins (always drawn, so
    // the arm shows even where a link shape is missing).
    this.skeleton = new THREE.LineSegments(
      new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(36), 3)),
      new THREE.LineBasicMaterial({ color: 0x404858 }));
    this.skeleton.frustumCulled = false;
    this.skeleton.visible = model.links.length === 0;
    this.root.add(this.skeleton);
    this.setState(robotJson.start, false);
  }

  setState(q, gripperClosed) {
    const frames = fkFrames(this.model.dh, q);
    for (let i = 0; i <= 6; i++) this.frames[i].matrix.copy(frames[i]);
    const pos = this.skeleton.geometry.attributes.position;
    for (let i = 0; i < 6; i++) {
      const a = new THREE.Vector3().setFromMatrixPosition(frames[i]);
      const b = new THREE.Vector3().setFromMatrixPosition(frames[i + 1]);
      pos.setXYZ(2 * i, a.x, a.y, a.z);
      pos.setXYZ(2 * i + 1, b.x, b.y, b.z);
    }
    pos.needsUpdate = true;
    this.open.visible = !gripperClosed;
    this.closed.visible = gripperClosed;
    this.q = q.slice();
    this.root.updateMatrixWorld(true);
  }

  /** World position of the flange (DH frame 6). */
  tip() {
    return new THREE.Vector3().setFromMatrixPosition(this.frames[6].matrixWorld).toArray();
  }
}

const arms = PLAN.robots.map((r, i) => {
  const model = DATA.robots[i];
  if (!model || !model.known) {
    console.warn(`robot ${r.name}: model ${r.model} unknown to the viewer, arm not drawn`);
    return null;
  }
  const arm = new Arm(r, model, i);
  scene.add(arm.root);
  return arm;
});
const robotIndex = new Map(PLAN.robots.map((r, i) => [r.name, i]));

// Power-grasp dummies: open grippers, translucent, at G_p,i on the part at P_obj.
const dummyGroup = new THREE.Group();
scene.add(dummyGroup);

function buildDummies(plan) {
  dummyGroup.clear();
  if (!plan) return;
  const goal = poseMatrix(plan.object_goal_pose);
  PLAN.robots.forEach((r, i) => {
    const model = DATA.robots[i];
    if (!model || !model.known) return;
    const flange = goal.clone()
      .multiply(poseMatrix(PLAN.grasps.power[i]))
      .multiply(poseMatrix(r.power_point).invert());
    const g = new THREE.Group();
    g.matrixAutoUpdate = false;
    g.matrix.copy(flange);
    const material = new THREE.MeshStandardMaterial({ color: COLORS.dummy, transparent: true, opacity: 0.35, depthWrite: false });
    for (const s of model.gripper.open) g.add(shapeMesh(s, material));
    dummyGroup.add(g);
  });
}

// The chosen axis's rotation sense: a cone along the signed axis (right-hand rule: "ccw" is
// positive about axis[1] − axis[0]) at the end it points to.
const arrowGroup = new THREE.Group();
scene.add(arrowGroup);

function buildArrow(plan) {
  arrowGroup.clear();
  const c = plan ? PLAN.candidates.find((x) => x.id === plan.candidate) : undefined;
  if (!c) return;
  const a = new THREE.Vector3(...c.axis[0]), b = new THREE.Vector3(...c.axis[1]);
  const dir = b.clone().sub(a);
  if (dir.lengthSq() === 0) return;
  dir.normalize();
  const tip = c.direction === 'ccw' ? b : a;
  if (c.direction !== 'ccw') dir.negate();
  const cone = new THREE.Mesh(new THREE.ConeGeometry(0.015, 0.05, 16),
    new THREE.MeshStandardMaterial({ color: COLORS.chosen, depthTest: false }));
  cone.renderOrder = 2;
  cone.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), dir);
  cone.position.copy(tip).addScaledVector(dir, 0.025);
  arrowGroup.add(cone);
}

// ---------- timeline ----------

/** Segments of one plan laid end to end: [{seg, robot, t0, t1}], and the total duration. */
function buildTimeline(plan) {
  const items = [];
  let t0 = 0;
  if (plan) {
    for (const seg of plan.segments) {
      const n = seg.points.length;
      const dur = n > 0 ? seg.points[n - 1].t : 0;
      items.push({ seg, robot: robotIndex.get(seg.robot), t0, t1: t0 + dur });
      t0 += dur;
    }
  }
  return { items, total: t0 };
}

/** Index i with pts[i].t <= t < pts[i+1].t (clamped), and the fraction between them. */
function locate(pts, t) {
  let lo = 0, hi = pts.length - 1;
  if (t <= pts[0].t) return [0, 0];
  if (t >= pts[hi].t) return [hi, 0];
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (pts[mid].t <= t) lo = mid; else hi = mid;
  }
  return [lo, (t - pts[lo].t) / (pts[lo + 1].t - pts[lo].t)];
}

function interpolatePose(p0, p1, s) {
  const m = new THREE.Matrix4();
  const a = new THREE.Vector3(...p0.xyz), b = new THREE.Vector3(...p1.xyz);
  const qa = new THREE.Quaternion(...p0.quat_xyzw).normalize(), qb = new THREE.Quaternion(...p1.quat_xyzw).normalize();
  m.compose(a.lerp(b, s), qa.slerp(qb, s), new THREE.Vector3(1, 1, 1));
  return m;
}

/**
 * The state of the world at time t: each arm's joints (linear interpolation between points;
 * an arm not moving holds its last configuration), its gripper (open during reach/regrasp,
 * closed from a segment's last point and while rotating) and the part pose (μ_rot's
 * object_pose, then object_goal_pose).
 */
function stateAt(plan, timeline, t) {
  const q = PLAN.robots.map((r) => r.start.slice());
  const closed = PLAN.robots.map(() => false);
  let object = pInit.clone();
  let segment = timeline.items.length ? timeline.items[0].seg.name : '';
  for (const it of timeline.items) {
    const pts = it.seg.points;
    if (it.robot === undefined || pts.length === 0) continue;
    if (t >= it.t1) {
      q[it.robot] = pts[pts.length - 1].q;
      closed[it.robot] = true;
      if (it.seg.kind === 'rotate') object = poseMatrix(plan.object_goal_pose);
      segment = it.seg.name;
      continue;
    }
    if (t < it.t0) break;
    segment = it.seg.name;
    const [i, s] = locate(pts, t - it.t0);
    const j = Math.min(i + 1, pts.length - 1);
    q[it.robot] = lerpJoints(pts[i].q, pts[j].q, s);
    closed[it.robot] = it.seg.kind === 'rotate';
    if (it.seg.kind === 'rotate' && pts[i].object_pose) {
      object = interpolatePose(pts[i].object_pose, (pts[j].object_pose || pts[i].object_pose), s);
    }
    break;
  }
  return { q, closed, object, segment };
}

// ---------- UI ----------

const ui = {
  status: document.getElementById('status'),
  planSelect: document.getElementById('plan-select'),
  play: document.getElementById('play'),
  slider: document.getElementById('timeline'),
  speed: document.getElementById('speed'),
  time: document.getElementById('time'),
  segment: document.getElementById('segment'),
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

const fmt = (x, d = 3) => (x === null || x === undefined ? '—' : Number(x).toFixed(d));
const deg = (x) => (x === null || x === undefined ? '—' : (x * 180 / Math.PI).toFixed(1) + '°');

function candidateText(c) {
  return `#${c.id} ${c.direction}  length ${fmt(c.length)} m  θ_max ${deg(c.theta_max)}  score ${fmt(c.score)}  θ_goal ${deg(c.theta_goal)}  ${c.outcome}`;
}

function highlightCandidates(hoverId) {
  dirty = true;
  const chosen = currentPlan ? currentPlan.candidate : -1;
  for (const [id, mesh] of candidateMeshes) {
    const c = mesh.userData.candidate;
    const isChosen = id === chosen, isHover = id === hoverId;
    mesh.material.color.setHex(isChosen ? COLORS.chosen : candidateColor(c));
    mesh.material.opacity = isChosen || isHover ? 1.0 : 0.85;
    // The chosen and hovered axes show through the part (an axis lies on its edge).
    mesh.material.depthTest = !(isChosen || isHover);
    mesh.renderOrder = isChosen || isHover ? 2 : 0;
    const s = isChosen ? 2.2 : isHover ? 1.8 : 1.0;
    mesh.scale.set(s, 1, s);
  }
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
  arms.forEach((arm, i) => arm && arm.setState(st.q[i], st.closed[i]));
  part.matrix.copy(st.object);
  part.updateMatrixWorld(true);
  ui.slider.value = timeline.total > 0 ? String(Math.round(1000 * time / timeline.total)) : '0';
  ui.time.textContent = `${time.toFixed(2)} / ${timeline.total.toFixed(2)} s`;
  ui.segment.textContent = currentPlan ? st.segment : '—';
  return st;
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
  buildDummies(currentPlan);
  buildArrow(currentPlan);
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
  ui.showHull.addEventListener('change', () => { part.getObjectByName('hull-edges').visible = ui.showHull.checked; });
  ui.showCandidates.addEventListener('change', () => {
    candidateGroup.visible = ui.showCandidates.checked;
    arrowGroup.visible = ui.showCandidates.checked;
  });
  ui.showDummies.addEventListener('change', () => { dummyGroup.visible = ui.showDummies.checked; });
  fillCandidateTable();

  // Hover tooltip for candidate axes in the 3D view.
  const raycaster = new THREE.Raycaster();
  const mouse = new THREE.Vector2();
  renderer.domElement.addEventListener('pointermove', (ev) => {
    const r = renderer.domElement.getBoundingClientRect();
    mouse.set(((ev.clientX - r.left) / r.width) * 2 - 1, -((ev.clientY - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(mouse, camera);
    const hit = candidateGroup.visible ? raycaster.intersectObjects([...candidateMeshes.values()])[0] : undefined;
    if (hit) {
      const c = hit.object.userData.candidate;
      const same = PLAN.candidates.filter((o) => o.axis[0].join() === c.axis[0].join() && o.axis[1].join() === c.axis[1].join());
      ui.tooltip.textContent = same.map(candidateText).join('\n');
      ui.tooltip.style.left = `${ev.clientX + 12}px`;
      ui.tooltip.style.top = `${ev.clientY + 12}px`;
      ui.tooltip.hidden = false;
      highlightCandidates(c.id);
    } else if (!ui.tooltip.hidden) {
      ui.tooltip.hidden = true;
      highlightCandidates(-1);
    }
  });
}

// ---------- camera and loop ----------

/** Looks at the part from beyond it, away from the arms' bases, from above and a little aside. */
function fitCamera() {
  const radius = Math.max(sceneSize.x, sceneSize.y, 1.0) * 0.75;
  const target = new THREE.Vector3().setFromMatrixPosition(pInit);
  target.z = PLAN.support_height + 0.2;
  const bases = new THREE.Vector3();
  for (const r of PLAN.robots) bases.add(new THREE.Vector3(...r.base.xyz).multiplyScalar(1 / PLAN.robots.length));
  const dir = new THREE.Vector3(target.x - bases.x, target.y - bases.y, 0);
  if (dir.lengthSq() < 1e-6) dir.set(1, -1, 0);
  dir.normalize().applyAxisAngle(new THREE.Vector3(0, 0, 1), 0.6);
  camera.position.copy(target).addScaledVector(dir, 1.5 * radius).add(new THREE.Vector3(0, 0, 1.1 * radius));
  controls.target.copy(target);
  controls.update();
}

function render() {
  renderer.render(scene, camera);
  framesRendered++;
}

function onResize() {
  camera.aspect = container.clientWidth / Math.max(container.clientHeight, 1);
  camera.updateProjectionMatrix();
  renderer.setSize(container.clientWidth, container.clientHeight);
  render();
}
window.addEventListener('resize', onResize);

// Frames are drawn while playing and after any change of view or state, not when idle.
controls.addEventListener('change', () => { dirty = true; });
for (const el of [ui.showHull, ui.showCandidates, ui.showDummies]) el.addEventListener('change', () => { dirty = true; });
renderer.domElement.addEventListener('pointermove', () => { dirty = true; });

let lastFrame = performance.now();
function tick(now) {
  const dt = Math.min((now - lastFrame) / 1000, 0.1);
  lastFrame = now;
  if (playing) {
    const next = time + dt * Number(ui.speed.value || 1);
    applyTime(next);
    if (next >= timeline.total) setPlaying(false);
    dirty = true;
  }
  controls.update();
  if (dirty) {
    render();
    dirty = false;
  }
  requestAnimationFrame(tick);
}

/** Largest distance (m) between the JS FK flange position and Rust's FK for the embedded checks. */
function fkError() {
  let worst = 0;
  DATA.robots.forEach((model) => {
    if (!model || !model.known) return;
    for (const c of model.fk_check) {
      const f = fkFrames(model.dh, c.q)[6];
      const expected = poseMatrix(c.flange);
      const a = new THREE.Vector3().setFromMatrixPosition(f), b = new THREE.Vector3().setFromMatrixPosition(expected);
      worst = Math.max(worst, a.distanceTo(b));
      // Rotation: compare the x and z axes as unit vectors.
      for (const col of [0, 2]) {
        const ea = new THREE.Vector3().setFromMatrixColumn(f, col), eb = new THREE.Vector3().setFromMatrixColumn(expected, col);
        worst = Math.max(worst, ea.distanceTo(eb));
      }
    }
  });
  return worst;
}

setupUi();
fitCamera();
selectPlan(Math.min(DATA.options.initial_plan, Math.max(PLAN.plans.length - 1, 0)));
setPlaying(Boolean(DATA.options.autoplay));

window.pregraspViewer = {
  get framesRendered() { return framesRendered; },
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
  /** Current joint vector of arm i. */
  armJoints: (i) => (arms[i] ? arms[i].q.slice() : null),
  /** World position of the part frame. */
  objectPosition: () => new THREE.Vector3().setFromMatrixPosition(part.matrix).toArray(),
  fkError,
  candidateCount: () => candidateMeshes.size,
  hullEdgeCount: () => DATA.hull_edges.length,
};
requestAnimationFrame((now) => { lastFrame = now; tick(now); });
