//! FK against reference poses computed independently from the same DH tables
//! (`tests/data/ur-fk-reference.json`; where its figures come from: `tests/data/README.md`).

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use pregrasp_robot::{UrKinematics, UrModel};

/// The reference file, part of the crate: no path outside the repository.
const REFERENCE: &str = include_str!("data/ur-fk-reference.json");

fn reference() -> serde_json::Value {
    serde_json::from_str(REFERENCE).expect("reference JSON parses")
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

#[test]
fn fk_matches_every_reference_pose() {
    let data = reference();
    let obj = data.as_object().expect("object keyed by model");
    let mut checked = 0;
    for model in UrModel::ALL {
        let cases = obj[model.name()].as_array().expect("cases");
        assert!(!cases.is_empty());
        let kin = UrKinematics::new(model);
        for case in cases {
            let q: [f64; 6] = floats(&case["q"]).try_into().expect("6 joints");
            let xyz = floats(&case["xyz"]);
            let quat = floats(&case["quat_xyzw"]);
            let want_p = Vector3::new(xyz[0], xyz[1], xyz[2]);
            let want_r = UnitQuaternion::from_quaternion(Quaternion::new(
                quat[3], quat[0], quat[1], quat[2],
            ));
            let got = kin.fk(&q);
            let dp = (got.translation.vector - want_p).norm();
            let dr = 2.0 * (got.rotation.conjugate() * want_r).imag().norm();
            assert!(dp < 1e-9, "{model} q={q:?}: position error {dp}");
            assert!(dr < 1e-9, "{model} q={q:?}: rotation error {dr}");
            // fk_frames ends at the same flange pose.
            let frames = kin.fk_frames(&q);
            assert!((frames[6].translation.vector - want_p).norm() < 1e-12 + dp);
            checked += 1;
        }
    }
    assert_eq!(
        checked,
        obj.values()
            .map(|v| v.as_array().unwrap().len())
            .sum::<usize>()
    );
    // Every model, 12 cases each, the first at the zero configuration.
    assert_eq!(checked, 12 * UrModel::ALL.len());
}

/// `fk_frames` against an independent composition of the DH matrices
/// `Rz(θ)·Tz(d)·Tx(a)·Rx(α)` built with nalgebra.
#[test]
fn fk_frames_compose_the_dh_transforms() {
    use nalgebra::{Isometry3, Translation3};
    use std::f64::consts::FRAC_PI_2;
    let alpha = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, -FRAC_PI_2, 0.0];
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        let dh = model.dh();
        let d = [dh.d1, 0.0, 0.0, dh.d4, dh.d5, dh.d6];
        let a = [0.0, dh.a2, dh.a3, 0.0, 0.0, 0.0];
        let q = [0.3, -1.1, 2.0, -0.4, 1.7, -2.9];
        let frames = kin.fk_frames(&q);
        assert_eq!(frames[0], Isometry3::identity());
        let mut t = Isometry3::identity();
        for i in 0..6 {
            t = t
                * Isometry3::rotation(Vector3::z() * q[i])
                * Translation3::new(a[i], 0.0, d[i])
                * Isometry3::rotation(Vector3::x() * alpha[i]);
            assert!((frames[i + 1].translation.vector - t.translation.vector).norm() < 1e-14);
            assert!(frames[i + 1].rotation.angle_to(&t.rotation) < 1e-12);
        }
        let flange = kin.fk(&q);
        assert!((flange.translation.vector - frames[6].translation.vector).norm() < 1e-14);
        assert!(flange.rotation.angle_to(&frames[6].rotation) < 1e-12);
    }
}

#[test]
fn model_tables() {
    use std::f64::consts::PI;
    for model in UrModel::ALL {
        assert_eq!(UrModel::from_name(model.name()), Some(model));
        assert_eq!(model.name().parse::<UrModel>(), Ok(model));
        let lim = model.joint_limits();
        assert_eq!(lim[2], (-PI, PI));
        for j in [0, 1, 3, 4, 5] {
            assert_eq!(lim[j], (-2.0 * PI, 2.0 * PI));
        }
        assert!(model.max_joint_accel().iter().all(|&a| a == 1.4));
        // Reach ≈ |a2| + |a3| + d6-ish: the datasheet reach within 10 %.
        let dh = model.dh();
        let arm = -dh.a2 - dh.a3;
        assert!((arm - model.reach()).abs() < 0.1 * model.reach(), "{model}");
    }
    assert_eq!(UrModel::from_name("UR10E"), Some(UrModel::Ur10e));
    assert_eq!(UrModel::from_name("ur7"), None);
    assert!("ur7"
        .parse::<UrModel>()
        .unwrap_err()
        .to_string()
        .contains("ur7"));
    assert_eq!(UrModel::Ur5e.max_joint_speed(), [PI; 6]);
    assert_eq!(UrModel::Ur3e.max_joint_speed()[3], 2.0 * PI);
    assert_eq!(UrModel::Ur10e.max_joint_speed()[0], 2.0 * PI / 3.0);
    assert_eq!(UrModel::Ur16e.max_joint_speed()[2], PI);
}
