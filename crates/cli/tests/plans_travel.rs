//! A plan file finds its scene and mesh wherever it is opened from, and after its folder moved
//! with them: the paths it records relative to its own folder (`scene.file_from_plan`,
//! `object.mesh_from_plan`).

mod common;

use std::path::Path;

use common::pregrasp;

/// The part where the plan put it, as `--object-pose` takes it (lift removed).
fn plan_pose(plan: &serde_json::Value) -> String {
    let p = &plan["object"]["initial_pose"];
    let (xyz, q) = (&p["xyz"], &p["quat_xyzw"]);
    let z = xyz[2].as_f64().unwrap() - plan["planner"]["lift"].as_f64().unwrap();
    format!(
        "{} {} {z} {} {} {} {}",
        xyz[0], xyz[1], q[0], q[1], q[2], q[3]
    )
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn a_plan_moved_with_its_inputs_or_opened_elsewhere_finds_them() {
    let root = tempfile::tempdir().unwrap();
    let cell = root.path().join("cell");
    std::fs::create_dir(&cell).unwrap();
    let out = pregrasp(&cell, &["example", "write", "parts"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    std::fs::create_dir_all(cell.join("runs/today")).unwrap();
    // Planned from the cell's folder into a sub-folder.
    let out = pregrasp(
        &cell,
        &[
            "plan",
            "parts/chair_side.toml",
            "-o",
            "runs/today/plan.json",
            "--quiet",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let plan = read_json(&cell.join("runs/today/plan.json"));
    assert_eq!(plan["scene"]["file"], "parts/chair_side.toml");
    assert_eq!(
        plan["scene"]["file_from_plan"],
        "../../parts/chair_side.toml"
    );
    assert_eq!(
        plan["object"]["mesh_from_plan"],
        "../../parts/meshes/chair_side.stl"
    );

    // The whole folder moves; the commands run from somewhere else entirely.
    let moved = root.path().join("moved");
    std::fs::rename(&cell, &moved).unwrap();
    let elsewhere = root.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    let plan_path = moved.join("runs/today/plan.json");
    let plan_arg = plan_path.to_str().unwrap();
    let pose = plan_pose(&plan);
    for args in [
        vec!["check", plan_arg],
        vec!["view", plan_arg, "-o", "view.html"],
        vec!["physics", plan_arg],
        vec!["export", plan_arg, "--format", "csv", "-o", "cell-out"],
        vec![
            "replan",
            plan_arg,
            "--object-pose",
            &pose,
            "-o",
            "again.json",
        ],
    ] {
        let out = pregrasp(&elsewhere, &args);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {out:?}");
    }
    // The replanned file records where the inputs are from its own folder.
    let again = read_json(&elsewhere.join("again.json"));
    assert_eq!(
        again["scene"]["file_from_plan"],
        "../moved/parts/chair_side.toml"
    );
    assert_eq!(
        pregrasp(&elsewhere, &["check", "again.json"]).status.code(),
        Some(0)
    );

    // Without the recorded paths the moved plan cannot find its scene: the extension is what
    // carries it.
    let mut bare = plan.clone();
    bare["scene"]
        .as_object_mut()
        .unwrap()
        .remove("file_from_plan");
    bare["object"]
        .as_object_mut()
        .unwrap()
        .remove("mesh_from_plan");
    let bare_path = moved.join("runs/today/bare.json");
    std::fs::write(&bare_path, serde_json::to_string(&bare).unwrap()).unwrap();
    let out = pregrasp(
        &elsewhere,
        &[
            "replan",
            bare_path.to_str().unwrap(),
            "--object-pose",
            &pose,
            "-o",
            "bare-again.json",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("chair_side.toml"),
        "{out:?}"
    );
}
