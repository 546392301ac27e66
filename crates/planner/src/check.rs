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
//! closes on — measured here again from the mesh, not read from the file.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_collision::{
    ArmModel, CollisionWorld, Grip, GripFailure, ObjectGeometry, ObjectPlacement, WorldState,
};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{
    GraspKind, PlanFile, PlanJson, PlanStatus, PointJson, PoseJson, SegmentJson, SegmentKind,
    SegmentName,
};
use pregrasp_io::scene::{DEFAULT_FINGER_SUPPORT_CLEARANCE, DEFAULT_LINK_CLEARANCE};
use pregrasp_robot::{joint_sweep_radii, Gripper2F85, GripperState, Joints};

use crate::context::{grips as close_grips, Grips};
use crate::timeline::{lerp_joints, lerp_pose, substeps, CONTACT_ZONE};

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

/// Checks every plan in `file`; `mesh` is the object mesh in the object frame (scaled).
pub fn check_plan(file: &PlanFile, mesh: &Mesh) -> CheckReport {
    if let Err(e) = crate::plan_format::validate(file) {
        let mut structure = Rule::new();
        structure.fail(format!("malformed plan file: {e}"));
        return CheckReport {
            rules: vec![structure.result(0, STRUCTURE, |_| String::new())],
            closest_grasp_to_support: None,
            malformed: Some(e),
        };
    }
    match PlanChecker::new(file, mesh) {
        Ok(checker) => checker.check(file),
        Err(e) => {
            let mut structure = Rule::new();
            structure.fail(e);
            CheckReport {
                rules: vec![structure.result(0, STRUCTURE, |_| String::new())],
                closest_grasp_to_support: None,
                malformed: None,
            }
        }
    }
}

/// The models a plan file is checked with — arms, the collision world with the plan's
/// clearances, the widths the grippers close on, the part's hull — built once for any number of
/// plans of the same file header (robots, grasps, planner settings, support, mesh).
pub struct PlanChecker {
    arms: [ArmModel; 2],
    world: CollisionWorld,
    grips: Result<HeldGrips, String>,
    lowest_candidates: Vec<Point3<f64>>,
    clearances: (f64, f64),
}

impl PlanChecker {
    /// The models of `file`'s header; an error when its robots cannot be modelled.
    pub fn new(file: &PlanFile, mesh: &Mesh) -> Result<PlanChecker, String> {
        Self::sharing_part(file, mesh, None, None, None)
    }

    /// [`PlanChecker::new`] with the part's collision geometry (its mesh `mesh`, with the BVH)
    /// taken from another world of the same part rather than built again: the planner hands
    /// its own, the geometry of the mesh alone; the checker's clearances and hull are its own.
    /// `grips`: how the grippers close at the file's grasps, when the caller has closed them
    /// on the same part (the planner verifying its own plans); closed again otherwise. `hull`:
    /// the vertices of the mesh's convex hull, when the caller has them (Algorithm 1's).
    pub fn sharing_part(
        file: &PlanFile,
        mesh: &Mesh,
        part: Option<Arc<ObjectGeometry>>,
        grips: Option<&Grips>,
        hull: Option<&[Point3<f64>]>,
    ) -> Result<PlanChecker, String> {
        let arms = arm_models(file)?;
        let link_clearance = file
            .planner
            .link_clearance
            .unwrap_or(DEFAULT_LINK_CLEARANCE);
        let finger_clearance = file
            .planner
            .finger_support_clearance
            .unwrap_or(DEFAULT_FINGER_SUPPORT_CLEARANCE);
        let world = match part {
            Some(part) => {
                CollisionWorld::with_part(Some(file.support_height), Some(part), arms.clone())
            }
            None => CollisionWorld::new(file.support_height, Some(mesh), arms.clone()),
        }
        .with_margin(link_clearance)
        .with_grasp_support_margin(finger_clearance);
        let grips = held_grips(file, &world, grips);
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

    /// Checks every plan in `file` (whose header must be the one the checker was built for).
    pub fn check(&self, file: &PlanFile) -> CheckReport {
        let mut structure = Rule::new();
        let mut limits = Rule::new();
        let mut collisions = Rule::new();
        let mut states_checked = 0u64;
        let mut rotation = Rule::new();
        let mut grasps = Rule::new();
        let planned = file.status == PlanStatus::Planned;
        if planned && file.plans.is_empty() {
            structure.fail(format!(
                "status is \"{}\" but there is no plan",
                file.status
            ));
        }
        if !planned && !file.plans.is_empty() {
            structure.fail(format!(
                "status is \"{}\" but plans are present",
                file.status
            ));
        }
        let (link_clearance, finger_clearance) = self.clearances;
        let (arms, world, lowest_candidates) = (&self.arms, &self.world, &self.lowest_candidates);
        let grips = match &self.grips {
            Ok(g) => Some(g.clone()),
            Err(e) => {
                collisions.fail(e.clone());
                None
            }
        };
        let mut finger_support = f64::INFINITY;
        for (index, plan) in file.plans.iter().enumerate() {
            let mut cx = PlanCheck {
                file,
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
                        detail: format!("{} plan(s): {STRUCTURE_OK}", file.plans.len()),
                    },
                },
                limits.result(1, "joint limits and joint speeds", |x| {
                    format!("{:.1} % of a limit", x * 100.0)
                }),
                collision_result(
                    collisions,
                    states_checked,
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
    file: &PlanFile,
    world: &CollisionWorld,
    known: Option<&Grips>,
) -> Result<HeldGrips, String> {
    let power = file.grasps.power.each_ref().map(PoseJson::to_isometry);
    let closed = match known {
        Some(g) => g.clone(),
        None => close_grips(world, &file.grasps.support.to_isometry(), &power),
    };
    let name = |arm: usize| &file.robots[arm].name;
    let [s0, s1] = closed.support;
    let [p0, p1] = closed.power;
    let support = |arm: usize, g: Result<Grip, GripFailure>| {
        g.map_err(|e| format!("support grasp of arm {}: {e}", name(arm)))
    };
    let power = |arm: usize, g: Result<Grip, GripFailure>| {
        g.map_err(|e| format!("power grasp of arm {}: {e}", name(arm)))
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
    states: u64,
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
                 mm); closest grasping gripper to the support: {:.2} mm",
                CHECK_RESOLUTION * 1e3,
                FINE_CHECK_RESOLUTION * 1e3,
                link * 1e3,
                finger * 1e3,
                finger_support * 1e3
            ),
        },
    }
}

