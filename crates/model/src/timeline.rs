//! The plan on one time line: what both arms, both grippers and the part do at every instant of
//! the four segments (μ_sup1, μ_rot, μ_mas1, μ_sup2). This module is the one place these rules
//! live; the planner, `pregrasp check`, the exports and the viewer's data all walk it.
//!
//! The rules (`docs/plan-format.md`, "Segments"): the segments run one after another, each
//! starting when the one before it ends. One arm moves per segment, linearly in joint space
//! between neighbouring points; the other arm holds its last configuration (`start` before its
//! first segment). A gripper is open at the start, opens when one of its `reach` / `regrasp`
//! segments begins and closes at that segment's last point; it stays closed through `rotate`.
//! The part sits at P_init until `rot`, follows `object_pose` during it (translation linear,
//! rotation slerp between points) and stays at P_obj after.
//!
//! Gripper–part contact is allowed only for a gripper that holds the part, and within the last
//! [`CONTACT_ZONE`] of a straight approach and the first [`CONTACT_ZONE`] of the `sup2` retreat.

use nalgebra::Isometry3;
use pregrasp_robot::{GripperState, Joints};

use crate::plan::{Closing, Plan, PlanSet};
use crate::terms::{GraspKind, PlanStatus, SegmentKind, SegmentName};

/// Length of the straight approach (and retreat) within which a gripper may touch the part it
/// closes on or releases (plan-format.md, rule 2): 2 cm.
pub const CONTACT_ZONE: f64 = 0.02;

/// Largest mismatch (rad) tolerated between where an arm is and the first point of its next
/// segment: the plan format has no jumps, a larger gap means a corrupt plan.
pub const CONTINUITY_TOL: f64 = 1e-6;

/// Everything the collision model needs at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct Moment {
    pub q: [Joints; 2],
    pub gripper: [GripperState; 2],
    /// The part's world pose.
    pub object: Isometry3<f64>,
    /// Whether gripper `i` may touch the part at this instant.
    pub contact_allowed: [bool; 2],
}

impl Moment {
    /// Both arms at `q` with their grippers open, the part at `object`, no contact allowed.
    pub fn at_rest(q: [Joints; 2], object: Isometry3<f64>) -> Moment {
        Moment {
            q,
            gripper: [GripperState::Open; 2],
            object,
            contact_allowed: [false; 2],
        }
    }

    /// The same moment with arm `arm` at `q` holding the part: gripper closed on it (`grip`,
    /// where its closing stopped), contact between that gripper and the part allowed.
    pub fn holding(mut self, arm: usize, q: Joints, grip: GripperState) -> Moment {
        self.q[arm] = q;
        self.gripper[arm] = grip;
        self.contact_allowed[arm] = true;
        self
    }
}

/// Interpolates two joint vectors linearly, `s` in `[0, 1]`.
pub fn lerp_joints(a: &Joints, b: &Joints, s: f64) -> Joints {
    let mut q = *a;
    for i in 0..6 {
        q[i] = a[i] + (b[i] - a[i]) * s;
    }
    q
}

/// Interpolates two poses: translation linearly, rotation by slerp, `s` in `[0, 1]`.
pub fn lerp_pose(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    a.lerp_slerp(b, s)
}

/// Number of sub-steps needed so that no point of the arm moves more than `resolution` per
/// step, given per-joint sweep radii `w` (any point moves at most Σ w_i |Δq_i|).
pub fn substeps(a: &Joints, b: &Joints, w: &Joints, resolution: f64) -> usize {
    let bound: f64 = (0..6).map(|i| w[i] * (b[i] - a[i]).abs()).sum();
    ((bound / resolution).ceil() as usize).max(1)
}

/// Why a plan cannot be laid on one time line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TimelineError {
    #[error("the plan file has status \"{status}\" and no plan to export ({})", reason.as_deref().unwrap_or("no reason given"))]
    NoPlan {
        status: PlanStatus,
        reason: Option<String>,
    },
    #[error("--plan {index} is out of range: the plan file has {count} plan(s), 0..{count}")]
    PlanIndex { index: usize, count: usize },
    #[error("plan cannot be exported: segment {segment}: its arm {arm} is not one of the plan's {arms} arms")]
    UnknownArm {
        segment: SegmentName,
        arm: usize,
        arms: usize,
    },
    #[error("plan cannot be exported: segment {segment}: no points")]
    NoPoints { segment: SegmentName },
    #[error("plan cannot be exported: segment {segment}: first point has t = {t} (must be 0)")]
    FirstTime { segment: SegmentName, t: f64 },
    #[error("plan cannot be exported: segment {segment}: point {point}: t does not grow")]
    TimeNotGrowing { segment: SegmentName, point: usize },
    #[error("plan cannot be exported: segment {segment}: point {point}: non-finite value")]
    NotFinite { segment: SegmentName, point: usize },
    #[error("plan cannot be exported: segment {segment}: point {point} has no object_pose")]
    NoObjectPose { segment: SegmentName, point: usize },
    #[error("plan cannot be exported: segment {segment}: first point is {gap:.3e} rad from where {arm} is")]
    Jump {
        segment: SegmentName,
        gap: f64,
        arm: String,
    },
}

