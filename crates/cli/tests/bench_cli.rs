//! `pregrasp bench plan` reports cold (a fresh `pregrasp plan` process per run), warm (runs in
//! one process after a warm-up) and known (the part's knowledge kept between those runs too)
//! side by side (issue 50).

mod common;

use common::{examples_dir, pregrasp};

#[test]
fn bench_plan_reports_cold_processes_and_warm_runs() {
    let dir = tempfile::tempdir().unwrap();
    let scene = examples_dir().join("chair_side.toml");
    let args = [
        "bench",
        "plan",
        scene.to_str().unwrap(),
        "--runs",
        "2",
        "--threads",
        "1",
    ];
    let out = pregrasp(dir.path(), &[&args[..], &["--json"]].concat());
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["status"], "planned");
    let ms = |v: &serde_json::Value| v["median_ms"].as_f64().unwrap();
    let (process, cold_total) = (
        ms(&report["cold"]["process"]),
        ms(&report["cold"]["stages"]["total"]),
    );
    let warm_total = ms(&report["stages"]["total"]);
    let known_total = ms(&report["known"]["stages"]["total"]);
    // The whole process holds the plan it times; every stage took some time.
    assert!(process > cold_total && cold_total > 0.0, "{report}");
    assert!(warm_total > 0.0 && known_total > 0.0, "{report}");
    for stage in ["axes", "grips", "poses", "paths", "total"] {
        assert!(
            ms(&report["cold"]["stages"][stage]) > 0.0,
            "{stage}: {report}"
        );
    }
    // The text form puts both side by side; the runs leave no plan file behind.
    let text = pregrasp(dir.path(), &args);
    let stdout = String::from_utf8_lossy(&text.stdout);
    assert!(
        stdout.contains("cold median / p95")
            && stdout.contains("known median / p95")
            && stdout.contains("process"),
        "{stdout}"
    );
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
}
