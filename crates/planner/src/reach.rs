//! Reach motions (paper §VI-B, `ReachPath1/2/3`): μ_sup1, μ_mas1 and μ_sup2.
//!
//! Each ends with a straight approach: the tool comes in along its own z axis from a stand-off
//! `approach_distance` back from the grasp. The approach is built backwards from the goal
//! configuration (IK with branch continuity), so the motion ends exactly at the configuration
//! the previous stages chose. μ_sup2 starts with the mirror image, a straight retreat from the
//! grasp it releases. The gripper may touch the part only within [`CONTACT_ZONE`] of the grasp;
//! the rest of the line, and the transit between start and stand-off (RRT-Connect, then
//! shortcutting), must keep clear of everything.

use nalgebra::{Isometry3, Translation3};
use pregrasp_motion::{
    rrt_connect_until, simplify_by, straight_line, time_parameterize, CartesianError,
    CartesianSettings, PlanStatus, RestToRest, RrtConnectSettings, State,
};
use std::sync::Mutex;

use pregrasp_collision::{Contact, WorldState};
use pregrasp_motion::StateValidator;
use pregrasp_robot::Joints;

use crate::context::{world_state, PlanningContext, FINE_RESOLUTION};
use crate::timing::{scaled, time_along, CONTACT_SCALE, TRANSIT_SCALE};
use pregrasp_model::timeline::{Moment, CONTACT_ZONE};

/// Iterations RRT-Connect may spend on one reach query (the deterministic stop).
pub const RRT_MAX_ITERATIONS: usize = 4000;

/// A timed reach motion of one arm.
#[derive(Clone, Debug)]
pub struct ReachMotion {
    pub q: Vec<Joints>,
    pub t: Vec<f64>,
    /// Index of the stand-off point where the straight approach begins.
    pub approach_from: usize,
    /// Index where the initial straight retreat ends (μ_sup2 only).
    pub retreat_to: Option<usize>,
}

/// Why a reach motion failed, by stage. A blocked straight line names the pair of bodies that
/// touched, when the line failed on a collision.
#[derive(Clone, Debug, PartialEq)]
pub enum ReachFailure {
    Retreat(CartesianError, Option<Contact>),
    Approach(CartesianError, Option<Contact>),
    Transit(PlanStatus),
}

/// The words after `"μ_sup1: "` (or the other reach motion's name) in the plan file.
impl std::fmt::Display for ReachFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let line = |f: &mut std::fmt::Formatter<'_>,
                    what: &str,
                    e: &CartesianError,
                    c: &Option<Contact>| match (e, c) {
            (CartesianError::Collision { .. }, Some(c)) => {
                write!(f, "straight {what}: {} touches {}", c.a, c.b)
            }
            _ => write!(f, "straight {what}: {e}"),
        };
        match self {
            ReachFailure::Retreat(e, c) => line(f, "retreat", e, c),
            ReachFailure::Approach(e, c) => line(f, "approach", e, c),
            ReachFailure::Transit(status) => write!(f, "transit motion: {status:?}"),
        }
    }
}

/// One reach query: arm `arm` moves from `from` to `goal`; everything else is as in `scene`.
pub struct ReachQuery<'a> {
    pub arm: usize,
    /// The rest of the world during the motion (this arm's entry of `q` is ignored).
    pub scene: &'a Moment,
    pub from: Joints,
    pub goal: Joints,
    /// Start with a straight retreat from the grasp held at `from` (μ_sup2).
    pub retreat: bool,
    pub seed: u64,
}

/// The straight pieces of a reach motion, validated: cheap and deterministic, so Algorithm 3
/// computes them for every combination before it spends time on any transit.
#[derive(Clone, Debug)]
pub struct ReachLines {
    /// From `from` to the end of the retreat (just `[from]` without a retreat).
    pub retreat: Vec<Joints>,
    /// From the stand-off to `goal`.
    pub approach: Vec<Joints>,
}

