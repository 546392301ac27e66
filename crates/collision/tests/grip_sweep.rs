//! The closing's sweep answers "how low do the fingers get" three ways that must agree:
//! [`Grip::lowest`] (culled by spheres and circles), [`Grip::clears`] (the same test as a
//! yes/no, stopping early) and a plain minimum over [`Grip::swept_points`].

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pregrasp_collision::fixtures::frame_mesh;
use pregrasp_collision::{close_on_part, Grip, ObjectGeometry};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

/// A pinch and a power grasp across a 40 × 25 mm bar of a frame (as `benches/collision.rs`).
fn grips() -> &'static [Grip; 2] {
    static GRIPS: OnceLock<[Grip; 2]> = OnceLock::new();
    GRIPS.get_or_init(|| {
        let part = ObjectGeometry::new(&frame_mesh(0.5, 0.3, 0.04, 0.025)).unwrap();
        let down = UnitQuaternion::from_euler_angles(PI, 0.0, FRAC_PI_2);
        let at = |z: f64| Isometry3::from_parts(Translation3::new(0.0, 0.13, z), down);
        [at(0.018 + 0.150), at(0.0125 + 0.118)].map(|flange| {
            close_on_part(&part, &pregrasp_robot::Gripper::default(), &flange)
                .expect("the gripper closes on the bar")
        })
    })
}

/// The plain minimum of world z over the swept points (without the sag allowance).
fn brute_lowest(grip: &Grip, flange: &Isometry3<f64>) -> f64 {
    grip.swept_points()
        .iter()
        .map(|p| (flange * p).z)
        .fold(f64::INFINITY, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn lowest_clears_and_the_plain_minimum_agree(
        which in 0usize..2,
        roll in -PI..PI, pitch in -FRAC_PI_2..FRAC_PI_2, yaw in -PI..PI,
        z in -0.2f64..0.2,
        offset in -0.02f64..0.02,
    ) {
        let grip = &grips()[which];
        let flange = Isometry3::from_parts(
            Translation3::from(Vector3::new(0.1, -0.2, z)),
            UnitQuaternion::from_euler_angles(roll, pitch, yaw),
        );
        let lowest = grip.lowest(&flange);
        // `lowest` subtracts the sweep's sag allowance (0.1 mm) from the exact minimum.
        let exact = brute_lowest(grip, &flange);
        prop_assert!((exact - lowest - 1e-4).abs() < 1e-12, "lowest {lowest} vs minimum {exact}");
        // Around the answer and exactly at it, `clears` says what `lowest` says.
        for height in [lowest + offset, lowest, lowest - 1e-15, lowest + 1e-15] {
            prop_assert_eq!(grip.clears(&flange, height), lowest > height, "height {}", height);
        }
    }
}
