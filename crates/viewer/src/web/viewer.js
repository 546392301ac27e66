// pregrasp plan viewer. Reads the JSON embedded in <script id="pregrasp-data">, draws the
// world (z up, metres) with a small WebGL renderer of its own (no library, no network: the
// page is one file) and animates the selected plan. Exposes `window.pregraspViewer` for
// tests and the console. Without WebGL the page says so and still lists the candidates.

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

// ---------- math: 3-vectors as arrays, 4×4 matrices column-major in Float64Array ----------

const v3 = {
  add: (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
  sub: (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]],
  scale: (a, s) => [a[0] * s, a[1] * s, a[2] * s],
  dot: (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2],
  cross: (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]],
  len: (a) => Math.hypot(a[0], a[1], a[2]),
  dist: (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]),
  norm: (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; },
  lerp: (a, b, s) => [a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s, a[2] + (b[2] - a[2]) * s],
};

/** Two unit vectors perpendicular to unit `u` and to each other (right-handed with u). */
function basis(u) {
  const e1 = v3.norm(v3.cross(Math.abs(u[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0], u));
  return [e1, v3.cross(u, e1)];
}

const m4 = {
  identity() { const m = new Float64Array(16); m[0] = m[5] = m[10] = m[15] = 1; return m; },
  /** a · b */
  mul(a, b) {
    const o = new Float64Array(16);
    for (let c = 0; c < 4; c++) {
      for (let r = 0; r < 4; r++) {
        o[4 * c + r] = a[r] * b[4 * c] + a[4 + r] * b[4 * c + 1] + a[8 + r] * b[4 * c + 2] + a[12 + r] * b[4 * c + 3];
      }
    }
    return o;
  },
  /** From a row-major 3×3 rotation and a translation. */
  rt(R, t) {
    const m = m4.identity();
    m[0] = R[0]; m[4] = R[1]; m[8] = R[2];
    m[1] = R[3]; m[5] = R[4]; m[9] = R[5];
    m[2] = R[6]; m[6] = R[7]; m[10] = R[8];
    m[12] = t[0]; m[13] = t[1]; m[14] = t[2];
    return m;
  },
  /** Columns x, y, z (each scaled) and origin o. */
  frame(x, y, z, o) {
    const m = m4.identity();
    m.set(x, 0); m.set(y, 4); m.set(z, 8); m.set(o, 12);
    return m;
  },
  /** Inverse of a rigid transform. */
  invRigid(m) {
    const R = [m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]]; // transpose, row-major
    const t = [m[12], m[13], m[14]];
    return m4.rt(R, [-v3.dot(R.slice(0, 3), t), -v3.dot(R.slice(3, 6), t), -v3.dot(R.slice(6, 9), t)]);
  },
  point: (m, p) => [
    m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12],
    m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13],
    m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14]],
  dir: (m, v) => [
    m[0] * v[0] + m[4] * v[1] + m[8] * v[2],
    m[1] * v[0] + m[5] * v[1] + m[9] * v[2],
    m[2] * v[0] + m[6] * v[1] + m[10] * v[2]],
  column: (m, c) => [m[4 * c], m[4 * c + 1], m[4 * c + 2]],
  position: (m) => [m[12], m[13], m[14]],
  perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2), m = new Float64Array(16);
    m[0] = f / aspect; m[5] = f; m[10] = (far + near) / (near - far); m[11] = -1;
    m[14] = (2 * far * near) / (near - far);
    return m;
  },
  lookAt(eye, target, up) {
    const z = v3.norm(v3.sub(eye, target)), x = v3.norm(v3.cross(up, z)), y = v3.cross(z, x);
    return m4.rt([...x, ...y, ...z], [-v3.dot(x, eye), -v3.dot(y, eye), -v3.dot(z, eye)]);
  },
};

/** Unit quaternion [x, y, z, w] (normalised here) as a row-major rotation matrix. */
function quatMatrix(q) {
  const n = Math.hypot(q[0], q[1], q[2], q[3]) || 1;
  const [x, y, z, w] = q.map((c) => c / n);
  return [
    1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
    2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
    2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)];
}

