//! `pregrasp check` on malformed plan files (issue 18, findings 1 and 2): refused before any
//! motion is judged, exit 1, with the path of the offending field.

mod common;

use common::{plan_chair_side, pregrasp};

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde_json::Value;

/// A fresh plan of the chair side in `dir/plan.json` (the mesh beside it), as JSON.
fn planned(dir: &Path) -> Value {
    plan_chair_side(dir);
    serde_json::from_str(&std::fs::read_to_string(dir.join("plan.json")).unwrap()).unwrap()
}

/// Writes `plan` edited by `edit` and runs `check` on it: (exit code, stderr, seconds).
fn check_edited(edit: impl FnOnce(&mut Value)) -> (Option<i32>, String, f64) {
    let tmp = tempfile::tempdir().unwrap();
    let mut plan = planned(tmp.path());
    edit(&mut plan);
    let path: PathBuf = tmp.path().join("edited.json");
    std::fs::write(&path, serde_json::to_string(&plan).unwrap()).unwrap();
    let t0 = Instant::now();
    let out = pregrasp(tmp.path(), &["check", "edited.json"]);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        t0.elapsed().as_secs_f64(),
    )
}

#[test]
fn check_refuses_an_absurd_joint_value_at_once() {
    let (code, err, secs) =
        check_edited(|p| p["plans"][0]["segments"][2]["points"][3]["q"][0] = 1.2e29.into());
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("plans[0].segments[2].points[3].q[0]"), "{err}");
    assert!(
        secs < Duration::from_secs(60).as_secs_f64(),
        "took {secs} s"
    );
}

/// One edit of a plan file.
type Edit = Box<dyn FnOnce(&mut Value)>;

#[test]
fn check_refuses_plans_that_do_not_follow_the_format() {
    let cases: Vec<(&str, Edit)> = vec![
        ("status", Box::new(|p| p["status"] = "maybe".into())),
        ("status", Box::new(|p| p["status"] = "".into())),
        (
            "object.initial_pose.quat_xyzw",
            Box::new(|p| {
                p["object"]["initial_pose"]["quat_xyzw"] = serde_json::json!([0, 0, 0, 0])
            }),
        ),
        (
            "plans[0].object_goal_pose.quat_xyzw",
            Box::new(|p| {
                p["plans"][0]["object_goal_pose"]["quat_xyzw"] = serde_json::json!([0, 0, 0, 0])
            }),
        ),
        (
            "plans[0].segments[1].name",
            Box::new(|p| p["plans"][0]["segments"][1]["name"] = "".into()),
        ),
        (
            "robots[1].model",
            Box::new(|p| p["robots"][1]["model"] = "ur99".into()),
        ),
    ];
    for (field, edit) in cases {
        let (code, err, _) = check_edited(edit);
        assert_eq!(code, Some(1), "{field}: {err}");
        assert!(err.contains(field), "expected {field} in: {err}");
    }
}
