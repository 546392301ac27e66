//! Link and gripper geometry: the fitted shapes contain every vertex of the description meshes,
//! the 2F-85 fingers follow the real linkage and keep the stroke free, and the self-collision
//! pairs tell collision truths.

mod common;

use common::{intersects, placed};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{Capsule as PCapsule, Cuboid};
use pregrasp_robot::{
    arm_geometry, fitted_links_of, flange_sweep_radii, group_sweep_radii, joint_sweep_radii,
    linkage, FingerPair, Gripper2F85, GripperState, Joints, Primitive, UrKinematics, UrModel,
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

/// Every vertex of the description meshes lies inside the fitted shapes of its link (no
/// under-approximation), for every model with fitted data; prints each link's shapes and the
/// largest outward excess the fit measured.
#[test]
fn every_mesh_vertex_is_inside_its_link_shapes() {
    let mut fitted = 0;
    for model in UrModel::ALL {
        let Some(links) = fitted_links_of(model) else {
            continue;
        };
        fitted += 1;
        let geometry = arm_geometry(model);
        for link in links {
            let vertices = mesh_vertices(model.name(), &link.name);
            assert!(!vertices.is_empty(), "{model} {}: no vertices", link.name);
            // Signed distance outside the nearest shape (≤ 0 inside); the foot's bottom rim,
            // below the mounting gap, is not modelled.
            let worst = worst_outside(link.frame, &vertices, |v| {
                link.shapes
                    .iter()
                    .map(|&i| outside_distance(&geometry.links[i].primitive, v))
                    .fold(f64::INFINITY, f64::min)
            });
            assert!(
                worst <= 1e-6,
                "{model} {}: a mesh vertex lies {:.3} mm outside the shapes",
                link.name,
                worst * 1e3
            );
            println!(
                "{model:6} {:10} {} shape(s), {} vertices inside, excess {:.1} mm",
                link.name,
                link.shapes.len(),
                vertices.len(),
                link.excess_mm.unwrap_or(f64::NAN)
            );
        }
    }
    assert_eq!(fitted, UrModel::ALL.len(), "every model has fitted shapes");
}

/// The description-mesh vertices of `link` of `model` (its DH frame) that the shapes must
/// contain: `data/ur_link_vertices.json`, made with the shapes by `tools/geometry/derive.py`.
fn mesh_vertices(model: &str, link: &str) -> Vec<Point3<f64>> {
    link_vertices(model, link, "hull")
}

/// `key` ("hull": for the shapes, "piece_vertices": for the exact pieces) of `link` of
/// `model` in `data/ur_link_vertices.json`.
fn link_vertices(model: &str, link: &str, key: &str) -> Vec<Point3<f64>> {
    let file: serde_json::Value =
        serde_json::from_str(include_str!("../data/ur_link_vertices.json")).unwrap();
    let xyz = |p: &serde_json::Value| {
        Point3::new(
            p[0].as_f64().unwrap(),
            p[1].as_f64().unwrap(),
            p[2].as_f64().unwrap(),
        )
    };
    file["models"][model]["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == link)
        .map(|l| l[key].as_array().unwrap().iter().map(xyz).collect())
        .unwrap_or_default()
}

/// The exact tier ([`pregrasp_robot::ConvexPieces`]): every description-mesh vertex nearest the
/// pieces' boundary (the 1500 per link that `tools/geometry/derive_pieces.py` found least deep
/// inside; the others lie deeper) is in the union of its link's pieces, and every piece lies
/// within its `slack` of the shape it refines, so the shape grown by the slack bounds it.
#[test]
fn every_mesh_vertex_is_inside_its_link_pieces() {
    for model in UrModel::ALL {
        let geometry = arm_geometry(model);
        for link in fitted_links_of(model).unwrap() {
            let mut hulls = Vec::new();
            for &i in &link.shapes {
                let shape = &geometry.links[i];
                let pieces = shape
                    .pieces
                    .unwrap_or_else(|| panic!("{model} {}: no pieces", shape.name));
                for piece in &pieces.pieces {
                    let reach = piece
                        .iter()
                        .map(|v| outside_distance(&shape.primitive, v))
                        .fold(0.0, f64::max);
                    assert!(
                        reach <= pieces.slack + 1e-9,
                        "{model} {}: a piece reaches {:.3} mm outside, slack {:.3} mm",
                        shape.name,
                        reach * 1e3,
                        pieces.slack * 1e3
                    );
                    hulls.push(
                        parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(piece)
                            .expect("a piece is a solid polytope"),
                    );
                }
            }
            let vertices = link_vertices(model.name(), &link.name, "piece_vertices");
            assert!(
                vertices.len() >= 100,
                "{model} {}: too few test vertices",
                link.name
            );
            let worst = worst_outside(link.frame, &vertices, |v| {
                use parry3d_f64::query::PointQuery;
                hulls
                    .iter()
                    .map(|h| h.distance_to_local_point(v, true))
                    .fold(f64::INFINITY, f64::min)
            })
            .max(0.0);
            assert!(
                worst <= 1e-6,
                "{model} {}: a mesh vertex lies {:.4} mm outside the pieces",
                link.name,
                worst * 1e3
            );
            println!(
                "{model:6} {:10} {} piece(s), {} vertices inside, excess {:.1} mm (shapes {:.1} mm)",
                link.name,
                hulls.len(),
                vertices.len(),
                link.pieces_excess_mm.unwrap_or(f64::NAN),
                link.excess_mm.unwrap_or(f64::NAN)
            );
        }
    }
}

/// The largest `outside(v)` over the vertices a link's model must contain: all of them, except
/// on the base (frame 0) those below [`BASE_MOUNT_GAP`] — the base's shapes start 2 mm above the
/// mounting plane, so that the plane the arm stands on never registers as a contact.
fn worst_outside(
    frame: usize,
    vertices: &[Point3<f64>],
    outside: impl Fn(&Point3<f64>) -> f64,
) -> f64 {
    vertices
        .iter()
        .filter(|v| frame != 0 || v.z >= BASE_MOUNT_GAP)
        .map(outside)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Height above the mounting plane where the base shapes start (m).
const BASE_MOUNT_GAP: f64 = 0.002;

/// How far `p` lies outside `prim` (m; ≤ 0 inside).
fn outside_distance(prim: &Primitive, p: &Point3<f64>) -> f64 {
    match prim {
        Primitive::Capsule(c) => c.segment_distance(p) - c.radius,
        // Rounded rims included (0 inside or on it).
        Primitive::Cylinder(c) => c.outside_distance(p),
        Primitive::Cuboid { pose, half_extents } => {
            let l = pose.inverse_transform_point(p);
            (0..3)
                .map(|i| l[i].abs() - half_extents[i])
                .fold(f64::NEG_INFINITY, f64::max)
        }
    }
}

/// The UR5e foot is a Ø151 mm cylinder: a point 1 mm outside it radially is outside the model
/// at every height of the foot (the old square box reached 114 mm from the axis).
#[test]
fn base_is_a_round_foot() {
    let geometry = arm_geometry(UrModel::Ur5e);
    let base: Vec<_> = geometry.links.iter().filter(|l| l.frame == 0).collect();
    assert!(!base.is_empty());
    for z in [0.01, 0.03, 0.05, 0.08] {
        for k in 0..16 {
            let phi = k as f64 * PI / 8.0;
            let p = Point3::new(0.0766 * phi.cos(), 0.0766 * phi.sin(), z);
            assert!(
                base.iter()
                    .all(|l| outside_distance(&l.primitive, &p) > 0.0),
                "z {z}, φ {phi}"
            );
        }
    }
}

/// The pads follow the MuJoCo Menagerie 2F-85 (facts table, gap → pad centre z) within
/// 0.5 mm, and their contact faces are half the gap from the axis.
#[test]
fn pads_follow_the_menagerie_linkage() {
    let l = linkage();
    for (gap, z) in [
        (0.0852, 0.1416),
        (0.0700, 0.1467),
        (0.0533, 0.1507),
        (0.0356, 0.1534),
        (0.0172, 0.1547),
    ] {
        let pair = FingerPair::at_gap(gap);
        let [right, left] = pair.configs();
        let c = right.pad_center(l);
        assert!(
            (c.y - z).abs() < 5e-4,
            "gap {gap}: pad centre {} vs {z}",
            c.y
        );
        assert!((pair.gap() - gap).abs() < 1e-6, "gap {gap}: {}", pair.gap());
        assert!((c.x - gap / 2.0).abs() < 1e-6, "gap {gap}");
        assert_eq!(left, right, "the fingers are mirror images");
    }
    // Pad tips: 160.2 mm open, 173.5 mm closed (menagerie), within 0.5 mm.
    let tip = |pair: FingerPair| pair.configs()[0].pad_tip(l).y;
    assert!((tip(FingerPair::open()) - 0.1602).abs() < 5e-4);
    assert!((tip(FingerPair::at_gap(0.0)) - 0.1735).abs() < 5e-4);
}

/// The finger boxes hold their convex pieces in every state the fingers can take (parallel
/// and curled), and fit them open (3 mm at most deeper; the pieces, not the boxes, decide
/// contacts).
#[test]
fn finger_boxes_hold_their_pieces_and_no_more() {
    let g = Gripper2F85::default();
    let solids = g.finger_solids();
    let n_static = g.static_count();
    for state in g.sample_states() {
        let frames = g.shape_frames(state);
        let shapes = g.shapes(state);
        for (k, solid) in solids.links.iter().enumerate() {
            let shape = &shapes[n_static + k];
            let frame = frames[n_static + k];
            let Primitive::Cuboid { pose, half_extents } = shape.primitive else {
                unreachable!("finger shapes are boxes")
            };
            let mut deepest_piece = f64::NEG_INFINITY;
            for v in solid.pieces.pieces.iter().flatten() {
                let p = frame * v;
                let local = pose.inverse() * p;
                assert!(
                    (0..3).all(|i| local[i].abs() <= half_extents[i] + 1e-9),
                    "{}: a piece vertex outside its box",
                    shape.name
                );
                deepest_piece = deepest_piece.max(p.z);
            }
            let m = pose.rotation.to_rotation_matrix();
            let deepest_box = pose.translation.z
                + (0..3)
                    .map(|i| m[(2, i)].abs() * half_extents[i])
                    .sum::<f64>();
            assert!(
                state != GripperState::Open || deepest_box - deepest_piece < 3e-3,
                "{}: box {deepest_box}, pieces {deepest_piece}",
                shape.name
            );
        }
    }
}

#[test]
fn open_gripper_leaves_the_85mm_stroke_free() {
    let g = Gripper2F85::default();
    let open = g.shapes(GripperState::Open);
    assert!(open
        .iter()
        .all(|s| s.name.starts_with("gripper_") && s.frame == 6));
    // The volume swept by the pads: between the open pad faces, the 22 mm pad width, the pad
    // z span (37.5 mm centred on the open pad centre).
    let pad = FingerPair::open().configs()[0].pad_center(linkage());
    let stroke = (
        Isometry3::translation(0.0, 0.0, pad.y),
        Box::new(Cuboid::new(Vector3::new(pad.x - 1e-4, 0.011, 0.0185)))
            as Box<dyn parry3d_f64::shape::Shape>,
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
    let closed = g.shapes(GripperState::fully_closed());
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
    for state in [
        GripperState::Open,
        GripperState::at_gap(0.03),
        GripperState::fully_closed(),
    ] {
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
        // Elbow and wrist_1 folded so the gripper points back at the arm: somewhere it hits.
        let grid = || (-7..=7).map(|k| k as f64 * 0.4);
        let gripper_hits = grid().any(|q4| {
            grid().any(|q3| {
                self_collisions(model, &[0.0, -FRAC_PI_2, q3, q4, FRAC_PI_2, 0.0])
                    .iter()
                    .any(|(a, _)| a.starts_with("gripper"))
            })
        });
        assert!(gripper_hits, "{model}");
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
    // Also the per-group bounds (`group_sweep_radii`): absolute, vertical without the base
    // joint, relative to every earlier frame, and the flange origin's (`flange_sweep_radii`).
    let g = Gripper2F85::default();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        let radii = joint_sweep_radii(model, &g.into());
        assert!(
            radii.windows(2).all(|w| w[0] >= w[1] - 1e-12),
            "{model}: {radii:?}"
        );
        let geometry = arm_geometry(model);
        // Probe points: capsule ends pushed out by the radius, gripper box corners.
        let mut probes: Vec<(usize, Point3<f64>)> = Vec::new();
        for l in &geometry.links {
            if let Primitive::Cylinder(c) = l.primitive {
                let d = (c.b - c.a).normalize();
                let u = d
                    .cross(&Vector3::x())
                    .try_normalize(1e-9)
                    .unwrap_or(d.cross(&Vector3::y()).normalize());
                let w = d.cross(&u);
                for e in [c.a, c.b] {
                    for k in 0..8 {
                        let phi = k as f64 * PI / 4.0;
                        probes.push((l.frame, e + c.radius * (phi.cos() * u + phi.sin() * w)));
                    }
                }
            }
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
            .chain(g.shapes(GripperState::fully_closed()))
        {
            if let Primitive::Cuboid {
                pose,
                half_extents: h,
            } = s.primitive
            {
                for sx in [-1.0, 1.0] {
                    for sy in [-1.0, 1.0] {
                        for sz in [-1.0, 1.0] {
                            probes.push((7, pose * Point3::new(sx * h.x, sy * h.y, sz * h.z)));
                        }
                    }
                }
            }
        }
        let groups = group_sweep_radii(model, &g.into());
        let flange = flange_sweep_radii(model);
        for _ in 0..200 {
            let q: Joints = std::array::from_fn(|_| rng.random_range(-PI..PI));
            let dq: Joints = std::array::from_fn(|_| rng.random_range(-0.05..0.05));
            let q2: Joints = std::array::from_fn(|i| q[i] + dq[i]);
            let bound: f64 = (0..6).map(|i| radii[i] * dq[i].abs()).sum();
            let (f1, f2) = (kin.fk_frames(&q), kin.fk_frames(&q2));
            // A group's own bound, vertically without the base joint, and relative to every
            // frame before it by the joints between.
            let group_bound = |from: usize, g: usize| -> f64 {
                (from..6).map(|i| groups[i][g] * dq[i].abs()).sum()
            };
            for (g, p) in &probes {
                let f = (*g).min(6);
                let moved = (f1[f] * p - f2[f] * p).norm();
                assert!(
                    moved <= bound + 1e-12,
                    "{model}: moved {moved} > bound {bound}"
                );
                assert!(moved <= group_bound(0, *g) + 1e-12, "{model} group {g}");
                let up = ((f1[f] * p).z - (f2[f] * p).z).abs();
                assert!(
                    up <= group_bound(1, *g) + 1e-12,
                    "{model} group {g} vertical"
                );
                for near in 0..=f {
                    let rel =
                        (f1[near].inverse() * f1[f] * p - f2[near].inverse() * f2[f] * p).norm();
                    assert!(
                        rel <= group_bound(near, *g) + 1e-12,
                        "{model}: group {g} relative to frame {near}: {rel}"
                    );
                }
            }
            let flange_moved = (f1[6].translation.vector - f2[6].translation.vector).norm();
            let flange_bound: f64 = (0..6).map(|i| flange[i] * dq[i].abs()).sum();
            assert!(flange_moved <= flange_bound + 1e-12, "{model}: flange");
        }
    }
}
