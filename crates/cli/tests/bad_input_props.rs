//! Generated bad input (issue 18): mutated scenes and plan files never panic the libraries,
//! are answered with the documented error, and through the binary exit 0, 1 or 2 — with
//! nothing written when the answer is "bad input".

mod common;

use std::path::Path;
use std::sync::OnceLock;

use common::mutate::{mutate_plan, mutate_scene};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use proptest::prelude::*;
use proptest::sample::Index;
use serde_json::Value;

fn chair_scene() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| pregrasp_examples::by_name("chair_side").unwrap().scene_toml)
}

fn chair_plan() -> &'static (Value, pregrasp_examples::Mesh) {
    static PLAN: OnceLock<(Value, pregrasp_examples::Mesh)> = OnceLock::new();
    PLAN.get_or_init(|| {
        let ex = pregrasp_examples::by_name("chair_side").unwrap();
        let scene = Scene::from_str(&ex.scene_toml, Path::new("examples/chair_side.toml")).unwrap();
        let options = pregrasp_planner::pipeline::PlanOptions {
            max_plans: 1,
            ..Default::default()
        };
        let file = pregrasp_planner::pipeline::plan(&scene, &ex.mesh, &options, &|_| {}, &|| {})
            .unwrap()
            .file;
        (serde_json::from_str(&file.to_json()).unwrap(), ex.mesh)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// The scene loader answers any mutated scene with a scene or one error naming the file.
    #[test]
    fn mutated_scenes_are_loaded_or_refused_by_name(
        line in any::<Index>(), kind in any::<u8>(), value in any::<Index>(), cut in any::<Index>()
    ) {
        let text = mutate_scene(chair_scene(), line, kind, value, cut);
        match Scene::from_str(&text, Path::new("mutated.toml")) {
            Ok(scene) => {
                prop_assert!(scene.support_height.is_finite());
                prop_assert!(scene.robots.iter().all(|r| r.start.iter().all(|q| q.is_finite() && q.abs() <= 7.0)));
            }
            Err(e) => prop_assert!(e.to_string().starts_with("mutated.toml"), "{e}"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// A mutated plan file is refused when read, refused by the format check with the path of
    /// a field, or judged by `check` — never a panic, never an endless check.
    #[test]
    fn mutated_plans_are_refused_or_judged(
        leaf in any::<Index>(), kind in any::<u8>(), value in any::<Index>()
    ) {
        let (plan, mesh) = chair_plan();
        let text = mutate_plan(plan, leaf, kind, value);
        if let Ok(file) = PlanFile::from_json_str(&text, "mutated.json") {
            let report = check_plan(&file, mesh);
            if let Some(m) = &report.malformed {
                prop_assert!(!m.is_empty());
                prop_assert!(!report.is_valid());
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Through the binary: exit 0 (planned), 2 (no plan) or 1 (bad input, with one `error:`
    /// line and no plan file written).
    #[test]
    fn the_binary_answers_mutated_scenes_with_a_documented_code(
        line in any::<Index>(), kind in any::<u8>(), value in any::<Index>(), cut in any::<Index>()
    ) {
        let dir = tempfile::tempdir().unwrap();
        let ex = pregrasp_examples::by_name("chair_side").unwrap();
        pregrasp_examples::write_example(dir.path(), &ex).unwrap();
        let text = mutate_scene(&ex.scene_toml, line, kind, value, cut);
        std::fs::write(dir.path().join("chair_side.toml"), &text).unwrap();
        let out = common::pregrasp(dir.path(), &["plan", "chair_side.toml", "-o", "out.json", "--quiet"]);
        let code = out.status.code();
        prop_assert!(matches!(code, Some(0..=2)), "{code:?}");
        let written = dir.path().join("out.json").exists();
        if code == Some(1) {
            prop_assert!(!written, "bad input left a plan file");
            let stderr = String::from_utf8_lossy(&out.stderr);
            prop_assert_eq!(stderr.lines().filter(|l| l.starts_with("error:")).count(), 1, "{}", stderr);
        } else {
            prop_assert!(written);
        }
    }
}

/// Finding 4 of issue 18: start values of 1e308 / -1e30 are bad input (exit 1, naming the
/// robot and the joint), for `plan` and for `axes`, not "no plan" or success.
#[test]
fn finding_4_absurd_start_values_are_bad_input_naming_robot_and_joint() {
    for value in ["1e308", "-1e30"] {
        let dir = tempfile::tempdir().unwrap();
        let ex = pregrasp_examples::by_name("chair_side").unwrap();
        pregrasp_examples::write_example(dir.path(), &ex).unwrap();
        let start = ex
            .scene_toml
            .lines()
            .find(|l| l.trim_start().starts_with("start"))
            .unwrap()
            .to_string();
        let key = start.split('=').next().unwrap().trim().to_string();
        let bad = format!("{key} = [{value}, -1.8, 1.8, -1.5708, -1.5708, 0.0]");
        let text = ex.scene_toml.replacen(&start, &bad, 1);
        std::fs::write(dir.path().join("chair_side.toml"), text).unwrap();
        for cmd in [
            &["plan", "chair_side.toml", "-o", "out.json"][..],
            &["axes", "chair_side.toml"][..],
        ] {
            let out = common::pregrasp(dir.path(), cmd);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{value} {cmd:?}: {stderr}");
            assert!(
                stderr.contains("robot[0]") && stderr.contains(&key),
                "{stderr}"
            );
            assert!(!dir.path().join("out.json").exists());
        }
    }
}
