//! Convex hull faces and feature edges: counts from Euler's formula, no flat-face diagonals,
//! collinear splits merged, flat and degenerate inputs.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use pregrasp_geometry::shapes::{cuboid, prism, subdivided_cuboid, uv_sphere};
use pregrasp_geometry::{ConvexHull, HullError};

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

/// Every feature edge of an axis-aligned box is parallel to a coordinate axis and has the
/// length of one of the box's sides.
fn assert_box_edges(hull: &ConvexHull, size: [f64; 3]) {
    assert_eq!(hull.faces.len(), 6);
    assert_eq!(hull.feature_edges.len(), 12);
    let mut per_axis = [0; 3];
    for (i, &[a, b]) in hull.feature_edges.iter().enumerate() {
        let d = hull.vertices[b] - hull.vertices[a];
        let k = d.iamax();
        assert!(
            (d.norm() - d[k].abs()).abs() < 1e-12,
            "edge {i} is not axis-aligned: {d:?}"
        );
        assert!((hull.feature_edge_length(i) - size[k]).abs() < 1e-12);
        per_axis[k] += 1;
    }
    assert_eq!(per_axis, [4, 4, 4]);
}

#[test]
fn box_has_six_faces_and_twelve_edges_without_diagonals() {
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.4, 0.03));
    let hull = ConvexHull::of_mesh(&mesh).unwrap();
    assert_eq!(hull.triangles.len(), 12);
    assert_box_edges(&hull, [0.6, 0.4, 0.03]);
    for f in &hull.faces {
        assert_eq!(f.vertices.len(), 4);
        for &v in &f.vertices {
            assert!((f.normal.dot(&hull.vertices[v].coords) - f.offset).abs() < 1e-12);
        }
        // Outward: every hull vertex is on the inner side.
        for v in &hull.vertices {
            assert!(f.normal.dot(&v.coords) <= f.offset + 1e-12);
        }
    }
}

#[test]
fn collinear_and_coplanar_extra_points_do_not_split_edges() {
    let (x, y, z) = (0.6, 0.4, 0.03);
    let mut pts = Vec::new();
    // A 5 × 4 × 3 grid of points on the surface and inside the box.
    for i in 0..5 {
        for j in 0..4 {
            for k in 0..3 {
                pts.push(p(
                    x * i as f64 / 4.0,
                    y * j as f64 / 3.0,
                    z * k as f64 / 2.0,
                ));
            }
        }
    }
    let hull = ConvexHull::from_points(&pts).unwrap();
    assert_box_edges(&hull, [x, y, z]);
}

#[test]
fn triangular_prism_has_five_faces_and_nine_edges() {
    let mesh = prism(&[[0.0, 0.0], [0.5, 0.0], [0.1, 0.3]], 0.0, 0.8);
    let hull = ConvexHull::of_mesh(&mesh).unwrap();
    assert_eq!(hull.faces.len(), 5);
    assert_eq!(hull.feature_edges.len(), 9);
    let mut lengths: Vec<f64> = (0..9).map(|i| hull.feature_edge_length(i)).collect();
    lengths.sort_by(f64::total_cmp);
    let mut expected = vec![
        0.5,
        0.5,
        0.1f64.hypot(0.3),
        0.1f64.hypot(0.3),
        0.4f64.hypot(0.3),
    ];
    expected.push(0.4f64.hypot(0.3));
    expected.extend([0.8, 0.8, 0.8]);
    expected.sort_by(f64::total_cmp);
    for (a, b) in lengths.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-12, "{lengths:?} vs {expected:?}");
    }
}

#[test]
fn rotated_box_with_f32_rounding_still_merges_faces() {
    let rot = UnitQuaternion::from_euler_angles(0.3, -0.7, 1.1);
    let pose = Isometry3::from_parts(Translation3::new(0.4, -0.2, 0.9), rot);
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.4, 0.03)).transformed(&pose);
    let rounded: Vec<Point3<f64>> = mesh
        .vertices
        .iter()
        .map(|v| v.map(|c| f64::from(c as f32)))
        .collect();
    let hull = ConvexHull::from_points(&rounded).unwrap();
    assert_eq!(hull.faces.len(), 6);
    assert_eq!(hull.feature_edges.len(), 12);
}

#[test]
fn sphere_faces_and_edges_satisfy_euler() {
    let (rings, segments) = (8, 12);
    let mesh = uv_sphere(p(0.0, 0.0, 0.0), 0.5, rings, segments);
    let hull = ConvexHull::of_mesh(&mesh).unwrap();
    // Quads between inner rings are planar trapezoids; the polar caps are triangles.
    let faces = (segments * (rings - 2) + 2 * segments) as usize;
    assert_eq!(hull.vertices.len(), mesh.vertices.len());
    assert_eq!(hull.faces.len(), faces);
    assert_eq!(hull.feature_edges.len(), hull.vertices.len() + faces - 2);
}

#[test]
fn flat_point_set_gets_a_two_sided_polygon() {
    let pts = [
        p(0.0, 0.0, 0.1),
        p(1.0, 0.0, 0.1),
        p(1.0, 0.5, 0.1),
        p(0.0, 0.5, 0.1),
        p(0.5, 0.25, 0.1),
        p(0.5, 0.0, 0.1),
    ];
    let hull = ConvexHull::from_points(&pts).unwrap();
    assert_eq!(hull.vertices.len(), 4);
    assert_eq!(hull.faces.len(), 2);
    assert!((hull.faces[0].normal.dot(&hull.faces[1].normal) + 1.0).abs() < 1e-12);
    assert!(hull.faces[0].normal.z.abs() > 1.0 - 1e-12);
    let mut lengths: Vec<f64> = (0..4).map(|i| hull.feature_edge_length(i)).collect();
    lengths.sort_by(f64::total_cmp);
    assert_eq!(lengths, vec![0.5, 0.5, 1.0, 1.0]);
}

#[test]
fn degenerate_inputs_are_errors() {
    assert_eq!(
        ConvexHull::from_points(&[p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)]),
        Err(HullError::TooFewPoints(2))
    );
    let line: Vec<_> = (0..5).map(|i| p(i as f64, 2.0 * i as f64, 0.0)).collect();
    assert_eq!(ConvexHull::from_points(&line), Err(HullError::Collinear));
    let nan = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, f64::NAN, 0.0),
        p(0.0, 0.0, 1.0),
    ];
    assert_eq!(ConvexHull::from_points(&nan), Err(HullError::NonFinite));
}

#[test]
fn hull_is_deterministic() {
    let mesh = uv_sphere(p(0.1, 0.2, 0.3), 0.25, 6, 9);
    let a = ConvexHull::of_mesh(&mesh).unwrap();
    let b = ConvexHull::of_mesh(&mesh).unwrap();
    assert_eq!(a, b);
}

#[test]
fn subdivided_box_hull_ignores_face_grid_points() {
    let mesh = subdivided_cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.4, 0.03), 6);
    assert_eq!(mesh.triangles.len(), 12 * 36);
    // Outward winding: the signed volume is the box's.
    let vol: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize].coords);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum();
    assert!((vol - 0.6 * 0.4 * 0.03).abs() < 1e-12, "{vol}");
    let hull = ConvexHull::of_mesh(&mesh).unwrap();
    assert_box_edges(&hull, [0.6, 0.4, 0.03]);
}
