// pregrasp plan viewer, part 1 of 4 (html.rs joins math.js, renderer.js, timeline.js, viewer.js
// into one script): 3-vectors and 4×4 matrices, poses and UR forward kinematics, and the triangle
// geometry of the shapes drawn.

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

/** Rotation by angle t about the unit axis u, as a matrix. */
function axisAngleMatrix(u, t) {
  const s = Math.sin(t / 2);
  return m4.rt(quatMatrix([u[0] * s, u[1] * s, u[2] * s, Math.cos(t / 2)]), [0, 0, 0]);
}

/**
 * Frames 0..=6 of an arm model in its base frame, [6] = flange. A built-in arm by its DH rows
 * ([0] = identity, [i] = T_1···T_i); an arm from a robot description by its chain steps:
 * [0] = frame0, [i+1] = [i]·Rot(axis_i, q_i)·link_i.
 */
function fkFrames(model, q) {
  const c = model.chain;
  if (c) {
    const frames = [poseMatrix(c.frame0)];
    for (let i = 0; i < 6; i++) {
      frames.push(m4.mul(m4.mul(frames[i], axisAngleMatrix(c.axes[i], q[i])), poseMatrix(c.links[i])));
    }
    return frames;
  }
  const dh = model.dh;
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

/** A convex piece: its hull's triangles, flat shaded. */
function hull(g, positions, triangles) {
  for (const [i, j, k] of triangles) {
    const a = positions[i], b = positions[j], c = positions[k];
    g.tri(a, b, c, v3.norm(v3.cross(v3.sub(b, a), v3.sub(c, a))));
  }
  return g;
}

/** One link or gripper shape (capsule, cylinder, cuboid or hull) in its owning frame. */
function shapeGeometry(g, s) {
  if (s.kind === 'hull') return hull(g, s.positions, s.triangles);
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

