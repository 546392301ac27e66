//! The planning context: a validated scene turned into models — the two arms in the world,
//! the collision world (support, object mesh, arms), P_init — shared read-only by every
//! pipeline stage (so candidates can be evaluated in parallel without locks).

use std::sync::{Arc, OnceLock};

use nalgebra::Isometry3;
use pregrasp_collision::{ArmModel, CollisionWorld, Contact, Grip, ObjectPlacement, WorldState};
use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_io::scene::Scene;
use pregrasp_model::PadContact;
use pregrasp_motion::{JointSpace, MotionValidator};
use pregrasp_robot::{ArmKinematics, GripperState, Joints};

use crate::clock::StageClock;
pub use crate::closings::{grips, pad_contact, support_closings, Grips, KnownClosings};
use crate::closings::{grips_knowing, holds_support_alike};
use crate::error::PlanError;
use pregrasp_model::timeline::Moment;

/// Resolution (m) at which motions are validated: no point of an arm moves farther than this
/// between two checked states (bound Σ w_i |Δq_i|, with w_i the joint sweep radii).
pub const MOTION_RESOLUTION: f64 = 0.005;

/// Resolution (m) of motions while a gripper grasps (μ_rot, the last centimetres of an approach,
/// the first of the `sup2` retreat): finer than the finger–support clearance, since a fingertip
/// pinch works a few millimetres above the table.
pub const FINE_RESOLUTION: f64 = 0.001;

/// Margin (m) the planner adds to each clearance of the scene (`link_clearance`,
/// `finger_support_clearance`) for the motion between checked states: every point of a
/// validated motion lies within half the resolution of a checked state, so more than half the
/// resolution keeps the whole motion — not only its checked states — as clear as the plan
/// checker demands (it applies the clearances without this margin).
pub const PLANNING_MARGIN: f64 = 0.003;

/// [`PLANNING_MARGIN`]'s counterpart for the grasping gripper vs the support, whose motions
/// are validated at [`FINE_RESOLUTION`].
pub const FINE_PLANNING_MARGIN: f64 = 0.0006;

/// Read-only models of one planning problem.
pub struct PlanningContext<'a> {
    pub scene: &'a Scene,
    pub mesh: &'a Mesh,
    /// P_init: the object pose raised by the lift.
    pub p_init: Isometry3<f64>,
    /// The world as the planner sees it (with [`PLANNING_MARGIN`]).
    pub world: CollisionWorld,
    /// Joint spaces (limits and sweep-radius weights) of both arms.
    pub spaces: [JointSpace<6>; 2],
    /// Arm names, for messages.
    pub names: [String; 2],
    /// How the grippers close on the part.
    pub grips: Grips,
    /// Where each arm's pads bear on the part at G_s, should it support (for the grip check).
    pub support_pads: [Option<PadContact>; 2],
    /// When `sup1` has already run (re-planning `--from rot`): the supportive arm's joints,
    /// which μ_rot must start from (within [`FIXED_START_TOLERANCE`]).
    pub fixed_rot_start: Option<(usize, Joints)>,
    /// Time spent per part of Algorithm 3 (summed over candidates).
    pub clock: StageClock,
}

/// Largest joint difference (rad) between μ_rot's first point and a fixed start.
pub const FIXED_START_TOLERANCE: f64 = 1e-6;

/// What a planning context can take from an earlier one of the same part: the part's geometry
/// (its BVH and convex hull) and how the grippers close on it at the scene's grasps. All live
/// in the object frame, so they hold for any pose of the part: `replan` in a cell, the part
/// measured again and again, builds them once
/// ([`PlanOptions::known`](crate::pipeline::PlanOptions::known)).
#[derive(Clone)]
pub struct PartKnowledge {
    /// The mesh they were built from, by content ([`mesh_fingerprint`]): only that mesh may
    /// use them.
    mesh: u64,
    part: Arc<pregrasp_collision::ObjectGeometry>,
    /// The mesh's convex hull (object frame), `None` when it has none (Algorithm 1 then finds
    /// no candidate and says why).
    hull: Option<Arc<ConvexHull>>,
    support: Isometry3<f64>,
    power: [Isometry3<f64>; 2],
    /// Per arm: precision and power point distance from the flange.
    points: [(f64, f64); 2],
    grips: Grips,
    /// The seating ([`crate::seat`]) it was built with: the scene's power grasps before it,
    /// the part's rest offsets along their approaches, how far each moved (`power` holds the
    /// seated grasps).
    seated_from: [Isometry3<f64>; 2],
    rest: [f64; 2],
    moved: [f64; 2],
    seated_by: crate::seat::SeatRule,
}

