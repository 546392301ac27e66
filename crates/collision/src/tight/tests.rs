use super::polytope::{Graph, Hulled};
use super::*;
use crate::shape::parry_cylinder;
use nalgebra::{Translation3, UnitQuaternion};
use parry3d_f64::query;
use parry3d_f64::shape::{Capsule as PCapsule, ConvexPolyhedron, Cuboid as PCuboid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A remembered separating axis only ever answers what GJK answers: every piece of the
/// UR5e against a box moved step by step towards, through and away from it, the box's
/// clearance asked at a few margins, with and without the axis of the last step.
#[test]
fn remembered_axes_answer_as_gjk_does() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut asked, mut near_count, mut by_axis) = (0, 0, 0);
    let geometry = pregrasp_robot::arm_geometry(pregrasp_robot::UrModel::Ur5e);
    let boxed = PCuboid::new(Vector3::new(0.03, 0.05, 0.02));
    for (l, link) in geometry.links.iter().enumerate() {
        let Some(src) = link.pieces else { continue };
        for (k, pts) in src.pieces.iter().enumerate() {
            let poly = Polytope::new(pts.clone());
            poly.prepare();
            let climb = Climb::new(&poly);
            let c = pts.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / pts.len() as f64;
            let from = Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2)) + c;
            let to = c - (from - c);
            let turn = Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2));
            for step in 0..60 {
                let t = step as f64 / 59.0;
                let pose = Isometry3::new(from + (to - from) * t, turn * t);
                for margin in [0.0, 0.005, 0.03] {
                    let key = (1000 * l + k, usize::from(margin > 0.0) + 1);
                    let p1 = Isometry3::identity();
                    let cold = near(&p1, &climb, &pose, &boxed, margin);
                    let slot = separator_slot(key);
                    let known = SEPARATORS.with(|s| s[slot].get().0 == key);
                    let keyed = near_keyed(key, &p1, &climb, &pose, &boxed, margin);
                    assert_eq!(
                        keyed, cold,
                        "{} piece {k} step {step} margin {margin}",
                        link.name
                    );
                    asked += 1;
                    near_count += usize::from(cold);
                    by_axis += usize::from(known && !cold);
                }
            }
        }
    }
    assert!(
        near_count > asked / 10 && by_axis > asked / 3,
        "{asked} asked, {near_count} near, {by_axis} apart with a remembered axis"
    );
}

/// Climbing the hull graph finds the vertex a scan finds, for every piece of every UR model,
/// cold and warm started, in random and axis-aligned directions (where vertices tie).
#[test]
fn climbs_find_the_scans_support_points() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut pieces, mut graphs) = (0, 0);
    for model in pregrasp_robot::UrModel::ALL {
        let geometry = pregrasp_robot::arm_geometry(model);
        for link in &geometry.links {
            let Some(src) = link.pieces else { continue };
            for pts in &src.pieces {
                let poly = Polytope::new(pts.clone());
                let graph = Graph::new(pts, Hulled::Prepared);
                pieces += 1;
                graphs += usize::from(graph.is_some());
                let _ = poly.graph.set(graph);
                let warm = Climb::new(&poly);
                for k in 0..200 {
                    let dir = if k < 6 {
                        let mut d = Vector3::zeros();
                        d[k / 2] = if k % 2 == 0 { 1.0 } else { -1.0 };
                        d
                    } else {
                        Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0))
                    };
                    let want = parry3d_f64::utils::point_cloud_support_point(&dir, pts);
                    assert_eq!(
                        Climb::new(&poly).local_support_point(&dir),
                        want,
                        "{model} {}",
                        link.name
                    );
                    assert_eq!(
                        warm.local_support_point(&dir),
                        want,
                        "{model} {}",
                        link.name
                    );
                }
            }
        }
    }
    assert!(pieces > 300, "{pieces} pieces");
    assert!(
        graphs * 10 > pieces * 9,
        "{graphs} graphs of {pieces} pieces"
    );
}

