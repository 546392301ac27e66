//! Collision truths on hand-built scenes: the support, a frame-shaped part, a grasped bar,
//! two arms, margins and the single-arm validity checker.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_collision::fixtures::{box_mesh, frame_mesh};
use pregrasp_collision::{
    joint_space, ArmModel, ArmValidity, CollisionWorld, ObjectPlacement, Placed, WorldState,
};
use pregrasp_motion::StateValidator;
use pregrasp_robot::{Gripper2F85, GripperState, Joints, UrModel};

/// A raised, bent pose: shoulder up, elbow bent, tool pointing down in front of the arm.
const UP: Joints = [0.0, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0];

fn arm(name: &str, base: Isometry3<f64>) -> ArmModel {
    ArmModel::new(name, UrModel::Ur5e, base, Gripper2F85::default())
}

/// Left arm at the origin, right arm far away (5 m along y).
fn two_arms() -> [ArmModel; 2] {
    [
        arm("left", Isometry3::identity()),
        arm("right", Isometry3::translation(0.0, 5.0, 0.0)),
    ]
}

fn capsule_of(arm: &ArmModel, q: &Joints, name: &str) -> (Point3<f64>, Point3<f64>, f64) {
    arm.placed_shapes(q, GripperState::Open)
        .into_iter()
        .find_map(|(n, s)| match s {
            Placed::Capsule { a, b, radius } if n == name => Some((a, b, radius)),
            // A rounded cylinder reaches its core's radius plus the border at mid-length.
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } if n == name => Some((a, b, radius + border)),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no capsule or cylinder named {name}"))
}

#[test]
fn arm_through_the_table_collides_with_the_support() {
    let world = CollisionWorld::try_new(Some(0.0), None, two_arms()).expect("a valid mesh");
    let up = WorldState::new([UP, [0.0; 6]]);
    assert_eq!(world.check(&up), Ok(()));
    // Shoulder lift turned down: the upper arm points into the table.
    let q: Joints = [0.0, FRAC_PI_2, 0.0, 0.0, 0.0, 0.0];
    let elbow = world.arms()[0].kin.fk_frames(&q)[2].translation.vector;
    assert!(
        elbow.z < -0.2,
        "the test pose must put the elbow under the table: {elbow}"
    );
    let down = WorldState::new([q, [0.0; 6]]);
    let c = world.check(&down).unwrap_err();
    assert_eq!(c.b, "support");
    assert!(
        c.a.starts_with("left/") && !c.a.contains("gripper"),
        "{c:?}"
    );
    assert_eq!(world.check_arm(0, &down).unwrap_err(), c);
    assert_eq!(world.check_arm(1, &down), Ok(()), "arm 1 is not involved");
    let (d, a, b) = world.clearance(&down);
    assert!(d < -0.1, "deep penetration expected, got {d} for {a}–{b}");
    assert_eq!(b, "support");
}

#[test]
fn base_link_may_touch_the_support_it_is_mounted_on() {
    let world = CollisionWorld::try_new(Some(0.0), None, two_arms()).expect("a valid mesh");
    let s = WorldState::new([UP, UP]);
    assert_eq!(world.check(&s), Ok(()));
    let (d, a, b) = world.clearance(&s);
    assert!(d > 0.0, "{a}–{b} at {d}");
    assert!(!a.ends_with("/base") && !b.ends_with("/base"));
}

#[test]
fn margin_turns_a_near_miss_into_a_contact() {
    let world = CollisionWorld::try_new(Some(0.0), None, two_arms()).expect("a valid mesh");
    let s = WorldState::new([UP, UP]);
    let (d, a, b) = world.clearance(&s);
    assert!(d > 0.01);
    let tight = world.clone().with_margin(d + 1e-3);
    let c = tight.check(&s).unwrap_err();
    // Both arms stand alike: the nearest pair is the same link pair on either arm.
    let link = |n: &str| n.split_once('/').map(|(_, l)| l.to_string());
    assert_eq!((link(&c.a), link(&c.b)), (link(&a), link(&b)));
    assert_eq!(world.with_margin(d - 1e-3).check(&s), Ok(()));
}

/// A frame standing across the forearm: its plane normal is the forearm axis, centred on
/// the forearm capsule's midpoint, shifted in its plane by `offset` (m).
fn frame_across_forearm(arm: &ArmModel, q: &Joints, offset: f64) -> (Isometry3<f64>, f64) {
    let (a, b, r) = capsule_of(arm, q, "left/forearm_tube");
    let axis = (b - a).normalize();
    let rot = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap();
    let in_plane = rot * Vector3::x();
    let mid = nalgebra::center(&a, &b);
    // The frame mesh spans z ∈ [0, t]: centre it on the midpoint along the axis.
    let t = 0.03;
    let origin = mid - axis * (0.5 * t) + in_plane * offset;
    (
        Isometry3::from_parts(Translation3::from(origin.coords), rot),
        r,
    )
}

#[test]
fn arm_through_a_frame_opening_is_free_through_its_bar_collides() {
    // Opening 0.30 × 0.30, bars 0.05 wide: a forearm (r < 0.06) passes through the middle.
    let (outer, bar) = (0.40, 0.05);
    let mesh = frame_mesh(outer, outer, bar, 0.03);
    let world = CollisionWorld::try_new(Some(-1.0), Some(&mesh), two_arms()).expect("a valid mesh");
    let q = UP;
    let (through_opening, r) = frame_across_forearm(&world.arms()[0], &q, 0.0);
    assert!(r + 0.01 < 0.5 * (outer - 2.0 * bar));
    let mut s = WorldState::new([q, [0.0; 6]]);
    s.object = ObjectPlacement::Fixed(through_opening);
    assert_eq!(
        world.check(&s),
        Ok(()),
        "the forearm passes through the opening"
    );
    // Clearance and margin agree: the first contact appears exactly at the clearance.
    let (d, a, b) = world.clearance(&s);
    assert!(d > 0.0, "{a}–{b} at {d}");
    assert_eq!(world.clone().with_margin(d - 1e-4).check(&s), Ok(()));
    assert!(world.clone().with_margin(d + 1e-4).check(&s).is_err());
    // The part's convex hull would have collided: the opening is what makes it free.
    let (through_bar, _) = frame_across_forearm(&world.arms()[0], &q, 0.5 * (outer - bar));
    s.object = ObjectPlacement::Fixed(through_bar);
    let c = world.check(&s).unwrap_err();
    assert_eq!(
        (c.a.as_str(), c.b.as_str()),
        ("left/forearm_tube", "object")
    );
    let (d, _, _) = world.clearance(&s);
    assert!(d <= 0.0);
}

#[test]
fn gripper_may_touch_the_bar_it_grasps_only_with_the_grasp_flag() {
    let mut arms = two_arms();
    arms[0].gripper = Gripper2F85::default().into();
    let g = arms[0].gripper.clone();
    // A 30 mm square bar along the finger-width axis (flange y), centred on the power point.
    let bar = box_mesh(Point3::origin(), Vector3::new(0.015, 0.15, 0.015), 1);
    let world = CollisionWorld::try_new(Some(-1.0), Some(&bar), arms).expect("a valid mesh");
    let q = UP;
    let flange = world.arms()[0].flange_world(&q);
    let mut s = WorldState::new([q, [0.0; 6]]);
    s.gripper[0] = GripperState::fully_closed();
    for placement in [
        ObjectPlacement::Fixed(flange * g.power_point()),
        ObjectPlacement::Attached {
            arm: 0,
            flange_to_object: g.power_point(),
        },
    ] {
        s.object = placement;
        s.grasping = [false, false];
        let c = world.check(&s).unwrap_err();
        assert!(c.a.starts_with("left/gripper"), "{c:?}");
        assert_eq!(c.b, "object");
        s.grasping = [true, false];
        assert_eq!(world.check(&s), Ok(()), "{placement:?}");
        assert_eq!(world.check_arm(0, &s), Ok(()));
        // The flag of the other arm does not help.
        s.grasping = [false, true];
        assert!(world.check(&s).is_err());
    }
}

#[test]
fn two_arms_touching_name_both_links() {
    // Facing each other along x: the right base turned by π, 1.4 m away, both stretched.
    let facing = |x: f64| {
        [
            arm("left", Isometry3::identity()),
            arm(
                "right",
                Isometry3::from_parts(
                    Translation3::new(-x, 0.0, 0.0),
                    UnitQuaternion::from_euler_angles(0.0, 0.0, PI),
                ),
            ),
        ]
    };
    let s = WorldState::new([[0.0; 6], [0.0; 6]]);
    let near = CollisionWorld::try_new(Some(-1.0), None, facing(1.4)).expect("a valid mesh");
    let c = near.check(&s).unwrap_err();
    assert!(
        c.a.starts_with("left/") && c.b.starts_with("right/"),
        "{c:?}"
    );
    assert_eq!(near.check_arm(0, &s).unwrap_err(), c);
    let c1 = near.check_arm(1, &s).unwrap_err();
    assert!(
        c1.a.starts_with("right/") && c1.b.starts_with("left/"),
        "{c1:?}"
    );
    let far = CollisionWorld::try_new(Some(-1.0), None, facing(2.6)).expect("a valid mesh");
    assert_eq!(far.check(&s), Ok(()));
    let (d, a, b) = far.clearance(&s);
    assert!(d > 0.0, "{a}–{b} at {d}");
    let (d, a, b) = near.clearance(&s);
    assert!(
        d <= 0.0 && a.starts_with("left/") && b.starts_with("right/"),
        "{a}–{b} at {d}"
    );
}

#[test]
fn static_cuboid_obstacle_is_named() {
    let world = CollisionWorld::try_new(Some(-1.0), None, two_arms())
        .expect("a valid mesh")
        .with_obstacle_cuboid(
            "box",
            Isometry3::translation(-0.2, 0.0, 0.163),
            Vector3::new(0.05, 0.3, 0.05),
        );
    let c = world
        .check(&WorldState::new([[0.0; 6], [0.0; 6]]))
        .unwrap_err();
    assert!(c.a.starts_with("left/upper_arm") && c.b == "box", "{c:?}");
    assert_eq!(world.check(&WorldState::new([UP, [0.0; 6]])), Ok(()));
}

#[test]
fn attached_part_moves_with_the_flange_and_hits_obstacles() {
    let plate = box_mesh(Point3::origin(), Vector3::new(0.1, 0.1, 0.005), 2);
    let g = Gripper2F85::default();
    let world =
        CollisionWorld::try_new(Some(-1.0), Some(&plate), two_arms()).expect("a valid mesh");
    let flange = world.arms()[0].flange_world(&UP);
    let part_world = flange * g.power_point();
    // A cuboid just around where the held plate is, far from the gripper itself.
    let world = world.with_obstacle_cuboid(
        "post",
        Isometry3::translation(
            part_world.translation.x + 0.09,
            part_world.translation.y + 0.09,
            part_world.translation.z,
        ),
        Vector3::new(0.02, 0.02, 0.02),
    );
    let mut s = WorldState::new([UP, [0.0; 6]]);
    s.gripper[0] = GripperState::fully_closed();
    s.grasping[0] = true;
    s.object = ObjectPlacement::Attached {
        arm: 0,
        flange_to_object: g.power_point(),
    };
    let c = world.check_arm(0, &s).unwrap_err();
    assert_eq!((c.a.as_str(), c.b.as_str()), ("object", "post"));
    assert_eq!(world.check(&s).unwrap_err(), c);
    // The same part held by the far arm is not near the post.
    s.object = ObjectPlacement::Attached {
        arm: 1,
        flange_to_object: g.power_point(),
    };
    s.grasping = [false, true];
    s.gripper = [GripperState::Open, GripperState::fully_closed()];
    assert_eq!(world.check(&s), Ok(()));
}

#[test]
fn arm_validity_rejects_limits_and_contacts() {
    let world = CollisionWorld::try_new(Some(0.0), None, two_arms()).expect("a valid mesh");
    let v = ArmValidity::new(&world, 0, WorldState::new([[0.0; 6], UP]));
    assert!(v.is_valid(&UP));
    assert!(!v.is_valid(&[0.0, FRAC_PI_2, 0.0, 0.0, 0.0, 0.0]));
    let mut beyond = UP;
    beyond[2] = 3.5; // elbow limit is ±π
    assert!(!v.is_valid(&beyond));
    let space = joint_space(&world.arms()[0]);
    assert_eq!(space.upper[2], UrModel::Ur5e.joint_limits()[2].1);
    let radii = pregrasp_robot::joint_sweep_radii(UrModel::Ur5e, &Gripper2F85::default().into());
    assert_eq!(space.weights, radii);
}

/// A box touches the part's mesh exactly where parry's own box–mesh test says so: random
/// boxes, turned every way, placed through, across and beside the bars of a frame.
#[test]
fn boxes_touch_the_part_where_parry_says_they_do() {
    use parry3d_f64::shape::Cuboid;
    use rand::{Rng, SeedableRng};
    let mesh = frame_mesh(0.6, 0.4, 0.05, 0.03);
    let object = pregrasp_collision::ObjectGeometry::new(&mesh).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
    let (mut touching, mut apart) = (0, 0);
    for _ in 0..4000 {
        let t = Vector3::new(
            rng.random_range(-0.4..0.4),
            rng.random_range(-0.3..0.3),
            rng.random_range(-0.08..0.1),
        );
        let axis = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * 3.0;
        let pose = Isometry3::from_parts(t.into(), UnitQuaternion::from_scaled_axis(axis));
        let half = Vector3::from_fn(|_, _| rng.random_range(0.002..0.06));
        let reference = parry3d_f64::query::intersection_test(
            &pose,
            &Cuboid::new(half),
            &Isometry3::identity(),
            object.trimesh(),
        )
        .unwrap();
        // Both test the box against the mesh's triangles (its surface).
        assert_eq!(
            object.box_touches(&pose, &half),
            reference,
            "{pose:?} {half:?}"
        );
        if reference {
            touching += 1;
        } else {
            apart += 1;
        }
    }
    assert!(
        touching > 500 && apart > 500,
        "{touching} touching, {apart} apart"
    );
}
