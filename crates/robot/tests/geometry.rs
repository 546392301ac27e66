//! Link and gripper geometry: the capsules enclose the measured UR5e housings wherever the
//! arm is, the 2F-85 keeps its stroke free, and the self-collision pairs tell collision truths.

mod common;

use common::{intersects, placed};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{Capsule as PCapsule, Cuboid};
use pregrasp_robot::{
    arm_geometry, joint_sweep_radii, Gripper2F85, GripperState, Joints, Primitive, UrKinematics,
    UrModel,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

/// The MuJoCo Menagerie UR5e body chain (an independent parameterisation of the arm):
/// per body, offset from its parent, an extra parent-to-body rotation, and the joint axis
/// in the body frame. World poses of the 6 moving bodies (shoulder … wrist_3) at `q`.
fn menagerie_bodies(q: &Joints) -> [Isometry3<f64>; 6] {
    let ry90 = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2);
    let id = UnitQuaternion::identity();
    let chain = [
        (Vector3::new(0.0, 0.0, 0.163), id, Vector3::z_axis()),
        (Vector3::new(0.0, 0.138, 0.0), ry90, Vector3::y_axis()),
        (Vector3::new(0.0, -0.131, 0.425), id, Vector3::y_axis()),
        (Vector3::new(0.0, 0.0, 0.392), ry90, Vector3::y_axis()),
        (Vector3::new(0.0, 0.127, 0.0), id, Vector3::z_axis()),
        (Vector3::new(0.0, 0.0, 0.1), id, Vector3::y_axis()),
    ];
    // The base body is turned by π about z.
    let mut pose = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI),
    );
    std::array::from_fn(|i| {
        let (offset, rot, axis) = chain[i];
        pose = pose
            * Isometry3::from_parts(Translation3::from(offset), rot)
            * Isometry3::rotation(axis.into_inner() * q[i]);
        pose
    })
}

/// Sample points on a cylinder (two rims and the mid circle) in a body frame.
fn cylinder_points(axis: usize, center: [f64; 3], r: f64, from: f64, to: f64) -> Vec<Point3<f64>> {
    let mut pts = Vec::new();
    for t in [from, 0.5 * (from + to), to] {
        for k in 0..16 {
            let phi = k as f64 * PI / 8.0;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut p = center;
            p[axis] = t;
            p[u] += r * phi.cos();
            p[v] += r * phi.sin();
            pts.push(Point3::from(p));
        }
        let mut c = center;
        c[axis] = t;
        pts.push(Point3::from(c));
    }
    pts
}

/// Measured UR5e housings per moving body (body index, points in the body frame), from
/// `shared/facts/ur5e-2f85.md`.
fn measured_housings() -> Vec<(usize, Vec<Point3<f64>>)> {
    vec![
        (0, cylinder_points(2, [0.0; 3], 0.060, -0.064, 0.072)), // shoulder pan housing
        (0, cylinder_points(1, [0.0; 3], 0.060, 0.0, 0.074)),    // shoulder lift motor
        (1, cylinder_points(1, [0.0; 3], 0.060, -0.078, 0.072)), // upper arm, shoulder end
        (
            1,
            cylinder_points(1, [0.0, 0.0, 0.425], 0.060, -0.078, 0.072),
        ), // elbow end
        (1, cylinder_points(2, [0.0; 3], 0.045, 0.09, 0.34)),    // upper arm tube
        (2, cylinder_points(1, [0.0; 3], 0.058, -0.057, 0.053)), // forearm elbow housing
        (2, cylinder_points(2, [0.0; 3], 0.038, 0.09, 0.34)),    // forearm tube
        (
            2,
            cylinder_points(1, [0.0, 0.0, 0.392], 0.040, -0.056, 0.053),
        ), // wrist-1 end
        (3, cylinder_points(1, [0.0; 3], 0.040, 0.053, 0.127)),  // wrist_1 joint part
        (
            3,
            cylinder_points(2, [0.0, 0.127, 0.0], 0.040, -0.056, 0.054),
        ), // wrist-2 housing
        (4, cylinder_points(1, [0.0, 0.0, 0.1], 0.040, -0.057, 0.053)), // wrist-3 housing
        (4, cylinder_points(2, [0.0; 3], 0.040, 0.054, 0.1)),    // wrist_2 joint part
        (5, cylinder_points(1, [0.0; 3], 0.044, 0.053, 0.099)),  // wrist_3 flange disc
    ]
}

