//! What the commands may and may not do to files (issue 33): never a device replaced by a file,
//! every output written or none, no output over an input, batch outputs that never collide.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_bad_input, examples_in, files_in, plan_chair_side, pregrasp, stderr};
use serde_json::Value;

/// A character device of our own (root: `mknod`), else `/dev/null` itself — which a process
/// that is not root could not replace anyway.
fn char_device(dir: &Path) -> PathBuf {
    let own = dir.join("null");
    let made = std::process::Command::new("mknod")
        .args([own.to_str().unwrap(), "c", "1", "3"])
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if made {
        own
    } else {
        PathBuf::from("/dev/null")
    }
}

fn is_char_device(path: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::metadata(path)
        .map(|m| m.file_type().is_char_device())
        .unwrap_or(false)
}

#[test]
fn output_to_a_character_device_leaves_it_a_device() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let dev = char_device(dir.path());
    let d = dev.to_str().unwrap();
    plan_chair_side(dir.path());
    let runs: [&[&str]; 5] = [
        &["plan", "chair_side.toml", "-o", d, "--html", d, "--quiet"],
        &["view", "plan.json", "-o", d],
        &[
            "robustness",
            "chair_side.toml",
            "--samples",
            "1",
            "--pos-mm",
            "2",
            "--json",
            d,
            "--svg",
            d,
            "--write-plan",
            d,
        ],
        &[
            "replan",
            "plan.json",
            "--scene",
            "chair_side.toml",
            "--object-pose",
            "0.6881 0.4466 0.001 0 0 -0.9989 0.0471",
            "-o",
            d,
        ],
        &["demo", "--dir", "demo", "-o", d, "--html", d, "--quiet"],
    ];
    for args in runs {
        let out = pregrasp(dir.path(), args);
        assert!(
            matches!(out.status.code(), Some(0 | 2)),
            "{args:?}: {}",
            stderr(&out)
        );
        assert!(is_char_device(&dev), "{args:?} replaced the device");
    }
}

#[test]
fn a_fifo_output_is_written_through() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let fifo = dir.path().join("pipe");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let out = pregrasp(
        dir.path(),
        &["plan", "chair_side.toml", "-o", "pipe", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let bytes = reader.join().unwrap();
    let plan: Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(plan["status"], "planned");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
}

#[test]
fn robustness_writes_all_its_outputs_or_none() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    std::fs::create_dir(dir.path().join("out")).unwrap();
    let before = files_in(dir.path());
    // One placement sample: the outputs are what is looked at.
    let robustness = |outputs: &[&str]| {
        let mut args = vec![
            "robustness",
            "chair_side.toml",
            "--samples",
            "1",
            "--pos-mm",
            "2",
        ];
        args.extend_from_slice(outputs);
        pregrasp(dir.path(), &args)
    };
    // The JSON's folder does not exist: refused before planning, the SVG is not written.
    let out = robustness(&["--svg", "out/r.svg", "--json", "missing/r.json"]);
    assert_bad_input(&out, "missing/r.json");
    assert_eq!(files_in(dir.path()), before);
    // A folder in the way of the plan: the same.
    std::fs::create_dir(dir.path().join("out/plan.json")).unwrap();
    let before = files_in(dir.path());
    let out = robustness(&["--svg", "out/r.svg", "--write-plan", "out/plan.json"]);
    assert_bad_input(&out, "is a folder");
    assert_eq!(files_in(dir.path()), before);
}

