//! Every command keeps the exit-code contract when the robot description it reads is mutated
//! (issue 46): an attribute made absurd (`nan`, `1e400`, `""`, `0 0 0`, a path to a device…),
//! a line deleted or doubled, a line wrapped in 100 000 elements, the text cut. The scenes
//! are the chair example with two FR3 (the 2F-85, or the Franka Hand the description
//! carries); the plan-reading commands read a plan made with the good description whose
//! description then changed. Never a panic, an abort or a hang; exit 1 prints one `error:`
//! line and writes nothing.
//!
//! `PREGRASP_DESCRIPTION_CASES` sets the number of cases (default 32; docs/hardening.md
//! quotes a longer run).

mod common;

use std::sync::OnceLock;

use common::described::{data_robots, fr3_scene, fr3_scene_text, run_with_cache};
use common::files_in;
use common::mutate::mutate_description;
use proptest::prelude::*;
use proptest::sample::Index;

/// The cache every case shares (entries are keyed by the description's bytes).
fn cache() -> &'static tempfile::TempDir {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| tempfile::tempdir().unwrap())
}

/// The commands, each reading `robot.urdf` through `fr3.toml`, `hand.toml` or `plan.json`.
const COMMANDS: [&str; 10] = [
    "plan fr3.toml -o out.json --quiet",
    "plan hand.toml -o out.json --quiet",
    "axes fr3.toml",
    "robustness fr3.toml --samples 1 --pos-mm 2 --json r.json",
    "check plan.json",
    "physics plan.json",
    "view plan.json -o v.html",
    "export plan.json -f csv,ros2 -o ex",
    "replan plan.json --object-pose 0.6881,0.4466,0.001,0,0,-0.9989,0.0471 -o re.json",
    "batch scenes -o bout",
];

/// A folder with the FR3 scenes, a plan made with the good description, and `robot.urdf`
/// replaced by `description`.
fn case_dir(description: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| t.to_string());
    std::fs::write(
        dir.path().join("hand.toml"),
        fr3_scene_text(dir.path(), true),
    )
    .unwrap();
    let out = run_with_cache(
        dir.path(),
        cache().path(),
        &["plan", "fr3.toml", "-o", "plan.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(0), "the good description plans");
    std::fs::create_dir(dir.path().join("scenes")).unwrap();
    for f in ["fr3.toml", "hand.toml"] {
        let text = std::fs::read_to_string(dir.path().join(f)).unwrap();
        let text = text.replace("urdf = \"robot.urdf\"", "urdf = \"../robot.urdf\"");
        let text = text.replace("mesh = \"meshes/", "mesh = \"../meshes/");
        std::fs::write(dir.path().join("scenes").join(f), text).unwrap();
    }
    std::fs::write(dir.path().join("robot.urdf"), description).unwrap();
    dir
}

fn run_case(command: usize, at: Index, kind: u8, value: Index) {
    let good = std::fs::read_to_string(data_robots().join("fr3.urdf")).unwrap();
    let mutated = mutate_description(&good, at, kind, value);
    let dir = case_dir(&mutated);
    let args: Vec<&str> = COMMANDS[command].split(' ').collect();
    let before = files_in(dir.path());
    let out = run_with_cache(dir.path(), cache().path(), &args);
    let code = out.status.code();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(
        matches!(code, Some(0..=2)),
        "{args:?}: exit {code:?} (a signal: None) {stderr}"
    );
    if code == Some(1) {
        let errors = stderr.lines().filter(|l| l.starts_with("error:")).count();
        assert_eq!(errors, 1, "{args:?}: {stderr}");
        assert_eq!(files_in(dir.path()), before, "{args:?} wrote on bad input");
    }
}

fn cases() -> u32 {
    std::env::var("PREGRASP_DESCRIPTION_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(32)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn every_command_keeps_the_exit_code_contract_on_mutated_descriptions(
        command in 0..COMMANDS.len(),
        at in any::<Index>(), kind in any::<u8>(), value in any::<Index>(),
    ) {
        run_case(command, at, kind, value);
    }
}
