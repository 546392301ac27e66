//! `pregrasp check`: re-verifies a plan file, with the project's own models, against every rule
//! of plan-format.md, "What a valid plan satisfies". It needs nothing but the plan file and the
//! object mesh it names: the arms, tool frames, grasps and poses all come from the file.
//!
//! Motions are checked as the format defines them — linear in joint space between neighbouring
//! points (the object's pose interpolated by slerp during `rot`) — at [`CHECK_RESOLUTION`]: no
//! point of a moving arm travels farther than that between two checked states, and at
//! [`FINE_CHECK_RESOLUTION`] where a gripper grasps (μ_rot, the last 2 cm of an approach and the
//! first 2 cm of a retreat). Rule 2 is applied with the clearances the plan's `planner` echo
//! states (`link_clearance`, `finger_support_clearance`; defaults when absent), on the same
//! link and gripper shapes as the planner, each gripper closed on the part at the width it
//! closes on — measured here again from the mesh, not read from the file. Where a gripper may
//! touch the part it grasps with its hand open (the approach's contact zone, the grasp before
//! the closing, the start of `sup2`'s retreat) it must not be inside it: no open link deeper
//! than [`OPEN_CONTACT_DEPTH`] (`open.rs`).

use std::path::Path;
use std::sync::Arc;

use nalgebra::Point3;
use pregrasp_collision::{
    ArmModel, CollisionError, CollisionWorld, Grip, GripFailure, ObjectGeometry, OPEN_CONTACT_DEPTH,
};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_model::{ArmSetup, GraspKind, Plan, PlanSet, PlanStatus, RobotModel};
use pregrasp_robot::{ArmDescription, Gripper};

use crate::context::{grips as close_grips, Grips};

mod motions;
mod open;
mod walk;

use walk::PlanCheck;

/// Largest travel of any arm point between two checked states (m).
pub const CHECK_RESOLUTION: f64 = 0.002;
/// Largest travel of any arm point between two checked states while a gripper grasps (m):
/// finer than the finger–support clearance.
pub const FINE_CHECK_RESOLUTION: f64 = 0.001;
/// Rule 3: how far the object may go below the support (m).
pub const BELOW_SUPPORT_TOLERANCE: f64 = 0.001;
/// Rule 3: how far an axis endpoint may move during `rot` (m).
pub const AXIS_MOTION_TOLERANCE: f64 = 0.002;
/// Rule 4: tool pose vs grasp pose.
pub const GRASP_POSITION_TOLERANCE: f64 = 0.001;
pub const GRASP_ANGLE_TOLERANCE: f64 = 0.01;
/// Rule 4: tool vs its straight approach/retreat line.
pub const LINE_POSITION_TOLERANCE: f64 = 0.002;
pub const LINE_ANGLE_TOLERANCE: f64 = 0.01;

/// Rounding a plan's time stamps may carry (s): half a microsecond, as written with six
/// decimals. Rule 1 judges speeds allowing it (see `check_limits`).
pub const ROUNDING_T: f64 = 5e-7;
/// Rounding a plan's joint values may carry (rad): half of 1e-6 rad, six decimals.
pub const ROUNDING_Q: f64 = 5e-7;

const STRUCTURE: &str = "plan structure (segments, robots, times, continuity)";
const STRUCTURE_OK: &str = "segments sup1, rot, mas1, sup2 in order, times increasing, continuous";

/// The verdict on one rule.
#[derive(Clone, Debug, PartialEq)]
pub struct RuleResult {
    /// Rule number in plan-format.md (0 = file structure, checked first).
    pub rule: u8,
    pub title: &'static str,
    /// `None`: not checkable from a plan file alone.
    pub ok: Option<bool>,
    /// The worst value found, or the first violation.
    pub detail: String,
}

/// The verdict on a whole plan file.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckReport {
    pub rules: Vec<RuleResult>,
    /// The closest any grasping gripper came to the support over all checked states (m;
    /// `None` when no state was checked).
    pub closest_grasp_to_support: Option<f64>,
    /// The file does not follow the plan format: the offending field's path and the problem.
    /// No motion was judged.
    pub malformed: Option<String>,
}

impl CheckReport {
    /// Valid iff no checked rule failed.
    pub fn is_valid(&self) -> bool {
        self.rules.iter().all(|r| r.ok != Some(false))
    }
}

