//! Hostile COLLADA files give an error, never a panic, an abort, a stack overflow or an
//! unbounded allocation (`geometry::collada` checks them before `mesh-loader` reads them);
//! valid ones (a cube of triangles, of quads, nested nodes, a unit) load as before.

use std::collections::BTreeSet;
use std::path::Path;

use nalgebra::Isometry3;
use pregrasp_urdf::geometry::collada::{self, MAX_DEPTH};
use pregrasp_urdf::geometry::mesh::{parse, LinkMesh};
use pregrasp_urdf::{CacheDir, GeometryOptions, UrdfError, UrdfGeometry, UrdfModel};

/// The corners of a 1000-unit cube: corner `i` has x, y, z = ±500 by bits 0, 1, 2 of `i`.
fn corners() -> String {
    (0..8)
        .flat_map(|i| [1, 2, 4].map(|b| if i & b != 0 { "500" } else { "-500" }))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Twelve triangles, each corner followed by the normal index of its face (offset 1).
const TRIANGLES: &str = r##"<triangles count="12">
          <input semantic="VERTEX" source="#cube-vertices" offset="0"/>
          <input semantic="NORMAL" source="#cube-normals" offset="1"/>
          <p>0 0 4 0 6 0 0 0 6 0 2 0  1 1 3 1 7 1 1 1 7 1 5 1  0 2 1 2 5 2 0 2 5 2 4 2
             2 3 6 3 7 3 2 3 7 3 3 3  0 4 2 4 3 4 0 4 3 4 1 4  4 5 5 5 7 5 4 5 7 5 6 5</p>
        </triangles>"##;

/// Six quads.
const POLYLIST: &str = r##"<polylist count="6">
          <input semantic="VERTEX" source="#cube-vertices" offset="0"/>
          <vcount>4 4 4 4 4 4</vcount>
          <p>0 4 6 2 1 3 7 5 0 1 5 4 2 6 7 3 0 2 3 1 4 5 7 6</p>
        </polylist>"##;

/// A cube in a COLLADA file: millimetres (`<unit meter="0.001">`), Z up, primitive `prim`,
/// one node with the transform elements `transform`.
fn cube(prim: &str, transform: &str) -> String {
    let positions = corners();
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="cube-mesh" name="cube">
      <mesh>
        <source id="cube-positions">
          <float_array id="cube-positions-array" count="24">{positions}</float_array>
          <technique_common>
            <accessor source="#cube-positions-array" count="8" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <source id="cube-normals">
          <float_array id="cube-normals-array" count="18">-1 0 0 1 0 0 0 -1 0 0 1 0 0 0 -1 0 0 1</float_array>
          <technique_common>
            <accessor source="#cube-normals-array" count="6" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="cube-vertices"><input semantic="POSITION" source="#cube-positions"/></vertices>
        {prim}
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="cube" name="cube" type="NODE">{transform}<instance_geometry url="#cube-mesh" name="cube"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
"##
    )
}

fn load(text: &str) -> std::io::Result<LinkMesh> {
    parse(
        text.as_bytes(),
        Path::new("m.dae"),
        [1.0; 3],
        &Isometry3::identity(),
    )
}

/// The error message of a file that must be refused, checked to be `InvalidData` and to
/// contain `part`.
fn refused(text: &str, part: &str) -> String {
    let err = load(text).expect_err("a hostile file was accepted");
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidData, "{err}");
    let message = err.to_string();
    assert!(message.contains(part), "{message:?} lacks {part:?}");
    message
}

/// The distinct vertices, rounded to 1e-6.
fn distinct(m: &LinkMesh) -> BTreeSet<[i64; 3]> {
    m.vertices
        .iter()
        .map(|p| [p.x, p.y, p.z].map(|c| (c * 1e6).round() as i64))
        .collect()
}

