//! Recognising UR arms in their ROS 2 descriptions, and the analytic FK/IK through the match.

mod common;

use std::f64::consts::{FRAC_PI_2, PI};

use common::{dist, fr3, model, random_q, rng, ur5e, xarm6};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use pregrasp_robot::{Joints, UrKinematics, UrModel};
use pregrasp_urdf::{recognise_ur, UrdfModel};

#[test]
fn every_shipped_ur_is_recognised_with_the_ros_base_turn() {
    for (file, want) in [
        ("ur3e.urdf", UrModel::Ur3e),
        ("ur5e.urdf", UrModel::Ur5e),
        ("ur10e.urdf", UrModel::Ur10e),
        ("ur16e.urdf", UrModel::Ur16e),
        ("ur5.urdf", UrModel::Ur5),
    ] {
        let chain = model(file).chain("base_link", "tool0").unwrap();
        let m = recognise_ur(&chain).unwrap_or_else(|| panic!("{file} not recognised"));
        assert_eq!(m.model, want, "{file}");
        // base_link → Base: π about z (the description's base_link → base joint).
        let turn = Isometry3::rotation(Vector3::z() * PI);
        let (dp, dr) = dist(&m.base, &turn);
        assert!(dp < 1e-12 && dr < 1e-12, "{file}: base {dp:e} {dr:e}");
        // tool0 is DH frame 6, up to the description's rounding (1.570796327 for π/2).
        let (dp, dr) = dist(&m.tool, &Isometry3::identity());
        assert!(dp < 1e-9 && dr < 1e-9, "{file}: tool {dp:e} {dr:e}");
        assert!(m.deviation < 1e-9, "{file}: deviation {:e}", m.deviation);
    }
}

/// The brief's check: the URDF chain's FK equals `UrKinematics::fk` composed with the two
/// fixed transforms, within 1e-9, at 1000 random joint vectors.
#[test]
fn ur5e_urdf_fk_equals_the_analytic_fk_with_the_fixed_transforms() {
    let chain = ur5e();
    let m = recognise_ur(&chain).unwrap();
    let kin = UrKinematics::new(UrModel::Ur5e);
    let mut r = rng(1);
    let (mut wp, mut wr) = (0.0_f64, 0.0_f64);
    for _ in 0..1000 {
        let q: Joints = random_q(&chain, &mut r, 0.0).try_into().unwrap();
        let (dp, dr) = dist(&chain.fk(&q), &(m.base * kin.fk(&q) * m.tool));
        wp = wp.max(dp);
        wr = wr.max(dr);
    }
    eprintln!("UR5e URDF vs DH FK, 1000 q: max {wp:.2e} m, {wr:.2e} rad");
    assert!(wp < 1e-9 && wr < 1e-9, "{wp:e} {wr:e}");
}

#[test]
fn other_base_and_tool_links_change_only_the_fixed_transforms() {
    let m = model("ur5e.urdf");
    // From the world link, through flange: tool = (flange → tool0)⁻¹ … i.e. tool0 → flange.
    let chain = m.chain("world", "flange").unwrap();
    let u = recognise_ur(&chain).unwrap();
    assert_eq!(u.model, UrModel::Ur5e);
    // ur_macro: flange → tool0 is rpy (π/2, 0, π/2); so flange in tool0 is its inverse.
    let tool0_in_flange = Isometry3::from_parts(
        Default::default(),
        UnitQuaternion::from_euler_angles(FRAC_PI_2, 0.0, FRAC_PI_2),
    );
    let (dp, dr) = dist(&u.tool, &tool0_in_flange.inverse());
    assert!(dp < 1e-9 && dr < 1e-9, "{dp:e} {dr:e}");
    // base_link_inertia is already turned by π: its DH base is the identity.
    let chain = m.chain("base_link_inertia", "tool0").unwrap();
    let u = recognise_ur(&chain).unwrap();
    let (dp, dr) = dist(&u.base, &Isometry3::identity());
    assert!(dp < 1e-12 && dr < 1e-12, "{dp:e} {dr:e}");
}

#[test]
fn non_ur_arms_and_altered_urs_are_not_recognised() {
    assert!(recognise_ur(&fr3()).is_none());
    assert!(recognise_ur(&xarm6()).is_none());
    let text = std::fs::read_to_string(common::data("ur5e.urdf")).unwrap();
    // The forearm 1 mm longer.
    let longer = text.replace(r#"xyz="-0.3922 0 0.1333""#, r#"xyz="-0.3932 0 0.1333""#);
    assert_ne!(longer, text);
    let chain = UrdfModel::from_urdf_str(&longer, "longer")
        .unwrap()
        .chain("base_link", "tool0")
        .unwrap();
    assert!(recognise_ur(&chain).is_none());
    // Shoulder lift reversed.
    let reversed = text.replacen(
        r#"<child link="upper_arm_link"/>
    <origin rpy="1.570796327 0 0" xyz="0 0 0"/>
    <axis xyz="0 0 1"/>"#,
        r#"<child link="upper_arm_link"/>
    <origin rpy="1.570796327 0 0" xyz="0 0 0"/>
    <axis xyz="0 0 -1"/>"#,
        1,
    );
    assert_ne!(reversed, text);
    let chain = UrdfModel::from_urdf_str(&reversed, "reversed")
        .unwrap()
        .chain("base_link", "tool0")
        .unwrap();
    assert!(recognise_ur(&chain).is_none());
}

/// Round trips through the analytic path: random q → URDF FK → `UrMatch::ik` → URDF FK.
/// Every analytic solution must land on the target within 1e-6, and the original q must be
/// among them.
#[test]
fn ur5e_analytic_ik_round_trips_through_the_urdf_chain() {
    let chain = ur5e();
    let m = recognise_ur(&chain).unwrap();
    let mut r = rng(2);
    let (mut wp, mut wr, mut found) = (0.0_f64, 0.0_f64, 0);
    for _ in 0..1000 {
        let q: Joints = random_q(&chain, &mut r, 0.0).try_into().unwrap();
        let target = chain.fk(&q);
        let sols = m.ik(&target, &q);
        assert!(!sols.is_empty());
        for s in &sols {
            let (dp, dr) = dist(&chain.fk(s), &target);
            wp = wp.max(dp);
            wr = wr.max(dr);
        }
        let d = pregrasp_urdf::joint_distance(&sols[0], &q);
        if d < 1e-6 {
            found += 1;
        }
        assert_eq!(m.ik_nearest(&target, &q).unwrap(), sols[0]);
    }
    eprintln!("UR5e analytic via URDF: 1000/1000 solved, max {wp:.2e} m {wr:.2e} rad, q itself first in {found}");
    assert!(wp < 1e-6 && wr < 1e-6);
    assert!(found >= 995, "{found}");
}
