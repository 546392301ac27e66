//! One plan walked segment by segment as the format defines it: structure and continuity (rule
//! 0), joint limits and speeds (rule 1), the states queued for the collision rule (rule 2) and
//! the gripper closing at every grasp; the motions themselves are in [`super::motions`].

use nalgebra::{Isometry3, Point3};
use pregrasp_collision::{ArmModel, CollisionWorld, ObjectPlacement, WorldState};
use pregrasp_model::{GraspKind, Plan, PlanSet, Segment, SegmentKind, SegmentName, Waypoint};
use pregrasp_robot::{GripperState, Joints};

use pregrasp_model::timeline::substeps;

use super::{
    HeldGrips, Rule, GRASP_ANGLE_TOLERANCE, GRASP_POSITION_TOLERANCE, ROUNDING_Q, ROUNDING_T,
};

/// Rule 4: a tool pose vs the grasp pose it should meet.
pub(super) fn grasp_error(rule: &mut Rule, dp: f64, da: f64, at: impl Fn() -> String) {
    let worst = (dp / GRASP_POSITION_TOLERANCE).max(da / GRASP_ANGLE_TOLERANCE);
    rule.value(worst, 1.0, || {
        format!("{}: {:.3} mm, {:.4} rad", at(), dp * 1e3, da)
    });
}

/// Pose error: (position error in m, rotation angle in rad).
pub(super) fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

pub(super) struct PlanCheck<'a> {
    pub(super) set: &'a PlanSet,
    pub(super) plan: &'a Plan,
    pub(super) index: usize,
    pub(super) arms: &'a [ArmModel; 2],
    pub(super) world: &'a CollisionWorld,
    /// How the grippers close at each grasp (`None`: a grip that cannot close, reported once).
    pub(super) grips: &'a Option<HeldGrips>,
    /// Closest a grasping gripper came to the support (m).
    pub(super) finger_support: &'a mut f64,
    /// The part's points that can be its lowest (its convex hull's vertices).
    pub(super) lowest_candidates: &'a [Point3<f64>],
    pub(super) structure: &'a mut Rule,
    pub(super) limits: &'a mut Rule,
    pub(super) collisions: &'a mut Rule,
    /// Rule 2 reports how many states it checked rather than a worst value.
    pub(super) states_checked: &'a mut u64,
    /// How many states of an open gripper next to its grasp were judged for penetration.
    pub(super) open_states: &'a mut u64,
    pub(super) rotation: &'a mut Rule,
    pub(super) grasps: &'a mut Rule,
    /// Whether the transits' states are checked or known free.
    pub(super) transits: super::Transits,
}

/// Edge `k → k+1` of a segment as (index of its end, number of checked sub-steps), so that no
/// arm point moves more than `resolution` between checked states; the last point is a single
/// state.
pub(super) fn edge(
    pts: &[Waypoint],
    k: usize,
    weights: &Joints,
    resolution: f64,
) -> (usize, usize) {
    if k + 1 < pts.len() {
        (
            k + 1,
            substeps(&pts[k].q, &pts[k + 1].q, weights, resolution),
        )
    } else {
        (k, 1)
    }
}

/// The states of one segment queued for rule 2, with their points `(k, f)`.
#[derive(Default)]
pub(super) struct Queued {
    pub(super) states: Vec<WorldState>,
    pub(super) at: Vec<(usize, f64)>,
}

impl Queued {
    /// An empty queue with room for `n` states: a segment's states are counted before they
    /// are queued, so the queue never grows (and copies its states) as they come.
    pub(super) fn with_capacity(n: usize) -> Self {
        Queued {
            states: Vec::with_capacity(n),
            at: Vec::with_capacity(n),
        }
    }
}

/// "plan I SEG point K", for messages.
pub(super) fn at(index: usize, seg: &Segment, k: usize) -> String {
    format!("plan {index} {} point {k}", seg.name)
}

impl<'a> PlanCheck<'a> {
    /// The name of arm `arm`, for messages.
    pub(super) fn name(&self, arm: usize) -> &str {
        self.set.arms.get(arm).map_or("?", |a| a.name.as_str())
    }

    pub(super) fn tool(&self, arm: usize, q: &Joints, precision: bool) -> Isometry3<f64> {
        let g = &self.arms[arm].gripper;
        let point = if precision {
            g.precision_point()
        } else {
            g.power_point()
        };
        self.arms[arm].flange_world(q) * point
    }

