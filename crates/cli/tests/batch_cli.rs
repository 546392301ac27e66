//! `pregrasp batch` from the command line.

mod common;

use common::described::run;
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

#[cfg(unix)]
#[test]
fn a_stamp_or_problem_set_that_is_a_fifo_is_not_waited_on() {
    // A batch's stamp (is this scene's plan up to date?) is read before it is written: a FIFO
    // under its name must not block the batch (issue 46: every file a command reads).
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    let ex = pregrasp_examples::by_name("stool_side").unwrap();
    pregrasp_examples::write_example(&scenes, &ex).unwrap();
    let out = run(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let stamp = dir.path().join("out/stool_side.stamp");
    std::fs::remove_file(&stamp).unwrap();
    let fifo = std::process::Command::new("mkfifo").arg(&stamp).status();
    assert!(fifo.unwrap().success());
    // The new stamp is written through the FIFO (outputs are): someone reads it.
    let reader = stamp.clone();
    std::thread::spawn(move || std::fs::read(reader));
    let out = run(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    // `bench reach` reads its problem set only as a regular file.
    let problems = dir.path().join("problems.json");
    let fifo = std::process::Command::new("mkfifo").arg(&problems).status();
    assert!(fifo.unwrap().success());
    let out = run(dir.path(), &["bench", "reach", "problems.json"]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a regular file"));
}
