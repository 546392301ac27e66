//! The plan as one time line, shared by every format.
//!
//! Plan time: the four segments played one after another, each starting when the one before it
//! ends (`docs/plan-format.md`, "Segments"). An arm moves only in the segments that name it,
//! linearly in joint space between neighbouring points, and holds still otherwise (at `start`
//! before its first segment). Its gripper is open at the start, opens when one of its `reach` /
//! `regrasp` segments begins and closes at that segment's last point. The part sits at
//! `initial_pose` until `rot`, follows `object_pose` during it (translation linear, rotation
//! slerp between points, as the checker interpolates) and stays at `object_goal_pose` after.

use nalgebra::Isometry3;
use pregrasp_io::plan_file::{
    GraspKind, PlanFile, PlanJson, PlanStatus, RobotModel, SegmentKind, SegmentName,
};
use pregrasp_robot::{GripperState, Joints, UrModel};

use crate::ExportError;

/// Largest mismatch (rad) tolerated between where an arm is and the first point of its next
/// segment: the plan format has no jumps, a larger gap means a corrupt plan.
pub const CONTINUITY_TOL: f64 = 1e-6;

/// A gripper command on the time line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GripEvent {
    /// Plan time (s).
    pub t: f64,
    /// `true`: close (on the part), `false`: open.
    pub close: bool,
    /// For a close: the segment's `grip_width` (m), when the plan gives it.
    pub width: Option<f64>,
    /// For a close: where the 2F-85's fingers stop on the part, when the plan gives it (a jaw
    /// gripper's stop is its `width`).
    pub fingers: Option<GripperState>,
    /// The segment the command belongs to.
    pub segment: usize,
}

/// One arm of the plan.
#[derive(Clone, Debug)]
pub struct Arm {
    pub name: String,
    pub model: RobotModel,
    /// The plan's names of the six joints, base to flange.
    pub joint_names: Vec<String>,
    /// Base pose in the world.
    pub base: Isometry3<f64>,
    pub start: Joints,
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
    /// Index into [`Timeline::arms`].
    pub arm: usize,
    /// Plan time of the first point (s).
    pub t0: f64,
    /// The grasp the segment's gripper holds when it ends.
    pub grasp: GraspKind,
    pub grip_width: Option<f64>,
    /// The segment's `fingers`, when the plan gives them (where the closing stops).
    pub fingers: Option<pregrasp_io::plan_file::FingersJson>,
    /// Points with plan times.
    pub points: Vec<(f64, Joints)>,
    /// Object poses at the points (`rot` only).
    pub object: Vec<Isometry3<f64>>,
}

impl Segment {
    /// Plan time of the last point (s).
    pub fn t_end(&self) -> f64 {
        self.points.last().map_or(self.t0, |p| p.0)
    }
}

/// The chosen plan of a plan file on one time line.
#[derive(Clone, Debug)]
pub struct Timeline {
    pub arms: Vec<Arm>,
    pub segments: Vec<Segment>,
    pub support_height: f64,
    pub object_initial: Isometry3<f64>,
    pub object_goal: Isometry3<f64>,
    /// Plan time at the end of the last segment (s).
    pub duration: f64,
    /// The grip force (N) the plan's quasi-static check recommends for the support grasp
    /// (`physics.grip_force_recommended`), when the plan carries one.
    pub support_grip_force: Option<f64>,
}

fn joint_gap(a: &Joints, b: &Joints) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Linear interpolation of two joint vectors.
pub fn lerp(a: &Joints, b: &Joints, s: f64) -> Joints {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * s)
}

/// Value at `t` of a piecewise-linear function given by strictly increasing knots (held
/// constant before the first and after the last).
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
    lerp(q0, q1, (t - t0) / (t1 - t0))
}

impl Timeline {
    /// Each arm's built-in model, or [`ExportError::NotUr`] for `format` (which needs them,
    /// for `why`).
    pub fn ur_models(
        &self,
        format: &'static str,
        why: &'static str,
    ) -> Result<Vec<UrModel>, ExportError> {
        self.arms
            .iter()
            .map(|a| {
                a.model.builtin().ok_or_else(|| ExportError::NotUr {
                    arm: a.name.clone(),
                    format,
                    why,
                })
            })
            .collect()
    }