fn arm_models(file: &PlanFile) -> Result<[ArmModel; 2], String> {
    if file.robots.len() != 2 {
        return Err(format!("expected 2 robots, found {}", file.robots.len()));
    }
    let build = |i: usize| -> Result<ArmModel, String> {
        let r = &file.robots[i];
        let model = r.model;
        let gripper = Gripper2F85 {
            precision_point_z: r.precision_point.xyz[2],
            power_point_z: r.power_point.xyz[2],
        };
        Ok(ArmModel::new(&r.name, model, r.base.to_isometry(), gripper))
    };
    Ok([build(0)?, build(1)?])
}

/// Pose error: (position error in m, rotation angle in rad).
fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

struct PlanCheck<'a> {
    file: &'a PlanFile,
    plan: &'a PlanJson,
    index: usize,
    arms: &'a [ArmModel; 2],
    world: &'a CollisionWorld,
    /// How the grippers close at each grasp (`None`: a grip that cannot close, reported once).
    grips: &'a Option<HeldGrips>,
    /// Closest a grasping gripper came to the support (m).
    finger_support: &'a mut f64,
    /// The part's points that can be its lowest (its convex hull's vertices).
    lowest_candidates: &'a [Point3<f64>],
    structure: &'a mut Rule,
    limits: &'a mut Rule,
    collisions: &'a mut Rule,
    /// Rule 2 reports how many states it checked rather than a worst value.
    states_checked: &'a mut u64,
    rotation: &'a mut Rule,
    grasps: &'a mut Rule,
}

/// Which straight line a point of a reach/regrasp segment lies on, if any.
#[derive(Clone, Copy)]
struct Line {
    /// The tool pose at the end that touches the part (the grasp end).
    grasp_end: Isometry3<f64>,
}

