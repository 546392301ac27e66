//! Golden answers: the plan files of the three committed examples (five plans each, timings
//! aside) and a checksum of the reach benchmark, compared with the files under `tests/golden/`.
//! Every change that must not change answers (a refactor, a faster check) is proven to give
//! the same ones; a change that means to change them rewrites the files (`PREGRASP_BLESS=1
//! cargo test -p pregrasp-planner --test golden`) and says why in its commit.

mod common;

use common::scenes::example_files;
use std::path::{Path, PathBuf};

use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_reach::{run_reach, ReachProblemSet, ReachSettings};

fn golden(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(name)
}

/// Compares `text` with the golden file `name`, or writes it when blessing.
fn compare(name: &str, text: &str) {
    let path = golden(name);
    if std::env::var_os("PREGRASP_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (PREGRASP_BLESS=1 writes it)", path.display()));
    if want != text {
        let line = want
            .lines()
            .zip(text.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(want.lines().count().min(text.lines().count()));
        panic!(
            "{name} differs from its golden file at line {}:\n  golden: {}\n  now:    {}",
            line + 1,
            want.lines().nth(line).unwrap_or("<end>"),
            text.lines().nth(line).unwrap_or("<end>")
        );
    }
}

#[test]
fn the_examples_plan_as_their_golden_files() {
    let options = PlanOptions {
        max_plans: 5,
        ..PlanOptions::default()
    };
    // The committed scene and mesh files, as `pregrasp plan examples/<name>.toml` run from the
    // repository's root reads them (paths in the plan file relative to it).
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let (scene, mesh) = example_files(name);
        let report =
            pregrasp_planner::plan_scene(&scene, &mesh, &options, &|_| {}, &|| {}).unwrap();
        let mut file = report.file;
        file.timing_ms.clear();
        compare(&format!("{name}.json"), &file.to_json());
    }
}

#[test]
fn the_reach_benchmark_gives_its_golden_paths() {
    let set = ReachProblemSet::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/reach-ur5-table-boxes.json"),
    )
    .unwrap();
    let mut settings = ReachSettings::default();
    // Iterations only: a wall-clock limit would make the answers depend on the machine.
    settings.rrt.max_time = None;
    let report = run_reach(&set, &settings);
    let length: f64 = report.outcomes.iter().map(|o| o.length).sum();
    let states: u64 = report.outcomes.iter().map(|o| o.states_checked).sum();
    let waypoints: usize = report.outcomes.iter().map(|o| o.waypoints).sum();
    let text = format!(
        "queries {}\nsolved {}\nlength_sum {length:.6}\nstates_checked {states}\nwaypoints {waypoints}\n",
        report.queries, report.solved
    );
    compare("reach-ur5-table-boxes.txt", &text);
}