    /// The plan `index` of `file` on one time line. Refuses a plan file without plans, an index
    /// out of range, unknown robots or models, and a plan whose segments are not continuous.
    pub fn new(file: &PlanFile, index: usize) -> Result<Timeline, ExportError> {
        if file.status != PlanStatus::Planned || file.plans.is_empty() {
            return Err(ExportError::NoPlan {
                status: file.status,
                reason: file
                    .reason
                    .clone()
                    .unwrap_or_else(|| "no reason given".into()),
            });
        }
        let plan: &PlanJson = file.plans.get(index).ok_or(ExportError::PlanIndex {
            index,
            count: file.plans.len(),
        })?;
        let mut arms = Vec::with_capacity(file.robots.len());
        for r in &file.robots {
            let model = r.model;
            arms.push(Arm {
                name: r.name.clone(),
                model,
                joint_names: r.joint_names.clone(),
                base: r.base.to_isometry(),
                start: r.start,
                knots: vec![(0.0, r.start)],
                grip: Vec::new(),
            });
        }
        let mut segments = Vec::with_capacity(plan.segments.len());
        let mut t = 0.0_f64;
        for (si, seg) in plan.segments.iter().enumerate() {
            let arm = arms
                .iter()
                .position(|a| a.name == seg.robot)
                .ok_or_else(|| {
                    ExportError::Plan(format!(
                        "segment {}: robot {:?} is not in `robots`",
                        seg.name, seg.robot
                    ))
                })?;
            if seg.points.is_empty() {
                return Err(ExportError::Plan(format!(
                    "segment {}: no points",
                    seg.name
                )));
            }
            if seg.points[0].t != 0.0 {
                return Err(ExportError::Plan(format!(
                    "segment {}: first point has t = {} (must be 0)",
                    seg.name, seg.points[0].t
                )));
            }
            let mut points = Vec::with_capacity(seg.points.len());
            let mut object = Vec::new();
            for (k, p) in seg.points.iter().enumerate() {
                if k > 0 && p.t <= seg.points[k - 1].t {
                    return Err(ExportError::Plan(format!(
                        "segment {}: point {k}: t does not grow",
                        seg.name
                    )));
                }
                if !p.t.is_finite() || p.q.iter().any(|x| !x.is_finite()) {
                    return Err(ExportError::Plan(format!(
                        "segment {}: point {k}: non-finite value",
                        seg.name
                    )));
                }
                points.push((t + p.t, p.q));
                if seg.kind == SegmentKind::Rotate {
                    let pose = p.object_pose.as_ref().ok_or_else(|| {
                        ExportError::Plan(format!(
                            "segment {}: point {k} has no object_pose",
                            seg.name
                        ))
                    })?;
                    object.push(pose.to_isometry());
                }
            }
            let a = &mut arms[arm];
            let (last_t, last_q) = *a.knots.last().expect("start knot");
            let gap = joint_gap(&last_q, &points[0].1);
            if gap > CONTINUITY_TOL {
                return Err(ExportError::Plan(format!(
                    "segment {}: first point is {gap:.3e} rad from where {} is",
                    seg.name, a.name
                )));
            }
            // The first point is where the arm already is: a hold knot at the segment start
            // (when time has passed since the arm's last knot) carries it to t.
            if t > last_t {
                a.knots.push((t, points[0].1));
            } else {
                a.knots.last_mut().expect("start knot").1 = points[0].1;
            }
            a.knots.extend(points.iter().skip(1).copied());
            if seg.kind.closes_at_end() {
                a.grip.push(GripEvent {
                    t,
                    close: false,
                    width: None,
                    fingers: None,
                    segment: si,
                });
                a.grip.push(GripEvent {
                    t: points.last().expect("non-empty").0,
                    close: true,
                    width: seg.grip_width,
                    fingers: seg.fingers.as_ref().map(|f| {
                        GripperState::Closed(pregrasp_robot::FingerPair {
                            driver: f.driver,
                            spring_link: f.spring_link,
                        })
                    }),
                    segment: si,
                });
            }
            let t_end = points.last().expect("non-empty").0;
            segments.push(Segment {
                name: seg.name,
                kind: seg.kind,
                arm,
                t0: t,
                grasp: seg.grasp,
                grip_width: seg.grip_width,
                fingers: seg.fingers,
                points,
                object,
            });
            t = t_end;
        }
        Ok(Timeline {
            arms,
            segments,
            support_height: file.support_height,
            object_initial: file.object.initial_pose.to_isometry(),
            object_goal: plan.object_goal_pose.to_isometry(),
            duration: t,
            support_grip_force: plan.physics.as_ref().and_then(|p| p.grip_force_recommended),
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
        rot.object[i].lerp_slerp(&rot.object[i + 1], (t - t0) / (t1 - t0))
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

    /// Index of the arm called `name`.
    pub fn arm_index(&self, name: &str) -> Option<usize> {
        self.arms.iter().position(|a| a.name == name)
    }
}
