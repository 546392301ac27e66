//! An arm from its robot description, through the commands a user runs: `plan` writes a file
//! that follows the schema, `check` finds the description from the plan and passes it, `view`
//! draws the arm by its chain, `export` writes CSV and ROS 2 trajectories with the
//! description's joint names and refuses URScript for a non-UR arm, leaving nothing behind.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_schema_valid, examples_in, files_in, pregrasp, stderr};
use serde_json::Value;

fn fr3_urdf() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots/fr3.urdf")
}

/// The chair example in `dir` with two FR3 (elbow held) in place of the UR5e.
fn fr3_chair(dir: &Path) {
    examples_in(dir);
    let text = std::fs::read_to_string(dir.join("chair_side.toml")).unwrap();
    let arm = format!(
        "urdf = {:?}\ntool_link = \"fr3_link8\"\nhold = {{ fr3_joint3 = 0.0 }}",
        fr3_urdf().display().to_string()
    );
    let start = "start = [0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]";
    let mut out = String::new();
    for line in text.lines() {
        if line.trim() == "model = \"ur5e\"" {
            out.push_str(&arm);
        } else if line.starts_with("start = ") {
            out.push_str(start);
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    std::fs::write(dir.join("fr3.toml"), out).unwrap();
}

#[test]
fn an_fr3_plan_is_checked_and_exported_as_csv_and_ros2_not_urscript() {
    let dir = tempfile::tempdir().unwrap();
    fr3_chair(dir.path());
    let out = pregrasp(dir.path(), &["plan", "fr3.toml", "-o", "p.json", "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_schema_valid(&dir.path().join("p.json"));
    let plan: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("p.json")).unwrap()).unwrap();
    assert_eq!(plan["robots"][0]["model"], "urdf");
    assert_eq!(plan["robots"][0]["joint_names"][2], "fr3_joint4");
    assert_eq!(plan["robots"][0]["urdf"]["held"]["fr3_joint3"], 0.0);

    let out = pregrasp(dir.path(), &["check", "p.json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));

    // The viewer draws the arm by its own chain and its links' convex pieces.
    let out = pregrasp(dir.path(), &["view", "p.json", "-o", "v.html"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let page = std::fs::read_to_string(dir.path().join("v.html")).unwrap();
    assert!(
        page.contains("\"chain\":{\"frame0\""),
        "no chain steps in the page"
    );
    assert!(
        page.contains("\"kind\":\"hull\""),
        "no link pieces in the page"
    );
    assert!(
        !page.contains("\"known\":false"),
        "an arm the page cannot draw"
    );

    let out = pregrasp(
        dir.path(),
        &["export", "p.json", "-f", "csv,ros2", "-o", "out"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let files = files_in(&dir.path().join("out"));
    assert!(files.iter().any(|f| f.ends_with(".csv")), "{files:?}");
    let yaml = files
        .iter()
        .find(|f| f.ends_with("_rot.yaml"))
        .expect("the rotation's trajectory");
    let yaml = std::fs::read_to_string(dir.path().join("out").join(yaml)).unwrap();
    assert!(yaml.contains("  - fr3_joint4\n"), "{yaml}");
    assert!(!yaml.contains("shoulder_pan_joint"), "{yaml}");

    let out = pregrasp(
        dir.path(),
        &["export", "p.json", "-f", "urscript", "-o", "ur"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("not a Universal Robots arm"), "{err}");
    assert!(!dir.path().join("ur").join("left.script").exists());
}
