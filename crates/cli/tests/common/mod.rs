//! Helpers shared by the CLI tests: run the real binary, find the committed examples.
#![allow(dead_code)]

pub mod mutate;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

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
