//! Robot descriptions with more links carrying collision geometry than the collision model
//! holds per arm (issue 46): an FR3 with 16 small parts fixed to its links plans (its links
//! that move together merged into one shape) instead of panicking, and a gripper of too many
//! parts is refused when the scene is read, naming the robot and the part, instead of
//! panicking when planning starts.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_bad_input, examples_in, pregrasp, stderr};

/// `fr3.urdf` written into `dir` (meshes named by absolute path), with `extra` small boxes
/// fixed to each of the links `parents` (one fixed child link per box).
fn crowded_fr3(dir: &Path, parents: &[&str], extra: usize) -> PathBuf {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots");
    let meshes = robots
        .join("meshes/franka_description/")
        .canonicalize()
        .unwrap();
    let text = std::fs::read_to_string(robots.join("fr3.urdf"))
        .unwrap()
        .replace(
            "package://franka_description/",
            &format!("file://{}/", meshes.display()),
        );
    let mut links = String::new();
    for parent in parents {
        for k in 0..extra {
            let z = 0.01 * k as f64;
            links += &format!(
                "<link name=\"{parent}_part{k}\"><collision><origin xyz=\"0 0 {z}\"/><geometry>\
                 <box size=\"0.02 0.02 0.02\"/></geometry></collision></link>\n\
                 <joint name=\"{parent}_part{k}_joint\" type=\"fixed\"><parent link=\"{parent}\"/>\
                 <child link=\"{parent}_part{k}\"/></joint>\n"
            );
        }
    }
    let path = dir.join("fr3_crowded.urdf");
    std::fs::write(&path, text.replacen("</robot>", &(links + "</robot>"), 1)).unwrap();
    path
}

/// The chair example in `dir` with two FR3 of `urdf` (elbow held), the gripper `gripper`.
fn chair_with(dir: &Path, urdf: &Path, gripper: &str) {
    examples_in(dir);
    let text = std::fs::read_to_string(dir.join("chair_side.toml")).unwrap();
    let arm = format!(
        "urdf = {:?}\ntool_link = \"fr3_link8\"\nhold = {{ fr3_joint3 = 0.0 }}",
        urdf.display().to_string()
    );
    let mut out = String::new();
    for line in text.lines() {
        let line = match line.trim() {
            "model = \"ur5e\"" => arm.as_str(),
            l if l.starts_with("start = ") => {
                "start = [0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]"
            }
            l if l.starts_with("gripper = ") => gripper,
            l if l.starts_with("power_point_z") && gripper.contains("urdf") => "",
            _ => line,
        };
        out.push_str(line);
        out.push('\n');
    }
    std::fs::write(dir.join("fr3.toml"), out).unwrap();
}

#[test]
fn an_arm_with_more_links_than_shapes_plans_instead_of_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let parents = ["fr3_link3", "fr3_link4", "fr3_link5", "fr3_link6"];
    let urdf = crowded_fr3(dir.path(), &parents, 4);
    chair_with(dir.path(), &urdf, "gripper = \"robotiq_2f85\"");
    let out = pregrasp(dir.path(), &["plan", "fr3.toml", "-o", "p.json", "--quiet"]);
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        matches!(out.status.code(), Some(0) | Some(2)),
        "a plan or no plan, not {:?}: {err}",
        out.status.code()
    );
}

#[test]
fn a_gripper_with_too_many_parts_is_refused_when_the_scene_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // The hand, its two fingers and 15 parts: 18 gripper shapes, at most 16.
    let urdf = crowded_fr3(dir.path(), &["fr3_hand"], 15);
    chair_with(dir.path(), &urdf, "gripper = \"urdf\"");
    let out = pregrasp(dir.path(), &["plan", "fr3.toml", "-o", "p.json", "--quiet"]);
    assert_bad_input(&out, "robot `left`: the gripper has 18 collision shapes");
    assert!(!stderr(&out).contains("panicked"));
}