/// Accumulates the worst value and the first violation of one rule across all plans.
struct Rule {
    worst: f64,
    worst_at: String,
    violation: Option<String>,
}

impl Rule {
    fn new() -> Self {
        Rule {
            worst: f64::NEG_INFINITY,
            worst_at: String::new(),
            violation: None,
        }
    }
    /// Records a value where larger is worse; `limit` is the largest allowed value.
    fn value(&mut self, value: f64, limit: f64, at: impl FnOnce() -> String) {
        if value > self.worst || self.violation.is_none() && value > limit {
            let at = at();
            if value > self.worst {
                self.worst = value;
                self.worst_at = at.clone();
            }
            if value > limit && self.violation.is_none() {
                self.violation = Some(at);
            }
        }
    }
    fn fail(&mut self, what: String) {
        if self.violation.is_none() {
            self.violation = Some(what);
        }
    }
    fn result(self, rule: u8, title: &'static str, unit: impl Fn(f64) -> String) -> RuleResult {
        match self.violation {
            Some(v) => RuleResult {
                rule,
                title,
                ok: Some(false),
                detail: v,
            },
            None if self.worst.is_finite() => RuleResult {
                rule,
                title,
                ok: Some(true),
                detail: format!("worst {} ({})", unit(self.worst), self.worst_at),
            },
            None => RuleResult {
                rule,
                title,
                ok: Some(true),
                detail: "nothing to check".into(),
            },
        }
    }
}

/// Checks every plan in `file`; `mesh` is the object mesh in the object frame (scaled). Arms
/// from a robot description are found from the current directory ([`check_plan_at`] finds
/// them from the plan file's).
pub fn check_plan(file: &PlanFile, mesh: &Mesh) -> CheckReport {
    check_plan_at(file, None, mesh)
}

/// [`check_plan`] of the file read from `plan_path`: a robot description the plan names is
/// found as its scene is ([`PlanFile::arms_and_grippers`]). The file is validated and turned
/// into the typed model ([`PlanFile::to_model`]); the rules are judged on the model.
pub fn check_plan_at(file: &PlanFile, plan_path: Option<&Path>, mesh: &Mesh) -> CheckReport {
    if let Err(e) = crate::plan_format::validate(file) {
        let mut structure = Rule::new();
        structure.fail(format!("malformed plan file: {e}"));
        return CheckReport {
            rules: vec![structure.result(0, STRUCTURE, |_| String::new())],
            closest_grasp_to_support: None,
            malformed: Some(e),
        };
    }
    let set = match file.to_model() {
        Ok(set) => set,
        Err(e) => return structure_failure(e.to_string()),
    };
    let checker = file
        .arms_and_grippers(plan_path)
        .and_then(|(arms, grippers)| {
            PlanChecker::sharing_part(&set, mesh, &arms, &grippers, None, None, None)
                .map_err(|e| e.to_string())
        });
    match checker {
        Ok(checker) => checker.check(&set),
        Err(e) => structure_failure(e),
    }
}

/// A report whose rule 0 fails with `why` and judges nothing else.
fn structure_failure(why: String) -> CheckReport {
    let mut structure = Rule::new();
    structure.fail(why);
    CheckReport {
        rules: vec![structure.result(0, STRUCTURE, |_| String::new())],
        closest_grasp_to_support: None,
        malformed: None,
    }
}

/// Why a plan set's arms cannot be modelled for the check.
#[derive(Debug, thiserror::Error)]
pub enum CheckerError {
    #[error("expected 2 robots, found {0}")]
    RobotCount(usize),
    #[error("robots[{arm}].model is {model}, the arm given is {given}")]
    ModelMismatch {
        arm: usize,
        model: RobotModel,
        given: String,
    },
    #[error(transparent)]
    Collision(#[from] CollisionError),
}

/// A grasp at which a gripper does not close on the part: the check of rule 2 fails with it.
#[derive(Clone, Debug)]
struct UnclosedGrip {
    grasp: GraspKind,
    arm: String,
    failure: GripFailure,
}

impl std::fmt::Display for UnclosedGrip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} grasp of arm {}: {}",
            self.grasp, self.arm, self.failure
        )
    }
}

