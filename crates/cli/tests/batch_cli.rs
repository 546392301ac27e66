//! `pregrasp batch` from the command line.

mod common;

use common::pregrasp;

#[test]
fn batch_writes_the_report_and_refuses_a_missing_folder() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    let ex = pregrasp_examples::by_name("stool_side").unwrap();
    pregrasp_examples::write_example(&scenes, &ex).unwrap();
    std::fs::write(scenes.join("broken.toml"), "not toml [").unwrap();
    let out = pregrasp(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    for f in [
        "summary.csv",
        "summary.json",
        "report.html",
        "stool_side.plan.json",
        "stool_side.html",
    ] {
        assert!(dir.path().join("out").join(f).is_file(), "{f}");
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("2 scenes: 1 planned, 0 no plan, 1 errors"),
        "{stdout}"
    );
    let missing = pregrasp(dir.path(), &["batch", "nowhere", "-o", "out2"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("nowhere"));
}
