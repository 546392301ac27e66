//! Volume and centre of mass from the closed mesh.

mod common;

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_physics::{MassError, MassProperties};

#[test]
fn box_volume_and_centroid_are_exact() {
    let m = MassProperties::from_mesh(&common::box_mesh(0.6, 0.04, 0.02)).unwrap();
    assert!((m.volume - 0.6 * 0.04 * 0.02).abs() < 1e-15);
    assert!((m.centroid - Point3::new(0.3, 0.02, 0.01)).norm() < 1e-12);
}

#[test]
fn centroid_moves_with_the_mesh_and_inward_winding_is_accepted() {
    let bar = common::box_mesh(0.5, 0.1, 0.03);
    let pose = Isometry3::new(Vector3::new(3.0, -2.0, 1.0), Vector3::new(0.3, -0.2, 1.1));
    let moved = MassProperties::from_mesh(&bar.transformed(&pose)).unwrap();
    let expected = pose * Point3::new(0.25, 0.05, 0.015);
    assert!((moved.centroid - expected).norm() < 1e-12);
    let inward = Mesh::new(
        bar.vertices.clone(),
        bar.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
    );
    let m = MassProperties::from_mesh(&inward).unwrap();
    assert!((m.volume - 0.5 * 0.1 * 0.03).abs() < 1e-15);
    assert!((m.centroid - Point3::new(0.25, 0.05, 0.015)).norm() < 1e-12);
}

#[test]
fn an_l_shape_has_its_centroid_between_its_legs() {
    // Two boxes sharing no faces but forming one solid: [0,1]×[0,0.1] and [0,0.1]×[0.1,1]
    // (extruded 0.02). Area-weighted centroid: legs of area 0.1 and 0.09.
    let a = common::box_mesh(1.0, 0.1, 0.02);
    let b = common::box_mesh(0.1, 0.9, 0.02).transformed(&Isometry3::translation(0.0, 0.1, 0.0));
    let mut vertices = a.vertices.clone();
    vertices.extend(b.vertices.iter().copied());
    let mut triangles = a.triangles.clone();
    triangles.extend(b.triangles.iter().map(|t| t.map(|i| i + 8)));
    let m = MassProperties::from_mesh(&Mesh::new(vertices, triangles)).unwrap();
    let cx = (0.1 * 0.5 + 0.09 * 0.05) / 0.19;
    let cy = (0.1 * 0.05 + 0.09 * 0.55) / 0.19;
    assert!((m.centroid - Point3::new(cx, cy, 0.01)).norm() < 1e-12);
    assert!((m.volume - 0.19 * 0.02).abs() < 1e-15);
}

#[test]
fn an_open_surface_is_refused() {
    let flat = Mesh::new(
        vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2]],
    );
    assert_eq!(
        MassProperties::from_mesh(&flat),
        Err(MassError::NotClosed { open: 3 })
    );
    // A box with one triangle missing: that triangle's three edges border one triangle only.
    let mut open_box = common::box_mesh(0.6, 0.04, 0.02);
    open_box.triangles.pop();
    assert_eq!(
        MassProperties::from_mesh(&open_box),
        Err(MassError::NotClosed { open: 3 })
    );
    // Closed but flat (a triangle and its reverse): no volume.
    let mut both_sides = flat.clone();
    both_sides.triangles.push([0, 2, 1]);
    assert!(matches!(
        MassProperties::from_mesh(&both_sides),
        Err(MassError::NoVolume { .. })
    ));
}
