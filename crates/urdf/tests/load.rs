//! Loading: chain extraction from the shipped URDFs, reference FK values, mimic joints, and
//! the error messages of bad URDFs.

mod common;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use common::{data, dist, fr3, model, ur5e, xarm6};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pregrasp_urdf::{Drive, JointKind, SerialChain, UrdfError, UrdfModel};

fn iso(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

#[test]
fn shipped_chains_have_the_expected_joints() {
    let c = fr3();
    assert_eq!(c.dof(), 7);
    assert_eq!(
        c.joint_names(),
        (1..=7).map(|i| format!("fr3_joint{i}")).collect::<Vec<_>>()
    );
    let l = c.limits();
    // robots/fr3/joint_limits.yaml: joint4 in [−3.0421, −0.1518], joint6 in [0.5445, 4.5169].
    assert_eq!(
        (l[3].lower, l[3].upper, l[3].velocity),
        (-3.0421, -0.1518, 2.62)
    );
    assert_eq!(
        (l[5].lower, l[5].upper, l[5].velocity),
        (0.5445, 4.5169, 4.18)
    );
    assert!(c.joints().iter().all(|j| j.kind == JointKind::Revolute));
    // The fixed joint fr3_joint8 is folded into the tip offset: 0.107 m along z.
    assert!((c.tip_offset().translation.vector - Vector3::new(0.0, 0.0, 0.107)).norm() < 1e-15);
    assert_eq!(c.links().first().unwrap().name, "fr3_link0");
    assert_eq!(c.links().last().unwrap().name, "fr3_link8");
    assert_eq!(c.links().len(), 9);

    let x = xarm6();
    assert_eq!(x.dof(), 6);
    assert_eq!(x.limits()[2].lower, -3.927);
    let u = ur5e();
    assert_eq!(u.dof(), 6);
    assert_eq!(u.limits()[2].upper, PI);
    assert_eq!(u.limits()[0].upper, 2.0 * PI);
    // base_link, base_link_inertia, six moving links, flange, tool0.
    let names: Vec<&str> = u.links().iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names[..2], ["base_link", "base_link_inertia"]);
    assert_eq!(names[names.len() - 2..], ["flange", "tool0"]);
}

#[test]
fn model_lists_roots_leaves_and_mimics() {
    let m = model("fr3.urdf");
    assert_eq!(m.root_links(), ["base"]);
    assert_eq!(
        m.leaf_links(),
        ["fr3_hand_tcp", "fr3_leftfinger", "fr3_rightfinger"]
    );
    let mimics = m.mimic_joints();
    assert_eq!(mimics.len(), 1);
    assert_eq!(mimics[0].joint, "fr3_finger_joint2");
    assert_eq!(mimics[0].master, "fr3_finger_joint1");
    assert_eq!((mimics[0].multiplier, mimics[0].offset), (1.0, 0.0));
    // The arm chain records the file's mimic relations although none is on it.
    assert_eq!(fr3().mimics(), &mimics[..]);
    // A chain through the left finger gets the prismatic finger joint as an 8th variable.
    let c = m.chain("fr3_link0", "fr3_leftfinger").unwrap();
    assert_eq!(c.dof(), 8);
    assert_eq!(c.joints()[7].kind, JointKind::Prismatic);
    assert_eq!(c.limits()[7].upper, 0.04);
}