    pub(super) fn run(&mut self) {
        let index = self.index;
        let plan: &'a Plan = self.plan;
        if plan.segments.len() != 4 {
            self.structure.fail(format!(
                "plan {}: {} segments, expected 4",
                index,
                plan.segments.len()
            ));
            return;
        }
        let arms = self.set.arms.len();
        let (sup, mas) = (plan.roles.supportive, plan.roles.master);
        if sup >= arms || mas >= arms {
            self.structure
                .fail(format!("plan {}: master/supportive name no robot", index));
            return;
        }
        if sup == mas {
            self.structure.fail(format!(
                "plan {}: master and supportive are the same arm",
                index
            ));
            return;
        }
        for (seg, name) in plan.segments.iter().zip(SegmentName::ALL) {
            let kind = name.kind();
            let robot_ok = seg.arm == if name.by_master() { mas } else { sup };
            if seg.name != *name || seg.kind != kind || !robot_ok {
                self.structure.fail(format!(
                    "plan {}: segment \"{}\" ({}, robot {}) where {name} ({kind}) was expected",
                    index,
                    seg.name,
                    seg.kind,
                    self.name(seg.arm)
                ));
                return;
            }
            if let Err(e) = self.segment_structure(seg) {
                self.structure.fail(e);
                return;
            }
        }
        let Some(candidate) = self.set.candidates.iter().find(|c| c.id == plan.candidate) else {
            self.structure.fail(format!(
                "plan {}: candidate {} is not listed",
                index, plan.candidate
            ));
            return;
        };
        let axis: [Point3<f64>; 2] = candidate.axis;

        let p_init = self.set.object.initial_pose;
        let p_obj = plan.object_goal_pose;
        let g_s = self.set.grasps.support;
        let g_p = self.set.grasps.power;
        let mut q = [self.set.arms[0].start, self.set.arms[1].start];
        let mut gripper = [GripperState::Open; 2];
        let mut holding = [false; 2];
        let mut object = p_init;

        for seg in &plan.segments {
            let arm = if seg.name.by_master() { mas } else { sup };
            // Continuity: every segment starts where its arm is.
            let first = seg.points[0].q;
            let jump = (0..6)
                .map(|i| (first[i] - q[arm][i]).abs())
                .fold(0.0, f64::max);
            if jump > 1e-6 {
                self.structure.fail(format!(
                    "plan {} {}: starts {:.4} rad away from where arm {} is",
                    index,
                    seg.name,
                    jump,
                    self.name(arm)
                ));
                return;
            }
            self.check_limits(arm, seg);
            match seg.kind {
                SegmentKind::Rotate => {
                    gripper[arm] = self.held(arm, true);
                    holding[arm] = true;
                    self.check_rotation(arm, seg, &q, &gripper, &holding, &axis, &p_init, &g_s);
                    let last = seg.points.last().expect("≥ 2 points");
                    object = last.object_pose.unwrap_or(object);
                    // The planner proved the later transits with the part at P_obj exactly.
                    if object != p_obj {
                        self.transits = super::Transits::Checked;
                    }
                    let (dp, da) = pose_error(&object, &p_obj);
                    grasp_error(self.grasps, dp, da, || {
                        format!("plan {} rot: last object_pose vs object_goal_pose", index)
                    });
                }
                SegmentKind::Reach | SegmentKind::Regrasp => {
                    let precision = seg.name.grasp() == GraspKind::Support;
                    let goal = if precision {
                        object * g_s
                    } else {
                        object * g_p[arm]
                    };
                    gripper[arm] = GripperState::Open;
                    holding[arm] = false;
                    let closed = self.held(arm, precision);
                    self.check_reach(
                        arm, seg, &q, &gripper, &holding, &object, precision, &goal, closed,
                    );
                    gripper[arm] = closed;
                    holding[arm] = true;
                }
            }
            q[arm] = seg.points.last().expect("≥ 2 points").q;
        }
    }

    pub(super) fn segment_structure(&self, seg: &Segment) -> Result<(), String> {
        let index = self.index;
        let n = seg.points.len();
        if n < 2 {
            return Err(format!("plan {} {}: fewer than 2 points", index, seg.name));
        }
        if seg.points[0].t != 0.0 {
            return Err(format!(
                "plan {} {}: t does not start at 0",
                index, seg.name
            ));
        }
        for k in 1..n {
            let (t0, t1) = (seg.points[k - 1].t, seg.points[k].t);
            if t1.is_nan() || t1 <= t0 {
                return Err(format!(
                    "{}: t does not increase strictly",
                    at(index, seg, k)
                ));
            }
        }
        if seg.points.iter().flat_map(|p| p.q).any(|x| !x.is_finite()) {
            return Err(format!(
                "plan {} {}: a joint value is not finite",
                index, seg.name
            ));
        }
        let approach = seg.approach_from;
        if seg.kind != SegmentKind::Rotate && approach.is_none_or(|a| a >= n) {
            return Err(format!(
                "plan {} {}: approach_from missing or out of range",
                index, seg.name
            ));
        }
        if seg.kind == SegmentKind::Regrasp {
            match (seg.retreat_to, approach) {
                (Some(r), Some(a)) if r <= a => {}
                _ => {
                    return Err(format!(
                        "plan {} {}: retreat_to missing or after approach_from",
                        index, seg.name
                    ))
                }
            }
        }
        if seg.kind == SegmentKind::Rotate && seg.points.iter().any(|p| p.object_pose.is_none()) {
            return Err(format!("plan {} rot: a point has no object_pose", index));
        }
        Ok(())
    }

