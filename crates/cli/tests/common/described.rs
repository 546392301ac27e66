//! A scene whose arms come from a robot description in the test's folder, and a run of the
//! binary that cannot hang the suite.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use super::examples_in;

/// The committed robot descriptions.
pub fn data_robots() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots")
}

/// Runs `pregrasp ARGS` in `dir` with the cache in `dir/cache`; a run still going after
/// two minutes is a hang: it is killed and the test fails.
pub fn run(dir: &Path, args: &[&str]) -> Output {
    run_with_cache(dir, &dir.join("cache"), args)
}

/// [`run`] with the cache in `cache`.
pub fn run_with_cache(dir: &Path, cache: &Path, args: &[&str]) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_pregrasp"))
        .current_dir(dir)
        .env("PREGRASP_CACHE_DIR", cache)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let pid = child.id();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || tx.send(child.wait_with_output()));
    match rx.recv_timeout(Duration::from_secs(120)) {
        Ok(out) => out.unwrap(),
        Err(_) => {
            let _ = Command::new("kill").args(["-9", &pid.to_string()]).status();
            panic!("pregrasp {args:?} hangs");
        }
    }
}

/// The chair example in `dir` as `fr3.toml`, its two arms the FR3 of `dir/robot.urdf` (the
/// committed description, written there by `edit`), with the Franka Hand it carries when
/// `hand`. The meshes are found through `dir/franka_description`, a link to the committed
/// package.
pub fn fr3_scene(dir: &Path, hand: bool, edit: impl Fn(&str) -> String) {
    examples_in(dir);
    let fr3 = std::fs::read_to_string(data_robots().join("fr3.urdf")).unwrap();
    std::fs::write(dir.join("robot.urdf"), edit(&fr3)).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(
        data_robots().join("meshes/franka_description"),
        dir.join("franka_description"),
    )
    .unwrap();
    std::fs::write(dir.join("fr3.toml"), fr3_scene_text(dir, hand)).unwrap();
}

/// The text of the chair example in `dir` with the FR3 of `robot.urdf` for its arms, with
/// the Franka Hand when `hand`.
pub fn fr3_scene_text(dir: &Path, hand: bool) -> String {
    let text = std::fs::read_to_string(dir.join("chair_side.toml")).unwrap();
    let mut arm =
        "urdf = \"robot.urdf\"\ntool_link = \"fr3_link8\"\nhold = { fr3_joint3 = 0.0 }".to_string();
    if hand {
        arm.push_str("\ngripper = \"urdf\"");
    }
    let mut out = String::new();
    for line in text.lines() {
        let t = line.trim();
        if t == "model = \"ur5e\"" {
            out.push_str(&arm);
        } else if t.starts_with("start = ") {
            out.push_str("start = [0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]");
        } else if hand
            && ["gripper =", "precision_point_z", "power_point_z"]
                .iter()
                .any(|k| t.starts_with(k))
        {
            continue;
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}
