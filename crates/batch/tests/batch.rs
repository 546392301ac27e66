//! `pregrasp batch` as a library: the examples plus a broken scene, the summary files, reuse
//! of up-to-date plans, re-planning after a change, the same records for any thread count.

use pregrasp_batch::SceneStatus;
use std::path::Path;

use pregrasp_batch::report::{self, Counts};
use pregrasp_batch::{discover, run, Record};
use pregrasp_planner::pipeline::PlanOptions;

fn folder(dir: &Path) {
    for ex in pregrasp_examples::all() {
        pregrasp_examples::write_example(dir, &ex).unwrap();
    }
    std::fs::write(
        dir.join("broken.toml"),
        "name = \"broken\"\n[support]\nheight = \"high\"\n",
    )
    .unwrap();
}

/// The columns that do not depend on timing or on reuse.
fn stable(records: &[Record]) -> Vec<(String, SceneStatus, Option<f64>, usize, String)> {
    records
        .iter()
        .map(|r| {
            (
                r.scene.clone(),
                r.status,
                r.best_score,
                r.plans,
                r.check.clone(),
            )
        })
        .collect()
}

#[test]
fn a_folder_with_a_broken_scene() {
    let dir = tempfile::tempdir().unwrap();
    folder(dir.path());
    let out = dir.path().join("out");
    let scenes = discover(dir.path(), Some(&out)).unwrap();
    assert_eq!(scenes.len(), 4);
    let options = PlanOptions::default();
    let first = run(dir.path(), &out, &scenes, &options, &|_| {}).unwrap();
    let c = Counts::of(&first);
    assert_eq!((c.scenes, c.planned, c.no_plan, c.error), (4, 3, 0, 1));
    let broken = first.iter().find(|r| r.scene == "broken.toml").unwrap();
    assert_eq!(broken.status, SceneStatus::Error);
    assert!(broken.reason.as_deref().unwrap().contains("support.height"));
    for r in first.iter().filter(|r| r.status == SceneStatus::Planned) {
        assert_eq!(r.check, "valid", "{}", r.scene);
        assert!(out.join(r.plan_file.as_ref().unwrap()).is_file());
        assert!(out.join(r.view_file.as_ref().unwrap()).is_file());
        assert!(!r.reused);
    }

    report::write(&out, &first, "test").unwrap();
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "header + 4 rows");
    assert!(csv
        .lines()
        .next()
        .unwrap()
        .starts_with("scene,status,reason"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["counts"]["planned"], 3);
    assert_eq!(json["scenes"].as_array().unwrap().len(), 4);
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("href=\"chair_side.html\"") && html.contains("1 errors"));

    // Rerun: everything up to date is reused, with the same outcome.
    let again = run(dir.path(), &out, &scenes, &options, &|_| {}).unwrap();
    assert_eq!(stable(&again), stable(&first));
    assert_eq!(Counts::of(&again).reused, 3);

    // A changed scene is planned again; the others are still reused.
    let chair = dir.path().join("chair_side.toml");
    let text = std::fs::read_to_string(&chair).unwrap();
    std::fs::write(&chair, format!("{text}\n# edited\n")).unwrap();
    let third = run(dir.path(), &out, &scenes, &options, &|_| {}).unwrap();
    let replanned: Vec<&str> = third
        .iter()
        .filter(|r| r.status == SceneStatus::Planned && !r.reused)
        .map(|r| r.scene.as_str())
        .collect();
    assert_eq!(replanned, ["chair_side.toml"]);
    assert_eq!(stable(&third), stable(&first));
}

#[test]
fn the_records_do_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    folder(dir.path());
    let scenes = discover(dir.path(), None).unwrap();
    let go = |threads: usize, out: &str| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                run(
                    dir.path(),
                    &dir.path().join(out),
                    &scenes,
                    &PlanOptions::default(),
                    &|_| {},
                )
                .unwrap()
            })
    };
    let (a, b) = (go(1, "one"), go(2, "two"));
    assert_eq!(stable(&a), stable(&b));
    for r in a.iter().filter(|r| r.status == SceneStatus::Planned) {
        let read = |out: &str| {
            std::fs::read(dir.path().join(out).join(r.plan_file.as_ref().unwrap())).unwrap()
        };
        let (x, y) = (read("one"), read("two"));
        // Byte for byte but the measured times.
        let strip = |b: Vec<u8>| {
            let mut v: serde_json::Value = serde_json::from_slice(&b).unwrap();
            v["timing_ms"] = serde_json::Value::Null;
            v
        };
        assert_eq!(strip(x), strip(y), "{}", r.scene);
    }
}

#[test]
fn a_folder_without_scenes_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    assert!(discover(dir.path(), None).is_err());
    assert!(discover(&dir.path().join("missing"), None).is_err());
}