/// A polytope builds its graph after [`BUILD_AFTER`] scans, not before.
#[test]
fn the_graph_is_built_once_asked_often() {
    let cube: Vec<P> = (0..8)
        .map(|k| P::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64))
        .collect();
    let poly = Polytope::new(cube);
    let dir = Vector3::new(0.3, 0.2, 0.1);
    for _ in 0..BUILD_AFTER {
        let cold = Climb::new(&poly);
        assert_eq!(cold.local_support_point(&dir), P::new(1.0, 1.0, 1.0));
        assert!(poly.graph.get().is_none());
    }
    let climb = Climb::new(&poly);
    assert_eq!(climb.local_support_point(&dir), P::new(1.0, 1.0, 1.0));
    assert!(matches!(poly.graph.get(), Some(Some(_))));
    // A cube's faces tie along the axes: the scan's answer, the first vertex.
    assert_eq!(
        climb.local_support_point(&Vector3::x()),
        P::new(1.0, 0.0, 0.0)
    );
    // Prepared, a polytope climbs from its first question.
    let prepared = Polytope::new(poly.points.clone());
    prepared.prepare();
    assert!(matches!(prepared.graph.get(), Some(Some(_))));
    assert_eq!(
        Climb::new(&prepared).local_support_point(&dir),
        P::new(1.0, 1.0, 1.0)
    );
}