/// FR3 at q = 0, the joint origins of robots/fr3/kinematics.yaml composed by hand: joint1
/// lifts 0.333; joint2 turns −π/2 about x, so joint3's (0, −0.316, 0) points up (+0.316);
/// joint3 turns back; joint4 adds x 0.0825; joint4 turns +π/2, so joint5's
/// (−0.0825, 0.384, 0) is x −0.0825 and z +0.384; joint5 turns back, joint6 turns +π/2,
/// joint7 adds x 0.088 and turns +π/2 (link7 = Rx(π)); joint8 is 0.107 along link7's z, i.e.
/// down. Flange: (0.088, 0, 0.333 + 0.316 + 0.384 − 0.107) = (0.088, 0, 0.926), Rx(π).
#[test]
fn fr3_zero_configuration_by_hand() {
    let c = fr3();
    let flange = c.fk(&[0.0; 7]);
    let (dp, dr) = dist(&flange, &iso([0.088, 0.0, 0.926], [PI, 0.0, 0.0]));
    assert!(dp < 1e-12 && dr < 1e-12, "{dp:e} {dr:e}");
    // The hand TCP: fr3_hand_joint turns −π/4 about z, fr3_hand_tcp_joint is 0.1034 along z.
    let tcp = model("fr3.urdf")
        .chain("fr3_link0", "fr3_hand_tcp")
        .unwrap();
    let want =
        iso([0.088, 0.0, 0.926 - 0.1034], [PI, 0.0, 0.0]) * iso([0.0; 3], [0.0, 0.0, -FRAC_PI_4]);
    let (dp, dr) = dist(&tcp.fk(&[0.0; 7]), &want);
    assert!(dp < 1e-12 && dr < 1e-12, "{dp:e} {dr:e}");
    // A general q against the product of the origins of kinematics.yaml written out here.
    let q = [0.3, -0.4, 0.5, -1.2, 0.7, 1.9, -0.8];
    let origins = [
        ([0.0, 0.0, 0.333], [0.0, 0.0, 0.0]),
        ([0.0, 0.0, 0.0], [-FRAC_PI_2, 0.0, 0.0]),
        ([0.0, -0.316, 0.0], [FRAC_PI_2, 0.0, 0.0]),
        ([0.0825, 0.0, 0.0], [FRAC_PI_2, 0.0, 0.0]),
        ([-0.0825, 0.384, 0.0], [-FRAC_PI_2, 0.0, 0.0]),
        ([0.0, 0.0, 0.0], [FRAC_PI_2, 0.0, 0.0]),
        ([0.088, 0.0, 0.0], [FRAC_PI_2, 0.0, 0.0]),
    ];
    let mut t = Isometry3::identity();
    for (i, (xyz, rpy)) in origins.iter().enumerate() {
        t = t * iso(*xyz, *rpy) * iso([0.0; 3], [0.0, 0.0, q[i]]);
    }
    t *= iso([0.0, 0.0, 0.107], [0.0; 3]);
    let (dp, dr) = dist(&c.fk(&q), &t);
    assert!(dp < 1e-14 && dr < 1e-14, "{dp:e} {dr:e}");
}

/// UR5e at q = 0: the DH flange is at (a2 + a3, −d4 − d6, d1 − d5) =
/// (−0.8172, −0.2329, 0.0628) in the controller Base frame, which is `base_link` turned by π
/// about z: (0.8172, 0.2329, 0.0628) in `base_link`. (The description's 2e-11 m offsets
/// and 1.570796327 roll keep it 1e-10 away.)
#[test]
fn ur5e_zero_configuration_by_hand() {
    let t = ur5e().fk(&[0.0; 6]);
    let p = t.translation.vector;
    assert!(
        (p - Vector3::new(0.8172, 0.2329, 0.0628)).norm() < 1e-9,
        "{p}"
    );
}

/// xArm6 at q = 0 from its joint origins: z 0.267, then joint3 (0.0535, −0.2845, 0) under
/// Rx(−π/2) gives x 0.0535, z +0.2845; joint4 (0.0775, 0.3425, 0) gives x +0.0775,
/// z −0.3425; joint6 (0.076, 0.097, 0) under Rx(−π/2)·Rx(−π/2)·Rx(π/2) gives x +0.076,
/// z −0.097: (0.207, 0, 0.112). The description writes π/2 as 1.5708, hence 1e-6.
#[test]
fn xarm6_zero_configuration_by_hand() {
    let p = xarm6().fk(&[0.0; 6]).translation.vector;
    assert!((p - Vector3::new(0.207, 0.0, 0.112)).norm() < 1e-6, "{p}");
}

