//! Helpers shared by the CLI tests: run the real binary, find the committed examples.
#![allow(dead_code)]

pub mod described;
pub mod mutate;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

/// Runs `pregrasp ARGS` in `dir` and waits for it.
pub fn pregrasp(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pregrasp"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the binary runs")
}

/// The repository's `examples/` folder.
pub fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Plans the committed chair-side example into `dir/plan.json` (the mesh is found through the
/// plan's `object.mesh`) and asserts that it planned.
pub fn plan_chair_side(dir: &Path) {
    let scene = examples_dir().join("chair_side.toml");
    let out = pregrasp(
        dir,
        &[
            "plan",
            scene.to_str().unwrap(),
            "-o",
            "plan.json",
            "--quiet",
        ],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The plan file with its `timing_ms` removed (the only part that may differ between runs).
pub fn plan_without_timing(path: &Path) -> String {
    let mut value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    value.as_object_mut().unwrap().remove("timing_ms");
    serde_json::to_string_pretty(&value).unwrap()
}

/// What a run wrote on stderr.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The example scenes and meshes copied into `dir` (so a test may write beside them).
pub fn examples_in(dir: &Path) {
    let out = pregrasp(dir, &["example", "write", "."]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// Exit 1 with exactly one `error:` line on stderr that contains `needle`.
pub fn assert_bad_input(out: &Output, needle: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "one error line: {err}");
    assert!(err.contains(needle), "expected {needle:?} in: {err}");
}

/// The files in `dir` (recursively), relative, sorted.
pub fn files_in(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
            }
            out.push(p.strip_prefix(dir).unwrap().display().to_string());
        }
    }
    out.sort();
    out
}

pub fn schema_validator() -> jsonschema::Validator {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/plan.schema.json");
    let schema: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    jsonschema::validator_for(&schema).expect("the schema compiles")
}

pub fn assert_schema_valid(path: &Path) {
    let plan: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let validator = schema_validator();
    let errors: Vec<String> = validator
        .iter_errors(&plan)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{}: {errors:?}", path.display());
}