impl std::fmt::Debug for PartKnowledge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PartKnowledge")
            .field("support", &self.support)
            .field("power", &self.power)
            .finish_non_exhaustive()
    }
}

impl PartKnowledge {
    /// The part's geometry and closings for `scene` on `mesh` (as a planning context builds
    /// them).
    /// The power grasps are the seated ones ([`crate::seat`]), as the pipeline plans with.
    pub fn new(scene: &Scene, mesh: &Mesh) -> Result<PartKnowledge, PlanError> {
        let part =
            Arc::new(pregrasp_collision::ObjectGeometry::new(mesh).map_err(PlanError::Mesh)?);
        let arms = arm_models(scene)?;
        let rule = crate::seat::SeatRule::first_for(scene.planner.power_hold);
        let (seated, power_grips) = crate::seat::planned_scene(scene, &part, &arms, rule);
        let moved = seated.as_ref().map_or([0.0; 2], |(_, m)| *m);
        let planned = seated.as_ref().map_or(scene, |(s, _)| s);
        let closed = KnownClosings {
            power: Some(power_grips),
            ..KnownClosings::default()
        };
        let ctx = PlanningContext::with_part(planned, mesh, None, Some(part), closed, Some(arms))?;
        let hull = ConvexHull::of_mesh(mesh).ok().map(Arc::new);
        Ok(PartKnowledge::of(&ctx, hull, scene, (moved, rule)))
    }

    /// The seating of `scene`'s power grasps by `rule` ([`crate::seat::planned_scene`]'s
    /// scene) when this knowledge was built by the same rule for the same mesh, grasps, tool
    /// points and rest offsets (a part measured at another pose on the same face): `None` when
    /// it was not.
    #[allow(clippy::type_complexity, clippy::option_option)]
    pub(crate) fn seating(
        &self,
        scene: &Scene,
        mesh: &Mesh,
        rule: crate::seat::SeatRule,
    ) -> Option<Option<(Scene, [f64; 2])>> {
        let same = self.seated_by == rule
            && self.fits_mesh(mesh)
            && self.seated_from == scene.grasps.power
            && self.support == scene.grasps.support
            && self.points == tool_points(scene)
            && self.rest == crate::seat::rest_offsets(scene);
        same.then(|| {
            // Moved along the approach, or only across onto the bar's mid-plane.
            (self.power != self.seated_from).then(|| {
                let mut s = scene.clone();
                s.grasps.power = self.power;
                (s, self.moved)
            })
        })
    }

    /// The part's collision geometry (object frame).
    pub fn part(&self) -> Arc<pregrasp_collision::ObjectGeometry> {
        self.part.clone()
    }

    /// What `ctx` built for `scene` with its power grasps seated (`moved` each, by `rule`), and
    /// `hull`, the convex hull of its mesh.
    fn of(
        ctx: &PlanningContext,
        hull: Option<Arc<ConvexHull>>,
        scene: &Scene,
        (moved, rule): ([f64; 2], crate::seat::SeatRule),
    ) -> PartKnowledge {
        PartKnowledge {
            mesh: mesh_fingerprint(ctx.mesh),
            part: ctx.world.part().expect("a planning world has the part"),
            hull,
            support: ctx.scene.grasps.support,
            power: ctx.scene.grasps.power,
            points: tool_points(ctx.scene),
            grips: ctx.grips.clone(),
            seated_from: scene.grasps.power,
            rest: crate::seat::rest_offsets(scene),
            moved,
            seated_by: rule,
        }
    }