/// A gripper command on the time line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GripEvent {
    /// Plan time (s).
    pub t: f64,
    /// `true`: close (on the part), `false`: open.
    pub close: bool,
    /// For a close: the segment's closing width (m), when the plan gives it.
    pub width: Option<f64>,
    /// For a close: where the 2F-85's fingers stop on the part, when the plan gives it (a jaw
    /// gripper's stop is its `width`).
    pub fingers: Option<GripperState>,
    /// For a close: the grip force (N) to close with, when its segment gives it
    /// ([`crate::Segment::grip_force`]).
    pub force: Option<f64>,
    /// The segment the command belongs to.
    pub segment: usize,
}

/// One arm on the time line.
#[derive(Clone, Debug)]
pub struct Arm {
    /// Index into [`PlanSet::arms`].
    pub index: usize,
    pub name: String,
    /// The arm's knots `(plan time, q)`, strictly increasing in time: `start` at 0, then the
    /// points of its segments (a segment's first point, equal to where the arm already is, is
    /// merged with the knot before it when the times coincide).
    pub knots: Vec<(f64, Joints)>,
    /// Gripper commands in time order.
    pub grip: Vec<GripEvent>,
}

/// One segment on the time line.
#[derive(Clone, Debug)]
pub struct Segment {
    pub name: SegmentName,
    pub kind: SegmentKind,
    /// Index into [`Timeline::arms`] (and [`PlanSet::arms`]).
    pub arm: usize,
    /// Plan time of the first point (s).
    pub t0: f64,
    /// The grasp the segment's gripper holds when it ends.
    pub grasp: GraspKind,
    /// How the gripper holds the part once closed.
    pub closing: Closing,
    /// The grip force (N) a closing segment closes with, when it gives it
    /// ([`crate::Segment::grip_force`]; [`Timeline::support_grip_force`] is the plan's pinch
    /// force, for a `sup1` without one).
    pub grip_force: Option<f64>,
    /// Points with plan times.
    pub points: Vec<(f64, Joints)>,
    /// Part poses at the points (`rot` only).
    pub object: Vec<Isometry3<f64>>,
}

impl Segment {
    /// Plan time of the last point (s).
    pub fn t_end(&self) -> f64 {
        self.points.last().map_or(self.t0, |p| p.0)
    }
}

/// One plan of a plan set on one time line.
#[derive(Clone, Debug)]
pub struct Timeline {
    pub arms: Vec<Arm>,
    pub segments: Vec<Segment>,
    pub support_height: f64,
    pub object_initial: Isometry3<f64>,
    pub object_goal: Isometry3<f64>,
    /// Plan time at the end of the last segment (s).
    pub duration: f64,
    /// The grip force (N) the plan's grip check recommends for the support grasp, when the
    /// plan carries one.
    pub support_grip_force: Option<f64>,
}

