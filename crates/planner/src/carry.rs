//! Will the power grasps carry the part? The carry check ([`pregrasp_physics::carry`]) of a
//! candidate's final state: the part at P_obj held by both arms' power grasps as their real
//! closings hold it ([`crate::context::Grips`]), lifted. It depends on P_obj alone, so it runs
//! once Algorithm 2 has found the pose, before any motion is planned. A candidate whose grasps
//! need more than the gripper's largest force to carry the part ([`Uncarried::beyond_gripper`])
//! is refused with `[physics] reject` (the default); one that carries it only without the
//! safety factor, or that no force carries, is kept and its plan says so in
//! `physics.warnings`, unless `[physics] reject_uncarried` refuses it too (before any motion is
//! planned).
//!
//! The check decides *whether* the power grasps can carry the part; they close (`mas1`, `sup2`)
//! at the gripper's largest force, not at `safety_factor ×` its minimum. Replayed at that
//! setting (20–44 N, on 40 plans of the examples and 30 generated parts,
//! `tools/gripper_truth/plan_sweep.py`), 10 plans the check carries rose only 29–38 mm of a
//! 50 mm lift and tilted 4–13°, plans that lift at 235 N (rise ≥ 46 mm, tilt ≤ 2.4°): the real
//! closing lets a wrapped bar push the fingers open at a low setting, which the check's rigid
//! wrap does not see.

use std::fmt;

use crate::hold_kind::hold_kind;
use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_collision::{pad_patches, CollisionWorld, Grip};
use pregrasp_io::scene::Scene;
use pregrasp_physics::carry::LIFT_ACCELERATION;
use pregrasp_physics::{
    min_carry_force, CarryOutcome, CarryProblem, HoldKind, PartMass, PhysicsSettings, PowerHold,
    GRAVITY,
};

use crate::context::{Grips, PlanningContext};
use crate::hold_kind::PAD_HALF_WIDTH;

/// The 2F-85's fingers' width along the bar (m), their pads' (`docs/hardware-facts.md`): the
/// lever of a wrap's moments per newton of squeeze ([`PowerHold::wrap_moment_arm`]).
const FINGER_WIDTH: f64 = 2.0 * PAD_HALF_WIDTH;

/// The carry check of one scene: the part's mass and the power grasps' closings, known once.
pub struct CarryCheck {
    /// Weight (N) and centre of mass (object frame); `None` when the part has no mass
    /// properties (the grip check says why), and then nothing is checked.
    part: Option<(f64, Point3<f64>)>,
    /// Each arm's power grasp, in the object frame; `None` when its gripper does not close there (Algorithm 2 then
    /// refuses every pose).
    holds: [Option<PowerHold>; 2],
    mu: f64,
    safety_factor: f64,
    /// Each arm's gripper's force range (N).
    range: [(f64, f64); 2],
}

/// The forces the power grasps close with (N, per arm in the scene's order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarryForces {
    /// The smallest grip force that carries the part (both grippers alike).
    pub minimum: f64,
    /// The force to set on each arm's gripper: its largest (see the module documentation).
    pub set: [f64; 2],
}

/// Why the power grasps cannot carry the part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Uncarried {
    /// They need `required` = `safety_factor × minimum` (N), more than a gripper's
    /// `max_force`.
    NeedsMoreForce {
        required: f64,
        safety_factor: f64,
        minimum: f64,
        max_force: f64,
    },
    /// No grip force holds the part in both hands.
    NoForce {
        /// How each hand's closing ends.
        kinds: [HoldKind; 2],
    },
}

impl fmt::Display for Uncarried {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Uncarried::NeedsMoreForce {
                required,
                safety_factor,
                minimum,
                max_force,
            } => write!(
                f,
                "carry: the power grasps need {required:.0} N (safety factor {safety_factor} × \
                 {minimum:.0} N) to lift the part, more than the gripper's {max_force:.0} N"
            ),
            Uncarried::NoForce { kinds } => write!(
                f,
                "carry: no grip force lifts the part in the power grasps (closings: {} and {})",
                word(kinds[0]),
                word(kinds[1])
            ),
        }
    }
}

/// The carry check's verdict at one P_obj ([`CarryCheck::check`]): the forces that carry the
/// part, or why none does; `None` where nothing is known to check with.
pub type CarryVerdict = Option<Result<CarryForces, Uncarried>>;

impl Uncarried {
    /// Whether the smallest grip force that carries the part is more than the gripper's
    /// largest, margin or not. The planner refuses such a candidate with `[physics] reject`
    /// (the default). One that falls short only by the safety factor is kept, flagged, unless
    /// `[physics] reject_uncarried`; so is one that no force carries ([`Uncarried::NoForce`]):
    /// that verdict is the contact model's, which has no way to balance the load, and it
    /// knows a description's gripper less well than the 2F-85 (no measured pad patches).
    pub fn beyond_gripper(&self) -> bool {
        match *self {
            Uncarried::NeedsMoreForce {
                minimum, max_force, ..
            } => minimum > max_force,
            Uncarried::NoForce { .. } => false,
        }
    }
}