/// The corners of a unit cube centred at `c` (1e-6 units).
fn unit_cube_at(c: [f64; 3]) -> BTreeSet<[i64; 3]> {
    (0..8)
        .map(|i| {
            let mut v = [0; 3];
            for (k, b) in [1, 2, 4].into_iter().enumerate() {
                let s = if i & b != 0 { 0.5 } else { -0.5 };
                v[k] = ((c[k] + s) * 1e6).round() as i64;
            }
            v
        })
        .collect()
}

#[test]
fn a_valid_cube_with_a_unit_and_a_node_transform_still_loads() {
    let text = cube(TRIANGLES, "<translate>1 2 3</translate>");
    let m = load(&text).unwrap();
    assert_eq!(m.triangles.len(), 12);
    assert_eq!(m.vertices.len(), 36);
    assert_eq!(distinct(&m), unit_cube_at([1.0, 2.0, 3.0]));
    // Exactly what mesh-loader gives on its own: the check changes nothing on valid files.
    let direct = mesh_loader::Loader::default()
        .load_from_slice(text.as_bytes(), "m.dae")
        .unwrap();
    let direct: Vec<[f32; 3]> = direct
        .meshes
        .iter()
        .flat_map(|m| m.vertices.clone())
        .collect();
    assert_eq!(direct.len(), m.vertices.len());
    for (a, b) in direct.iter().zip(&m.vertices) {
        assert_eq!([a[0] as f64, a[1] as f64, a[2] as f64], [b.x, b.y, b.z]);
    }
}

#[test]
fn a_valid_polylist_cube_with_a_matrix_still_loads() {
    let matrix = "<matrix>1 0 0 0.5  0 1 0 0  0 0 1 -1  0 0 0 1</matrix>";
    let m = load(&cube(POLYLIST, matrix)).unwrap();
    assert_eq!(m.triangles.len(), 12, "six quads, two triangles each");
    assert_eq!(distinct(&m), unit_cube_at([0.5, 0.0, -1.0]));
    // Rotate and scale elements are read too.
    let rs = "<rotate>0 0 1 90</rotate><scale>2 2 2</scale>";
    assert_eq!(load(&cube(POLYLIST, rs)).unwrap().triangles.len(), 12);
}

/// `<node>` elements nested to the depth limit: read by mesh-loader's recursive reader in the
/// test thread's stack (2 MB) without overflowing it.
#[test]
fn nodes_nested_up_to_the_depth_limit_still_load() {
    // COLLADA, library_visual_scenes, visual_scene, the cube's node: 4 levels, then `levels`.
    let levels = MAX_DEPTH as usize - 4;
    let inner = "<node>".repeat(levels) + &"</node>".repeat(levels);
    let text = cube(TRIANGLES, &inner);
    assert_eq!(load(&text).unwrap().triangles.len(), 12);
    let deeper = "<node>".repeat(levels + 1) + &"</node>".repeat(levels + 1);
    refused(
        &cube(TRIANGLES, &deeper),
        "is nested more than 256 levels deep",
    );
}