/// How rule 2 treats the transits of a reach or regrasp — the points from the end of its
/// retreat (its first point, without one) to `approach_from`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Transits {
    /// Every state, as for any plan file.
    Checked,
    /// Only the transit's first state: the planner has just proved its edges. Each edge of a
    /// transit is an edge of a path the planner's motion validator accepted in the same world
    /// (the same part and arm models, the other arm, the part and the held fingers where the
    /// plan puts them: `reach::reach_transit`), with each clearance grown by
    /// [`PLANNING_MARGIN`](crate::context::PLANNING_MARGIN) and states checked every
    /// [`MOTION_RESOLUTION`](crate::context::MOTION_RESOLUTION): every state *between* its
    /// checked ones keeps the clearance this check applies; the time parameterisation samples
    /// points on those edges (`pregrasp_motion::timing`). Pairs that do not involve the moving
    /// arm do not change along a segment and are checked at its other states; a transit's
    /// gripper is open and touches nothing, so rules 4 and the open hand's do not apply there.
    /// A plan whose `rot` does not end at its P_obj exactly (the pose the planner proved
    /// `mas1` and `sup2` with) has its later transits checked whole.
    Proven,
}

/// The models a plan set is checked with — arms, the collision world with the plan's
/// clearances, the widths the grippers close on, the part's hull — built once for any number of
/// plans of the same cell (robots, grasps, planner settings, support, mesh).
pub struct PlanChecker {
    arms: [ArmModel; 2],
    world: CollisionWorld,
    grips: Result<HeldGrips, UnclosedGrip>,
    lowest_candidates: Vec<Point3<f64>>,
    clearances: (f64, f64),
}

impl PlanChecker {
    /// The models of `set`'s cell, with the part's collision geometry (its mesh `mesh`, with
    /// the BVH) taken from another world of the same part when `part` is given rather than
    /// built again: the planner hands its own, the geometry of the mesh alone; the checker's
    /// clearances and hull are its own. `grips`: how the grippers close at the grasps, when the
    /// caller has closed them on the same part (the planner verifying its own plans); closed
    /// again otherwise. `hull`: the vertices of the mesh's convex hull, when the caller has them
    /// (Algorithm 1's).
    ///
    /// `arms`, `grippers`: the plan's ([`PlanFile::arms_and_grippers`], or the scene's).
    pub fn sharing_part(
        set: &PlanSet,
        mesh: &Mesh,
        arms: &[ArmDescription; 2],
        grippers: &[Gripper; 2],
        part: Option<Arc<ObjectGeometry>>,
        grips: Option<&Grips>,
        hull: Option<&[Point3<f64>]>,
    ) -> Result<PlanChecker, CheckerError> {
        let arms = arm_models(set, arms, grippers)?;
        PlanChecker::with_arms(set, mesh, arms, part, grips, hull)
    }

    /// [`PlanChecker::sharing_part`] with the arms of `models` (the planner's, built for the
    /// same robots): each placed under the plan's name and base rather than built again.
    pub fn sharing_models(
        set: &PlanSet,
        mesh: &Mesh,
        models: &[ArmModel; 2],
        part: Option<Arc<ObjectGeometry>>,
        grips: Option<&Grips>,
        hull: Option<&[Point3<f64>]>,
    ) -> Result<PlanChecker, CheckerError> {
        let arms = placed_models(set, models)?;
        PlanChecker::with_arms(set, mesh, arms, part, grips, hull)
    }

    fn with_arms(
        set: &PlanSet,
        mesh: &Mesh,
        arms: [ArmModel; 2],
        part: Option<Arc<ObjectGeometry>>,
        grips: Option<&Grips>,
        hull: Option<&[Point3<f64>]>,
    ) -> Result<PlanChecker, CheckerError> {
        let link_clearance = set.settings.link_clearance;
        let finger_clearance = set.settings.finger_support_clearance;
        let world = match part {
            Some(part) => {
                CollisionWorld::with_part(Some(set.support_height), Some(part), arms.clone())
            }
            None => CollisionWorld::try_new(Some(set.support_height), Some(mesh), arms.clone())?,
        }
        .with_margin(link_clearance)
        .with_grasp_support_margin(finger_clearance);
        let grips = held_grips(set, &world, grips);
        let world = match &grips {
            Ok(g) => world.with_held_fingers([
                &[g.support[0].state(), g.power[0].state()],
                &[g.support[1].state(), g.power[1].state()],
            ]),
            Err(_) => world,
        };
        // The lowest point of the part is always a vertex of its convex hull.
        let lowest_candidates = match hull {
            Some(vertices) => vertices.to_vec(),
            None => pregrasp_geometry::hull::ConvexHull::of_mesh(mesh)
                .map(|h| h.vertices)
                .unwrap_or_else(|_| mesh.vertices.clone()),
        };
        Ok(PlanChecker {
            arms,
            world,
            grips,
            lowest_candidates,
            clearances: (link_clearance, finger_clearance),
        })
    }