/** A pose JSON `{xyz, quat_xyzw}` as a matrix (parent <- child). */
const poseMatrix = (p) => m4.rt(quatMatrix(p.quat_xyzw), p.xyz);

function slerp(a, b, s) {
  const na = Math.hypot(...a) || 1, nb = Math.hypot(...b) || 1;
  a = a.map((c) => c / na);
  b = b.map((c) => c / nb);
  let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  if (d < 0) { b = b.map((c) => -c); d = -d; }
  if (d > 0.9995) return a.map((c, i) => c + (b[i] - c) * s);
  const th = Math.acos(d), sa = Math.sin((1 - s) * th) / Math.sin(th), sb = Math.sin(s * th) / Math.sin(th);
  return a.map((c, i) => sa * c + sb * b[i]);
}

const interpolatePose = (p0, p1, s) => m4.rt(quatMatrix(slerp(p0.quat_xyzw, p1.quat_xyzw, s)), v3.lerp(p0.xyz, p1.xyz, s));

/** Standard DH link transform T_i = Rz(θ)·Tz(d)·Tx(a)·Rx(α). */
function dhMatrix(theta, d, a, alpha) {
  const ct = Math.cos(theta), st = Math.sin(theta), ca = Math.cos(alpha), sa = Math.sin(alpha);
  return m4.rt([ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca], [a * ct, a * st, d]);
}

/** DH frames 0..=6 in the arm base frame: [0] = identity, [i] = T_1···T_i, [6] = flange. */
function fkFrames(dh, q) {
  const frames = [m4.identity()];
  for (let i = 0; i < 6; i++) frames.push(m4.mul(frames[i], dhMatrix(q[i], dh.d[i], dh.a[i], dh.alpha[i])));
  return frames;
}

const lerpJoints = (q0, q1, s) => q0.map((v, i) => v + (q1[i] - v) * s);

// ---------- geometry: triangle lists with normals, built on the CPU ----------

/** Triangles (`tri`: positions + normals per vertex) or line segments (`lines`: positions). */
class Geometry {
  constructor(lines = false) { this.lines = lines; this.p = []; this.n = []; }
  vertex(p, n) { this.p.push(p[0], p[1], p[2]); this.n.push(n[0], n[1], n[2]); }
  tri(a, b, c, na, nb = na, nc = na) { this.vertex(a, na); this.vertex(b, nb); this.vertex(c, nc); }
  // Lines are unlit; their normal only has to be a unit vector (a zero one would give NaN).
  segment(a, b) { this.vertex(a, [0, 0, 1]); this.vertex(b, [0, 0, 1]); }
  append(g) { this.p.push(...g.p); this.n.push(...g.n); return this; }
  get count() { return this.p.length / 3; }
}

const SEGMENTS = 20;

/** Side of a cylinder from a to b (no caps), radius r. */
function tube(g, a, b, r) {
  const u = v3.norm(v3.sub(b, a)), [e1, e2] = basis(u);
  for (let i = 0; i < SEGMENTS; i++) {
    const t0 = (2 * Math.PI * i) / SEGMENTS, t1 = (2 * Math.PI * (i + 1)) / SEGMENTS;
    const n0 = v3.add(v3.scale(e1, Math.cos(t0)), v3.scale(e2, Math.sin(t0)));
    const n1 = v3.add(v3.scale(e1, Math.cos(t1)), v3.scale(e2, Math.sin(t1)));
    const a0 = v3.add(a, v3.scale(n0, r)), a1 = v3.add(a, v3.scale(n1, r));
    const b0 = v3.add(b, v3.scale(n0, r)), b1 = v3.add(b, v3.scale(n1, r));
    g.tri(a0, a1, b1, n0, n1, n1);
    g.tri(a0, b1, b0, n0, n1, n0);
  }
  return g;
}

