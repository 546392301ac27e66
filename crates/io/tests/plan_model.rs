//! The plan file and the typed model: the golden plans read into the model and written back
//! are the same entries, field for field.

use std::path::Path;

use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::plan_model::{plan_json, robot_json};

fn golden(name: &str) -> PlanFile {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../planner/tests/golden")
        .join(name);
    PlanFile::read(&path).expect("golden plan reads")
}

/// `a` and `b` have the same keys, words and exact integers, and numbers within 1e-15.
fn same(a: &serde_json::Value, b: &serde_json::Value, at: &str) {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() <= 1e-15, "{at}: {x} vs {y}");
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                same(x, y, &format!("{at}[{i}]"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(
                x.keys().collect::<Vec<_>>(),
                y.keys().collect::<Vec<_>>(),
                "{at}"
            );
            for (k, v) in x {
                same(v, &y[k], &format!("{at}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

#[test]
fn golden_plans_go_through_the_model_and_back_unchanged() {
    for name in ["chair_side.json", "shelf_side.json", "stool_side.json"] {
        let file = golden(name);
        let set = file.to_model().expect("a valid file is a plan set");
        assert_eq!(set.plans.len(), file.plans.len(), "{name}");
        assert!(!set.plans.is_empty(), "{name}: golden files hold plans");
        for (plan, entry) in set.plans.iter().zip(&file.plans) {
            let mut back = plan_json(&set.arms, plan);
            back.physics = entry.physics.clone();
            back.robustness = entry.robustness.clone();
            // Poses are normalised on the way in: equal to the last bits of a quaternion.
            same(
                &serde_json::to_value(&back).unwrap(),
                &serde_json::to_value(entry).unwrap(),
                &format!("{name}: plans[candidate {}]", plan.candidate),
            );
            assert_eq!(set.arms[plan.roles.master].name, entry.master);
        }
        for (arm, robot) in set.arms.iter().zip(&file.robots) {
            same(
                &serde_json::to_value(robot_json(arm)).unwrap(),
                &serde_json::to_value(robot).unwrap(),
                name,
            );
        }
    }
}

#[test]
fn a_segment_of_a_robot_the_file_does_not_have_is_refused_by_name() {
    let mut file = golden("chair_side.json");
    file.plans[0].segments[2].robot = "left_arm_typo".into();
    let err = file.to_model().unwrap_err().to_string();
    assert_eq!(
        err,
        "plans[0].segments[2].robot: \"left_arm_typo\" is not one of the file's robots"
    );
}