#[test]
fn deep_nesting_of_100000_levels_is_an_error_not_a_stack_overflow() {
    let n = 100_000;
    let nodes = "<node>".repeat(n) + &"</node>".repeat(n);
    let text = format!(
        r#"<COLLADA version="1.4.1"><library_visual_scenes><visual_scene id="s">{nodes}</visual_scene></library_visual_scenes></COLLADA>"#
    );
    refused(&text, "is nested more than 256 levels deep");
    // Any element, not only <node>.
    let deep = "<extra>".repeat(n) + &"</extra>".repeat(n);
    refused(
        &format!(r#"<COLLADA version="1.4.1">{deep}</COLLADA>"#),
        "nested",
    );
}

#[test]
fn an_index_out_of_range_in_p_is_an_error() {
    let text = cube(TRIANGLES, "").replacen("<p>0 0 4 0", "<p>8 0 4 0", 1);
    refused(
        &text,
        "index 8 (value 0) for its POSITION input at offset 0",
    );
    // The normal index (offset 1) is checked against the normals (6).
    let text = cube(TRIANGLES, "").replacen("<p>0 0 4 0", "<p>0 6 4 0", 1);
    refused(&text, "index 6 (value 1) for its NORMAL input at offset 1");
    let text = cube(POLYLIST, "").replacen("<p>0 4 6 2", "<p>0 4 6 99", 1);
    refused(&text, "index 99");
}

#[test]
fn an_accessor_of_stride_0_is_an_error() {
    let text =
        cube(TRIANGLES, "").replacen(r#"count="8" stride="3""#, r#"count="8" stride="0""#, 1);
    refused(&text, "declares stride 0");
}

#[test]
fn a_huge_declared_count_is_an_error_not_an_allocation() {
    let text = cube(TRIANGLES, "").replacen(r#"count="24""#, r#"count="4000000000""#, 1);
    let m = refused(&text, "declares count 4000000000 but holds 24 numbers");
    assert!(
        m.contains("`<float_array id=\"cube-positions-array\">`"),
        "{m}"
    );
    // A 1 KB file.
    let small = r#"<COLLADA version="1.4.1"><library_geometries><geometry id="g"><mesh>
        <source id="s"><float_array id="x" count="4000000000">1 2 3 4 5 6 7 8 9</float_array></source>
        </mesh></geometry></library_geometries></COLLADA>"#;
    refused(
        small,
        "`<float_array id=\"x\">` (line 2) declares count 4000000000 but holds 9 numbers",
    );
    // The primitive counts mesh-loader reserves before reading.
    let t = cube(TRIANGLES, "").replacen(
        r#"<triangles count="12""#,
        r#"<triangles count="4000000000""#,
        1,
    );
    refused(&t, "holds 72 indices, not 24000000000");
    let p = cube(POLYLIST, "").replacen(
        r#"<polylist count="6""#,
        r#"<polylist count="4000000000""#,
        1,
    );
    refused(
        &p,
        "holds 6 values but its primitive declares count 4000000000",
    );
}

#[test]
fn accessors_reading_past_their_array_are_errors() {
    let text =
        cube(TRIANGLES, "").replacen(r#"count="8" stride="3""#, r#"count="9" stride="3""#, 1);
    refused(&text, "reads 9 x 3 values from offset 0 (27) but its array");
    let text = cube(TRIANGLES, "").replacen(
        r#"count="6" stride="3""#,
        r#"count="6" stride="3" offset="1""#,
        1,
    );
    refused(&text, "(19) but its array \"#cube-normals-array\" holds 18");
    // mesh-loader's position counter underflows on a count of 0.
    let text =
        cube(TRIANGLES, "").replacen(r#"count="6" stride="3""#, r#"count="0" stride="3""#, 1);
    refused(&text, "declares count 0");
}

#[test]
fn constructs_that_panic_or_hang_in_mesh_loader_are_errors() {
    let base = cube(TRIANGLES, "");
    // An input offset of u32::MAX (offset + 1 overflows).
    let t = base.replacen(r#"offset="1"/>"#, r#"offset="4294967295"/>"#, 1);
    refused(&t, "declares offset 4294967295");
    // A VERTEX input naming another <vertices> (a `todo!()`).
    let t = base.replacen(
        r##"source="#cube-vertices" offset="0""##,
        r##"source="#other" offset="0""##,
        1,
    );
    refused(&t, "names \"#other\"");
    // A position source that is no accessor, or an accessor of a missing array.
    let t = base.replacen(
        r##"<input semantic="POSITION" source="#cube-positions"/>"##,
        r##"<input semantic="POSITION" source="#nowhere"/>"##,
        1,
    );
    refused(&t, "which is no <source> with an <accessor>");
    let t = base.replacen(
        r##"<accessor source="#cube-positions-array""##,
        r##"<accessor source="#gone""##,
        1,
    );
    refused(&t, "reads \"#gone\", which is no data array");
    // Positions of two values (mesh-loader reads none, then indexes them).
    let t = base.replacen(r#"count="8" stride="3""#, r#"count="8" stride="2""#, 1);
    refused(&t, "positions need stride >= 3");
    // Positions read from an (empty) name array, the last array of their <source> (the one
    // mesh-loader keeps): it unwraps it as numbers.
    let t = base.replacen(
        "</float_array>",
        r#"</float_array><Name_array id="cube-positions-array" count="0"/>"#,
        1,
    );
    refused(&t, "a name array, not numbers");
    // A non-empty name array in a <source> (mesh-loader's reader never ends).
    let t = base.replacen(
        "</source>",
        r#"<Name_array id="n" count="1">a</Name_array></source>"#,
        1,
    );
    refused(&t, "holds names");
    // Triangles declaring faces with no <p> at all.
    let t = base
        .replacen("<p>", "<extra>", 1)
        .replacen("</p>", "</extra>", 1);
    refused(
        &t,
        "<p> holds 0 indices where its count and <vcount> need 72",
    );
    // <polygons> with a <p> before any <input> (a division by zero).
    let t = base.replacen(
        TRIANGLES,
        r#"<polygons count="1"><p>0 1 2</p></polygons>"#,
        1,
    );
    refused(&t, "a <p> before any <input>");
    // Polygons of fewer than three vertices (mesh-loader recurses once per such polygon).
    let t = cube(POLYLIST, "").replacen("<vcount>4 4", "<vcount>2 6", 1);
    refused(&t, "a polygon of 2 vertices");
    // An <input> after the indices (they would be walked with another stride).
    let t = base.replacen(
        "</triangles>",
        r##"<input semantic="COLOR" source="#cube-normals" offset="2"/></triangles>"##,
        1,
    );
    refused(&t, "an <input> after <p>");
}

#[test]
fn xml_bombs_are_errors() {
    // Namespace declarations copied to every element that declares one.
    let decls: String = (0..100).map(|i| format!(" xmlns:a{i}=\"u{i}\"")).collect();
    refused(
        &format!(r#"<COLLADA version="1.4.1"{decls}/>"#),
        "namespace declarations",
    );
    // Entities (DTDs are refused).
    let dtd = r#"<!DOCTYPE c [<!ENTITY a "aaaa">]><COLLADA version="1.4.1">&a;</COLLADA>"#;
    refused(dtd, "not well-formed XML");
    // The check runs on a COLLADA file whatever its extension says.
    assert!(collada::is_collada(Path::new("m.DAE"), b""));
    assert!(collada::is_collada(Path::new("m.Dae"), b""));
    assert!(collada::is_collada(Path::new("m"), b"<?xml?><COLLADA"));
    assert!(!collada::is_collada(Path::new("m.stl"), b"<COLLADA"));
}

/// Through the whole path: a URDF whose collision mesh is hostile gives `UrdfError::Mesh`
/// naming the link and the file; the same URDF with a valid cube computes.
#[test]
fn a_urdf_naming_a_hostile_collada_mesh_is_a_mesh_error() {
    let tmp = tempfile::tempdir().unwrap();
    let urdf = tmp.path().join("r.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="r"><link name="base"><collision><geometry><mesh filename="bad.dae"/></geometry></collision></link></robot>"#,
    )
    .unwrap();
    let opts = GeometryOptions {
        cache: CacheDir::Off,
        ..Default::default()
    };
    let hostile = cube(TRIANGLES, "").replacen(r#"count="24""#, r#"count="4000000000""#, 1);
    std::fs::write(tmp.path().join("bad.dae"), hostile).unwrap();
    let model = UrdfModel::from_file(&urdf).unwrap();
    let err = UrdfGeometry::compute(&model, &opts).unwrap_err();
    let UrdfError::Mesh {
        ref link,
        ref path,
        ref message,
        ..
    } = err
    else {
        panic!("{err}")
    };
    assert_eq!(link, "base");
    assert!(path.ends_with("bad.dae"), "{path}");
    assert!(message.contains("declares count 4000000000"), "{message}");
    std::fs::write(tmp.path().join("bad.dae"), cube(POLYLIST, "")).unwrap();
    let g = UrdfGeometry::compute(&model, &opts).unwrap();
    assert_eq!(g.links.len(), 1);
}
