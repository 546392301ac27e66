//! `pregrasp plan`, `check` and `demo` run as the real binary in temporary directories.

mod common;

use common::{examples_dir, plan_chair_side, plan_without_timing, pregrasp};

use std::path::Path;

#[test]
fn plan_writes_a_plan_that_check_accepts_and_is_the_same_for_1_and_2_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = examples_dir().join("chair_side.toml");
    let scene = scene.to_str().unwrap();
    let one = pregrasp(
        tmp.path(),
        &["plan", scene, "-o", "one.json", "--threads", "1", "--quiet"],
    );
    assert_eq!(
        one.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&one.stderr)
    );
    let two = pregrasp(
        tmp.path(),
        &["plan", scene, "-o", "two.json", "--threads", "2", "--quiet"],
    );
    assert_eq!(two.status.code(), Some(0));
    assert_eq!(
        plan_without_timing(&tmp.path().join("one.json")),
        plan_without_timing(&tmp.path().join("two.json"))
    );
    let check = pregrasp(tmp.path(), &["check", "one.json"]);
    let out = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(0), "{out}");
    for rule in 1..=4 {
        assert!(out.contains(&format!("rule {rule} ok")), "{out}");
    }
}

#[test]
fn a_broken_mesh_exits_1_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(examples_dir().join("chair_side.toml")).unwrap();
    std::fs::create_dir(tmp.path().join("meshes")).unwrap();
    // A binary STL header that promises 1000 triangles and delivers none.
    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&1000u32.to_le_bytes());
    std::fs::write(tmp.path().join("meshes/chair_side.stl"), stl).unwrap();
    std::fs::write(tmp.path().join("scene.toml"), scene).unwrap();
    let out = pregrasp(tmp.path(), &["plan", "scene.toml", "-o", "plan.json"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("chair_side.stl"), "{err}");
    assert!(err.contains("object.mesh"), "{err}");
    assert!(!tmp.path().join("plan.json").exists());
    assert_eq!(
        std::fs::read_dir(tmp.path()).unwrap().count(),
        2,
        "no temp file left behind"
    );
}

#[test]
fn a_support_grasp_through_the_table_exits_2_with_a_no_plan_file() {
    let tmp = tempfile::tempdir().unwrap();
    write_far_support_scene(&tmp.path().join("scene.toml"));
    let out = pregrasp(
        tmp.path(),
        &["plan", "scene.toml", "-o", "plan.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(2));
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("plan.json")).unwrap())
            .unwrap();
    assert_eq!(plan["status"], "no_plan");
    let reason = plan["reason"].as_str().unwrap();
    assert!(
        reason.starts_with("grasp: support grasp of arm") && reason.contains("into the support"),
        "{reason}"
    );
    assert_eq!(plan["plans"].as_array().unwrap().len(), 0);
}

/// Writes the chair-side scene (mesh path made absolute) with its support grasp G_s moved two
/// metres along object x, out of both arms' reach.
fn write_far_support_scene(path: &Path) {
    // G_s turned to approach from below, through the table: the fingers still close on the
    // bar, but inside the support.
    let scene = std::fs::read_to_string(examples_dir().join("chair_side.toml")).unwrap();
    let mesh = examples_dir().join("meshes/chair_side.stl");
    let scene = scene.replace("meshes/chair_side.stl", mesh.to_str().unwrap());
    let line = scene
        .lines()
        .find(|l| l.starts_with("support = {"))
        .expect("support line");
    let flipped = line.replace("rpy_deg = [180.00,", "rpy_deg = [0.00,");
    assert_ne!(
        line, flipped,
        "support grasp written as rpy_deg = [180, ...]"
    );
    std::fs::write(path, scene.replace(line, &flipped)).unwrap();
}

#[test]
fn check_reports_the_failed_rule_and_exits_2() {
    let tmp = tempfile::tempdir().unwrap();
    plan_chair_side(tmp.path());
    let path = tmp.path().join("plan.json");
    let mut plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    plan["grasps"]["support"]["xyz"][2] =
        serde_json::json!(plan["grasps"]["support"]["xyz"][2].as_f64().unwrap() + 0.005);
    std::fs::write(&path, serde_json::to_string(&plan).unwrap()).unwrap();
    let check = pregrasp(tmp.path(), &["check", "plan.json"]);
    let out = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(2), "{out}");
    assert!(out.contains("rule 4 FAIL"), "{out}");
    assert!(out.contains("INVALID"), "{out}");
}

