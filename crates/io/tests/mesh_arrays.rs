//! A mesh given as arrays (the Python API's `Scene.from_arrays`) gets a file's checks.

use pregrasp_io::mesh_io::{mesh_from_arrays, MeshError};

/// A unit tetrahedron in millimetres.
fn tetra() -> (Vec<[f64; 3]>, Vec<[i64; 3]>) {
    (
        vec![
            [0.0, 0.0, 0.0],
            [1000.0, 0.0, 0.0],
            [0.0, 1000.0, 0.0],
            [0.0, 0.0, 1000.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

#[test]
fn arrays_are_scaled_and_a_closed_mesh_has_no_warning() {
    let (v, f) = tetra();
    let loaded = mesh_from_arrays(&v, &f, "part.stl", 0.001).unwrap();
    assert_eq!(loaded.mesh.vertices.len(), 4);
    assert_eq!(loaded.mesh.triangles.len(), 4);
    assert_eq!(loaded.mesh.vertices[1].x, 1.0);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn bad_arrays_are_errors_naming_the_element() {
    let (mut v, mut f) = tetra();
    f.push([0, 1, 4]);
    let e = mesh_from_arrays(&v, &f, "part.stl", 1.0).unwrap_err();
    assert!(matches!(
        e,
        MeshError::BadIndex {
            face: 4,
            index: 4,
            ..
        }
    ));
    assert_eq!(
        e.to_string(),
        "part.stl: face 4 uses vertex 4, but there are 4 vertices"
    );
    f.pop();
    f.push([-1, 0, 1]);
    assert!(matches!(
        mesh_from_arrays(&v, &f, "part.stl", 1.0),
        Err(MeshError::BadIndex { index: -1, .. })
    ));
    f.pop();
    v[2][1] = f64::NAN;
    assert!(matches!(
        mesh_from_arrays(&v, &f, "part.stl", 1.0),
        Err(MeshError::NonFinite { index: 2, .. })
    ));
    v[2][1] = 1.0;
    assert!(matches!(
        mesh_from_arrays(&v, &f, "part.stl", 0.0),
        Err(MeshError::Scale { .. })
    ));
    assert!(matches!(
        mesh_from_arrays(&v, &[[0, 0, 1]], "part.stl", 1.0),
        Err(MeshError::NoTriangles { .. })
    ));
}

#[test]
fn an_open_mesh_is_accepted_with_a_warning() {
    let (v, mut f) = tetra();
    f.pop();
    let loaded = mesh_from_arrays(&v, &f, "part.stl", 0.001).unwrap();
    assert_eq!(loaded.warnings.len(), 1);
    assert!(
        loaded.warnings[0].contains("3 open edge(s)"),
        "{:?}",
        loaded.warnings
    );
}

#[test]
fn a_part_scaled_to_nothing_or_to_a_kilometre_is_not_a_part() {
    let (v, f) = tetra();
    for (scale, words) in [
        (5e-324, "less than 1 mm"),
        (1e-9, "less than 1 mm"),
        (1.0, "more than 100 m"),
    ] {
        match mesh_from_arrays(&v, &f, "part.stl", scale) {
            Err(MeshError::NotAPart { reason, .. }) => assert!(reason.contains(words), "{reason}"),
            other => panic!("scale {scale}: {other:?}"),
        }
    }
    // Triangles that are all slivers (three points on a line) have no area.
    let line = vec![[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]];
    assert!(matches!(
        mesh_from_arrays(&line, &[[0, 1, 2]], "part.stl", 1.0),
        Err(MeshError::NotAPart { .. })
    ));
    assert!(mesh_from_arrays(&v, &f, "part.stl", 0.001).is_ok());
}
