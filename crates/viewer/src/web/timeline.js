// pregrasp plan viewer, part 3 of 4: the plan's timeline — segments end to end, and the state
// of the world at a time t, by the rules of docs/plan-format.md (the same ones the planner's
// crate::timeline and the exporters apply).


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