    /// Rule 1: joint limits at every point, joint speeds between neighbouring points. A plan
    /// written by another tool may round its numbers ([`ROUNDING_T`], [`ROUNDING_Q`]): a speed
    /// counts as over the limit only if it is over it for every time stamp and joint value
    /// those numbers may have stood for — the joint change shrunk by twice the joint rounding,
    /// the interval grown by twice the time rounding.
    pub(super) fn check_limits(&mut self, arm: usize, seg: &Segment) {
        let index = self.index;
        let model = &self.arms[arm];
        let lim = model.joint_limits();
        let vmax = model.max_joint_speed();
        for (k, p) in seg.points.iter().enumerate() {
            for (j, &(lo, hi)) in lim.iter().enumerate() {
                // Fraction of the way from the middle of the range to a limit.
                let mid = 0.5 * (lo + hi);
                let frac = ((p.q[j] - mid).abs() - ROUNDING_Q).max(0.0) / (0.5 * (hi - lo));
                self.limits.value(frac, 1.0, || {
                    format!("{} joint {} position", at(index, seg, k), j + 1)
                });
            }
            if k > 0 {
                let prev = &seg.points[k - 1];
                let dt = p.t - prev.t + 2.0 * ROUNDING_T;
                for (j, v) in vmax.iter().enumerate() {
                    let dq = ((p.q[j] - prev.q[j]).abs() - 2.0 * ROUNDING_Q).max(0.0);
                    let frac = dq / dt / v;
                    self.limits.value(frac * (1.0 - 1e-9), 1.0, || {
                        format!("{} joint {} speed", at(index, seg, k), j + 1)
                    });
                }
            }
        }
    }

    pub(super) fn state(
        &self,
        q: [Joints; 2],
        gripper: [GripperState; 2],
        object: Isometry3<f64>,
        contact: [bool; 2],
    ) -> WorldState {
        WorldState {
            q,
            gripper,
            object: ObjectPlacement::Fixed(object),
            grasping: contact,
        }
    }

    /// Rule 2 at one state: queued for [`collide_all`](Self::collide_all) with its point.
    /// The fingers of arm `arm` holding G_s (`support`) or its power grasp.
    pub(super) fn held(&self, arm: usize, support: bool) -> GripperState {
        match self.grips {
            Some(g) if support => g.support[arm].state(),
            Some(g) => g.power[arm].state(),
            None => GripperState::fully_closed(),
        }
    }

    /// Rule 2 for the closing itself: the fingers of arm `arm`, closing at the last point
    /// `q` of `seg` on G_s (`support`) or its power grasp, keep the finger–support clearance
    /// in every pose they pass through ([`Grip::lowest`]).
    pub(super) fn check_closing(&mut self, arm: usize, seg: &Segment, q: &Joints, support: bool) {
        let Some(grips) = self.grips else {
            return;
        };
        let grip = if support {
            &grips.support[arm]
        } else {
            &grips.power[arm]
        };
        let flange = self.arms[arm].flange_world(q);
        let above = grip.lowest(&flange) - self.set.support_height;
        *self.finger_support = self.finger_support.min(above);
        let clearance = self.world.grasp_support_margin();
        if above < clearance {
            let n = seg.points.len();
            self.collisions.fail(format!(
                "{}: the closing fingers of arm {} come {:.2} mm from the support (clearance {:.2} mm)",
                at(self.index, seg, n - 1),
                self.name(arm),
                above * 1e3,
                clearance * 1e3
            ));
        }
    }

    pub(super) fn collide(&mut self, state: WorldState, at: (usize, f64), queue: &mut Queued) {
        *self.states_checked += 1;
        queue.states.push(state);
        queue.at.push(at);
    }

    /// Rule 2 at every queued state of a segment in which arm `moving` moves, in order: the
    /// first in contact is reported as `what` at its point `(k, f)`, and the closest the
    /// moving gripper came to the support while grasping is recorded. Both are exact over the
    /// states, found by ranges in one pass ([`CollisionWorld::check_states`]).
    pub(super) fn collide_all(
        &mut self,
        moving: usize,
        queue: &Queued,
        what: impl Fn(usize, f64) -> String,
    ) {
        let found = crate::halves::check_states(self.world, &queue.states);
        if let Some(d) = found.closest_grasp[moving] {
            *self.finger_support = self.finger_support.min(d);
        }
        if let Some(i) = found.first_contact {
            let c = self
                .world
                .check(&queue.states[i])
                .expect_err("the first state in contact");
            let (k, f) = queue.at[i];
            self.collisions
                .fail(format!("{}: {} touches {}", what(k, f), c.a, c.b));
        }
    }
}
