//! `pregrasp physics` on a rotation that hangs the part on the pads' twist (the stool side's
//! candidate 2, `pregrasp_physics::twist`): the verdict says so and the exit status is 2; with
//! the scene's `[physics] max_twist_arm = 1` the same plan holds.

mod common;

use common::pregrasp;

#[test]
fn a_rotation_hanging_on_the_twist_lifts_off_the_support() {
    let root = tempfile::tempdir().unwrap();
    let out = pregrasp(root.path(), &["example", "write", "parts"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let scene = root.path().join("parts/stool_side.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    // Kept, flagged: the plan file holds the candidate the planner would refuse.
    std::fs::write(&scene, format!("{text}\n[physics]\nreject = false\n")).unwrap();
    let plan = [
        "plan",
        "parts/stool_side.toml",
        "-o",
        "plan.json",
        "--quiet",
    ];
    let out = pregrasp(root.path(), &plan);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let file: serde_json::Value =
        serde_json::from_slice(&std::fs::read(root.path().join("plan.json")).unwrap()).unwrap();
    let hangs = file["plans"]
        .as_array()
        .unwrap()
        .iter()
        .position(|p| p["physics"]["verdict"] == "lifts_off_support")
        .expect("a plan whose rotation hangs on the twist");
    assert_eq!(file["plans"][hangs]["candidate"], 2);

    let out = pregrasp(root.path(), &["physics", "plan.json"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{stdout}");
    assert!(stdout.contains("LIFTS OFF THE SUPPORT"), "{stdout}");
    assert!(
        stdout.contains("the part hangs from the pinch on the pads' twist, its weight 87.4 mm"),
        "{stdout}"
    );

    // The rule off in the scene the plan names: every plan holds.
    let off = format!("{text}\n[physics]\nreject = false\nmax_twist_arm = 1\n");
    std::fs::write(&scene, off).unwrap();
    let out = pregrasp(root.path(), &["physics", "plan.json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
}