/** A flat disc at c, normal n, radius r. */
function disc(g, c, n, r) {
  const [e1, e2] = basis(n);
  for (let i = 0; i < SEGMENTS; i++) {
    const t0 = (2 * Math.PI * i) / SEGMENTS, t1 = (2 * Math.PI * (i + 1)) / SEGMENTS;
    const p0 = v3.add(c, v3.add(v3.scale(e1, r * Math.cos(t0)), v3.scale(e2, r * Math.sin(t0))));
    const p1 = v3.add(c, v3.add(v3.scale(e1, r * Math.cos(t1)), v3.scale(e2, r * Math.sin(t1))));
    g.tri(c, p0, p1, n);
  }
  return g;
}

function cylinder(g, a, b, r) {
  const u = v3.norm(v3.sub(b, a));
  tube(g, a, b, r);
  disc(g, a, v3.scale(u, -1), r);
  return disc(g, b, u, r);
}

function sphere(g, c, r) {
  const rings = 10;
  const at = (i, j) => {
    const th = (Math.PI * i) / rings, ph = (2 * Math.PI * j) / SEGMENTS;
    return [Math.sin(th) * Math.cos(ph), Math.sin(th) * Math.sin(ph), Math.cos(th)];
  };
  for (let i = 0; i < rings; i++) {
    for (let j = 0; j < SEGMENTS; j++) {
      const n00 = at(i, j), n01 = at(i, j + 1), n10 = at(i + 1, j), n11 = at(i + 1, j + 1);
      const p = (n) => v3.add(c, v3.scale(n, r));
      g.tri(p(n00), p(n10), p(n11), n00, n10, n11);
      g.tri(p(n00), p(n11), p(n01), n00, n11, n01);
    }
  }
  return g;
}

function capsule(g, a, b, r) {
  if (v3.dist(a, b) > 1e-9) tube(g, a, b, r);
  sphere(g, a, r);
  return sphere(g, b, r);
}

/** A box of half extents h posed by matrix m. */
function box(g, m, h) {
  for (let axis = 0; axis < 3; axis++) {
    for (const s of [-1, 1]) {
      const n = [0, 0, 0];
      n[axis] = s;
      const u = (axis + 1) % 3, v = (axis + 2) % 3;
      const corner = (cu, cv) => { const p = [0, 0, 0]; p[axis] = s * h[axis]; p[u] = cu * h[u]; p[v] = cv * h[v]; return m4.point(m, p); };
      const nw = m4.dir(m, n);
      g.tri(corner(-1, -1), corner(1, -1), corner(1, 1), nw);
      g.tri(corner(-1, -1), corner(1, 1), corner(-1, 1), nw);
    }
  }
  return g;
}

function cone(g, base, tip, r) {
  const u = v3.norm(v3.sub(tip, base)), [e1, e2] = basis(u);
  const slope = r / v3.dist(base, tip);
  for (let i = 0; i < SEGMENTS; i++) {
    const t0 = (2 * Math.PI * i) / SEGMENTS, t1 = (2 * Math.PI * (i + 1)) / SEGMENTS;
    const d0 = v3.add(v3.scale(e1, Math.cos(t0)), v3.scale(e2, Math.sin(t0)));
    const d1 = v3.add(v3.scale(e1, Math.cos(t1)), v3.scale(e2, Math.sin(t1)));
    const n0 = v3.norm(v3.add(d0, v3.scale(u, slope))), n1 = v3.norm(v3.add(d1, v3.scale(u, slope)));
    g.tri(v3.add(base, v3.scale(d0, r)), v3.add(base, v3.scale(d1, r)), tip, n0, n1, v3.norm(v3.add(n0, n1)));
  }
  return disc(g, base, v3.scale(u, -1), r);
}

/** One link or gripper shape (capsule, cylinder or cuboid) in its owning frame. */
function shapeGeometry(g, s) {
  if (s.kind === 'capsule') return capsule(g, s.a, s.b, s.radius);
  if (s.kind === 'cylinder') return cylinder(g, s.a, s.b, s.radius);
  if (s.kind === 'cuboid') return box(g, poseMatrix(s.pose), s.half_extents);
  console.warn(`shape ${s.name}: unknown kind ${s.kind}, not drawn`);
  return g;
}