    /// Checks every plan of `set` (whose cell must be the one the checker was built for).
    pub fn check(&self, set: &PlanSet) -> CheckReport {
        self.check_plans(set, &set.plans)
    }

    /// Checks `plans` as the plans of `set`'s cell (its own `plans` are not read), every
    /// state of every motion.
    pub fn check_plans(&self, set: &PlanSet, plans: &[Plan]) -> CheckReport {
        self.check_plans_with(set, plans, Transits::Checked)
    }

    /// [`check_plans`](Self::check_plans) for plans the planner has just built with this cell's
    /// models ([`Transits::Proven`]): their transits are not checked again. The planner asks
    /// about one plan at a time; `pregrasp check` never asks this.
    pub(crate) fn check_own_plans(&self, set: &PlanSet, plans: &[Plan]) -> CheckReport {
        self.check_plans_with(set, plans, Transits::Proven)
    }

    fn check_plans_with(&self, set: &PlanSet, plans: &[Plan], transits: Transits) -> CheckReport {
        let mut structure = Rule::new();
        let mut limits = Rule::new();
        let mut collisions = Rule::new();
        let mut states_checked = 0u64;
        let mut open_states = 0u64;
        let mut rotation = Rule::new();
        let mut grasps = Rule::new();
        let planned = set.status == PlanStatus::Planned;
        if planned && plans.is_empty() {
            structure.fail(format!("status is \"{}\" but there is no plan", set.status));
        }
        if !planned && !plans.is_empty() {
            structure.fail(format!(
                "status is \"{}\" but plans are present",
                set.status
            ));
        }
        let (link_clearance, finger_clearance) = self.clearances;
        let (arms, world, lowest_candidates) = (&self.arms, &self.world, &self.lowest_candidates);
        let grips = match &self.grips {
            Ok(g) => Some(g.clone()),
            Err(e) => {
                collisions.fail(e.to_string());
                None
            }
        };
        let mut finger_support = f64::INFINITY;
        for (index, plan) in plans.iter().enumerate() {
            let mut cx = PlanCheck {
                set,
                plan,
                index,
                arms,
                world,
                grips: &grips,
                finger_support: &mut finger_support,
                lowest_candidates,
                structure: &mut structure,
                limits: &mut limits,
                collisions: &mut collisions,
                states_checked: &mut states_checked,
                transits,
                open_states: &mut open_states,
                rotation: &mut rotation,
                grasps: &mut grasps,
            };
            cx.run();
        }
        let mm = |x: f64| format!("{:.2} mm", x * 1e3);
        CheckReport {
            closest_grasp_to_support: finger_support.is_finite().then_some(finger_support),
            malformed: None,
            rules: vec![
                match structure.violation {
                    Some(v) => RuleResult {
                        rule: 0,
                        title: STRUCTURE,
                        ok: Some(false),
                        detail: v,
                    },
                    None => RuleResult {
                        rule: 0,
                        title: STRUCTURE,
                        ok: Some(true),
                        detail: format!("{} plan(s): {STRUCTURE_OK}", plans.len()),
                    },
                },
                limits.result(1, "joint limits and joint speeds", |x| {
                    format!("{:.1} % of a limit", x * 100.0)
                }),
                collision_result(
                    collisions,
                    (states_checked, open_states),
                    finger_support,
                    (link_clearance, finger_clearance),
                ),
                rotation.result(
                    3,
                    "rotation keeps the part on the support about a fixed axis",
                    mm,
                ),
                grasps.result(
                    4,
                    "tool poses at grasps and on approach/retreat lines",
                    |x| format!("{:.2} % of a tolerance", x * 100.0),
                ),
                RuleResult {
                    rule: 5,
                    title: "determinism",
                    ok: None,
                    detail: "not checkable from one file: plan the scene twice and compare bytes"
                        .into(),
                },
            ],
        }
    }
}

/// How the grippers close on the part, per arm: at G_s and at its power grasp.
#[derive(Clone)]
struct HeldGrips {
    support: [Grip; 2],
    power: [Grip; 2],
}