fn word(kind: HoldKind) -> &'static str {
    match kind {
        HoldKind::Pinch => "pinch",
        HoldKind::Encompassing => "encompassing",
        HoldKind::Caged => "caged (tips on each other)",
        HoldKind::OneSided => "one-sided",
    }
}

impl CarryCheck {
    /// The check of `ctx`'s scene; `part`: its mass properties, when it has them.
    pub fn new(
        ctx: &PlanningContext,
        part: Option<&PartMass>,
        settings: &PhysicsSettings,
    ) -> CarryCheck {
        CarryCheck::of(ctx.scene, &ctx.world, &ctx.grips, part, settings)
    }

    /// The check of `scene`'s power grasps closed as `grips` on the part of `world`.
    pub fn of(
        scene: &Scene,
        world: &CollisionWorld,
        grips: &Grips,
        part: Option<&PartMass>,
        settings: &PhysicsSettings,
    ) -> CarryCheck {
        let holds = [0, 1].map(|arm| {
            let grip = grips.power[arm].as_ref().ok()?;
            hold_in_object(scene, world, arm, grip)
        });
        CarryCheck {
            part: part.map(|p| (p.mass * GRAVITY, p.centroid)),
            holds,
            mu: settings.mu_pad,
            safety_factor: settings.safety_factor,
            range: scene
                .robots
                .each_ref()
                .map(|r| r.gripper_model().grip_force_range()),
        }
    }

    /// The forces that carry the part at `p_obj`, or why none within the grippers' range
    /// does. `None` when nothing is known to check with.
    pub fn check(&self, p_obj: &Isometry3<f64>) -> CarryVerdict {
        let (weight, com) = self.part?;
        let [Some(a), Some(b)] = self.holds else {
            return None;
        };
        let place = |h: &PowerHold| PowerHold {
            frame: p_obj * h.frame,
            squeeze: h.squeeze.map(|p| p_obj * p),
            ..*h
        };
        let problem = CarryProblem {
            com: p_obj * com,
            weight,
            lift_acceleration: LIFT_ACCELERATION,
            holds: [place(&a), place(&b)],
            mu: self.mu,
        };
        let max_force = self.range[0].1.min(self.range[1].1);
        Some(match min_carry_force(&problem) {
            Ok(CarryOutcome::Carried(c)) => {
                let required = self.safety_factor * c.grip_force;
                if required > max_force {
                    Err(Uncarried::NeedsMoreForce {
                        required,
                        safety_factor: self.safety_factor,
                        minimum: c.grip_force,
                        max_force,
                    })
                } else {
                    Ok(CarryForces {
                        minimum: c.grip_force,
                        set: self.range.map(|r| r.1),
                    })
                }
            }
            Ok(CarryOutcome::CannotCarry) => Err(Uncarried::NoForce {
                kinds: [a.closing, b.closing],
            }),
            // The solver could not decide: nothing is known (the plan is not flagged, and its
            // power grasps get no force of their own).
            Err(_) => return None,
        })
    }
}

/// Arm `arm`'s power grasp closed as `grip`, in the object frame: the squeeze at the pads'
/// patches where both pads bear on the part, else across the grasp's `x` at the closed width.
fn hold_in_object(
    scene: &Scene,
    world: &CollisionWorld,
    arm: usize,
    grip: &Grip,
) -> Option<PowerHold> {
    let grasp = scene.grasps.power[arm];
    let gripper = &world.arms()[arm].gripper;
    let flange = grasp * gripper.power_point().inverse();
    let patches = pad_patches(world.object()?, gripper, &flange, grip);
    let (squeeze, torsion_radius, patch_half_extent) = match patches {
        [Some(a), Some(b)] => {
            // The patches as rectangles: the pad's full width along the bar, the rest of the
            // smaller area across it.
            let along = PAD_HALF_WIDTH;
            let across = a.area.min(b.area) / (4.0 * along);
            (
                [flange * a.center, flange * b.center],
                a.torsion_radius.min(b.torsion_radius),
                [along, across],
            )
        }
        _ => {
            let o = Point3::from(grasp.translation.vector);
            let x = grasp.rotation * Vector3::x();
            let half = 0.5 * grip.width();
            ([o + half * x, o - half * x], 0.0, [0.0; 2])
        }
    };
    Some(PowerHold {
        frame: grasp,
        squeeze,
        torsion_radius,
        patch_half_extent,
        wrap_moment_arm: FINGER_WIDTH,
        closing: hold_kind(&grip.kinds),
    })
}
