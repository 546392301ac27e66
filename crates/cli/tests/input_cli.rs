//! Bad input is refused before any work: a start configuration beyond the joint limits exits 1
//! naming the robot and the joint, and writes nothing. `kin fk` / `kin ik` take numbers as
//! Python or a UR controller log prints them, negative exponents included, without `--`.

mod common;

use common::{examples_dir, pregrasp};

use std::path::Path;

/// The chair-side example in `dir` (scene + mesh) with the right arm's start line replaced.
fn chair_with_right_start(dir: &Path, start: &str) {
    let scene = std::fs::read_to_string(examples_dir().join("chair_side.toml")).unwrap();
    let right = scene.find("name = \"right\"").expect("right arm");
    let line = right + scene[right..].find("start = [").unwrap();
    let end = line + scene[line..].find('\n').unwrap();
    let scene = format!("{}{start}{}", &scene[..line], &scene[end..]);
    std::fs::create_dir(dir.join("meshes")).unwrap();
    std::fs::copy(
        examples_dir().join("meshes/chair_side.stl"),
        dir.join("meshes/chair_side.stl"),
    )
    .unwrap();
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
}

#[test]
fn plan_refuses_a_start_beyond_the_joint_limits_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    chair_with_right_start(
        tmp.path(),
        "start = [9.5, -1.8000, 1.8000, -1.5708, -1.5708, 0.0000]",
    );
    let out = pregrasp(
        tmp.path(),
        &[
            "plan",
            "scene.toml",
            "-o",
            "plan.json",
            "--html",
            "plan.html",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "scene.toml: robot[1].start[0]: 9.5 rad is outside the ur5e joint limits \
             [-6.283, 6.283] (shoulder_pan of robot \"right\")"
        ),
        "{err}"
    );
    let mut left: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["meshes", "scene.toml"], "no plan, page or temp file");
    // `axes` refuses the same scene the same way.
    let out = pregrasp(tmp.path(), &["axes", "scene.toml"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("shoulder_pan of robot \"right\""));
}

#[test]
fn plan_refuses_an_elbow_beyond_pi_in_degrees() {
    let tmp = tempfile::tempdir().unwrap();
    chair_with_right_start(tmp.path(), "start_deg = [180, -103, 190, -90, -90, 0]");
    let out = pregrasp(tmp.path(), &["plan", "scene.toml", "-o", "plan.json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("robot[1].start_deg[2]: 190")
            && err.contains("outside the ur5e joint limits [-180, 180]°")
            && err.contains("(elbow of robot \"right\")"),
        "{err}"
    );
    assert!(!tmp.path().join("plan.json").exists());
}

/// `kin fk ARGS --json`: the joint vector as parsed and the flange position.
fn fk_json(args: &[&str]) -> serde_json::Value {
    let tmp = tempfile::tempdir().unwrap();
    let mut all = vec!["kin", "fk", "--json"];
    all.extend_from_slice(args);
    let out = pregrasp(tmp.path(), &all);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn kin_fk_takes_negative_numbers_in_exponent_form() {
    let q = [
        "-3.3e-05",
        "-1.5707963267948966",
        "1.5707963267948966",
        "-1.5707963267948966",
        "-1.5707963267948966",
        "1e-05",
    ];
    let want: Vec<f64> = q.iter().map(|s| s.parse().unwrap()).collect();
    let plain = fk_json(&q);
    assert_eq!(plain["q"], serde_json::json!(want));
    // The same with `--` (which always worked), with upper-case and signed exponents, and as a
    // Python list pasted whole.
    let mut dashed = vec!["--"];
    dashed.extend_from_slice(&q);
    assert_eq!(fk_json(&dashed), plain);
    let other_spellings = [
        "-3.3E-05",
        "-1.5707963267948966e+00",
        "+1.5707963267948966",
        "-15.707963267948966e-1",
        "-1.5707963267948966",
        "1E-5",
    ];
    assert_eq!(fk_json(&other_spellings), plain);
    let python_list = [
        "[-3.3e-05,",
        "-1.5707963267948966,",
        "1.5707963267948966,",
        "-1.5707963267948966,",
        "-1.5707963267948966,",
        "1e-05]",
    ];
    assert_eq!(fk_json(&python_list), plain);
    // `--json` after the numbers is still the flag.
    let tmp = tempfile::tempdir().unwrap();
    let mut after = vec!["kin", "fk"];
    after.extend_from_slice(&q);
    after.push("--json");
    let out = pregrasp(tmp.path(), &after);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap(),
        plain
    );
}

#[test]
fn kin_ik_takes_pose_and_seed_in_exponent_form_and_inverts_fk() {
    let q = [0.4, -1.2, 1.1, -1.3, -1.6, 2.5e-05];
    let fk = fk_json(
        &q.map(|v| format!("{v:e}"))
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    let mut pose: Vec<String> = fk["xyz"]
        .as_array()
        .unwrap()
        .iter()
        .chain(fk["quat_xyzw"].as_array().unwrap())
        .map(|v| format!("{:e}", v.as_f64().unwrap()))
        .collect();
    assert!(
        pose.iter().any(|s| s.starts_with('-') && s.contains("e-")),
        "the pose has a negative number with a negative exponent: {pose:?}"
    );
    pose.insert(0, "--pose".into());
    let mut args: Vec<String> = vec!["kin".into(), "ik".into(), "--json".into()];
    args.extend(pose);
    args.push("--seed".into());
    args.extend(q.map(|v| format!("{v:e}")));
    let tmp = tempfile::tempdir().unwrap();
    let out = pregrasp(
        tmp.path(),
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ik: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let first: Vec<f64> = ik["solutions"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    for (a, b) in first.iter().zip(q) {
        assert!((a - b).abs() < 1e-9, "{first:?} vs {q:?}");
    }
}

#[test]
fn kin_refuses_words_that_are_not_numbers() {
    let tmp = tempfile::tempdir().unwrap();
    let out = pregrasp(tmp.path(), &["kin", "fk", "0", "0", "1.5x", "0", "0", "0"]);
    assert_eq!(out.status.code(), Some(64), "a usage error");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("\"1.5x\" is not a number"), "{err}");
    // A word that is neither a number nor an option is an unknown option.
    let out = pregrasp(tmp.path(), &["kin", "fk", "0", "0", "-x1", "0", "0", "0"]);
    assert_eq!(out.status.code(), Some(64));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unexpected argument '-x'"));
    let out = pregrasp(tmp.path(), &["kin", "fk", "0", "0", "0", "0", "0"]);
    assert_ne!(out.status.code(), Some(0), "five angles are too few");
    let out = pregrasp(tmp.path(), &["kin", "fk", "0", "0", "nan", "0", "0", "0"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("elbow is not a finite number"));
}
