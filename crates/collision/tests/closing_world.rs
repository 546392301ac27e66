//! [`PartClosing`] — the closing world of a part's triangle mesh and the support — closes the
//! fingers exactly as a world of exact solids does: on the bars of the MuJoCo table
//! (`crates/robot/data/gripper_truth/`, whose agreement with MuJoCo `pregrasp-robot`'s
//! `closing_truth` test measures), a bar as a 12-triangle mesh in its own frame with the grasp
//! and the table placed around it gives the same fingers as a parry cuboid and a half-space.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::query::intersection_test;
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid};
use pregrasp_collision::fixtures::box_mesh;
use pregrasp_collision::{FingerShapes, ObjectGeometry, PartClosing};
use pregrasp_robot::{close_fingers, ClosingWorld, FingerLinkage, PlanarPose, Touch};
use serde_json::Value;

#[path = "../../robot/tests/common/menagerie.rs"]
mod menagerie;

fn data(name: &str) -> Value {
    let path = format!(
        "{}/../robot/data/gripper_truth/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A convex piece as a parry hull and its vertices.
type Piece = (ConvexPolyhedron, Vec<Point3<f64>>);

/// The Menagerie finger's collision pieces as parry hulls, per link, for the `+x` finger and
/// its mirror image (`[+x, −x]`).
fn finger_solids() -> [Vec<Vec<Piece>>; 2] {
    let raw = menagerie::collision_pieces(1.0);
    [1.0, -1.0].map(|sign: f64| {
        raw.iter()
            .map(|link| {
                link.iter()
                    .map(|pts| {
                        let v: Vec<Point3<f64>> = pts
                            .iter()
                            .map(|p| Point3::new(sign * p.x, p.y, p.z))
                            .collect();
                        (ConvexPolyhedron::from_convex_hull(&v).unwrap(), v)
                    })
                    .collect()
            })
            .collect()
    })
}

/// The same bar and table as exact solids, in G.
struct Solids<'a> {
    pieces: &'a [Vec<Vec<Piece>>; 2],
    bar: Cuboid,
    bar_pose: Isometry3<f64>,
    table: Option<f64>,
}

impl ClosingWorld for Solids<'_> {
    fn touch(&self, side: f64, link: usize, pose: &PlanarPose) -> Touch {
        let frame = pose.to_isometry(side);
        let pieces = &self.pieces[usize::from(side < 0.0)][link];
        if let Some(z) = self.table {
            if pieces
                .iter()
                .flat_map(|(_, v)| v.iter())
                .any(|v| (frame * v).z > z)
            {
                return Touch::Support;
            }
        }
        let rel = frame.inverse() * self.bar_pose;
        if pieces.iter().any(|(hull, _)| {
            intersection_test(&rel, &self.bar, &Isometry3::identity(), hull).unwrap()
        }) {
            return Touch::Part;
        }
        Touch::Nothing
    }
}

#[test]
fn a_bar_as_a_mesh_closes_the_fingers_as_the_solid_bar_does() {
    let truth = data("closing_2f85.json");
    let raw = menagerie::collision_pieces(1.0);
    let shapes = FingerShapes::new(&raw).unwrap();
    let pieces = finger_solids();
    let linkage = FingerLinkage::robotiq_2f85();
    let (mut rows, mut worst) = (0, 0.0_f64);
    // Every fourth simulated row: all widths, depths, tilts, with and without the table.
    for row in truth["rows"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["status"] == "simulated")
        .step_by(4)
    {
        let bar = &row["bar"];
        let get = |k: &str| bar[k].as_f64().unwrap();
        let half = Vector3::new(0.5 * get("width"), 0.15, 0.5 * get("thickness"));
        let bar_pose = Isometry3::from_parts(
            Translation3::new(0.0, 0.0, get("z_center")),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), get("tilt_deg").to_radians()),
        );
        let table = row["table_z"].as_f64();
        let solids = Solids {
            pieces: &pieces,
            bar: Cuboid::new(half),
            bar_pose,
            table,
        };
        // The mesh in the bar's own frame; G and the table placed in it.
        let object = ObjectGeometry::new(&box_mesh(Point3::origin(), half, 2)).unwrap();
        let up = bar_pose.rotation.inverse() * Vector3::z();
        let mesh_world = PartClosing::new(
            &object,
            &shapes,
            bar_pose.inverse(),
            table.map(|z| (up, z - bar_pose.translation.vector.z)),
        );
        let a = close_fingers(&solids, &linkage);
        let b = close_fingers(&mesh_world, &linkage);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.kind, y.kind, "{}", row["id"]);
            assert_eq!(x.support.is_some(), y.support.is_some(), "{}", row["id"]);
            let d = (x.config.pad_center(&linkage) - y.config.pad_center(&linkage)).norm();
            worst = worst.max(d);
        }
        rows += 1;
    }
    eprintln!("{rows} bars: worst pad-centre difference {:.2e} m", worst);
    assert!(rows > 100);
    assert!(worst < 1e-4, "{worst}");
}

