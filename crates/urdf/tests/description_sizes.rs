//! A description larger than any robot is refused in words before the steps that grow with
//! the square of its links (issue 46): more than `MAX_LINKS` links, more than
//! `MAX_COLLISION_LINKS` links with collision geometry or `MAX_COLLISION_ELEMENTS` elements.

use pregrasp_urdf::geometry::{CacheDir, GeometryOptions, UrdfGeometry};
use pregrasp_urdf::limits::{MAX_COLLISION_ELEMENTS, MAX_COLLISION_LINKS, MAX_LINKS};
use pregrasp_urdf::UrdfModel;

/// A root link and `n` links fixed to it, each with `elements` collision boxes.
fn star(n: usize, elements: usize) -> String {
    let mut s = String::from("<robot name=\"star\"><link name=\"root\"/>");
    let boxes = "<collision><geometry><box size=\"0.01 0.01 0.01\"/></geometry></collision>"
        .repeat(elements);
    for i in 0..n {
        s += &format!(
            "<link name=\"l{i}\">{boxes}</link><joint name=\"j{i}\" type=\"fixed\">\
             <parent link=\"root\"/><child link=\"l{i}\"/></joint>"
        );
    }
    s + "</robot>"
}

fn no_cache() -> GeometryOptions {
    GeometryOptions {
        cache: CacheDir::Off,
        ..GeometryOptions::default()
    }
}

#[test]
fn a_description_of_more_links_than_any_robot_is_refused() {
    let err = UrdfModel::from_urdf_str(&star(MAX_LINKS, 0), "star.urdf").unwrap_err();
    assert_eq!(
        err.to_string(),
        "star.urdf: 10001 links: more than the 10000 a description may have"
    );
    assert!(UrdfModel::from_urdf_str(&star(MAX_LINKS - 1, 0), "star.urdf").is_ok());
}

#[test]
fn too_many_links_or_elements_with_collision_geometry_are_refused() {
    let model = UrdfModel::from_urdf_str(&star(MAX_COLLISION_LINKS + 1, 1), "star.urdf").unwrap();
    let err = UrdfGeometry::compute(&model, &no_cache()).unwrap_err();
    assert!(
        err.to_string()
            .contains("513 links with <collision> elements: more than the 512"),
        "{err}"
    );
    let per_link = MAX_COLLISION_ELEMENTS / 8 + 1;
    let model = UrdfModel::from_urdf_str(&star(8, per_link), "star.urdf").unwrap();
    let err = UrdfGeometry::compute(&model, &no_cache()).unwrap_err();
    assert!(
        err.to_string()
            .contains("<collision> elements: more than the 4096"),
        "{err}"
    );
}
