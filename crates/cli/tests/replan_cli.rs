//! `pregrasp replan` and `pregrasp robustness` from the command line.

mod common;

use common::{examples_dir, plan_chair_side, pregrasp};

/// The plan's object pose moved by (`dx`, `dy`) on the table, as `--object-pose` takes it.
fn shifted_pose(plan: &serde_json::Value, dx: f64, dy: f64) -> String {
    let p = &plan["object"]["initial_pose"];
    let (xyz, q) = (&p["xyz"], &p["quat_xyzw"]);
    format!(
        "{} {} 0 {} {} {} {}",
        xyz[0].as_f64().unwrap() + dx,
        xyz[1].as_f64().unwrap() + dy,
        q[0],
        q[1],
        q[2],
        q[3]
    )
}

#[test]
fn replan_writes_a_plan_that_passes_check() {
    let dir = tempfile::tempdir().unwrap();
    plan_chair_side(dir.path());
    let plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("plan.json")).unwrap()).unwrap();
    let pose = shifted_pose(&plan, 0.004, -0.002);
    let out = pregrasp(
        dir.path(),
        &[
            "replan",
            "plan.json",
            "--object-pose",
            &pose,
            "-o",
            "new.json",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("kept the plan's rotation axis"));
    let check = pregrasp(dir.path(), &["check", "new.json"]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");

    // sup1 has run: keep it, plan the rest from where the arms stand.
    let out = pregrasp(
        dir.path(),
        &[
            "replan",
            "plan.json",
            "--object-pose",
            &pose,
            "--from",
            "rot",
            "-o",
            "rest.json",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let rest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("rest.json")).unwrap()).unwrap();
    assert_eq!(
        rest["plans"][0]["segments"][0],
        plan["plans"][0]["segments"][0]
    );
    let check = pregrasp(dir.path(), &["check", "rest.json"]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
}

#[test]
fn a_bad_pose_is_bad_input_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    plan_chair_side(dir.path());
    for pose in [
        "1 2 3",
        "0 0 0 0 0 0 0",
        "0 0 0 0 0 0 nan",
        "1e9 0 0 0 0 0 1",
        "a b c d e f g",
    ] {
        let out = pregrasp(
            dir.path(),
            &[
                "replan",
                "plan.json",
                "--object-pose",
                pose,
                "-o",
                "new.json",
            ],
        );
        assert_eq!(out.status.code(), Some(1), "{pose}: {out:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--object-pose"),
            "{pose}"
        );
        assert!(!dir.path().join("new.json").exists(), "{pose}");
    }
}

#[test]
fn robustness_options_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let scene = examples_dir().join("chair_side.toml");
    let scene = scene.to_str().unwrap();
    let out = pregrasp(dir.path(), &["robustness", scene, "--samples", "0"]);
    assert_eq!(out.status.code(), Some(64), "{out:?}");
    let out = pregrasp(dir.path(), &["robustness", scene, "--pos-mm=-1"]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let out = pregrasp(
        dir.path(),
        &[
            "robustness",
            scene,
            "--samples",
            "2",
            "--pos-mm",
            "3",
            "--json",
            "r.json",
            "--svg",
            "r.svg",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("r.json")).unwrap()).unwrap();
    assert_eq!(report["samples"].as_array().unwrap().len(), 2);
    let chart = std::fs::read_to_string(dir.path().join("r.svg")).unwrap();
    assert!(
        chart.starts_with("<svg") && chart.contains("±3 mm"),
        "{chart}"
    );
}

/// An auto-grasp scene: `replan` and `robustness` follow the grasps its search chose.
#[test]
fn replan_follows_the_grasps_an_auto_scene_chose() {
    let dir = tempfile::tempdir().unwrap();
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    pregrasp_examples::write_example(dir.path(), &ex).unwrap();
    let text = ex.scene_toml.clone();
    let start = text.find("[grasps]").unwrap();
    let end = start + 1 + text[start + 1..].find("\n[").unwrap();
    let auto = format!(
        "{}[grasps]\nmode = \"auto\"\n{}",
        &text[..start],
        &text[end..]
    );
    std::fs::write(dir.path().join("chair_side.toml"), auto).unwrap();
    let out = pregrasp(
        dir.path(),
        &["plan", "chair_side.toml", "-o", "plan.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("plan.json")).unwrap()).unwrap();
    let pose = shifted_pose(&plan, 0.003, 0.0);
    let out = pregrasp(
        dir.path(),
        &[
            "replan",
            "plan.json",
            "--object-pose",
            &pose,
            "-o",
            "new.json",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let new: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("new.json")).unwrap()).unwrap();
    assert_eq!(new["grasps"]["support"], plan["grasps"]["support"]);
    assert_eq!(new["grasps"]["power"], plan["grasps"]["power"]);
    let check = pregrasp(dir.path(), &["check", "new.json"]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
}

/// The plan's own `object.initial_pose` (the part raised by the 1 mm lift) as the measurement:
/// brought back onto the table and planned, where taken as measured it fails (the part would
/// hang 1 mm above the table).
#[test]
fn a_measured_pose_is_brought_onto_the_support_first() {
    let dir = tempfile::tempdir().unwrap();
    plan_chair_side(dir.path());
    let plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("plan.json")).unwrap()).unwrap();
    let pose = shifted_pose(&plan, 0.0, 0.0).replacen(" 0 ", " 0.001 ", 1);
    let run = |extra: &[&str]| {
        let mut args = vec![
            "replan",
            "plan.json",
            "--object-pose",
            &pose,
            "-o",
            "re.json",
        ];
        args.extend_from_slice(extra);
        pregrasp(dir.path(), &args)
    };
    let out = run(&[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("moved 1.00 mm, turned 0.00°"), "{stdout}");
    let out = run(&["--as-measured"]);
    assert_eq!(out.status.code(), Some(2));
    // 3 cm above the table is no measurement error.
    let high = shifted_pose(&plan, 0.0, 0.0).replacen(" 0 ", " 0.03 ", 1);
    let out = pregrasp(
        dir.path(),
        &[
            "replan",
            "plan.json",
            "--object-pose",
            &high,
            "-o",
            "re2.json",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("check the measurement"), "{err}");
    assert!(!dir.path().join("re2.json").exists());
}

#[test]
fn bench_replan_replans_near_the_pose_and_reports_the_time() {
    let dir = tempfile::tempdir().unwrap();
    let scene = examples_dir().join("chair_side.toml");
    let out = pregrasp(
        dir.path(),
        &[
            "bench",
            "replan",
            scene.to_str().unwrap(),
            "--samples",
            "3",
            "--threads",
            "1",
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(
        stdout.contains("3 placements") && stdout.contains("3 planned, 3 kept the plan's axis"),
        "{stdout}"
    );
    let bad = pregrasp(
        dir.path(),
        &["bench", "replan", scene.to_str().unwrap(), "--pos-mm=-1"],
    );
    assert_eq!(bad.status.code(), Some(1), "{bad:?}");
}