/// The exact solids of a table row's bar (no table) and the fingers' `pieces`
/// ([`finger_solids`]), the bar moved `dx` along the fingers' closing axis (`+x`: towards the
/// `+x` finger).
fn bar_solids<'a>(pieces: &'a [Vec<Vec<Piece>>; 2], row: &Value, dx: f64) -> Solids<'a> {
    let bar = &row["bar"];
    let get = |k: &str| bar[k].as_f64().unwrap();
    Solids {
        pieces,
        bar: Cuboid::new(Vector3::new(
            0.5 * get("width"),
            0.15,
            0.5 * get("thickness"),
        )),
        bar_pose: Isometry3::from_parts(
            Translation3::new(dx, 0.0, get("z_center")),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), get("tilt_deg").to_radians()),
        ),
        table: None,
    }
}

/// A bar the pads pinch is pinched from both sides when it lies a micrometre off the fingers'
/// mid-plane: the first pad to meet it stops both drivers, and the other pad, within
/// `pregrasp_robot::CONTACT_SLACK` of driver travel of the bar (about 10 µm of pad travel), touches it too.
/// Without that slack, which finger ended on nothing hung on a micrometre (parallel_bars_89's
/// master, centred on its bar to 1 µm, closed on one side at every fingertip depth). A bar
/// 0.3 mm off is held on one side, the other finger closing on nothing.
///
/// 2–4 µm off, all 417 closings of the 139 such bars pinch on both sides too. Before a finger
/// resting on the coupler's stop was tried there first (`pregrasp_robot::closing`), 19 of the
/// 420 closings of the 140 bars pinched then ended on one side: the search closed the spring
/// link up from its last angle at each driver step and passed the pad through a tilted pose
/// that touched first, stopping the drivers up to 27 µm of pad travel early (docs/physics.md,
/// "A micrometre off the mid-plane").
#[test]
fn a_pinch_does_not_hang_on_a_micrometre() {
    use pregrasp_robot::ClosingKind;
    let truth = data("closing_2f85.json");
    let linkage = FingerLinkage::robotiq_2f85();
    let pieces = finger_solids();
    let kinds = |row: &Value, dx: f64| {
        close_fingers(&bar_solids(&pieces, row, dx), &linkage).map(|c| c.kind)
    };
    // Bars without a table or tilt that both pads pinch when centred.
    let pinched: Vec<&Value> = truth["rows"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["status"] == "simulated" && r["table_z"].is_null())
        .filter(|r| r["bar"]["tilt_deg"].as_f64() == Some(0.0))
        .filter(|r| kinds(r, 0.0) == [ClosingKind::Pinch; 2])
        .collect();
    // 139: w55_t45_d05 was pinched before the finger on the coupler's stop stayed there; now
    // its spring links meet the bar first and both fingers wrap it, as MuJoCo's do.
    assert_eq!(pinched.len(), 139);
    for row in &pinched {
        for dx in [0.5e-6, -1e-6, 1e-6, 2e-6, -3e-6, 4e-6] {
            let k = kinds(row, dx);
            assert_eq!(k, [ClosingKind::Pinch; 2], "{} {dx}", row["id"]);
        }
        for (dx, far) in [(3e-4, 1), (-3e-4, 0)] {
            let k = kinds(row, dx);
            assert_eq!(k[far], ClosingKind::Closed, "{} {dx}", row["id"]);
            assert_ne!(k[1 - far], ClosingKind::Closed, "{} {dx}", row["id"]);
        }
    }
}
