//! `describe_arm`: a URDF arm as the planner uses it. The link shapes are the arm's links (not
//! the hand the description carries), each in the frame that moves with it, and placed by the
//! planner's frames they are where the description's own kinematics puts the links.

mod common;

use common::{data, dist, random_q, rng};
use pregrasp_urdf::{describe_arm, CacheDir, GeometryOptions, UrdfArm, UrdfGeometry};

fn options() -> GeometryOptions {
    GeometryOptions {
        cache: CacheDir::Off,
        ..GeometryOptions::default()
    }
}

#[test]
fn fr3_arm_links_sit_in_their_frames() {
    let arm = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    let held = [("fr3_joint3", 0.0)];
    let d = describe_arm(&arm, &held, &[], &options()).unwrap();
    assert_eq!(d.ur, None);
    assert!(d.key.starts_with("urdf:"));
    let names: Vec<(&str, usize)> = d.geometry.links.iter().map(|l| (l.name, l.frame)).collect();
    // Link 3 turns with joint 2 once joint 3 is held; the hand and fingers are the gripper's.
    assert_eq!(
        names,
        [
            ("fr3_link0", 0),
            ("fr3_link1", 1),
            ("fr3_link2", 2),
            ("fr3_link3", 2),
            ("fr3_link4", 3),
            ("fr3_link5", 4),
            ("fr3_link6", 5),
            ("fr3_link7", 6),
        ]
    );
    // Placed by the planner's frames, every piece vertex is where the description's own
    // kinematics puts it; and every vertex is inside its shape's primitive box.
    let geometry = UrdfGeometry::load(&arm.model, &options()).unwrap().geometry;
    let full = &arm.chain;
    let mut r = rng(11);
    for _ in 0..20 {
        let mut q7 = random_q(full, &mut r, 0.05);
        q7[2] = 0.0;
        let q: [f64; 6] = [q7[0], q7[1], q7[3], q7[4], q7[5], q7[6]];
        let frames = d.kin.fk_frames(&q);
        let links = full.link_frames(&q7);
        for shape in &d.geometry.links {
            let k = full
                .links()
                .iter()
                .position(|l| l.name == shape.name)
                .unwrap();
            let g = geometry.index_of(shape.name).unwrap();
            let pieces = &shape.pieces.unwrap().pieces;
            for (piece, original) in pieces.iter().zip(&geometry.links[g].pieces) {
                for (v, o) in piece.iter().zip(original) {
                    let a = frames[shape.frame] * v;
                    let b = links[k] * o;
                    assert!((a - b).norm() < 1e-9, "{}: {}", shape.name, (a - b).norm());
                }
            }
        }
    }
    let (dp, _) = dist(&d.kin.fk(&[0.0; 6]), &full.fk(&[0.0; 7]));
    assert!(dp < 1e-12);
    // Self-collision pairs are between arm links only, never a link with itself.
    assert!(!d.geometry.self_collision_pairs.is_empty());
    assert!(d
        .geometry
        .self_collision_pairs
        .iter()
        .all(|&(a, b)| a < b && b < d.geometry.links.len()));
}

#[test]
fn a_description_is_built_once() {
    let arm = UrdfArm::load(data("xarm6.urdf").as_ref(), None, None).unwrap();
    let a = describe_arm(&arm, &[], &[], &options()).unwrap();
    let b = describe_arm(&arm, &[], &[], &options()).unwrap();
    assert!(std::sync::Arc::ptr_eq(&a.geometry, &b.geometry));
    assert_eq!(a.joint_names[0], "joint1");
    assert_eq!(a.geometry.links.len(), 7);
}

/// An allowed pair is not checked; the same arm without it is another description.
#[test]
fn allowed_pairs_leave_the_self_collision_check() {
    let arm = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    let held = [("fr3_joint3", 0.0)];
    let plain = describe_arm(&arm, &held, &[], &options()).unwrap();
    let name_pairs = |d: &pregrasp_robot::ArmDescription| -> Vec<(&str, &str)> {
        let links = &d.geometry.links;
        d.geometry
            .self_collision_pairs
            .iter()
            .map(|&(a, b)| (links[a].name, links[b].name))
            .collect()
    };
    let checked = name_pairs(&plain);
    let (a, b) = checked[0];
    let allowed = describe_arm(&arm, &held, &[(b, a)], &options()).unwrap();
    assert_ne!(plain.key, allowed.key);
    let left = name_pairs(&allowed);
    assert_eq!(left.len() + 1, checked.len());
    assert!(!left.contains(&(a, b)));
    let err = describe_arm(&arm, &held, &[("fr3_link9", a)], &options()).unwrap_err();
    assert!(err.to_string().contains("fr3_link9"), "{err}");
}

/// An FR3 with 4 small boxes fixed to each of links 3 to 6: 24 arm links with pieces, more
/// than the collision model's 18 link shapes. Links that move with one frame are merged until
/// it fits; every piece is kept, each in its frame, and the plain FR3 is not merged.
#[test]
fn an_arm_with_more_links_than_shapes_is_merged_per_frame() {
    let text = std::fs::read_to_string(data("fr3.urdf")).unwrap();
    let mut extra = String::new();
    for parent in ["fr3_link3", "fr3_link4", "fr3_link5", "fr3_link6"] {
        for k in 0..4 {
            extra += &format!(
                "<link name=\"{parent}_part{k}\"><collision><origin xyz=\"0 0 {}\"/><geometry>\
                 <box size=\"0.02 0.02 0.02\"/></geometry></collision></link>\
                 <joint name=\"{parent}_part{k}_joint\" type=\"fixed\"><parent link=\"{parent}\"/>\
                 <child link=\"{parent}_part{k}\"/></joint>\n",
                0.01 * k as f64
            );
        }
    }
    let text = text.replacen("</robot>", &(extra + "</robot>"), 1);
    let model = pregrasp_urdf::UrdfModel::from_urdf_str(&text, "fr3_crowded").unwrap();
    let arm = UrdfArm::from_model(model, None, Some("fr3_link8")).unwrap();
    let opts = GeometryOptions {
        urdf_dir: Some(data("").into()),
        ..options()
    };
    let held = [("fr3_joint3", 0.0)];
    let d = describe_arm(&arm, &held, &[], &opts).unwrap();
    let links = &d.geometry.links;
    assert_eq!(links.len(), pregrasp_robot::MAX_LINK_SHAPES);
    let pieces: usize = links.iter().map(|l| l.pieces.unwrap().pieces.len()).sum();
    assert_eq!(pieces, 8 + 16, "every piece is kept");
    // Merged shapes name their links; a box of link 4 moves with link 4's frame.
    let link4 = links
        .iter()
        .find(|l| l.name.starts_with("fr3_link4"))
        .unwrap();
    assert_eq!(link4.frame, 3);
    assert!(links
        .iter()
        .filter(|l| l.name.contains("fr3_link4_part"))
        .all(|l| l.frame == 3));
    assert!(d
        .geometry
        .self_collision_pairs
        .iter()
        .all(|&(a, b)| a < b && b < links.len()));
    let plain = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    let plain = describe_arm(&plain, &held, &[], &options()).unwrap();
    assert!(plain.geometry.links.iter().all(|l| !l.name.contains('+')));
}