/// Shortcutting rounds after RRT-Connect (seeded; the greedy pass and waypoint removal run
/// regardless): one batch ([`pregrasp_motion::simplify::SHORTCUT_BATCH`]) whose candidates
/// are ranked by how much faster they make the transit as it is timed (rest to rest per edge,
/// [`RestToRest`]) and checked best first, the first valid one applied. A candidate that does
/// not pay costs no collision check.
pub const SHORTCUT_ROUNDS: usize = 8;

impl ReachQuery<'_> {
    /// This arm's states with everything else as in the query, with or without contact
    /// allowed between its gripper and the part; `touched` remembers the last contact found.
    fn validity<'v>(
        &self,
        ctx: &'v PlanningContext,
        contact: bool,
        touched: Option<&'v Mutex<Option<Contact>>>,
    ) -> ArmFree<'v> {
        let mut m = self.scene.clone();
        m.contact_allowed[self.arm] = contact;
        ArmFree {
            ctx,
            arm: self.arm,
            state: world_state(&m),
            touched,
        }
    }
}

/// Validity of one arm's states in a reach query (a [`StateValidator`] that also certifies
/// whole joint boxes, so straight edges far from everything cost a few checks).
struct ArmFree<'v> {
    ctx: &'v PlanningContext<'v>,
    arm: usize,
    /// The world with this arm's joints to be replaced.
    state: WorldState,
    touched: Option<&'v Mutex<Option<Contact>>>,
}

impl ArmFree<'_> {
    fn at(&self, q: &State<6>) -> WorldState {
        let mut s = self.state;
        s.q[self.arm] = *q;
        s
    }
}

impl StateValidator<6> for ArmFree<'_> {
    fn is_valid(&self, q: &State<6>) -> bool {
        match self.touched {
            None => self.ctx.world.is_arm_free(self.arm, &self.at(q)),
            Some(touched) => match self.ctx.world.check_arm(self.arm, &self.at(q)) {
                Ok(()) => true,
                Err(c) => {
                    *touched.lock().expect("not poisoned") = Some(c);
                    false
                }
            },
        }
    }

    fn is_valid_around(&self, q: &State<6>, reach: &State<6>) -> bool {
        // A box only spares its states their own checks (a failed one is split, down to states
        // checked exactly), so its primitives decide.
        self.ctx
            .world
            .is_arm_clear_within(self.arm, &self.at(q), reach)
    }

    fn around_limit(&self) -> f64 {
        pregrasp_collision::SWEEP_LIMIT
    }
}

/// The retreat (μ_sup2 only) and the approach of a reach query.
pub fn reach_lines(ctx: &PlanningContext, query: &ReachQuery) -> Result<ReachLines, ReachFailure> {
    let kin = &ctx.arm(query.arm).kin;
    // The line stops at the first invalid state: remember what touched there.
    let touched: Mutex<Option<Contact>> = Mutex::new(None);
    let strict = query.validity(ctx, false, Some(&touched));
    let touching = query.validity(ctx, true, Some(&touched));
    let strict_motion = ctx.motion_validator(query.arm, &strict);
    // Within the contact zone the gripper may be a few millimetres above the table.
    let contact_motion = ctx.motion_validator_at(query.arm, &touching, FINE_RESOLUTION);
    let fk = |q: &State<6>| kin.fk(q);
    let ik = |pose: &Isometry3<f64>, seed: &State<6>| kin.ik_nearest(pose, seed);
    let line = CartesianSettings {
        max_translation_step: 0.005,
        max_rotation_step: 2f64.to_radians(),
        max_joint_jump: 0.3,
    };
    let distance = ctx.scene.planner.approach_distance;
    let zone = CONTACT_ZONE.min(distance);
    let back = |q: &Joints, by: f64| kin.fk(q) * Translation3::new(0.0, 0.0, -by);

    // A straight line away from the grasp held at `q`: first `zone` with contact allowed,
    // then clear of everything, to the stand-off.
    let away = |q: &Joints| -> Result<Vec<Joints>, CartesianError> {
        let mut path = straight_line(fk, ik, &contact_motion, q, &back(q, zone), &line)?;
        if distance > zone {
            let mid = *path.last().expect("non-empty");
            let rest = straight_line(fk, ik, &strict_motion, &mid, &back(q, distance), &line)?;
            path.extend_from_slice(&rest[1..]);
        }
        Ok(path)
    };
    let retreat = if query.retreat {
        away(&query.from)
            .map_err(|e| ReachFailure::Retreat(e, touched.lock().expect("not poisoned").take()))?
    } else {
        vec![query.from]
    };
    let mut approach = away(&query.goal)
        .map_err(|e| ReachFailure::Approach(e, touched.lock().expect("not poisoned").take()))?;
    approach.reverse();
    Ok(ReachLines { retreat, approach })
}

