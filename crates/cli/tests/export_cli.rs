//! `pregrasp export` as the real binary: writes every format from a planned example, refuses
//! a plan-less file, an out-of-range --plan and an unknown --format with exit 1, writing nothing.

mod common;

use common::{plan_chair_side, pregrasp};

use std::path::Path;

/// A temporary directory with `plan.json` planned from the chair side (its mesh is found
/// through the plan's absolute `object.mesh`).
fn planned() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    plan_chair_side(tmp.path());
    tmp
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = match std::fs::read_dir(dir) {
        Ok(rd) => rd
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    v.sort();
    v
}

#[test]
fn export_all_writes_every_format() {
    let tmp = planned();
    let out = pregrasp(
        tmp.path(),
        &["export", "plan.json", "--format", "all", "-o", "cell"],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let files = entries(&tmp.path().join("cell"));
    for want in [
        "left.script",
        "right.script",
        "left.csv",
        "right.csv",
        "plan.glb",
    ] {
        assert!(files.contains(&want.to_string()), "{want} in {files:?}");
    }
    assert!(files.iter().any(|f| f.ends_with("_rot.yaml")), "{files:?}");
    assert!(
        files.iter().all(|f| !f.starts_with('.')),
        "no temporary files: {files:?}"
    );
    // The same command again gives the same bytes.
    let again = pregrasp(tmp.path(), &["export", "plan.json", "-o", "cell2"]);
    assert_eq!(again.status.code(), Some(0));
    for f in &files {
        assert_eq!(
            std::fs::read(tmp.path().join("cell").join(f)).unwrap(),
            std::fs::read(tmp.path().join("cell2").join(f)).unwrap(),
            "{f}"
        );
    }
    // --sync-io reaches the scripts.
    let io = pregrasp(
        tmp.path(),
        &[
            "export",
            "plan.json",
            "-f",
            "urscript",
            "-o",
            "io",
            "--sync-io",
            "2,6",
        ],
    );
    assert_eq!(io.status.code(), Some(0));
    let s = std::fs::read_to_string(tmp.path().join("io/left.script")).unwrap();
    assert!(s.contains("PG_SYNC_OUT = 2\n") && s.contains("PG_SYNC_IN = 6\n"));
}

#[test]
fn bad_requests_exit_1_with_a_message_and_write_nothing() {
    let tmp = planned();
    let dir = tmp.path();
    let mut no_plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("plan.json")).unwrap()).unwrap();
    no_plan["status"] = "no_plan".into();
    no_plan["reason"] = "no rotation axis candidate".into();
    no_plan["plans"] = serde_json::json!([]);
    std::fs::write(
        dir.join("none.json"),
        serde_json::to_string_pretty(&no_plan).unwrap(),
    )
    .unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["export", "none.json", "-o", "x"], "no_plan"),
        (
            &["export", "plan.json", "--plan", "99", "-o", "x"],
            "out of range",
        ),
        (
            &["export", "plan.json", "--format", "pdf", "-o", "x"],
            "unknown export format",
        ),
        (
            &["export", "plan.json", "--sync-io", "1", "-o", "x"],
            "--sync-io",
        ),
        (
            &["export", "plan.json", "--mesh", "missing.stl", "-o", "x"],
            "missing.stl",
        ),
    ];
    for (args, needle) in cases {
        let out = pregrasp(dir, args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(
            entries(&dir.join("x")).is_empty(),
            "{args:?} wrote something"
        );
    }
}
