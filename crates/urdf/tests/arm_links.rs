//! `GeometryOptions::arm`: the collision model of one arm's links only. Its pieces and its
//! self-collision pairs (checked, and excluded with their reason and tallies) are exactly the
//! whole file's among those links, and links of other branches are never derived or sampled.

mod common;

use std::collections::BTreeSet;
use std::path::PathBuf;

use common::data;
use pregrasp_urdf::geometry::select::arm_links;
use pregrasp_urdf::{CacheDir, GeometryOptions, UrdfArm, UrdfGeometry, UrdfModel};

fn options(arm: Option<&UrdfArm>) -> GeometryOptions {
    GeometryOptions {
        cache: CacheDir::Off,
        urdf_dir: Some(PathBuf::from(data(""))),
        arm: arm.map(|a| (a.base_link.clone(), a.tool_link.clone())),
        ..GeometryOptions::default()
    }
}

/// A pair by its links' names.
type Named = (String, String);

/// A model by names: links with their pieces, checked pairs, excluded pairs with their reason
/// and tallies.
type ByName = (
    Vec<(String, Vec<Vec<nalgebra::Point3<f64>>>)>,
    BTreeSet<Named>,
    Vec<(Named, String, usize, usize)>,
);

/// Every link with pieces (names, pieces), checked pairs and excluded pairs (with reason and
/// tallies) by name, keeping only the links in `keep`.
fn by_name(g: &UrdfGeometry, keep: &BTreeSet<String>) -> ByName {
    let name = |i: usize| g.links[i].link.clone();
    let kept = |a: usize, b: usize| keep.contains(&name(a)) && keep.contains(&name(b));
    let links = g
        .links
        .iter()
        .filter(|l| keep.contains(&l.link))
        .map(|l| (l.link.clone(), l.pieces.clone()))
        .collect();
    let pairs = g
        .self_collision_pairs
        .iter()
        .filter(|&&(a, b)| kept(a, b))
        .map(|&(a, b)| (name(a), name(b)))
        .collect();
    let excluded = g
        .excluded_pairs
        .iter()
        .filter(|e| kept(e.a, e.b))
        .map(|e| {
            let why = format!("{:?}", e.why);
            ((name(e.a), name(e.b)), why, e.hits, e.samples)
        })
        .collect();
    (links, pairs, excluded)
}

/// The arm's model equals the whole file's restricted to the arm's links.
fn same_as_whole_file(arm: &UrdfArm) {
    let keep = arm_links(&arm.model, &arm.base_link, &arm.tool_link).unwrap();
    let whole = UrdfGeometry::compute(&arm.model, &options(None)).unwrap();
    let own = UrdfGeometry::compute(&arm.model, &options(Some(arm))).unwrap();
    assert!(own.links.iter().all(|l| keep.contains(&l.link)));
    assert!(!own.self_collision_pairs.is_empty());
    assert_eq!(by_name(&own, &keep), by_name(&whole, &keep));
    assert_ne!(own.key, whole.key, "the arm is part of the cache key");
}

#[test]
fn fr3_arm_geometry_is_the_whole_files_among_its_links() {
    let arm = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    same_as_whole_file(&arm);
}

#[test]
fn xarm6_arm_geometry_is_the_whole_files_among_its_links() {
    let arm = UrdfArm::load(data("xarm6.urdf").as_ref(), None, None).unwrap();
    same_as_whole_file(&arm);
}

#[test]
fn the_arms_links_are_its_path_what_is_fixed_to_it_and_all_below_the_tool() {
    let arm = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    let keep = arm_links(&arm.model, "fr3_link2", "fr3_link8").unwrap();
    let mut expected: Vec<&str> = vec![
        "fr3_link2",
        "fr3_link3",
        "fr3_link4",
        "fr3_link5",
        "fr3_link6",
        "fr3_link7",
        "fr3_link8",
        "fr3_hand",
        "fr3_hand_tcp",
        "fr3_leftfinger",
        "fr3_rightfinger",
    ];
    expected.sort();
    assert_eq!(
        keep.iter().map(String::as_str).collect::<Vec<_>>(),
        expected
    );
    assert!(arm_links(&arm.model, "fr3_link8", "fr3_link2").is_err());
    assert!(arm_links(&arm.model, "base", "nowhere").is_err());
}