/// Plans the transit between validated lines (RRT-Connect, then shortcutting) and times the
/// whole motion: straight pieces along their length, the transit rest-to-rest per edge. Where
/// `stop` holds before an iteration of the search or before the shortcutting, the motion is no
/// longer wanted and the transit ends with [`PlanStatus::Stopped`]; until then, `stop` changes
/// nothing.
pub fn reach_transit(
    ctx: &PlanningContext,
    query: &ReachQuery,
    lines: &ReachLines,
    stop: &dyn Fn() -> bool,
) -> Result<ReachMotion, ReachFailure> {
    let arm = query.arm;
    let strict = query.validity(ctx, false, None);
    let strict_motion = ctx.motion_validator(arm, &strict);
    let transit_from = *lines.retreat.last().expect("non-empty");
    let standoff = lines.approach[0];
    let model = ctx.arm(arm);
    let (speed, accel) = (model.max_joint_speed(), model.max_joint_accel());
    let transit_limits = RestToRest {
        vmax: scaled(&speed, TRANSIT_SCALE),
        amax: scaled(&accel, TRANSIT_SCALE),
    };
    let settings = RrtConnectSettings {
        max_iterations: RRT_MAX_ITERATIONS,
        max_time: None,
        range: 0.5,
        seed: query.seed,
        simplify: false,
    };
    let transit = if transit_from == standoff {
        vec![standoff]
    } else {
        let result = rrt_connect_until(
            &ctx.spaces[arm],
            &strict_motion,
            &transit_from,
            &standoff,
            &settings,
            stop,
        );
        if result.status != PlanStatus::Solved {
            return Err(ReachFailure::Transit(result.status));
        }
        if stop() {
            return Err(ReachFailure::Transit(PlanStatus::Stopped));
        }
        simplify_by(
            &strict_motion,
            &result.path,
            query.seed,
            SHORTCUT_ROUNDS,
            &transit_limits,
        )
    };

    let time_line = |path: &[Joints]| -> Vec<f64> {
        let n = (path.len() - 1).max(1) as f64;
        let u: Vec<f64> = (0..path.len()).map(|k| k as f64 / n).collect();
        time_along(
            path,
            &u,
            &scaled(&speed, CONTACT_SCALE),
            &scaled(&accel, CONTACT_SCALE),
        )
    };
    let mut q: Vec<Joints> = Vec::new();
    let mut t: Vec<f64> = Vec::new();
    let append = |q: &mut Vec<Joints>, t: &mut Vec<f64>, points: &[Joints], times: &[f64]| {
        let offset = t.last().copied().unwrap_or(0.0);
        let skip = usize::from(!q.is_empty());
        for k in skip..points.len() {
            q.push(points[k]);
            t.push(offset + times[k]);
        }
    };
    let retreat_to = if query.retreat {
        append(&mut q, &mut t, &lines.retreat, &time_line(&lines.retreat));
        Some(lines.retreat.len() - 1)
    } else {
        append(&mut q, &mut t, &lines.retreat, &[0.0]);
        None
    };
    let timed = time_parameterize(&transit, &transit_limits.vmax, &transit_limits.amax);
    append(&mut q, &mut t, &timed.q, &timed.t);
    let approach_from = q.len() - 1;
    append(&mut q, &mut t, &lines.approach, &time_line(&lines.approach));
    Ok(ReachMotion {
        q,
        t,
        approach_from,
        retreat_to,
    })
}

/// Plans a whole reach motion: (retreat), transit, approach.
pub fn reach(ctx: &PlanningContext, query: &ReachQuery) -> Result<ReachMotion, ReachFailure> {
    let lines = reach_lines(ctx, query)?;
    reach_transit(ctx, query, &lines, &|| false)
}
