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

/// Every number of the plans' segments rounded to `decimals` places, as another tool may write
/// them.
fn round_points(plan: &mut Value, decimals: i32) {
    let scale = 10f64.powi(decimals);
    let round = |v: &mut Value| {
        let x = v.as_f64().unwrap();
        *v = ((x * scale).round() / scale).into();
    };
    for p in plan["plans"].as_array_mut().unwrap() {
        for seg in p["segments"].as_array_mut().unwrap() {
            for point in seg["points"].as_array_mut().unwrap() {
                round(&mut point["t"]);
                for q in point["q"].as_array_mut().unwrap() {
                    round(q);
                }
            }
        }
    }
}

/// Retimes the interval of plan 0's `mas1` with the largest joint change so that its fastest
/// joint moves at `factor` × the UR5e's 180°/s, shifting the later points with it.
fn retime_fastest_interval(plan: &mut Value, factor: f64) {
    let points = plan["plans"][0]["segments"][2]["points"]
        .as_array_mut()
        .unwrap();
    let q = |p: &Value, j: usize| p["q"][j].as_f64().unwrap();
    let (k, dq) = (1..points.len())
        .map(|k| {
            let dq = (0..6)
                .map(|j| (q(&points[k], j) - q(&points[k - 1], j)).abs())
                .fold(0.0, f64::max);
            (k, dq)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    let t = |p: &Value| p["t"].as_f64().unwrap();
    let shift = t(&points[k - 1]) + dq / (std::f64::consts::PI * factor) - t(&points[k]);
    for p in &mut points[k..] {
        let moved = t(p) + shift;
        p["t"] = moved.into();
    }
}

/// `check` judges a plan, not its rounding: a plan whose fastest joint runs exactly at its
/// speed limit still passes rule 1 with its time stamps and joints rounded to six decimals
/// (microseconds, micro-radians), as another tool may write them; 1 % over the limit fails.
#[test]
fn check_is_not_stricter_than_the_rounding_of_a_written_plan() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = planned(tmp.path());
    let run = |name: &str, plan: &Value| {
        std::fs::write(tmp.path().join(name), plan.to_string()).unwrap();
        let out = pregrasp(tmp.path(), &["check", name]);
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
        )
    };
    let mut at_limit = plan.clone();
    retime_fastest_interval(&mut at_limit, 1.0);
    for decimals in [6, 7, 9] {
        let mut rounded = at_limit.clone();
        round_points(&mut rounded, decimals);
        let (code, stdout) = run("rounded.json", &rounded);
        assert_eq!(code, Some(0), "{decimals} decimals: {stdout}");
    }
    let mut fast = plan.clone();
    retime_fastest_interval(&mut fast, 1.01);
    let (code, stdout) = run("fast.json", &fast);
    assert_eq!(code, Some(2), "{stdout}");
    assert!(
        stdout.contains("rule 1 FAIL") && stdout.contains("speed"),
        "{stdout}"
    );
}