#[test]
fn menagerie_chain_matches_dh_flange() {
    // Validates the independent chain used below: attachment_site = DH flange (≤ 1.5 mm,
    // the menagerie's millimetre rounding).
    let kin = UrKinematics::new(UrModel::Ur5e);
    let site = Isometry3::from_parts(
        Translation3::new(0.0, 0.1, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -FRAC_PI_2),
    );
    // Body origins at q = 0 as listed in the facts.
    let listed = [
        [0.0, 0.0, 0.163],
        [0.0, -0.138, 0.163],
        [-0.425, -0.007, 0.163],
        [-0.817, -0.007, 0.163],
        [-0.817, -0.134, 0.163],
        [-0.817, -0.134, 0.063],
    ];
    for (body, want) in menagerie_bodies(&[0.0; 6]).iter().zip(listed) {
        assert!((body.translation.vector - Vector3::from(want)).norm() < 1e-12);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..50 {
        let q: Joints = std::array::from_fn(|_| rng.random_range(-PI..PI));
        let mj = menagerie_bodies(&q)[5] * site;
        let dh = kin.fk(&q);
        assert!((mj.translation.vector - dh.translation.vector).norm() < 1.5e-3);
        assert!(mj.rotation.angle_to(&dh.rotation) < 1e-9);
    }
}

#[test]
fn capsules_enclose_measured_ur5e_housings_at_any_q() {
    let kin = UrKinematics::new(UrModel::Ur5e);
    let geometry = arm_geometry(UrModel::Ur5e);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut configs: Vec<Joints> = vec![[0.0; 6]];
    configs.extend((0..20).map(|_| std::array::from_fn(|_| rng.random_range(-PI..PI))));
    for q in &configs {
        let frames = kin.fk_frames(q);
        let bodies = menagerie_bodies(q);
        for (body, points) in measured_housings() {
            let dh_frame = body + 1;
            for p in &points {
                let world = bodies[body] * p;
                let inside = geometry.links.iter().any(|l| {
                    l.frame == dh_frame
                        && match l.primitive {
                            Primitive::Capsule(c) => {
                                c.contains(&(frames[dh_frame].inverse() * world))
                            }
                            Primitive::Cuboid { .. } => false,
                        }
                });
                assert!(
                    inside,
                    "body {body} point {p} (world {world}) outside, q={q:?}"
                );
            }
        }
    }
}

#[test]
fn base_box_encloses_the_measured_foot() {
    let geometry = arm_geometry(UrModel::Ur5e);
    let base = &geometry.links[geometry.index_of("base").expect("base shape")];
    assert_eq!(base.frame, 0);
    let Primitive::Cuboid { pose, half_extents } = base.primitive else {
        panic!("base is a box")
    };
    // Ø151 mm foot, z 0.002 … 0.099 (the lowest 2 mm are left to the mounting plane).
    for p in cylinder_points(2, [0.0; 3], 0.0755, 0.002, 0.099) {
        let local = pose.inverse() * p;
        assert!(
            (0..3).all(|i| local[i].abs() <= half_extents[i] + 1e-12),
            "{p}"
        );
    }
}

#[test]
fn open_gripper_leaves_the_85mm_stroke_free() {
    let g = Gripper2F85::default();
    let open = g.shapes(GripperState::Open);
    assert!(open
        .iter()
        .all(|s| s.name.starts_with("gripper_") && s.frame == 6));
    // The volume swept by the pads: 85 mm along x, the 22 mm pad width, the pad z span.
    let stroke = (
        Isometry3::translation(0.0, 0.0, 0.5 * (0.1228 + 0.1603)),
        Box::new(Cuboid::new(Vector3::new(
            0.0425,
            0.011,
            0.5 * (0.1603 - 0.1228),
        ))) as Box<dyn parry3d_f64::shape::Shape>,
    );
    for s in &open {
        assert!(
            !intersects(&placed(s, &Isometry3::identity()), &stroke),
            "{}",
            s.name
        );
    }
    // ... and the fingers do occupy the space just outside the pads.
    let outside = (
        Isometry3::translation(0.05, 0.0, 0.14),
        Box::new(Cuboid::new(Vector3::new(0.001, 0.001, 0.001)))
            as Box<dyn parry3d_f64::shape::Shape>,
    );
    assert!(open
        .iter()
        .any(|s| intersects(&placed(s, &Isometry3::identity()), &outside)));
    // Closed, the same pad volume is occupied.
    let closed = g.shapes(GripperState::Closed);
    assert!(closed
        .iter()
        .any(|s| intersects(&placed(s, &Isometry3::identity()), &stroke)));
}

#[test]
fn power_point_holds_a_bar_against_the_palm() {
    // A Ø28 mm bar along the finger-width axis (y) centred on the power point touches no
    // open-gripper shape; moved 20 mm deeper it hits the palm.
    let g = Gripper2F85::default();
    let bar = |z: f64| {
        (
            Isometry3::identity(),
            Box::new(PCapsule::new(
                Point3::new(0.0, -0.2, z),
                Point3::new(0.0, 0.2, z),
                0.014,
            )) as Box<dyn parry3d_f64::shape::Shape>,
        )
    };
    let open = g.shapes(GripperState::Open);
    let hit = |z| {
        open.iter()
            .any(|s| intersects(&placed(s, &Isometry3::identity()), &bar(z)))
    };
    assert!(!hit(g.power_point().translation.z));
    assert!(hit(g.power_point().translation.z - 0.02));
    assert!(g.precision_point().translation.z > g.power_point().translation.z);
}

fn self_collisions(model: UrModel, q: &Joints) -> Vec<(&'static str, &'static str)> {
    let kin = UrKinematics::new(model);
    let geometry = arm_geometry(model);
    let frames = kin.fk_frames(q);
    let placed_links: Vec<_> = geometry
        .links
        .iter()
        .map(|l| placed(l, &frames[l.frame]))
        .collect();
    let mut hits = Vec::new();
    for &(i, j) in &geometry.self_collision_pairs {
        if intersects(&placed_links[i], &placed_links[j]) {
            hits.push((geometry.links[i].name, geometry.links[j].name));
        }
    }
    for state in [GripperState::Open, GripperState::Closed] {
        for gs in Gripper2F85::default().shapes(state) {
            let pg = placed(&gs, &frames[6]);
            for i in Gripper2F85::forbidden_arm_links(&geometry) {
                if intersects(&pg, &placed_links[i]) {
                    hits.push((gs.name, geometry.links[i].name));
                }
            }
        }
    }
    hits
}

#[test]
fn typical_poses_are_free_of_self_collision() {
    for model in UrModel::ALL {
        for q in [
            [0.0; 6],
            [0.0, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0],
            [0.5, -1.2, 1.4, -1.8, -FRAC_PI_2, 0.3],
            [0.0, -FRAC_PI_2, 0.0, -FRAC_PI_2, 0.0, 0.0],
        ] {
            let hits = self_collisions(model, &q);
            assert!(hits.is_empty(), "{model} q={q:?}: {hits:?}");
        }
    }
}

#[test]
fn folded_arm_and_inward_gripper_collide() {
    for model in UrModel::ALL {
        // Elbow folded completely: the wrist comes back onto the shoulder.
        let folded = self_collisions(model, &[0.0, -FRAC_PI_2, PI, 0.0, 0.0, 0.0]);
        assert!(
            folded.iter().any(|(a, b)| a.starts_with("shoulder")
                || b.starts_with("shoulder")
                || a.starts_with("upper_arm")
                || b.starts_with("upper_arm")),
            "{model}: {folded:?}"
        );
        // Gripper pointing straight down beside the base axis, fingertips below the base
        // top, a finger over the foot: every IK solution puts the gripper into the base.
        let kin = UrKinematics::new(model);
        let base_top = model.dh().d1 - 0.064 * pregrasp_robot::housing_scale(model);
        // Approach axis −Z, closing axis (fingers) along the base's y axis.
        let down = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2);
        let flange = Isometry3::from_parts(
            Translation3::new(0.0, -1.001 * model.dh().d4, base_top + 0.1),
            down,
        );
        let sols = kin.ik(&flange, &[0.0; 6]);
        assert!(!sols.is_empty(), "{model}: pose reachable");
        for q in sols.iter().take(16) {
            let hits = self_collisions(model, q);
            assert!(
                hits.iter()
                    .any(|(a, b)| a.starts_with("gripper") && *b == "base"),
                "{model}: {hits:?}"
            );
        }
    }
}