#[test]
fn link_frames_and_jacobian_agree_with_fk() {
    let c = fr3();
    let q = [0.1, 0.2, -0.3, -1.5, 0.4, 1.2, 0.5];
    let frames = c.link_frames(&q);
    let (dp, dr) = dist(frames.last().unwrap(), &c.fk(&q));
    assert!(dp < 1e-15 && dr < 1e-15);
    assert_eq!(frames[0], Isometry3::identity());
    // Jacobian against central differences of the FK (position and rotation vector).
    let jac = c.jacobian(&q);
    let h = 1e-6;
    for i in 0..7 {
        let (mut a, mut b) = (q, q);
        a[i] += h;
        b[i] -= h;
        let e = pregrasp_urdf::pose_error(&c.fk(&a), &c.fk(&b)) / (2.0 * h);
        assert!((e - jac.column(i)).norm() < 1e-8, "column {i}");
    }
}

const TWO_LINKS: &str = r#"<robot name="toy">
  <link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0 0 1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="b"/><child link="c"/>
    <origin xyz="1 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.5" velocity="1" effort="1"/><mimic joint="j1" multiplier="0.5" offset="0.1"/></joint>
  <joint name="j3" type="fixed"><parent link="c"/><child link="d"/><origin xyz="0 0 0.2" rpy="0 0 1.5707963267948966"/></joint>
</robot>"#;

#[test]
fn mimic_joint_on_the_chain_follows_its_master() {
    let c = UrdfModel::from_urdf_str(TWO_LINKS, "toy.urdf")
        .unwrap()
        .chain("a", "d")
        .unwrap();
    assert_eq!(c.dof(), 1);
    assert_eq!(c.joints().len(), 2);
    assert_eq!(
        c.joints()[1].drive,
        Drive::Mimic {
            master: 0,
            multiplier: 0.5,
            offset: 0.1
        }
    );
    let q = 0.6;
    // j1 turns by q about z at height 1; j2 slides 0.5·q + 0.1 along the turned x, from x = 1.
    let r = 1.0 + 0.5 * q + 0.1;
    let p = c.fk(&[q]).translation.vector;
    assert!(
        (p - Vector3::new(r * q.cos(), r * q.sin(), 1.2)).norm() < 1e-15,
        "{p}"
    );
    assert_eq!(c.joint_values(&[q]), vec![q, 0.5 * q + 0.1]);
    // d/dq of the position: r·(−sin, cos) + 0.5·(cos, sin).
    let j = c.jacobian(&[q]);
    let want = Vector3::new(
        -r * q.sin() + 0.5 * q.cos(),
        r * q.cos() + 0.5 * q.sin(),
        0.0,
    );
    assert!((j.fixed_view::<3, 1>(0, 0) - want).norm() < 1e-15);
}

fn err(text: &str, base: &str, tip: &str) -> String {
    let e = UrdfModel::from_urdf_str(text, "bad.urdf").and_then(|m| m.chain(base, tip));
    let e: UrdfError = e.expect_err("the URDF should be rejected");
    let msg = e.to_string();
    assert!(msg.starts_with("bad.urdf: "), "{msg}");
    msg
}