/** The part mesh, flat shaded: one normal per triangle. */
function meshGeometry(mesh) {
  const g = new Geometry();
  const P = mesh.positions, I = mesh.indices;
  const at = (i) => [P[3 * i], P[3 * i + 1], P[3 * i + 2]];
  for (let k = 0; k + 2 < I.length; k += 3) {
    const a = at(I[k]), b = at(I[k + 1]), c = at(I[k + 2]);
    g.tri(a, b, c, v3.norm(v3.cross(v3.sub(b, a), v3.sub(c, a))));
  }
  return g;
}

// ---------- the WebGL renderer ----------

const VERTEX_SHADER = `
attribute vec3 aPos;
attribute vec3 aNormal;
uniform mat4 uModel;
uniform mat4 uViewProj;
uniform mat3 uNormal;
varying vec3 vWorld;
varying vec3 vNormal;
void main() {
  vec4 w = uModel * vec4(aPos, 1.0);
  vWorld = w.xyz;
  vNormal = uNormal * aNormal;
  gl_Position = uViewProj * w;
}`;

// Lambert with a sky/ground ambient; normals face the eye (two-sided, any winding).
const FRAGMENT_SHADER = `
precision mediump float;
uniform vec4 uColor;
uniform float uLit;
uniform vec3 uEye;
uniform vec3 uLight;
varying vec3 vWorld;
varying vec3 vNormal;
void main() {
  vec3 n = normalize(vNormal);
  if (dot(n, uEye - vWorld) < 0.0) n = -n;
  float sky = 0.5 + 0.5 * n.z;
  vec3 lit = uColor.rgb * (0.38 + 0.22 * sky + 0.5 * max(dot(n, uLight), 0.0));
  gl_FragColor = vec4(mix(uColor.rgb, lit, uLit), uColor.a);
}`;

class Renderer {
  /** Throws when WebGL is not available. */
  constructor(container) {
    this.canvas = document.createElement('canvas');
    container.appendChild(this.canvas);
    const options = { antialias: true, preserveDrawingBuffer: true };
    const gl = this.canvas.getContext('webgl', options) || this.canvas.getContext('experimental-webgl', options);
    if (!gl) {
      this.canvas.remove();
      throw new Error('this browser gives the page no WebGL context');
    }
    this.gl = gl;
    const compile = (type, text) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, text);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error('shader: ' + gl.getShaderInfoLog(s));
      return s;
    };
    const prog = gl.createProgram();
    gl.attachShader(prog, compile(gl.VERTEX_SHADER, VERTEX_SHADER));
    gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error('program: ' + gl.getProgramInfoLog(prog));
    gl.useProgram(prog);
    this.attr = { pos: gl.getAttribLocation(prog, 'aPos'), normal: gl.getAttribLocation(prog, 'aNormal') };
    this.uni = {};
    for (const u of ['uModel', 'uViewProj', 'uNormal', 'uColor', 'uLit', 'uEye', 'uLight']) this.uni[u] = gl.getUniformLocation(prog, u);
    gl.enableVertexAttribArray(this.attr.pos);
    gl.enableVertexAttribArray(this.attr.normal);
    gl.enable(gl.DEPTH_TEST);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.polygonOffset(1, 2);
    gl.uniform3fv(this.uni.uLight, v3.norm([0.4, -0.6, 1.0]));
    this.items = [];
  }

  /** Uploads a geometry; returns a handle for `add`. */
  upload(g) {
    const gl = this.gl, data = new Float32Array(g.p.length * 2);
    for (let i = 0; i < g.p.length; i++) data[2 * i - (i % 3)] = g.p[i];
    for (let i = 0; i < g.n.length; i++) data[2 * i - (i % 3) + 3] = g.n[i];
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return { buffer, count: g.count, lines: g.lines };
  }

  /**
   * Draws `geometry` every frame while `item.visible()`; `item.matrix()` is its world pose,
   * `item.color` [r, g, b, a] (or a function giving it); `depthTest` false (or a function
   * giving false) draws it over everything else.
   */
  add(geometry, item) {
    this.items.push(Object.assign({ lit: !geometry.lines, depthTest: true, visible: () => true, matrix: () => IDENTITY, order: 0 },
      item, { mesh: this.upload(geometry) }));
  }

  draw(camera, width, height, background) {
    const gl = this.gl;
    gl.viewport(0, 0, width, height);
    gl.clearColor(background[0], background[1], background[2], 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.uniformMatrix4fv(this.uni.uViewProj, false, new Float32Array(camera.viewProj));
    gl.uniform3fv(this.uni.uEye, camera.eye);
    // Opaque first, then translucent without depth writes, then what shows through.
    const value = (x) => (typeof x === 'function' ? x() : x);
    const visible = this.items.filter((it) => it.visible()).map((it) => {
      const color = value(it.color), depthTest = value(it.depthTest);
      return { it, color, depthTest, rank: (depthTest ? 0 : 2) + (color[3] < 1 ? 1 : 0) };
    }).sort((a, b) => a.rank - b.rank || a.it.order - b.it.order);
    for (const { it, color, depthTest } of visible) {
      const m = it.matrix();
      const translucent = color[3] < 1;
      gl.depthMask(!translucent);
      if (translucent) gl.enable(gl.BLEND); else gl.disable(gl.BLEND);
      if (depthTest) gl.enable(gl.DEPTH_TEST); else gl.disable(gl.DEPTH_TEST);
      // Surfaces with edges drawn on them sit a hair behind their lines.
      if (it.behindLines) gl.enable(gl.POLYGON_OFFSET_FILL); else gl.disable(gl.POLYGON_OFFSET_FILL);
      gl.uniformMatrix4fv(this.uni.uModel, false, new Float32Array(m));
      gl.uniformMatrix3fv(this.uni.uNormal, false, new Float32Array([m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]]));
      gl.uniform4fv(this.uni.uColor, color);
      gl.uniform1f(this.uni.uLit, it.lit ? 1 : 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, it.mesh.buffer);
      gl.vertexAttribPointer(this.attr.pos, 3, gl.FLOAT, false, 24, 0);
      gl.vertexAttribPointer(this.attr.normal, 3, gl.FLOAT, false, 24, 12);
      gl.drawArrays(it.mesh.lines ? gl.LINES : gl.TRIANGLES, 0, it.mesh.count);
    }
    gl.depthMask(true);
  }
}