#[test]
fn an_output_over_an_input_or_two_outputs_on_one_path_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let scene = std::fs::read(dir.path().join("chair_side.toml")).unwrap();
    let out = pregrasp(
        dir.path(),
        &["robustness", "chair_side.toml", "--json", "chair_side.toml"],
    );
    assert_bad_input(&out, "input of this command (the scene)");
    let out = pregrasp(
        dir.path(),
        &["plan", "chair_side.toml", "-o", "./meshes/chair_side.stl"],
    );
    assert_bad_input(&out, "input of this command (the mesh)");
    assert_eq!(
        std::fs::read(dir.path().join("chair_side.toml")).unwrap(),
        scene
    );
    let out = pregrasp(
        dir.path(),
        &[
            "robustness",
            "chair_side.toml",
            "--json",
            "r.out",
            "--svg",
            "./r.out",
        ],
    );
    assert_bad_input(&out, "given for two outputs");
    let out = pregrasp(
        dir.path(),
        &[
            "plan",
            "chair_side.toml",
            "-o",
            "p.json",
            "--html",
            "p.json",
        ],
    );
    assert_bad_input(&out, "given for two outputs");
    assert!(!dir.path().join("r.out").exists() && !dir.path().join("p.json").exists());
}

#[test]
fn batch_writes_nothing_when_its_summary_cannot_be_written() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    examples_in(&scenes);
    std::fs::create_dir_all(dir.path().join("out/summary.json")).unwrap();
    let before = files_in(dir.path());
    let out = pregrasp(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_bad_input(&out, "summary.json: is a folder");
    assert_eq!(files_in(dir.path()), before);
    // The scene folder itself as the output folder: refused in words.
    let out = pregrasp(dir.path(), &["batch", "scenes", "-o", "scenes"]);
    assert_bad_input(&out, "the output folder is the scene folder itself");
}

#[test]
fn batch_output_names_never_collide() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    examples_in(&scenes);
    let stool = std::fs::read_to_string(scenes.join("stool_side.toml")).unwrap();
    for name in ["report.toml", "x.toml", "x.plan.toml"] {
        std::fs::write(scenes.join(name), &stool).unwrap();
    }
    let out = pregrasp(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let o = dir.path().join("out");
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(o.join("summary.json")).unwrap()).unwrap();
    let rows = summary["scenes"].as_array().unwrap();
    let row = |name: &str| rows.iter().find(|r| r["scene"] == name).unwrap().clone();
    assert_eq!(row("report.toml")["status"], "error");
    assert!(row("report.toml")["reason"]
        .as_str()
        .unwrap()
        .contains("rename the scene"));
    // The report page is the batch's, and x / x.plan keep their own files.
    assert!(std::fs::read_to_string(o.join("report.html"))
        .unwrap()
        .contains("pregrasp batch"));
    for f in ["x.plan.json", "x.html", "x.plan.plan.json", "x.plan.html"] {
        assert!(o.join(f).is_file(), "{f}");
    }
    let x: Value =
        serde_json::from_str(&std::fs::read_to_string(o.join("x.plan.json")).unwrap()).unwrap();
    let xp: Value =
        serde_json::from_str(&std::fs::read_to_string(o.join("x.plan.plan.json")).unwrap())
            .unwrap();
    assert!(x["scene"]["file"].as_str().unwrap().ends_with("x.toml"));
    assert!(xp["scene"]["file"]
        .as_str()
        .unwrap()
        .ends_with("x.plan.toml"));
}

#[test]
fn batch_lists_links_pipes_and_clips_long_reasons() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    examples_in(&scenes);
    std::os::unix::fs::symlink("stool_side.toml", scenes.join("link.toml")).unwrap();
    assert!(std::process::Command::new("mkfifo")
        .arg(scenes.join("pipe.toml"))
        .status()
        .unwrap()
        .success());
    std::fs::write(scenes.join("long.toml"), "a".repeat(200_000)).unwrap();
    let out = pregrasp(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let rows = summary["scenes"].as_array().unwrap();
    let row = |name: &str| rows.iter().find(|r| r["scene"] == name).unwrap().clone();
    assert_eq!(row("link.toml")["status"], "planned");
    assert_eq!(row("pipe.toml")["status"], "error");
    assert!(row("pipe.toml")["reason"]
        .as_str()
        .unwrap()
        .contains("not a regular file"));
    let long = row("long.toml")["reason"].as_str().unwrap().to_string();
    assert!(
        long.chars().count() <= pregrasp_batch::MAX_REASON + 40,
        "{}",
        long.len()
    );
}