fn with_joint(joint: &str) -> String {
    format!(r#"<robot name="r"><link name="a"/><link name="b"/>{joint}</robot>"#)
}

#[test]
fn bad_urdfs_are_reported_with_file_and_element() {
    let m = err(TWO_LINKS, "a", "nowhere");
    assert!(
        m.contains("unknown link `nowhere`") && m.contains("tool link"),
        "{m}"
    );
    let m = err(TWO_LINKS, "base", "d");
    assert!(m.contains("unknown link `base`"), "{m}");
    let m = err(TWO_LINKS, "c", "a");
    assert!(m.contains("no path from link `c` down to link `a`"), "{m}");
    let m = err(TWO_LINKS, "c", "d");
    assert!(
        m.contains("no moving joint between link `c` and link `d`"),
        "{m}"
    );
    // The mimic joint j2 without its master j1 on the chain.
    let m = err(TWO_LINKS, "b", "d");
    assert!(m.contains("joint `j2`") && m.contains("mimics `j1`"), "{m}");

    let m = err(
        &with_joint(
            r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>"#,
        ),
        "a",
        "b",
    );
    assert!(m.contains("joint `j` (revolute) has no <limit"), "{m}");
    let m = err(
        &with_joint(
            r#"<joint name="p" type="prismatic"><parent link="a"/><child link="b"/></joint>"#,
        ),
        "a",
        "b",
    );
    assert!(m.contains("joint `p` (prismatic) has no <limit"), "{m}");
    let m = err(
        &with_joint(
            r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="1" upper="-1" velocity="1"/></joint>"#,
        ),
        "a",
        "b",
    );
    assert!(
        m.contains("joint `j` has an invalid <limit>: lower 1 > upper -1"),
        "{m}"
    );
    let m = err(
        &with_joint(
            r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/><limit lower="-1" upper="1" velocity="1"/></joint>"#,
        ),
        "a",
        "b",
    );
    assert!(
        m.contains("joint `j` has an unusable <axis xyz=\"0 0 0\">"),
        "{m}"
    );
    let m = err(
        &with_joint(
            r#"<joint name="f" type="floating"><parent link="a"/><child link="b"/></joint>"#,
        ),
        "a",
        "b",
    );
    assert!(m.contains("joint `f` is of type floating"), "{m}");
    let m = err(
        &with_joint(r#"<joint name="j" type="fixed"><parent link="a"/><child link="x"/></joint>"#),
        "a",
        "b",
    );
    assert!(m.contains("unknown link `x` (child of joint `j`)"), "{m}");
    let m = err(
        &with_joint(
            r#"<joint name="j" type="continuous"><parent link="a"/><child link="b"/><mimic joint="k"/></joint>"#,
        ),
        "a",
        "b",
    );
    assert!(m.contains("joint `j` mimics unknown joint `k`"), "{m}");
    // Two parents for `b`: a closed loop is not a serial chain.
    let m = err(
        r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
           <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
           <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"#,
        "a",
        "b",
    );
    assert!(
        m.contains("not a serial chain: link `b` is the child of two joints, `j1` and `j2`"),
        "{m}"
    );
    // A loop of parents.
    let m = err(
        r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
           <joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
           <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"#,
        "a",
        "b",
    );
    assert!(
        m.contains("not a serial chain") && m.contains("loop"),
        "{m}"
    );
    let m = err(
        r#"<robot name="r"><link name="a"/><link name="a"/></robot>"#,
        "a",
        "a",
    );
    assert!(m.contains("link name `a` is used twice"), "{m}");
    let m = err(r#"<robot name="r"><link name="a"></robot>"#, "a", "a");
    assert!(m.contains("not a valid URDF"), "{m}");
}

#[test]
fn a_missing_file_is_named() {
    let path = data("no-such-robot.urdf");
    let e = SerialChain::from_file(&path, "a", "b").unwrap_err();
    assert!(matches!(e, UrdfError::Io { .. }));
    assert!(
        e.to_string()
            .starts_with(&format!("{path}: cannot read the file")),
        "{e}"
    );
}

#[test]
fn continuous_joints_have_infinite_limits() {
    let c = UrdfModel::from_urdf_str(
        &with_joint(r#"<joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/></joint>"#),
        "c.urdf",
    )
    .unwrap()
    .chain("a", "b")
    .unwrap();
    let l = c.limits()[0];
    assert_eq!(
        (l.lower, l.upper, l.velocity),
        (f64::NEG_INFINITY, f64::INFINITY, f64::INFINITY)
    );
    assert_eq!(c.joints()[0].kind, JointKind::Continuous);
    // Rotation about y by 1 rad.
    let r = c.fk(&[1.0]).rotation;
    assert!(r.angle_to(&UnitQuaternion::from_euler_angles(0.0, 1.0, 0.0)) < 1e-15);
}
