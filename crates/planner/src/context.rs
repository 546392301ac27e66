//! The planning context: a validated scene turned into models — the two arms in the world,
//! the collision world (support, object mesh, arms), P_init — shared read-only by every
//! pipeline stage (so candidates can be evaluated in parallel without locks).

use nalgebra::Isometry3;
use pregrasp_collision::{ArmModel, CollisionWorld, Contact, ObjectPlacement, WorldState};
use pregrasp_geometry::Mesh;
use pregrasp_io::scene::Scene;
use pregrasp_motion::{JointSpace, MotionValidator};
use pregrasp_robot::{wrap_angle, Gripper2F85, Joints, UrKinematics, UrModel};

use crate::timeline::Moment;

/// Resolution (m) at which motions are validated: no point of an arm moves farther than this
/// between two checked states (bound Σ w_i |Δq_i|, with w_i the joint sweep radii).
pub const MOTION_RESOLUTION: f64 = 0.005;

/// Safety margin (m) the planner keeps between bodies that must not touch, on top of the
/// robot model's own inflation (`pregrasp_robot::LINK_MARGIN`). Every point of a validated
/// motion lies within `MOTION_RESOLUTION / 2` of a checked state, so this margin of more than
/// half the resolution makes the whole motion — not only its checked states — collision-free
/// for the plan checker, which uses no margin.
pub const PLANNING_MARGIN: f64 = 0.003;

/// A scene that cannot be turned into models.
#[derive(Debug, thiserror::Error)]
pub enum ContextError {
    #[error("{file}: robot[{index}].model: unknown robot model {model:?}")]
    UnknownModel {
        file: String,
        index: usize,
        model: String,
    },
}

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
}

impl<'a> PlanningContext<'a> {
    pub fn new(scene: &'a Scene, mesh: &'a Mesh) -> Result<Self, ContextError> {
        let arms = arm_models(scene)?;
        let spaces = [
            pregrasp_collision::joint_space(&arms[0]),
            pregrasp_collision::joint_space(&arms[1]),
        ];
        let world = CollisionWorld::new(scene.support_height, Some(mesh), arms)
            .with_margin(PLANNING_MARGIN);
        Ok(PlanningContext {
            scene,
            mesh,
            p_init: scene.initial_object_pose(),
            world,
            spaces,
            names: [scene.robots[0].name.clone(), scene.robots[1].name.clone()],
        })
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
        MotionValidator {
            space: &self.spaces[arm],
            validator,
            resolution: MOTION_RESOLUTION,
        }
    }

    /// Every IK solution of arm `arm` for a world flange pose, within limits, sorted by distance
    /// to the arm's start, that is collision-free with the gripper closed on the part at
    /// `object` (gripper–part contact allowed) and the other arm at its start configuration.
    pub fn free_ik(
        &self,
        arm: usize,
        flange_world: &Isometry3<f64>,
        object: &Isometry3<f64>,
    ) -> Vec<Joints> {
        let model = self.arm(arm);
        let target = model.base.inverse() * flange_world;
        let starts = self.starts();
        distinct_ik(&model.kin, &target, &starts[arm])
            .into_iter()
            .filter(|q| {
                let moment = Moment::at_rest(starts, *object).holding(arm, *q);
                self.check_arm(arm, &moment).is_ok()
            })
            .collect()
    }
}

/// One configuration per geometrically distinct IK solution (at most 8): of the ±2π variants
/// the joint limits allow, the one nearest to `seed`. The variants share one geometry, so
/// collision-checking one of each is enough. Sorted by distance to `seed`.
pub fn distinct_ik(kin: &UrKinematics, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
    let mut seen: Vec<Joints> = Vec::new();
    kin.ik(flange, seed)
        .into_iter()
        .filter(|q| {
            let wrapped = q.map(wrap_angle);
            let new = !seen
                .iter()
                .any(|s| (0..6).all(|j| (s[j] - wrapped[j]).abs() < 1e-9));
            if new {
                seen.push(wrapped);
            }
            new
        })
        .collect()
}

/// The two arm models of a scene, in world.
pub fn arm_models(scene: &Scene) -> Result<[ArmModel; 2], ContextError> {
    let build = |index: usize| -> Result<ArmModel, ContextError> {
        let spec = &scene.robots[index];
        let model = UrModel::from_name(&spec.model).ok_or_else(|| ContextError::UnknownModel {
            file: scene.file.display().to_string(),
            index,
            model: spec.model.clone(),
        })?;
        let gripper = Gripper2F85 {
            precision_point_z: spec.precision_point_z,
            power_point_z: spec.power_point_z,
        };
        Ok(ArmModel::new(&spec.name, model, spec.base, gripper))
    };
    Ok([build(0)?, build(1)?])
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
