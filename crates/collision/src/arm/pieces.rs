//! What an arm model is built from once per model: the exact pieces of its links and gripper
//! (shared by every world of that model) and the bounding spheres of its shape groups.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

use nalgebra::Isometry3;
use pregrasp_robot::{Gripper, LinkShape, PerShape};

use crate::closing::robotiq_finger_hull;
use crate::shape::Bounded;
use crate::tight::Tight;

use super::posed::place;

/// The exact pieces of the gripper's shapes (shared by every arm with that gripper).
pub(super) fn gripper_tight(gripper: &Gripper) -> Arc<Vec<Option<Tight>>> {
    static TIGHT: PerShape<Arc<Vec<Option<Tight>>>> = PerShape::new();
    TIGHT.get_or_build(gripper, |gripper| {
        // The 2F-85's finger links get the hulls the closing uses (see `robotiq_finger_hull`),
        // set now: built lazily, the first query's thread would decide which of two equal hulls
        // is built, and the baked table (`baked_hulls`) would hold one or the other by timing.
        let robotiq = gripper.robotiq().is_some();
        let statics = gripper.static_count();
        Arc::new(
            gripper
                .shape_pieces()
                .into_iter()
                .enumerate()
                .map(|(k, p)| {
                    let t = p.and_then(Tight::new)?;
                    Some(match k.checked_sub(statics) {
                        Some(j) if robotiq => t.with_hull(robotiq_finger_hull(j)),
                        _ => t,
                    })
                })
                .collect(),
        )
    })
}

/// A sphere around the gripper at every opening: centre on the flange axis, radius covering
/// every shape's bounding sphere at 65 openings from closed to open, plus 1 mm for the motion
/// between them (the fingers move less than that between neighbouring samples' spheres).
pub(super) fn gripper_sphere(gripper: &Gripper) -> (nalgebra::Point3<f64>, f64) {
    // The shapes (not the precision and power points) decide it.
    static SPHERE: PerShape<(nalgebra::Point3<f64>, f64)> = PerShape::new();
    if gripper.robotiq().is_some() {
        return (
            GRIPPER_SPHERE_CENTER,
            f64::from_bits(ROBOTIQ_2F85_SPHERE_RADIUS),
        );
    }
    SPHERE.get_or_build(gripper, gripper_sphere_of)
}

/// The centre of every gripper's sphere (flange frame).
const GRIPPER_SPHERE_CENTER: nalgebra::Point3<f64> = nalgebra::Point3::new(0.0, 0.0, 0.09);

/// The 2F-85's sphere radius ([`gripper_sphere_of`]; its bits), kept: the sampled openings
/// cost 1.6 M instructions, a fifth of building the arm models of a process. The test
/// `the_2f85_sphere_is_the_computed_one` computes it again.
const ROBOTIQ_2F85_SPHERE_RADIUS: u64 = 0x3fc1_9acb_88de_93fa;

/// [`gripper_sphere`], computed.
pub(super) fn gripper_sphere_of(gripper: &Gripper) -> (nalgebra::Point3<f64>, f64) {
    let center = GRIPPER_SPHERE_CENTER;
    let mut radius: f64 = 0.0;
    let states = gripper.sample_states();
    for state in states {
        gripper.for_each_shape(state, |_, _, prim| {
            let b = Bounded::new(place(&Isometry3::identity(), &prim));
            radius = radius.max((b.center - center).norm() + b.radius);
        });
    }
    (center, radius + 0.001)
}

/// Per DH frame, a sphere holding the bounding spheres of that frame's link shapes: centre at
/// the middle of their box, radius to the farthest one.
pub(super) fn frame_spheres(links: &[LinkShape]) -> [(nalgebra::Point3<f64>, f64); 7] {
    std::array::from_fn(|f| {
        let spheres: Vec<Bounded> = links
            .iter()
            .filter(|l| l.frame == f)
            .map(|l| {
                let mut b = Bounded::new(place(&Isometry3::identity(), &l.primitive));
                b.radius += l.pieces.map_or(0.0, |p| p.slack);
                b
            })
            .collect();
        if spheres.is_empty() {
            return (nalgebra::Point3::origin(), 0.0);
        }
        let mut lo = nalgebra::Point3::from([f64::INFINITY; 3]);
        let mut hi = nalgebra::Point3::from([f64::NEG_INFINITY; 3]);
        for b in &spheres {
            let r = nalgebra::Vector3::repeat(b.radius);
            lo = lo.inf(&(b.center - r));
            hi = hi.sup(&(b.center + r));
        }
        let c = nalgebra::center(&lo, &hi);
        let radius = spheres
            .iter()
            .map(|b| (b.center - c).norm() + b.radius)
            .fold(0.0, f64::max);
        (c, radius)
    })
}

/// Per link shape of an arm, its exact pieces where it has them.
pub(super) type TightSet = Arc<Vec<Option<Tight>>>;

/// The exact pieces of the link shapes of the arm named `key` ([`ArmDescription::key`]),
/// built once per process and arm, then shared by every arm of that kind.
///
/// [`ArmDescription::key`]: pregrasp_robot::ArmDescription::key
pub(super) fn tight_pieces(key: &str, links: &[LinkShape]) -> TightSet {
    static CACHE: OnceLock<Mutex<BTreeMap<String, TightSet>>> = OnceLock::new();
    let mut cache = CACHE
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    cache
        .entry(key.to_string())
        .or_insert_with(|| {
            Arc::new(
                links
                    .iter()
                    .map(|l| l.pieces.and_then(Tight::new))
                    .collect(),
            )
        })
        .clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_2f85_sphere_is_the_computed_one() {
        let gripper: Gripper = pregrasp_robot::Gripper2F85::default().into();
        let (center, radius) = gripper_sphere_of(&gripper);
        assert_eq!(
            (center, radius.to_bits()),
            (GRIPPER_SPHERE_CENTER, ROBOTIQ_2F85_SPHERE_RADIUS),
            "the 2F-85 changed: its sphere radius is {radius} ({:#x})",
            radius.to_bits()
        );
        assert_eq!(gripper_sphere(&gripper), (center, radius));
    }
}