    /// Whether it was built for this mesh, these grasps and these tool points (exactly).
    fn fits(&self, scene: &Scene, mesh: &Mesh) -> bool {
        self.support == scene.grasps.support
            && self.power == scene.grasps.power
            && self.points == tool_points(scene)
            && self.fits_mesh(mesh)
    }

    /// Whether it was built for this mesh (its hull is then the mesh's, whatever the grasps).
    pub fn fits_mesh(&self, mesh: &Mesh) -> bool {
        self.mesh == mesh_fingerprint(mesh)
    }

    /// The convex hull of the mesh it was built for (object frame), if the mesh has one.
    pub fn hull(&self) -> Option<&Arc<ConvexHull>> {
        self.hull.as_ref()
    }
}

/// A 64-bit digest of a mesh's vertices and triangles (every coordinate's bits, every index):
/// equal meshes give equal digests, and a different mesh colliding is a 2⁻⁶⁴ accident.
fn mesh_fingerprint(mesh: &Mesh) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |x: u64| {
        h = (h ^ x).wrapping_mul(0x0000_0100_0000_01b3).rotate_left(29);
    };
    mix(mesh.vertices.len() as u64);
    for v in &mesh.vertices {
        for c in v.coords.iter() {
            mix(c.to_bits());
        }
    }
    mix(mesh.triangles.len() as u64);
    for t in &mesh.triangles {
        for i in t {
            mix(u64::from(*i));
        }
    }
    h
}

/// Per arm of `scene`: its precision and power point distance from the flange.
fn tool_points(scene: &Scene) -> [(f64, f64); 2] {
    scene
        .robots
        .each_ref()
        .map(|r| (r.precision_point_z, r.power_point_z))
}

impl<'a> PlanningContext<'a> {
    /// The models of `scene` with the part `mesh`; an error when an arm cannot be modelled or
    /// the mesh cannot be a collision body.
    pub fn new(scene: &'a Scene, mesh: &'a Mesh) -> Result<Self, PlanError> {
        PlanningContext::with_knowledge(scene, mesh, None)
    }

    /// [`PlanningContext::new`], taking the part's geometry and closings from `known` when it
    /// was built for this mesh, these grasps and tool points (built afresh otherwise).
    pub fn with_knowledge(
        scene: &'a Scene,
        mesh: &'a Mesh,
        known: Option<&PartKnowledge>,
    ) -> Result<Self, PlanError> {
        PlanningContext::with_part(scene, mesh, known, None, KnownClosings::default(), None)
    }

    /// [`PlanningContext::with_knowledge`], with the part's collision geometry `part` (built
    /// from `mesh`) when `known` does not fit, the closings computed already (`closed`: the
    /// seating's at the power grasps, [`crate::seat`]; those at G_s, beside it) and the
    /// scene's arm models when the caller has built them ([`arm_models`]).
    pub fn with_part(
        scene: &'a Scene,
        mesh: &'a Mesh,
        known: Option<&PartKnowledge>,
        part: Option<Arc<pregrasp_collision::ObjectGeometry>>,
        closed: KnownClosings,
        arms: Option<[ArmModel; 2]>,
    ) -> Result<Self, PlanError> {
        let arms = match arms {
            Some(arms) => arms,
            None => arm_models(scene)?,
        };
        let spaces = [
            pregrasp_collision::joint_space(&arms[0]),
            pregrasp_collision::joint_space(&arms[1]),
        ];
        let params = &scene.planner;
        let known = known.filter(|k| k.fits(scene, mesh));
        let world = match (known, part) {
            (Some(k), _) => {
                CollisionWorld::with_part(Some(scene.support_height), Some(k.part.clone()), arms)
            }
            (None, Some(part)) => {
                CollisionWorld::with_part(Some(scene.support_height), Some(part), arms)
            }
            (None, None) => CollisionWorld::try_new(Some(scene.support_height), Some(mesh), arms)
                .map_err(PlanError::Mesh)?,
        }
        .with_margin(params.link_clearance + PLANNING_MARGIN)
        .with_grasp_support_margin(params.finger_support_clearance + FINE_PLANNING_MARGIN);
        let grips = match known {
            Some(k) => k.grips.clone(),
            None => grips_knowing(&world, &scene.grasps.support, &scene.grasps.power, closed),
        };
        let held = |arm: usize| -> Vec<GripperState> {
            [&grips.support[arm], &grips.power[arm]]
                .into_iter()
                .flatten()
                .map(Grip::state)
                .collect()
        };
        let world = world.with_held_fingers([&held(0), &held(1)]);
        let support_pad = |arm: usize| {
            let grip = grips.support[arm].as_ref().ok()?;
            let gripper = &world.arms()[arm].gripper;
            let point = gripper.precision_point();
            pad_contact(
                world.object()?,
                gripper,
                &scene.grasps.support,
                &point,
                grip,
            )
        };
        let first = support_pad(0);
        let same = holds_support_alike(world.arms());
        let support_pads = [first, if same { first } else { support_pad(1) }];
        Ok(PlanningContext {
            scene,
            mesh,
            p_init: scene.initial_object_pose(),
            world,
            spaces,
            names: [scene.robots[0].name.clone(), scene.robots[1].name.clone()],
            grips,
            support_pads,
            fixed_rot_start: None,
            clock: StageClock::default(),
        })
    }