/// The support-map GJK on raw vertices agrees with parry's own polyhedron (built as the
/// hull of the same vertices) against capsules, rounded cylinders, boxes and other pieces:
/// distances within 1e-5 (GJK's tolerance), and `within` is `distance ≤ margin` away from the boundary.
#[test]
fn pieces_agree_with_parry_polyhedra() {
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    let cloud = |rng: &mut ChaCha8Rng, c: Vector3<f64>| -> Vec<P> {
        (0..30)
            .map(|_| P::from(c + Vector3::from_fn(|_, _| rng.random_range(-0.05..0.05))))
            .collect()
    };
    let frame = Isometry3::new(Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.3, -0.5, 0.2));
    let mut checked = 0;
    for k in 0..300 {
        let pts = cloud(&mut rng, Vector3::zeros());
        let tight = Tight::new(&ConvexPieces {
            pieces: vec![pts.clone()],
            slack: 0.0,
        })
        .unwrap();
        let hull = ConvexPolyhedron::from_convex_hull(&pts).unwrap();
        let c = frame * P::from(Vector3::from_fn(|_, _| rng.random_range(-0.15..0.15)));
        let other_pts = cloud(&mut rng, c.coords);
        let (shape, reference) = match k % 4 {
            0 => {
                let (a, b) = (c, c + Vector3::new(0.05, 0.02, -0.03));
                let r = 0.02;
                let d = query::distance(
                    &frame,
                    &hull,
                    &Isometry3::identity(),
                    &PCapsule::new(a, b, r),
                );
                (Placed::Capsule { a, b, radius: r }, d.unwrap())
            }
            1 => {
                let (a, b, r, e) = (c, c + Vector3::new(0.0, 0.06, 0.01), 0.03, 0.005);
                let (pose, cyl) = parry_cylinder(&a, &b, r);
                let d = query::distance(&frame, &hull, &pose, &cyl).unwrap() - e;
                (
                    Placed::Cylinder {
                        a,
                        b,
                        radius: r,
                        border: e,
                    },
                    d.max(0.0),
                )
            }
            2 => {
                let pose = Isometry3::new(c.coords, Vector3::new(0.1, 0.7, -0.3));
                let half = Vector3::new(0.03, 0.01, 0.05);
                let d = query::distance(&frame, &hull, &pose, &PCuboid::new(half));
                (Placed::Cuboid { pose, half }, d.unwrap())
            }
            _ => {
                let other = ConvexPolyhedron::from_convex_hull(&other_pts).unwrap();
                let d = query::distance(&frame, &hull, &Isometry3::identity(), &other);
                // The bounding sphere holds the other piece (its points lie within 0.087 of c).
                (
                    Placed::Capsule {
                        a: c,
                        b: c,
                        radius: 0.09,
                    },
                    d.unwrap(),
                )
            }
        };
        // Shape 0 of a one-shape arm posed with every DH frame at `frame`.
        let dummy = pregrasp_robot::Primitive::Capsule(pregrasp_robot::Capsule {
            a: P::origin(),
            b: P::origin(),
            radius: 0.0,
        });
        let parts = [(0usize, dummy)];
        let own_table = [Some(tight)];
        let frames = [frame; 7];
        let b1 = Bounded::new(Placed::Capsule {
            a: P::from(frame.translation.vector),
            b: P::from(frame.translation.vector),
            radius: 0.1,
        });
        let s1 = Part {
            bounded: &b1,
            lookup: Some(Lookup {
                tight: &own_table,
                parts: &parts,
                frames: &frames,
                gripper_tight: &[],
                gripper_frames: &[],
                k: 0,
            }),
        };
        let other_table = [Some(
            Tight::new(&ConvexPieces {
                pieces: vec![other_pts],
                slack: 0.0,
            })
            .unwrap(),
        )];
        let ids = [Isometry3::identity(); 7];
        let b2 = Bounded::new(shape);
        let s2 = if k % 4 == 3 {
            Part {
                bounded: &b2,
                lookup: Some(Lookup {
                    tight: &other_table,
                    parts: &parts,
                    frames: &ids,
                    gripper_tight: &[],
                    gripper_frames: &[],
                    k: 0,
                }),
            }
        } else {
            Part::plain(&b2)
        };
        let d = distance(&s1, &s2);
        assert!(
            (d - reference).abs() < 1e-5,
            "case {k}: {d} vs parry {reference}"
        );
        for margin in [0.0, 0.005, 0.02] {
            if (reference - margin).abs() > 1e-5 {
                assert_eq!(
                    within(&s1, &s2, margin),
                    reference <= margin,
                    "case {k}, margin {margin}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 800);
}

/// `Tight::lowest` climbs the hull of the pieces: the same number, to the bit, as the least
/// world `z` over every vertex of every piece, for the 2F-85's finger links (the shapes the
/// closest-grasp test asks) in random frames and in axis-aligned ones (where vertices tie).
#[test]
fn lowest_is_the_least_height_of_every_vertex() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let solids = pregrasp_robot::FingerSolids::robotiq_2f85();
    for link in &solids.links {
        let tight = Tight::new(&link.pieces).expect("finger pieces are solids");
        let aligned = [
            UnitQuaternion::identity(),
            UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0),
            UnitQuaternion::from_euler_angles(std::f64::consts::FRAC_PI_2, 0.0, 0.0),
        ];
        let random = (0..200).map(|_| {
            UnitQuaternion::from_euler_angles(
                rng.random_range(-3.2..3.2),
                rng.random_range(-1.6..1.6),
                rng.random_range(-3.2..3.2),
            )
        });
        for rotation in aligned.into_iter().chain(random.collect::<Vec<_>>()) {
            let frame = Isometry3::from_parts(Translation3::new(0.1, -0.2, 0.3), rotation);
            let row = crate::distance::world_up_in(&frame);
            let least = link
                .pieces
                .pieces
                .iter()
                .flatten()
                .map(|v| row.dot(&v.coords))
                .fold(f64::INFINITY, f64::min)
                + frame.translation.vector.z;
            assert_eq!(tight.lowest(&frame), least, "{} at {rotation:?}", link.name);
        }
    }
}

/// The vertex graph's rows are the pairs sorted with their repeats removed: random pair lists
/// (repeats, vertices without pairs, pairs of a vertex with itself) against `sort` + `dedup`.
#[test]
fn adjacency_is_the_sorted_pairs() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for case in 0..300 {
        let n = rng.random_range(1..60usize);
        let m = rng.random_range(0..400usize);
        let edges: Vec<(u32, u32)> = (0..m)
            .map(|_| (rng.random_range(0..n as u32), rng.random_range(0..n as u32)))
            .collect();
        let (offsets, adjacent) = super::polytope::adjacency(n, &edges);
        let mut sorted = edges.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(adjacent.len(), sorted.len(), "case {case}");
        assert_eq!(offsets.len(), n + 1, "case {case}");
        for a in 0..n {
            let row: Vec<u32> = sorted
                .iter()
                .filter(|e| e.0 as usize == a)
                .map(|e| e.1)
                .collect();
            let (lo, hi) = (offsets[a] as usize, offsets[a + 1] as usize);
            assert_eq!(adjacent[lo..hi], row[..], "case {case}, vertex {a}");
        }
    }
}