/// Closes, on the mesh, each gripper at each grasp.
fn held_grips(
    set: &PlanSet,
    world: &CollisionWorld,
    known: Option<&Grips>,
) -> Result<HeldGrips, UnclosedGrip> {
    let closed = match known {
        Some(g) => g.clone(),
        None => close_grips(world, &set.grasps.support, &set.grasps.power),
    };
    let unclosed = |grasp: GraspKind, arm: usize, failure: GripFailure| UnclosedGrip {
        grasp,
        arm: set.arms[arm].name.clone(),
        failure,
    };
    let [s0, s1] = closed.support;
    let [p0, p1] = closed.power;
    let support = |arm: usize, g: Result<Grip, GripFailure>| {
        g.map_err(|e| unclosed(GraspKind::Support, arm, e))
    };
    let power = |arm: usize, g: Result<Grip, GripFailure>| {
        g.map_err(|e| unclosed(GraspKind::Power, arm, e))
    };
    let gaps = HeldGrips {
        support: [support(0, s0)?, support(1, s1)?],
        power: [power(0, p0)?, power(1, p1)?],
    };
    Ok(gaps)
}

/// Rule 2's verdict: the first contact, or how many states were checked and the closest a
/// grasping gripper came to the support.
fn collision_result(
    rule: Rule,
    (states, open_states): (u64, u64),
    finger_support: f64,
    (link, finger): (f64, f64),
) -> RuleResult {
    let title = "no forbidden contact (support, arms, grippers, object)";
    match rule.violation {
        Some(v) => RuleResult {
            rule: 2,
            title,
            ok: Some(false),
            detail: v,
        },
        None => RuleResult {
            rule: 2,
            title,
            ok: Some(true),
            detail: format!(
                "{states} states checked at {} mm of arm travel ({} mm while grasping), none \
                 closer than the clearances (links {:.1} mm, grasping gripper to support {:.1} \
                 mm); closest grasping gripper to the support: {:.2} mm; {open_states} states \
                 of an open gripper next to its grasp, none more than {:.1} mm inside the part",
                CHECK_RESOLUTION * 1e3,
                FINE_CHECK_RESOLUTION * 1e3,
                link * 1e3,
                finger * 1e3,
                finger_support * 1e3,
                OPEN_CONTACT_DEPTH * 1e3
            ),
        },
    }
}

/// The file's arms as `models` (one per robot, scene order), under the file's names and bases.
fn placed_models(set: &PlanSet, models: &[ArmModel; 2]) -> Result<[ArmModel; 2], CheckerError> {
    robot_count(set)?;
    let place = |i: usize| -> Result<ArmModel, CheckerError> {
        let r = &set.arms[i];
        same_model(r, i, models[i].description())?;
        Ok(models[i].placed(&r.name, r.base))
    };
    Ok([place(0)?, place(1)?])
}

/// The file's arms, `arms` their models (one per robot, scene order); two arms alike share
/// their primitives ([`ArmModel::placed`]).
fn arm_models(
    set: &PlanSet,
    arms: &[ArmDescription; 2],
    grippers: &[Gripper; 2],
) -> Result<[ArmModel; 2], CheckerError> {
    robot_count(set)?;
    for (i, arm) in arms.iter().enumerate() {
        same_model(&set.arms[i], i, arm)?;
    }
    let build = |i: usize| -> Result<ArmModel, CheckerError> {
        let r = &set.arms[i];
        Ok(ArmModel::from_description(
            &r.name,
            arms[i].clone(),
            r.base,
            grippers[i].clone(),
        )?)
    };
    let first = build(0)?;
    let second = if first.is_built_from(&arms[1], &grippers[1]) {
        first.placed(&set.arms[1].name, set.arms[1].base)
    } else {
        build(1)?
    };
    Ok([first, second])
}

/// Refuses a file without exactly two robots.
fn robot_count(set: &PlanSet) -> Result<(), CheckerError> {
    match set.arms.len() {
        2 => Ok(()),
        n => Err(CheckerError::RobotCount(n)),
    }
}

/// Refuses arm `i` of the file (`robot`) when its model is not `arm`'s.
fn same_model(robot: &ArmSetup, i: usize, arm: &ArmDescription) -> Result<(), CheckerError> {
    if robot.model.builtin() == arm.ur {
        return Ok(());
    }
    Err(CheckerError::ModelMismatch {
        arm: i,
        model: robot.model,
        given: arm.name().to_string(),
    })
}