/// Edge `k → k+1` of a segment as (index of its end, number of checked sub-steps), so that no
/// arm point moves more than `resolution` between checked states; the last point is a single
/// state.
fn edge(pts: &[PointJson], k: usize, weights: &Joints, resolution: f64) -> (usize, usize) {
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
struct Queued {
    states: Vec<WorldState>,
    at: Vec<(usize, f64)>,
}

/// "plan I SEG point K", for messages.
fn at(index: usize, seg: &SegmentJson, k: usize) -> String {
    format!("plan {index} {} point {k}", seg.name)
}

/// Rule 4: a tool pose vs the grasp pose it should meet.
fn grasp_error(rule: &mut Rule, dp: f64, da: f64, at: impl Fn() -> String) {
    let worst = (dp / GRASP_POSITION_TOLERANCE).max(da / GRASP_ANGLE_TOLERANCE);
    rule.value(worst, 1.0, || {
        format!("{}: {:.3} mm, {:.4} rad", at(), dp * 1e3, da)
    });
}

/// Rule 4: a tool pose vs the straight line ending at `line.grasp_end`.
fn line_error(rule: &mut Rule, tool: &Isometry3<f64>, line: &Line, at: impl Fn() -> String) {
    let end = &line.grasp_end;
    let dir: Vector3<f64> = end.rotation * Vector3::z();
    let v = tool.translation.vector - end.translation.vector;
    let off = (v - dir * v.dot(&dir)).norm();
    let angle = tool.rotation.angle_to(&end.rotation);
    let worst = (off / LINE_POSITION_TOLERANCE).max(angle / LINE_ANGLE_TOLERANCE);
    rule.value(worst, 1.0, || {
        format!(
            "{}: {:.3} mm off the line, {:.4} rad",
            at(),
            off * 1e3,
            angle
        )
    });
}

impl<'a> PlanCheck<'a> {
    fn robot_index(&self, name: &str) -> Option<usize> {
        self.file.robots.iter().position(|r| r.name == name)
    }

    fn tool(&self, arm: usize, q: &Joints, precision: bool) -> Isometry3<f64> {
        let g = &self.arms[arm].gripper;
        let point = if precision {
            g.precision_point()
        } else {
            g.power_point()
        };
        self.arms[arm].flange_world(q) * point
    }

    fn run(&mut self) {
        let index = self.index;
        let plan: &'a PlanJson = self.plan;
        if plan.segments.len() != 4 {
            self.structure.fail(format!(
                "plan {}: {} segments, expected 4",
                index,
                plan.segments.len()
            ));
            return;
        }
        let (Some(sup), Some(mas)) = (
            self.robot_index(&plan.supportive),
            self.robot_index(&plan.master),
        ) else {
            self.structure
                .fail(format!("plan {}: master/supportive name no robot", index));
            return;
        };
        if sup == mas {
            self.structure.fail(format!(
                "plan {}: master and supportive are the same arm",
                index
            ));
            return;
        }
        for (seg, name) in plan.segments.iter().zip(SegmentName::ALL) {
            let kind = name.kind();
            let robot_ok = if name.by_master() {
                seg.robot == plan.master
            } else {
                seg.robot == plan.supportive
            };
            if seg.name != *name || seg.kind != kind || !robot_ok {
                self.structure.fail(format!(
                    "plan {}: segment \"{}\" ({}, robot {}) where {name} ({kind}) was expected",
                    index, seg.name, seg.kind, seg.robot
                ));
                return;
            }
            if let Err(e) = self.segment_structure(seg) {
                self.structure.fail(e);
                return;
            }
        }
        let Some(candidate) = self.file.candidates.iter().find(|c| c.id == plan.candidate) else {
            self.structure.fail(format!(
                "plan {}: candidate {} is not listed",
                index, plan.candidate
            ));
            return;
        };
        let axis = candidate.axis.map(|p| Point3::new(p[0], p[1], p[2]));

        let p_init = self.file.object.initial_pose.to_isometry();
        let p_obj = plan.object_goal_pose.to_isometry();
        let g_s = self.file.grasps.support.to_isometry();
        let g_p = [
            self.file.grasps.power[0].to_isometry(),
            self.file.grasps.power[1].to_isometry(),
        ];
        let mut q = [self.file.robots[0].start, self.file.robots[1].start];
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
                    index, seg.name, jump, self.file.robots[arm].name
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
                    object = last
                        .object_pose
                        .as_ref()
                        .map(PoseJson::to_isometry)
                        .unwrap_or(object);
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

    fn segment_structure(&self, seg: &SegmentJson) -> Result<(), String> {
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
    fn check_limits(&mut self, arm: usize, seg: &SegmentJson) {
        let index = self.index;
        let model = self.arms[arm].model();
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

    fn state(
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
    fn held(&self, arm: usize, support: bool) -> GripperState {
        match self.grips {
            Some(g) if support => g.support[arm].state(),
            Some(g) => g.power[arm].state(),
            None => GripperState::fully_closed(),
        }
    }

    /// Rule 2 for the closing itself: the fingers of arm `arm`, closing at the last point
    /// `q` of `seg` on G_s (`support`) or its power grasp, keep the finger–support clearance
    /// in every pose they pass through ([`Grip::lowest`]).
    fn check_closing(&mut self, arm: usize, seg: &SegmentJson, q: &Joints, support: bool) {
        let Some(grips) = self.grips else {
            return;
        };
        let grip = if support {
            &grips.support[arm]
        } else {
            &grips.power[arm]
        };
        let flange = self.arms[arm].flange_world(q);
        let above = grip.lowest(&flange) - self.file.support_height;
        *self.finger_support = self.finger_support.min(above);
        let clearance = self.world.grasp_support_margin();
        if above < clearance {
            let n = seg.points.len();
            self.collisions.fail(format!(
                "{}: the closing fingers of arm {} come {:.2} mm from the support (clearance {:.2} mm)",
                at(self.index, seg, n - 1),
                self.file.robots[arm].name,
                above * 1e3,
                clearance * 1e3
            ));
        }
    }

    fn collide(&mut self, state: WorldState, at: (usize, f64), queue: &mut Queued) {
        *self.states_checked += 1;
        queue.states.push(state);
        queue.at.push(at);
    }

    /// Rule 2 at every queued state of a segment in which arm `moving` moves, in order: the
    /// first in contact is reported as `what` at its point `(k, f)`, and the closest the
    /// moving gripper came to the support while grasping is recorded. Both are exact over the
    /// states, found by ranges in one pass ([`CollisionWorld::check_states`]).
    fn collide_all(&mut self, moving: usize, queue: &Queued, what: impl Fn(usize, f64) -> String) {
        let found = self.world.check_states(None, &queue.states);
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

    /// Rules 2 and 4 along a reach (`sup1`, `mas1`) or regrasp (`sup2`) segment.
    #[allow(clippy::too_many_arguments)]
    fn check_reach(
        &mut self,
        arm: usize,
        seg: &SegmentJson,
        q: &[Joints; 2],
        gripper: &[GripperState; 2],
        holding: &[bool; 2],
        object: &Isometry3<f64>,
        precision: bool,
        goal: &Isometry3<f64>,
        closed: GripperState,
    ) {
        let index = self.index;
        let pts = &seg.points;
        let n = pts.len();
        let approach_from = seg.approach_from.unwrap_or(n - 1);
        let retreat_to = seg.retreat_to;
        let weights = joint_sweep_radii(self.arms[arm].model(), &self.arms[arm].gripper);
        // The retreat leaves the support grasp (precision point) the arm held at its first point.
        let retreat_line = retreat_to.map(|_| Line {
            grasp_end: self.tool(arm, &pts[0].q, true),
        });
        let approach_line = Line {
            grasp_end: self.tool(arm, &pts[n - 1].q, precision),
        };

        // Rule 4: the tool meets the grasp, and the stand-off is approach_distance back.
        let end = self.tool(arm, &pts[n - 1].q, precision);
        let (dp, da) = pose_error(&end, goal);
        grasp_error(self.grasps, dp, da, || {
            format!("{}: tool vs grasp", at(index, seg, n - 1))
        });
        let standoff = self.tool(arm, &pts[approach_from].q, precision);
        let d = (standoff.translation.vector - end.translation.vector).norm();
        let expected = self.file.planner.approach_distance;
        self.grasps
            .value((d - expected).abs() / GRASP_POSITION_TOLERANCE, 1.0, || {
                format!(
                    "{}: stand-off {:.2} mm from the grasp",
                    at(index, seg, approach_from),
                    d * 1e3
                )
            });

        let mut queue = Queued::default();
        for k in 0..n {
            // The straight lines may bring the gripper within millimetres of the support.
            let grasping_edge = k >= approach_from || retreat_to.is_some_and(|r| k < r);
            let resolution = if grasping_edge {
                FINE_CHECK_RESOLUTION
            } else {
                CHECK_RESOLUTION
            };
            let (edge_end, steps) = edge(pts, k, &weights, resolution);
            for s in 0..steps {
                let f = s as f64 / steps as f64;
                let qi = lerp_joints(&pts[k].q, &pts[edge_end].q, f);
                let mut all = *q;
                all[arm] = qi;
                let on_approach = k >= approach_from;
                let on_retreat = retreat_to.is_some_and(|r| edge_end <= r && (k < r || s == 0));
                let mut contact = *holding;
                contact[arm] = false;
                if on_approach {
                    let tool = self.tool(arm, &qi, precision);
                    line_error(self.grasps, &tool, &approach_line, || {
                        format!("{} (+{f:.2})", at(index, seg, k))
                    });
                    let dist = (tool.translation.vector
                        - approach_line.grasp_end.translation.vector)
                        .norm();
                    contact[arm] = dist <= CONTACT_ZONE + 1e-9;
                }
                if on_retreat {
                    let line = retreat_line.expect("retreat has a line");
                    let tool = self.tool(arm, &qi, true);
                    line_error(self.grasps, &tool, &line, || {
                        format!("{} (+{f:.2}) retreat", at(index, seg, k))
                    });
                    let dist = (tool.translation.vector - line.grasp_end.translation.vector).norm();
                    contact[arm] = contact[arm] || dist <= CONTACT_ZONE + 1e-9;
                }
                // The gripper closes at the last point.
                let mut grip = *gripper;
                if k == n - 1 {
                    grip[arm] = closed;
                    contact[arm] = true;
                }
                let state = self.state(all, grip, *object, contact);
                self.collide(state, (k, f), &mut queue);
            }
        }
        self.collide_all(arm, &queue, |k, f| {
            format!("plan {index} {} point {k} (+{f:.2})", seg.name)
        });
        self.check_closing(arm, seg, &pts[n - 1].q, precision);
    }

    /// Rules 2, 3 and 4 along `rot`.
    #[allow(clippy::too_many_arguments)]
    fn check_rotation(
        &mut self,
        arm: usize,
        seg: &SegmentJson,
        q: &[Joints; 2],
        gripper: &[GripperState; 2],
        holding: &[bool; 2],
        axis: &[Point3<f64>; 2],
        p_init: &Isometry3<f64>,
        g_s: &Isometry3<f64>,
    ) {
        let index = self.index;
        let pts = &seg.points;
        let n = pts.len();
        let weights = joint_sweep_radii(self.arms[arm].model(), &self.arms[arm].gripper);
        let support = self.file.support_height;
        let axis_band = self.file.planner.support_distance + self.file.planner.lift + 0.001;
        let init_inv = p_init.inverse();
        let poses: Vec<Isometry3<f64>> = pts
            .iter()
            .map(|p| p.object_pose.as_ref().expect("checked").to_isometry())
            .collect();
        let (dp, da) = pose_error(&poses[0], p_init);
        grasp_error(self.grasps, dp, da, || {
            format!("plan {} rot: first object_pose vs P_init", index)
        });
        let mut queue = Queued::default();
        for k in 0..n {
            // Rule 4: precision point on G_s at every point.
            let tool = self.tool(arm, &pts[k].q, true);
            let (dp, da) = pose_error(&tool, &(poses[k] * g_s));
            grasp_error(self.grasps, dp, da, || {
                format!("{}: tool vs object_pose·G_s", at(index, seg, k))
            });
            let (edge_end, steps) = edge(pts, k, &weights, FINE_CHECK_RESOLUTION);
            for s in 0..steps {
                let f = s as f64 / steps as f64;
                let object = lerp_pose(&poses[k], &poses[edge_end], f);
                // Rule 3: above the support, axis fixed and on the support.
                let lowest = self
                    .lowest_candidates
                    .iter()
                    .map(|v| (object * v).z)
                    .fold(f64::INFINITY, f64::min);
                let below = support - lowest;
                self.rotation.value(below, BELOW_SUPPORT_TOLERANCE, || {
                    format!(
                        "plan {} rot point {k} (+{f:.2}): part {:.2} mm below the support",
                        index,
                        below * 1e3
                    )
                });
                for (e, p) in axis.iter().enumerate() {
                    let moved = object * (init_inv * p);
                    let shift = (moved - p).norm();
                    self.rotation.value(shift, AXIS_MOTION_TOLERANCE, || {
                        format!(
                            "plan {} rot point {k} (+{f:.2}): axis end {e} moved {:.2} mm",
                            index,
                            shift * 1e3
                        )
                    });
                    let height = moved.z - support;
                    if height > axis_band {
                        self.rotation.fail(format!(
                            "plan {} rot point {k}: axis end {e} {:.2} mm above the support",
                            self.index,
                            height * 1e3
                        ));
                    }
                }
                let mut all = *q;
                all[arm] = lerp_joints(&pts[k].q, &pts[edge_end].q, f);
                let state = self.state(all, *gripper, object, *holding);
                self.collide(state, (k, f), &mut queue);
            }
        }
        self.collide_all(arm, &queue, |k, f| {
            format!("plan {index} rot point {k} (+{f:.2})")
        });
    }
}