fn joint_gap(a: &Joints, b: &Joints) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Value at `t` of a piecewise-linear function given by strictly increasing knots (held
/// constant before the first and after the last). `knots` must not be empty.
pub fn sample_knots(knots: &[(f64, Joints)], t: f64) -> Joints {
    let first = knots.first().expect("at least one knot");
    if t <= first.0 {
        return first.1;
    }
    // The last knot with time <= t.
    let i = knots.partition_point(|k| k.0 <= t) - 1;
    if i + 1 >= knots.len() {
        return knots[i].1;
    }
    let (t0, q0) = &knots[i];
    let (t1, q1) = &knots[i + 1];
    if t == *t0 {
        return *q0;
    }
    lerp_joints(q0, q1, (t - t0) / (t1 - t0))
}

impl Timeline {
    /// Plan `index` of `set` on one time line. Refuses a set without plans, an index out of
    /// range, a segment naming no arm, and a plan whose segments are not continuous.
    pub fn new(set: &PlanSet, index: usize) -> Result<Timeline, TimelineError> {
        if set.status != PlanStatus::Planned || set.plans.is_empty() {
            return Err(TimelineError::NoPlan {
                status: set.status,
                reason: set.reason.clone(),
            });
        }
        let plan: &Plan = set.plans.get(index).ok_or(TimelineError::PlanIndex {
            index,
            count: set.plans.len(),
        })?;
        let mut arms: Vec<Arm> = set
            .arms
            .iter()
            .enumerate()
            .map(|(i, r)| Arm {
                index: i,
                name: r.name.clone(),
                knots: vec![(0.0, r.start)],
                grip: Vec::new(),
            })
            .collect();
        let mut segments = Vec::with_capacity(plan.segments.len());
        let mut t = 0.0_f64;
        for (si, seg) in plan.segments.iter().enumerate() {
            let segment = seg.name;
            if seg.arm >= arms.len() {
                return Err(TimelineError::UnknownArm {
                    segment,
                    arm: seg.arm,
                    arms: arms.len(),
                });
            }
            if seg.points.is_empty() {
                return Err(TimelineError::NoPoints { segment });
            }
            if seg.points[0].t != 0.0 {
                return Err(TimelineError::FirstTime {
                    segment,
                    t: seg.points[0].t,
                });
            }
            let mut points = Vec::with_capacity(seg.points.len());
            let mut object = Vec::new();
            for (k, p) in seg.points.iter().enumerate() {
                if k > 0 && p.t <= seg.points[k - 1].t {
                    return Err(TimelineError::TimeNotGrowing { segment, point: k });
                }
                if !p.t.is_finite() || p.q.iter().any(|x| !x.is_finite()) {
                    return Err(TimelineError::NotFinite { segment, point: k });
                }
                points.push((t + p.t, p.q));
                if seg.kind == SegmentKind::Rotate {
                    let pose = p
                        .object_pose
                        .ok_or(TimelineError::NoObjectPose { segment, point: k })?;
                    object.push(pose);
                }
            }
            let a = &mut arms[seg.arm];
            let (last_t, last_q) = *a.knots.last().expect("start knot");
            let gap = joint_gap(&last_q, &points[0].1);
            if gap > CONTINUITY_TOL {
                return Err(TimelineError::Jump {
                    segment,
                    gap,
                    arm: a.name.clone(),
                });
            }
            // The first point is where the arm already is: a hold knot at the segment start
            // (when time has passed since the arm's last knot) carries it to t.
            if t > last_t {
                a.knots.push((t, points[0].1));
            } else {
                a.knots.last_mut().expect("start knot").1 = points[0].1;
            }
            a.knots.extend(points.iter().skip(1).copied());
            let t_end = points.last().expect("non-empty").0;
            let grip_force = seg.grip_force;
            if seg.kind.closes_at_end() {
                a.grip.push(GripEvent {
                    t,
                    close: false,
                    width: None,
                    fingers: None,
                    force: None,
                    segment: si,
                });
                a.grip.push(GripEvent {
                    t: t_end,
                    close: true,
                    width: seg.closing.width,
                    fingers: seg.closing.fingers.map(GripperState::Closed),
                    force: grip_force,
                    segment: si,
                });
            }
            segments.push(Segment {
                name: seg.name,
                kind: seg.kind,
                arm: seg.arm,
                t0: t,
                grasp: seg.grasp,
                closing: seg.closing,
                grip_force,
                points,
                object,
            });
            t = t_end;
        }
        Ok(Timeline {
            arms,
            segments,
            support_height: set.support_height,
            object_initial: set.object.initial_pose,
            object_goal: plan.object_goal_pose,
            duration: t,
            support_grip_force: plan.support_grip_force,
        })
    }

    /// Joint angles of arm `arm` at plan time `t`.
    pub fn q_at(&self, arm: usize, t: f64) -> Joints {
        sample_knots(&self.arms[arm].knots, t)
    }

    /// Whether the gripper of arm `arm` is closed at plan time `t` (commands at `t` applied),
    /// and the width it holds when the plan gives it.
    pub fn gripper_at(&self, arm: usize, t: f64) -> (bool, Option<f64>) {
        let mut state = (false, None);
        for e in &self.arms[arm].grip {
            if e.t <= t {
                state = (e.close, e.width);
            }
        }
        state
    }

    /// The grip force (N) the gripper of arm `arm` holds the part with at plan time `t`
    /// (commands at `t` applied): the force of the close in effect, `None` while open or when
    /// its segment gives none.
    pub fn grip_force_at(&self, arm: usize, t: f64) -> Option<f64> {
        let mut force = None;
        for e in &self.arms[arm].grip {
            if e.t <= t {
                force = e.force.filter(|_| e.close);
            }
        }
        force
    }

    /// The part's world pose at plan time `t`.
    pub fn object_at(&self, t: f64) -> Isometry3<f64> {
        let Some(rot) = self.segments.iter().find(|s| s.kind == SegmentKind::Rotate) else {
            return self.object_initial;
        };
        if t <= rot.t0 {
            return rot.object.first().copied().unwrap_or(self.object_initial);
        }
        if t >= rot.t_end() {
            return rot.object.last().copied().unwrap_or(self.object_goal);
        }
        let i = rot.points.partition_point(|p| p.0 <= t) - 1;
        let (t0, t1) = (rot.points[i].0, rot.points[i + 1].0);
        lerp_pose(&rot.object[i], &rot.object[i + 1], (t - t0) / (t1 - t0))
    }

    /// Every plan-point time of every segment, sorted, without duplicates.
    pub fn point_times(&self) -> Vec<f64> {
        let mut times: Vec<f64> = self
            .segments
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.0))
            .collect();
        times.push(0.0);
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
    }
}
