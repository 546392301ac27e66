//! Collision benchmarks (the reach planner's are in `pregrasp-reach`).
//!
//! - `check_arm/*`: one arm-vs-world check (UR5e + 2F-85 vs the support, a 10k-triangle
//!   part on it and the other arm), over seeded random configurations, and at a stand-off
//!   just above the part (the BVH is descended).
//! - `edge/boxes`, `edge/state_by_state`: one long free edge of the arm over the part (the pan
//!   turned by 1.5 rad, checked every 5 mm of arm travel), accepted by joint boxes
//!   (`ArmValidity`, `pregrasp_collision::sweep`) or checked one state after another.
//!
//! - `closing/pinch`, `closing/power`: the 2F-85's adaptive closing on a 40 × 25 mm bar of a
//!   frame (`close_on_part`): a pinch with the pads near the bar's bottom, and a power grasp
//!   whose fingers cage the bar.
//!
//! Run: `cargo bench -p pregrasp-collision --bench collision -- --warm-up-time 1 --measurement-time 3`.

use std::f64::consts::{FRAC_PI_2, PI};
use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use pregrasp_collision::fixtures::{plate_10k, stand_off, UP};
use pregrasp_collision::{
    joint_space, ArmModel, ArmValidity, CollisionWorld, ObjectPlacement, WorldState,
};
use pregrasp_motion::StateValidator;
use pregrasp_robot::{Gripper2F85, Joints, UrModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Pose of the 10k-triangle plate: on the table, in front of arm 0 (+x).
fn plate_pose() -> Isometry3<f64> {
    Isometry3::translation(0.5, 0.0, 0.0)
}

fn check_arm(c: &mut Criterion) {
    let g = Gripper2F85::default();
    let arms = [
        ArmModel::new("left", UrModel::Ur5e, Isometry3::identity(), g),
        ArmModel::new(
            "right",
            UrModel::Ur5e,
            Isometry3::from_parts(
                Translation3::new(1.0, 0.0, 0.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, PI),
            ),
            g,
        ),
    ];
    let plate = plate_10k();
    let world = CollisionWorld::try_new(Some(0.0), Some(&plate), arms).expect("a valid mesh");
    let mut state = WorldState::new([UP, UP]);
    state.object = ObjectPlacement::Fixed(plate_pose());
    let space = joint_space(&world.arms()[0]);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let configs: Vec<Joints> = (0..1024).map(|_| space.sample(&mut rng)).collect();
    let free = configs
        .iter()
        .filter(|q| {
            world.is_arm_free(
                0,
                &WorldState {
                    q: [**q, UP],
                    ..state
                },
            )
        })
        .count();
    eprintln!(
        "check_arm/random: {free} of {} configurations free",
        configs.len()
    );
    let mut k = 0;
    c.bench_function("check_arm/random", |b| {
        b.iter(|| {
            k = (k + 1) % configs.len();
            let mut s = state;
            s.q[0] = configs[k];
            black_box(world.is_arm_free(0, black_box(&s)))
        })
    });
    let kin = world.arms()[0].kin.clone();
    let near = kin
        .ik_nearest(
            &stand_off(0.5, 0.05, 0.02, 0.3),
            &[PI, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0],
        )
        .expect("stand-off reachable");
    let mut s = state;
    s.q[0] = near;
    let (d, a, bname) = world.clearance_arm(0, &s);
    eprintln!("check_arm/stand_off: clearance {d:.4} m ({a} – {bname})");
    c.bench_function("check_arm/stand_off", |b| {
        b.iter(|| black_box(world.is_arm_free(0, black_box(&s))))
    });
}

fn edge(c: &mut Criterion) {
    let plate = plate_10k();
    let arm = ArmModel::new(
        "left",
        UrModel::Ur5e,
        Isometry3::identity(),
        Gripper2F85::default(),
    );
    let world = CollisionWorld::single_arm(Some(0.0), Some(&plate), arm)
        .unwrap()
        .with_margin(0.008);
    let mut state = WorldState::new([UP, UP]);
    state.object = ObjectPlacement::Fixed(plate_pose());
    let space = joint_space(&world.arms()[0]);
    let boxes = ArmValidity::new(&world, 0, state);
    let one_by_one = |q: &Joints| boxes.is_valid(q);
    let a = [-0.75, -1.9, 1.9, -1.57, -1.57, 0.0];
    let b = [0.75, -1.7, 1.7, -1.57, -1.57, 0.4];
    let by_boxes = pregrasp_motion::MotionValidator::new(&space, &boxes, 0.005);
    let by_states = pregrasp_motion::MotionValidator::new(&space, &one_by_one, 0.005);
    let (mut n1, mut n2) = (0, 0);
    assert!(by_boxes.check_edge_counted(&a, &b, &mut n1));
    assert!(by_states.check_edge_counted(&a, &b, &mut n2));
    eprintln!(
        "edge: {} steps; {n1} checks with boxes, {n2} state by state",
        by_states.edge_steps(&a, &b)
    );
    c.bench_function("edge/boxes", |bch| {
        bch.iter(|| black_box(by_boxes.check_edge(black_box(&a), &b)))
    });
    c.bench_function("edge/state_by_state", |bch| {
        bch.iter(|| black_box(by_states.check_edge(black_box(&a), &b)))
    });
}

fn closing(c: &mut Criterion) {
    use pregrasp_collision::{close_on_part, fixtures::frame_mesh, ObjectGeometry};
    // A 0.5 × 0.3 m frame of 40 mm bars, 25 mm thick, lying on z = 0; grasps across the bar
    // at y = 0.13, approached from above (G's z down, x across the bar).
    let part = ObjectGeometry::new(&frame_mesh(0.5, 0.3, 0.04, 0.025)).unwrap();
    let down = UnitQuaternion::from_euler_angles(PI, 0.0, FRAC_PI_2);
    let at = |z_point: f64, point_z: f64| {
        Isometry3::from_parts(Translation3::new(0.0, 0.13, z_point + point_z), down)
    };
    let pinch = at(0.018, 0.150);
    let power = at(0.0125, 0.118);
    let mut group = c.benchmark_group("closing");
    group.bench_function("pinch", |b| {
        b.iter(|| {
            black_box(
                close_on_part(
                    &part,
                    &pregrasp_robot::Gripper::default(),
                    black_box(&pinch),
                )
                .is_ok(),
            )
        })
    });
    group.bench_function("power", |b| {
        b.iter(|| {
            black_box(
                close_on_part(
                    &part,
                    &pregrasp_robot::Gripper::default(),
                    black_box(&power),
                )
                .is_ok(),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, check_arm, edge, closing);
criterion_main!(benches);
