//! The exact tier decides near contact: a small box in the gap between a link's cylinders and
//! the real link (its convex pieces) is clear, although the cylinders alone would call it a
//! contact; the same box moved onto the pieces is a contact; the clearance reported is the
//! pieces' distance.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_collision::shape::pair_intersects;
use pregrasp_collision::{ArmModel, CollisionWorld, Placed, WorldState};
use pregrasp_robot::{arm_geometry, Gripper2F85, GripperState, Joints, Primitive, UrModel};

/// A raised, bent pose: shoulder up, elbow bent, tool pointing down in front of the arm.
const UP: Joints = [0.0, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0];
const MARGIN: f64 = 0.005;
const HALF: f64 = 0.002;

fn arms() -> [ArmModel; 2] {
    let arm = |name: &str, base| ArmModel::new(name, UrModel::Ur5e, base, Gripper2F85::default());
    [
        arm("left", Isometry3::identity()),
        arm("right", Isometry3::translation(0.0, 5.0, 0.0)),
    ]
}

fn world_with_box(center: Point3<f64>) -> CollisionWorld {
    CollisionWorld::try_new(Some(-1.0), None, arms())
        .expect("a valid mesh")
        .with_margin(MARGIN)
        .with_obstacle_cuboid(
            "box",
            Isometry3::from_parts(
                Translation3::from(center.coords),
                UnitQuaternion::identity(),
            ),
            Vector3::repeat(HALF),
        )
}

/// Support of a link shape's primitive in direction `d` (its frame): the farthest point's
/// `d·x` (a rounded cylinder reaches as far as its sharp envelope only along the axis and
/// radially; its support is the core's plus the border).
fn primitive_support(prim: &Primitive, d: &Vector3<f64>) -> f64 {
    match prim {
        Primitive::Cylinder(c) => {
            let (a, b, r) = c.inset();
            let u = (b - a).normalize();
            let radial = (d - u * d.dot(&u)).norm();
            a.coords.dot(d).max(b.coords.dot(d)) + r * radial + c.border
        }
        Primitive::Capsule(c) => c.a.coords.dot(d).max(c.b.coords.dot(d)) + c.radius,
        Primitive::Cuboid { .. } => unreachable!("arm links are cylinders"),
    }
}

#[test]
fn pieces_decide_contact_in_the_gap_the_cylinders_leave() {
    let geometry = arm_geometry(UrModel::Ur5e);
    let world = world_with_box(Point3::new(0.0, 3.0, 3.0));
    let frames = world.arms()[0].kin.fk_frames(&UP);
    let mut tested = 0;
    for link in [
        "shoulder_pan",
        "upper_arm_elbow",
        "forearm_tube",
        "wrist_1_joint",
    ] {
        let Some(i) = geometry.index_of(link) else {
            continue;
        };
        let shape = &geometry.links[i];
        let pieces = shape.pieces.expect("arm links have pieces");
        let frame = frames[shape.frame];
        // Directions (link frame) with the widest gap between the shape and its pieces.
        let n = 400;
        let mut gaps: Vec<(f64, Vector3<f64>, Point3<f64>)> = (0..n)
            .map(|k| {
                // Fibonacci sphere.
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
                let phi = k as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
                let r = (1.0 - z * z).sqrt();
                let d = Vector3::new(r * phi.cos(), r * phi.sin(), z);
                let top = pieces
                    .pieces
                    .iter()
                    .flatten()
                    .max_by(|p, q| p.coords.dot(&d).total_cmp(&q.coords.dot(&d)))
                    .copied()
                    .unwrap();
                (
                    primitive_support(&shape.primitive, &d) - top.coords.dot(&d),
                    d,
                    top,
                )
            })
            .collect();
        gaps.sort_by(|a, b| b.0.total_cmp(&a.0));
        // The box's far side must stay inside the shape's margin band, its near side clear of
        // the pieces by 1 mm more than the margin.
        let reach = HALF * 3f64.sqrt();
        for &(gap, d, top) in gaps.iter().take(40) {
            if gap < MARGIN + 2.0 * reach + 0.002 {
                break;
            }
            let away = frame * (top + d * (MARGIN + reach + 0.001));
            let on = frame * (top - d * 0.0005);
            let clear_world = world_with_box(away);
            if clear_world.check(&WorldState::new([UP, [0.0; 6]])).is_err() {
                continue; // another link of the arm is near this spot
            }
            // The cylinder alone calls it a contact ...
            let placed = world.arms()[0]
                .placed_shapes(&UP, GripperState::Open)
                .into_iter()
                .find(|(n, _)| n == &format!("left/{link}"))
                .unwrap()
                .1;
            let cube = Placed::Cuboid {
                pose: Isometry3::translation(away.x, away.y, away.z),
                half: Vector3::repeat(HALF),
            };
            assert!(
                pair_intersects(&placed, &cube, MARGIN),
                "{link}: the box in the gap must be within the margin of the cylinder"
            );
            // ... the pieces clear it, by the distance the clearance reports ...
            let state = WorldState::new([UP, [0.0; 6]]);
            let (clearance, a, b) = clear_world.clearance(&state);
            assert!(
                clearance > MARGIN && clearance < gap,
                "{link}: clearance {clearance} between {a} and {b}, gap {gap}"
            );
            // ... and a box on the pieces is a contact with this link.
            let contact = world_with_box(on).check(&state).unwrap_err();
            assert!(
                contact.a == format!("left/{link}") || contact.b == format!("left/{link}"),
                "{link}: {contact:?}"
            );
            println!(
                "{link}: gap {:.1} mm, clearance {:.1} mm",
                gap * 1e3,
                clearance * 1e3
            );
            tested += 1;
            break;
        }
    }
    assert!(tested >= 2, "only {tested} links had a testable gap");
}
