//! Mesh loading: the three formats agree, vertices are welded, scale is applied, and every bad
//! file is refused with a message naming it.

use std::path::{Path, PathBuf};

use pregrasp_geometry::shapes::{cuboid, uv_sphere};
use pregrasp_geometry::Point;
use pregrasp_io::mesh_io::{load_mesh, parse_stl, write_stl, MeshError};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(name)
}

fn sorted_vertices(m: &pregrasp_geometry::Mesh) -> Vec<[f64; 3]> {
    let mut v: Vec<[f64; 3]> = m.vertices.iter().map(|p| [p.x, p.y, p.z]).collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v
}

#[test]
fn binary_ascii_and_obj_boxes_agree_and_are_welded() {
    let bin = load_mesh(&data("box.stl"), 1.0).unwrap();
    let solid = load_mesh(&data("box_solid_header.stl"), 1.0).unwrap();
    let ascii = load_mesh(&data("box_ascii.stl"), 1.0).unwrap();
    let obj = load_mesh(&data("box.obj"), 1.0).unwrap();
    for m in [&bin, &solid, &ascii, &obj] {
        assert_eq!(m.mesh.vertices.len(), 8, "welded to the 8 corners");
        assert_eq!(m.mesh.triangles.len(), 12);
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    }
    assert_eq!(bin.mesh, solid.mesh);
    // STL stores f32; compare the corner sets at f32 precision.
    let close = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| (0..3).all(|k| (x[k] - y[k]).abs() < 1e-7))
    };
    assert!(close(
        &sorted_vertices(&bin.mesh),
        &sorted_vertices(&ascii.mesh)
    ));
    assert!(close(
        &sorted_vertices(&bin.mesh),
        &sorted_vertices(&obj.mesh)
    ));
}

#[test]
fn scale_multiplies_coordinates() {
    let m1 = load_mesh(&data("box.stl"), 1.0).unwrap().mesh;
    let m2 = load_mesh(&data("box.stl"), 0.01).unwrap().mesh;
    for (a, b) in m1.vertices.iter().zip(&m2.vertices) {
        assert!((a * 0.01 - b).norm() < 1e-15);
    }
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            load_mesh(&data("box.stl"), bad),
            Err(MeshError::Scale { .. })
        ));
    }
}

#[test]
fn write_then_read_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    for (name, mesh) in [
        (
            "box.stl",
            cuboid(Point::new(-0.25, 0.0, 0.5), Point::new(0.5, 0.125, 0.75)),
        ),
        (
            "sphere.stl",
            uv_sphere(Point::new(0.0, 0.0, 0.0), 0.5, 10, 16),
        ),
    ] {
        let path = dir.path().join(name);
        write_stl(&path, &mesh).unwrap();
        let back = load_mesh(&path, 1.0).unwrap();
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        assert_eq!(back.mesh.vertices.len(), mesh.vertices.len());
        assert_eq!(back.mesh.triangles.len(), mesh.triangles.len());
        for (t0, t1) in mesh.triangles.iter().zip(&back.mesh.triangles) {
            for k in 0..3 {
                let (a, b) = (
                    mesh.vertices[t0[k] as usize],
                    back.mesh.vertices[t1[k] as usize],
                );
                assert!((a - b).norm() < 1e-6, "{a} vs {b}");
            }
        }
    }
}

#[test]
fn open_mesh_loads_with_a_warning() {
    let m = load_mesh(&data("open_box.stl"), 1.0).unwrap();
    assert_eq!(m.mesh.triangles.len(), 10);
    assert_eq!(m.warnings.len(), 1);
    assert!(
        m.warnings[0].contains("not watertight") && m.warnings[0].contains("4 open edge"),
        "{}",
        m.warnings[0]
    );
}

/// Every bad file: the error variant and a message that names the file.
#[test]
fn bad_files_are_refused_with_their_name() {
    let cases: [(&str, &str); 10] = [
        ("empty.stl", "empty"),
        ("truncated.stl", "truncated"),
        ("truncated_ascii.stl", "truncated"),
        ("not_a_mesh.stl", "PNG"),
        ("zero_triangles.stl", "no triangles"),
        ("nan.stl", "non-finite"),
        ("inf_ascii.stl", "finite"),
        ("not_a_mesh.obj", "no triangles"),
        ("box_scene.toml", "unsupported mesh format"),
        ("missing.stl", "cannot read"),
    ];
    for (file, expected) in cases {
        let err = load_mesh(&data(file), 1.0).expect_err(file);
        let msg = err.to_string();
        assert!(msg.contains(file), "{file}: {msg}");
        assert!(
            msg.contains(expected),
            "{file}: expected {expected:?} in {msg}"
        );
    }
}

#[test]
fn short_garbage_is_not_an_stl() {
    let err = parse_stl(b"hello", "x.stl", 1.0).unwrap_err();
    assert!(matches!(err, MeshError::Truncated { .. }), "{err}");
    let mut junk = vec![7u8; 300];
    junk[80..84].copy_from_slice(&2u32.to_le_bytes());
    let err = parse_stl(&junk, "x.stl", 1.0).unwrap_err();
    assert!(matches!(err, MeshError::NotAMesh { .. }), "{err}");
}

#[test]
fn ascii_stl_with_a_bare_solid_line_loads() {
    let text = std::fs::read_to_string(data("box_ascii.stl"))
        .unwrap()
        .replacen("solid box\n", "solid\n", 1);
    let m = parse_stl(text.as_bytes(), "bare.stl", 1.0).unwrap();
    assert_eq!((m.mesh.vertices.len(), m.mesh.triangles.len()), (8, 12));
}

#[test]
fn non_finite_message_points_at_the_vertex() {
    let err = load_mesh(&data("nan.stl"), 1.0).unwrap_err();
    // Triangle 3, corner 1 of the fixture is NaN.
    assert!(
        err.to_string().contains("vertex 10 (in file order)"),
        "{err}"
    );
}
