//! How the grippers close on the part at the scene's grasps: per arm at the support grasp G_s
//! (by its precision point) and at its power grasp (by its power point), from the part's mesh;
//! the closings a planning context takes from its caller, and where the pads bear.

use nalgebra::Isometry3;
use pregrasp_collision::{close_on_part, pad_patches, ArmModel, CollisionWorld, Grip, GripFailure};
use pregrasp_model::PadContact;

/// How the grippers close on the part, from its mesh: per arm, at the support grasp G_s (by
/// its precision point) and at its own power grasp.
#[derive(Clone, Debug)]
pub struct Grips {
    /// Closing at G_s of each arm, should it support.
    pub support: [Result<Grip, GripFailure>; 2],
    /// Closing of each arm at its power grasp.
    pub power: [Result<Grip, GripFailure>; 2],
}

/// `f(0)` and `f(1)` side by side: one computation per arm (its gripper's closings), each
/// independent of the other's.
pub(crate) fn each_arm<T: Send>(f: impl Fn(usize) -> T + Sync) -> [T; 2] {
    let (a, b) = rayon::join(|| f(0), || f(1));
    [a, b]
}

/// Whether both arms hold G_s alike: they hold it by their precision points, so with the same
/// precision point the closing on the part there, and its pad patches, are one.
pub(crate) fn holds_support_alike(arms: &[ArmModel; 2]) -> bool {
    arms[0].gripper.precision_point() == arms[1].gripper.precision_point()
}

/// How both grippers close on the part at G_s (`support`, by the precision point) and at their
/// power grasps (`power`, by the power point), from the part's mesh in `world`.
pub fn grips(
    world: &CollisionWorld,
    support: &Isometry3<f64>,
    power: &[Isometry3<f64>; 2],
) -> Grips {
    grips_knowing(world, support, power, KnownClosings::default())
}

/// Closings a planning context takes rather than computing them: `None` where it closes the
/// gripper itself.
#[derive(Clone, Debug, Default)]
pub struct KnownClosings {
    /// At G_s, per arm ([`support_closings`]).
    pub support: Option<[Result<Grip, GripFailure>; 2]>,
    /// At each arm's power grasp (the seating's, [`crate::seat`]).
    pub power: Option<[Result<Grip, GripFailure>; 2]>,
}

/// The closings of `arms` at G_s `support` (object frame) on `object`, held by their
/// precision points, side by side (one, where both arms hold it alike).
pub fn support_closings(
    object: &pregrasp_collision::ObjectGeometry,
    arms: &[ArmModel; 2],
    support: &Isometry3<f64>,
) -> [Result<Grip, GripFailure>; 2] {
    let close = |arm: usize| {
        let gripper = &arms[arm].gripper;
        close_on_part(
            object,
            gripper,
            &(support * gripper.precision_point().inverse()),
        )
    };
    let alike = holds_support_alike(arms);
    let (first, second) = rayon::join(|| close(0), || (!alike).then(|| close(1)));
    let second = second.unwrap_or_else(|| first.clone());
    [first, second]
}

/// [`grips`], taking the closings from `known` where given (they must be the closings at
/// `support` and `power`).
pub(crate) fn grips_knowing(
    world: &CollisionWorld,
    support: &Isometry3<f64>,
    power: &[Isometry3<f64>; 2],
    known: KnownClosings,
) -> Grips {
    let object = world.object().expect("the world has the part");
    // The closings are independent: run side by side (each answer is its own, so the result
    // does not depend on the threads).
    let close_power = |arm: usize| {
        let gripper = &world.arms()[arm].gripper;
        close_on_part(
            object,
            gripper,
            &(power[arm] * gripper.power_point().inverse()),
        )
    };
    let (at_support, at_power) = rayon::join(
        || {
            known
                .support
                .clone()
                .unwrap_or_else(|| support_closings(object, world.arms(), support))
        },
        || known.power.clone().unwrap_or_else(|| each_arm(close_power)),
    );
    Grips {
        support: at_support,
        power: at_power,
    }
}

/// Where the pads of `grip` bear on the part at `grasp` (object frame) held by `point` (the
/// tool point in the flange frame): both patches' midpoint in the grasp frame, the smaller
/// torsion radius, both areas. `None` unless both pads bear on it.
pub fn pad_contact(
    object: &pregrasp_collision::ObjectGeometry,
    gripper: &pregrasp_robot::Gripper,
    grasp: &Isometry3<f64>,
    point: &Isometry3<f64>,
    grip: &Grip,
) -> Option<PadContact> {
    let flange_in_object = grasp * point.inverse();
    let [a, b] = pad_patches(object, gripper, &flange_in_object, grip);
    let (a, b) = (a?, b?);
    let mid = point.inverse() * nalgebra::center(&a.center, &b.center);
    Some(PadContact {
        center: [mid.x, mid.y, mid.z],
        torsion_radius: a.torsion_radius.min(b.torsion_radius),
        area: [a.area, b.area],
    })
}