    /// The fingers of arm `arm` holding G_s (only called for an arm whose support grip
    /// closes; fully closed otherwise).
    pub fn support_grip(&self, arm: usize) -> GripperState {
        self.grips.support[arm]
            .as_ref()
            .map_or_else(|_| self.arm(arm).gripper.fully_closed(), Grip::state)
    }

    /// The width arm `arm` holds G_s with (m; 0 where its grip does not close).
    pub fn support_width(&self, arm: usize) -> f64 {
        self.grips.support[arm].as_ref().map_or(0.0, Grip::width)
    }

    /// The width arm `arm` holds its power grasp with (m; 0 where its grip does not close).
    pub fn power_width(&self, arm: usize) -> f64 {
        self.grips.power[arm].as_ref().map_or(0.0, Grip::width)
    }

    /// The fingers of arm `arm` holding its power grasp.
    pub fn power_grip(&self, arm: usize) -> GripperState {
        self.grips.power[arm]
            .as_ref()
            .map_or_else(|_| self.arm(arm).gripper.fully_closed(), Grip::state)
    }

    pub fn arm(&self, i: usize) -> &ArmModel {
        &self.world.arms()[i]
    }

    /// The arms' start configurations.
    pub fn starts(&self) -> [Joints; 2] {
        [self.scene.robots[0].start, self.scene.robots[1].start]
    }

    /// Is the whole world collision-free at this instant?
    pub fn check(&self, moment: &Moment) -> Result<(), Contact> {
        self.world.check(&world_state(moment))
    }

    /// Only the pairs involving arm `arm` (the other arm counts as an obstacle).
    pub fn check_arm(&self, arm: usize, moment: &Moment) -> Result<(), Contact> {
        self.world.check_arm(arm, &world_state(moment))
    }

    /// A motion validator for arm `arm` moving while everything else stays as in `moment`.
    pub fn motion_validator<'v, V: pregrasp_motion::StateValidator<6>>(
        &'v self,
        arm: usize,
        validator: &'v V,
    ) -> MotionValidator<'v, 6, V> {
        self.motion_validator_at(arm, validator, MOTION_RESOLUTION)
    }

    /// [`motion_validator`](Self::motion_validator) at another resolution (m).
    pub fn motion_validator_at<'v, V: pregrasp_motion::StateValidator<6>>(
        &'v self,
        arm: usize,
        validator: &'v V,
        resolution: f64,
    ) -> MotionValidator<'v, 6, V> {
        MotionValidator {
            space: &self.spaces[arm],
            validator,
            resolution,
        }
    }

    /// Every IK solution of arm `arm` for a world flange pose, within limits, sorted by distance
    /// to the arm's start, that is collision-free with the gripper closed on the part (`grip`)
    /// at `object` (gripper–part contact allowed) and the other arm at its start configuration —
    /// checked one by one as they are asked for ([`IkSet::free`]).
    pub fn free_ik(
        &self,
        arm: usize,
        flange_world: &Isometry3<f64>,
        object: &Isometry3<f64>,
        grip: GripperState,
    ) -> IkSet {
        let model = self.arm(arm);
        let target = model.base.inverse() * flange_world;
        let solutions = distinct_ik(&*model.kin, &target, &self.starts()[arm]);
        IkSet {
            arm,
            object: *object,
            grip,
            free: solutions.iter().map(|_| OnceLock::new()).collect(),
            solutions,
        }
    }
}