/// `fr3.urdf` under a new root link `world`, beside a cell of `n` fixtures with a box each on
/// another branch of the tree: each turns about its own vertical axis with `fr3_joint1` (a
/// `<mimic>`, so the tree's variables, and the sample stream, are the FR3's), each its own
/// body, so the whole file has `n·(n−1)/2` more pairs to sample.
fn fr3_in_a_cell(n: usize) -> UrdfModel {
    let text = std::fs::read_to_string(data("fr3.urdf")).unwrap();
    let mut extra = String::from(
        "<link name=\"world\"/>\n<joint name=\"world_fr3\" type=\"fixed\"><parent \
         link=\"world\"/><child link=\"base\"/></joint>\n",
    );
    for i in 0..n {
        let (x, y) = (1.0 + 0.1 * (i % 20) as f64, 0.1 * (i / 20) as f64);
        extra += &format!(
            "<link name=\"cell_{i}\"><collision><geometry><box size=\"0.04 0.04 0.04\"/>\
             </geometry></collision></link>\n<joint name=\"cell_joint_{i}\" type=\"revolute\">\
             <origin xyz=\"{x} {y} 0\"/><axis xyz=\"0 0 1\"/><parent link=\"world\"/>\
             <child link=\"cell_{i}\"/><limit lower=\"-3\" upper=\"3\" effort=\"1\" \
             velocity=\"1\"/><mimic joint=\"fr3_joint1\"/></joint>\n"
        );
    }
    let text = text.replacen("</robot>", &(extra + "</robot>"), 1);
    UrdfModel::from_urdf_str(&text, "fr3_cell").unwrap()
}

#[test]
fn self_collision_samples_only_the_arms_links() {
    let cell = UrdfArm::from_model(fr3_in_a_cell(400), Some("base"), Some("fr3_link8")).unwrap();
    let own = UrdfGeometry::compute(&cell.model, &options(Some(&cell))).unwrap();
    // No fixture link has pieces, so no pair names one.
    assert!(own.links.iter().all(|l| !l.link.starts_with("cell_")));
    assert_eq!(
        own.links.len(),
        11,
        "fr3_link0..7, the hand and its two fingers"
    );
    let plain = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    let alone = UrdfGeometry::compute(&plain.model, &options(Some(&plain))).unwrap();
    let keep = arm_links(&cell.model, &cell.base_link, &cell.tool_link).unwrap();
    assert_eq!(by_name(&own, &keep), by_name(&alone, &keep));
}

#[test]
fn links_off_the_arm_are_not_read_at_all() {
    // A fixture whose mesh is found nowhere (or would be a device): the arm does not need
    // it, so describing the arm reads nothing of it; the whole file still reports it.
    let text = std::fs::read_to_string(data("fr3.urdf")).unwrap();
    let extra = "<link name=\"world\"/>\n<joint name=\"world_fr3\" type=\"fixed\"><parent \
                 link=\"world\"/><child link=\"base\"/></joint>\n<link name=\"fixture\">\
                 <collision><geometry><mesh filename=\"/dev/zero.stl\" scale=\"nan 1 1\"/>\
                 </geometry></collision></link>\n<joint name=\"world_fixture\" type=\"fixed\">\
                 <parent link=\"world\"/><child link=\"fixture\"/></joint>\n";
    let text = text.replacen("</robot>", &format!("{extra}</robot>"), 1);
    let model = UrdfModel::from_urdf_str(&text, "fr3_fixture").unwrap();
    let arm = UrdfArm::from_model(model, Some("base"), Some("fr3_link8")).unwrap();
    let own = UrdfGeometry::compute(&arm.model, &options(Some(&arm))).unwrap();
    assert_eq!(own.links.len(), 11);
    let whole = UrdfGeometry::compute(&arm.model, &options(None)).unwrap_err();
    assert!(whole.to_string().contains("link `fixture`"), "{whole}");
}