#[test]
fn forbidden_links_are_all_but_wrist_3() {
    let geometry = arm_geometry(UrModel::Ur5e);
    let forbidden = Gripper2F85::forbidden_arm_links(&geometry);
    let wrist_3: Vec<usize> = (0..geometry.links.len())
        .filter(|&i| geometry.links[i].frame == 6)
        .collect();
    assert_eq!(forbidden.len() + wrist_3.len(), geometry.links.len());
    assert!(wrist_3.iter().all(|i| !forbidden.contains(i)));
    // Pairs are valid, ordered, unique and never adjacent links.
    let mut seen = std::collections::BTreeSet::new();
    for &(i, j) in &geometry.self_collision_pairs {
        assert!(i < j && j < geometry.links.len() && seen.insert((i, j)));
        assert!(geometry.links[i].frame.abs_diff(geometry.links[j].frame) >= 2);
    }
}

#[test]
fn sweep_radii_bound_point_displacement() {
    let g = Gripper2F85::default();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        let radii = joint_sweep_radii(model, &g);
        assert!(
            radii.windows(2).all(|w| w[0] >= w[1] - 1e-12),
            "{model}: {radii:?}"
        );
        let geometry = arm_geometry(model);
        // Probe points: capsule ends pushed out by the radius, gripper box corners.
        let mut probes: Vec<(usize, Point3<f64>)> = Vec::new();
        for l in &geometry.links {
            if let Primitive::Capsule(c) = l.primitive {
                for e in [c.a, c.b] {
                    for d in [
                        Vector3::x(),
                        -Vector3::x(),
                        Vector3::y(),
                        -Vector3::y(),
                        Vector3::z(),
                        -Vector3::z(),
                    ] {
                        probes.push((l.frame, e + c.radius * d));
                    }
                }
            }
        }
        for s in g
            .shapes(GripperState::Open)
            .into_iter()
            .chain(g.shapes(GripperState::Closed))
        {
            if let Primitive::Cuboid {
                pose,
                half_extents: h,
            } = s.primitive
            {
                for sx in [-1.0, 1.0] {
                    for sy in [-1.0, 1.0] {
                        for sz in [-1.0, 1.0] {
                            probes.push((6, pose * Point3::new(sx * h.x, sy * h.y, sz * h.z)));
                        }
                    }
                }
            }
        }
        for _ in 0..200 {
            let q: Joints = std::array::from_fn(|_| rng.random_range(-PI..PI));
            let dq: Joints = std::array::from_fn(|_| rng.random_range(-0.05..0.05));
            let q2: Joints = std::array::from_fn(|i| q[i] + dq[i]);
            let bound: f64 = (0..6).map(|i| radii[i] * dq[i].abs()).sum();
            let (f1, f2) = (kin.fk_frames(&q), kin.fk_frames(&q2));
            for (f, p) in &probes {
                let moved = (f1[*f] * p - f2[*f] * p).norm();
                assert!(
                    moved <= bound + 1e-12,
                    "{model}: moved {moved} > bound {bound}"
                );
            }
        }
    }
}