/// The IK solutions of one arm at one grasp with the part at a pose (the paper's `C_IK`),
/// sorted by distance to the arm's start. Whether each is collision-free is decided when it is
/// first asked for and remembered: the planner tries only the first few free ones, so the
/// others are never checked.
#[derive(Clone, Debug)]
pub struct IkSet {
    arm: usize,
    object: Isometry3<f64>,
    grip: GripperState,
    solutions: Vec<Joints>,
    free: Vec<OnceLock<bool>>,
}

impl IkSet {
    /// The collision-free solutions, in order (see [`PlanningContext::free_ik`]).
    pub fn free<'a>(&'a self, ctx: &'a PlanningContext) -> impl Iterator<Item = &'a Joints> + 'a {
        self.solutions
            .iter()
            .zip(&self.free)
            .filter(move |(q, free)| {
                *free.get_or_init(|| {
                    let moment = Moment::at_rest(ctx.starts(), self.object)
                        .holding(self.arm, **q, self.grip);
                    ctx.check_arm(self.arm, &moment).is_ok()
                })
            })
            .map(|(q, _)| q)
    }

    /// Whether no solution is collision-free.
    pub fn none_free(&self, ctx: &PlanningContext) -> bool {
        self.free(ctx).next().is_none()
    }
}

/// One configuration per geometrically distinct IK solution (at most 8): of the ±2π variants
/// the joint limits allow, the one nearest to `seed` ([`ArmKinematics::ik_distinct`]). The
/// variants share one geometry, so collision-checking one of each is enough. Sorted by
/// distance to `seed`.
pub fn distinct_ik(kin: &dyn ArmKinematics, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
    kin.ik_distinct(flange, seed)
}

/// The two arm models of a scene, in world.
///
/// [`PlanError::Arm`] if an arm and its gripper have more shapes than the collision model
/// holds, which a scene loaded by `pregrasp_io` never has: loading refuses such a robot with
/// an error naming it and the shape (`Cx::shapes_fit`), and a description's arm is merged down
/// to fit (`pregrasp_urdf::describe_arm`). Only a [`Scene`] built in code can have it.
pub fn arm_models(scene: &Scene) -> Result<[ArmModel; 2], PlanError> {
    // Each robot, its limits checked.
    let checked = |i: usize| {
        let spec = &scene.robots[i];
        // Transits are timed under these limits (`pregrasp_motion::time_parameterize`).
        let limits = [
            ("speed", spec.arm.kin.max_joint_speed()),
            ("acceleration", spec.arm.kin.max_joint_accel()),
        ];
        for (what, values) in limits {
            if let Some(j) = values.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(PlanError::JointLimit {
                    arm: spec.name.clone(),
                    joint: j + 1,
                    what,
                    value: values[j],
                });
            }
        }
        Ok(spec)
    };
    let (first, second) = (checked(0)?, checked(1)?);
    let arm = ArmModel::from_description(
        &first.name,
        first.arm.clone(),
        first.base,
        first.gripper_model(),
    )
    .map_err(PlanError::Arm)?;
    // Two arms alike (the usual cell) share their primitives: built once, placed twice.
    let gripper = second.gripper_model();
    let other = if arm.is_built_from(&second.arm, &gripper) {
        arm.placed(&second.name, second.base)
    } else {
        ArmModel::from_description(&second.name, second.arm.clone(), second.base, gripper)
            .map_err(PlanError::Arm)?
    };
    Ok([arm, other])
}

/// The collision world's view of a [`Moment`].
pub fn world_state(moment: &Moment) -> WorldState {
    WorldState {
        q: moment.q,
        gripper: moment.gripper,
        object: ObjectPlacement::Fixed(moment.object),
        grasping: moment.contact_allowed,
    }
}
