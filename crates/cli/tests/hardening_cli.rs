//! Bad input found by generated inputs (issue 18, findings 5 and 6): refused at once, in words.

mod common;

use common::examples_dir;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A copy of the chair-side scene in `dir` whose mesh entry is `meshes/chair_side.stl`.
fn scene_in(dir: &Path) {
    let text = std::fs::read_to_string(examples_dir().join("chair_side.toml")).unwrap();
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    std::fs::create_dir(dir.join("meshes")).unwrap();
}

#[test]
fn a_mesh_path_that_is_a_fifo_is_refused_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    scene_in(tmp.path());
    let fifo = tmp.path().join("meshes/chair_side.stl");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_pregrasp"))
        .current_dir(tmp.path())
        .args(["plan", "scene.toml", "-o", "plan.json", "--quiet"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if t0.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("plan blocked on a FIFO mesh");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(err.contains("not a regular file"), "{err}");
    assert!(!tmp.path().join("plan.json").exists());
}

#[test]
fn a_nan_coordinate_is_named_in_words() {
    let tmp = tempfile::tempdir().unwrap();
    scene_in(tmp.path());
    let stl = "solid bad\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 nan 0\nendloop\nendfacet\nendsolid bad\n";
    std::fs::write(tmp.path().join("meshes/chair_side.stl"), stl).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_pregrasp"))
        .current_dir(tmp.path())
        .args(["axes", "scene.toml"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("not a finite number"), "{err}");
    assert!(!err.contains("which is"), "{err}");
}

#[test]
fn view_refuses_a_speed_out_of_range() {
    let tmp = tempfile::tempdir().unwrap();
    for speed in ["0", "-1", "1e9", "nan"] {
        let out = Command::new(env!("CARGO_BIN_EXE_pregrasp"))
            .current_dir(tmp.path())
            .args([
                "view",
                "missing.json",
                "-o",
                "page.html",
                &format!("--speed={speed}"),
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "--speed {speed}");
        assert!(err.contains("--speed"), "{err}");
        assert!(!tmp.path().join("page.html").exists());
    }
}

/// Finding 3: command-line mistakes exit 64, never 2 ("no plan") or 1 (bad input); help and
/// version exit 0.
#[test]
fn usage_errors_exit_64_not_2() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_pregrasp"))
            .current_dir(tmp.path())
            .args(args)
            .output()
            .unwrap()
            .status
            .code()
    };
    assert_eq!(run(&["plan"]), Some(64), "missing argument");
    assert_eq!(run(&["frobnicate"]), Some(64), "unknown subcommand");
    assert_eq!(
        run(&[
            "plan",
            "s.toml",
            "-o",
            "p.json",
            "--max-plans",
            "99999999999999999999"
        ]),
        Some(64),
        "number too large"
    );
    assert_eq!(run(&["plan", "s.toml", "--no-such-option"]), Some(64));
    assert_eq!(run(&["--help"]), Some(0));
    assert_eq!(run(&["--version"]), Some(0));
    assert_eq!(run(&["plan", "--help"]), Some(0));
}