const IDENTITY = m4.identity();

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
    this.world = fkFrames(this.model.dh, q).map((f) => m4.mul(this.base, f));
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

/** The grip a segment's arm has once the segment's last point is reached. */
const gripAfter = (seg) => (seg.grasp === 'power' ? 'power' : 'precision');

/**
 * The state of the world at time t: each arm's joints (linear interpolation between points;
 * an arm not moving holds its last configuration), its grip (open during reach and regrasp,
 * closed from a segment's last point on and while rotating: `precision` on the support
 * grasp, `power` on a power grasp) and the part pose (μ_rot's object_pose, then
 * object_goal_pose).
 */
function stateAt(plan, timeline, t) {
  const q = PLAN.robots.map((r) => r.start.slice());
  const grip = PLAN.robots.map(() => 'open');
  let object = pInit;
  let segment = timeline.items.length ? timeline.items[0].seg.name : '';
  for (const it of timeline.items) {
    const pts = it.seg.points;
    if (it.robot === undefined || pts.length === 0) continue;
    if (t >= it.t1) {
      q[it.robot] = pts[pts.length - 1].q;
      grip[it.robot] = gripAfter(it.seg);
      if (it.seg.kind === 'rotate') object = poseMatrix(plan.object_goal_pose);
      segment = it.seg.name;
      continue;
    }
    if (t < it.t0) break;
    segment = it.seg.name;
    const [i, s] = locate(pts, t - it.t0);
    const j = Math.min(i + 1, pts.length - 1);
    q[it.robot] = lerpJoints(pts[i].q, pts[j].q, s);
    grip[it.robot] = it.seg.kind === 'rotate' ? gripAfter(it.seg) : 'open';
    if (it.seg.kind === 'rotate' && pts[i].object_pose) {
      object = interpolatePose(pts[i].object_pose, pts[j].object_pose || pts[i].object_pose, s);
    }
    break;
  }
  return { q, grip, object, segment };
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
      const f = fkFrames(model.dh, c.q)[6];
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