#[test]
fn check_of_a_missing_file_exits_1_naming_it() {
    let tmp = tempfile::tempdir().unwrap();
    let out = pregrasp(tmp.path(), &["check", "nope.json"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope.json"));
}

#[test]
fn demo_runs_from_nothing_and_writes_a_valid_plan() {
    let tmp = tempfile::tempdir().unwrap();
    let out = pregrasp(tmp.path(), &["demo"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("plan: candidate"), "{stdout}");
    assert!(tmp.path().join("demo-plan.json").exists());
    let check = pregrasp(tmp.path(), &["check", "demo-plan.json"]);
    assert_eq!(
        check.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&check.stdout)
    );
}

/// The repository's `docs/plan.schema.json`.
fn schema_file() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/plan.schema.json");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every plan file `plan` writes — planned or not — matches `docs/plan.schema.json`.
#[test]
fn plan_files_match_the_json_schema() {
    let schema: serde_json::Value = serde_json::from_str(&schema_file()).unwrap();
    let validator = jsonschema::validator_for(&schema).expect("the schema compiles");
    let tmp = tempfile::tempdir().unwrap();
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let scene = examples_dir().join(format!("{name}.toml"));
        let out = pregrasp(
            tmp.path(),
            &["plan", scene.to_str().unwrap(), "-o", "p.json", "--quiet"],
        );
        assert_eq!(out.status.code(), Some(0), "{name}");
        let plan: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(tmp.path().join("p.json")).unwrap())
                .unwrap();
        let errors: Vec<String> = validator
            .iter_errors(&plan)
            .map(|e| format!("{e} at {}", e.instance_path()))
            .collect();
        assert!(errors.is_empty(), "{name}: {errors:?}");
    }
    // A no-plan file too.
    write_far_support_scene(&tmp.path().join("far.toml"));
    let out = pregrasp(
        tmp.path(),
        &["plan", "far.toml", "-o", "none.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(2));
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("none.json")).unwrap())
            .unwrap();
    assert!(validator.is_valid(&plan));
}

/// `pregrasp schema plan` prints the repository's schema byte for byte, so tools can validate
/// plan files with the binary alone; the schema is draft 2020-12 and rejects a broken plan.
#[test]
fn schema_plan_prints_the_repository_schema() {
    let tmp = tempfile::tempdir().unwrap();
    let out = pregrasp(tmp.path(), &["schema", "plan"]);
    assert_eq!(out.status.code(), Some(0));
    let printed = String::from_utf8(out.stdout).unwrap();
    assert_eq!(printed, schema_file());
    let schema: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(
        schema["$schema"],
        "https://json-schema.org/draft/2020-12/schema"
    );
    assert_eq!(schema["properties"]["format"]["const"], "pregrasp.plan/1");
    let validator = jsonschema::validator_for(&schema).expect("the schema compiles");
    // A no-plan file passes; the same file with a third robot or a bad status does not.
    write_far_support_scene(&tmp.path().join("far.toml"));
    let run = pregrasp(
        tmp.path(),
        &["plan", "far.toml", "-o", "none.json", "--quiet"],
    );
    assert_eq!(run.status.code(), Some(2));
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("none.json")).unwrap())
            .unwrap();
    assert!(validator.is_valid(&plan));
    let mut three = plan.clone();
    let extra = three["robots"][0].clone();
    three["robots"].as_array_mut().unwrap().push(extra);
    assert!(!validator.is_valid(&three));
    let mut status = plan;
    status["status"] = serde_json::json!("maybe");
    assert!(!validator.is_valid(&status));
    // `schema scene` points at the scene format's document.
    let out = pregrasp(tmp.path(), &["schema", "scene"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("docs/scene-format.md"));
}

/// A plan with `grip_force` on each closing segment (issue 48) satisfies the schema; one out of
/// its range, or on `rot`'s object as a string, does not.
#[test]
fn the_schema_describes_grip_force() {
    let schema: serde_json::Value = serde_json::from_str(&schema_file()).unwrap();
    let validator = jsonschema::validator_for(&schema).expect("the schema compiles");
    let golden =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/golden/chair_side.json");
    let mut plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(golden).unwrap()).unwrap();
    // The golden files leave out the timings, which a plan file has.
    plan["timing_ms"] = serde_json::json!({"axes": 0.1, "poses": 0.1, "paths": 0.1, "total": 0.3});
    assert!(validator.is_valid(&plan));
    assert!(plan["plans"][0]["segments"][0]["grip_force"].is_number());
    let mut forces = plan.clone();
    forces["plans"][0]["segments"][2]["grip_force"] = serde_json::json!(120.5);
    forces["plans"][0]["segments"][3]["grip_force"] = serde_json::json!(60.0);
    let errors: Vec<String> = validator
        .iter_errors(&forces)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    for bad in [
        serde_json::json!(-5.0),
        serde_json::json!(0.0),
        serde_json::json!(1e9),
        serde_json::json!("NaN"),
    ] {
        let mut b = plan.clone();
        b["plans"][0]["segments"][2]["grip_force"] = bad.clone();
        assert!(!validator.is_valid(&b), "{bad}");
    }
}
