//! `segments[].grip_force` (issue 48): each closing's own grip force, through the file and the
//! model and back, omitted when absent, and refused by name when out of range.

use std::path::Path;

use pregrasp_io::plan_file::{PlanFile, SegmentName};
use pregrasp_io::plan_model::plan_json;

fn golden_text() -> String {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../planner/tests/golden/chair_side.json");
    std::fs::read_to_string(path).unwrap()
}

fn golden() -> PlanFile {
    PlanFile::from_json_str(&golden_text(), "chair_side.json").expect("golden plan reads")
}

#[test]
fn the_planner_writes_every_closings_force() {
    let file = golden();
    for plan in &file.plans {
        let recommended = plan.physics.as_ref().unwrap().grip_force_recommended;
        assert!(recommended.is_some());
        for seg in &plan.segments {
            // The pinch its recommended force, the power grasps the 2F-85's largest (the
            // carry check), `rot` none.
            let want = match seg.name {
                SegmentName::Sup1 => recommended,
                SegmentName::Mas1 | SegmentName::Sup2 => Some(235.0),
                SegmentName::Rot => None,
            };
            assert_eq!(seg.grip_force, want, "{}", seg.name);
        }
    }
}

#[test]
fn grip_force_round_trips_through_the_file_and_the_model() {
    let mut file = golden();
    let forces = [Some(33.25), None, Some(120.5), Some(60.125)];
    for (seg, f) in file.plans[0].segments.iter_mut().zip(forces) {
        seg.grip_force = f;
    }
    let text = file.to_json();
    let again = PlanFile::from_json_str(&text, "t.json").unwrap();
    assert_eq!(again, file);
    assert_eq!(again.to_json(), text, "byte for byte");
    let set = again.to_model().unwrap();
    let plan = &set.plans[0];
    let got: Vec<Option<f64>> = plan.segments.iter().map(|s| s.grip_force).collect();
    assert_eq!(got, forces);
    // What the exports command: the segment's own, else sup1's falls back to the pinch's.
    let closing: Vec<Option<f64>> = plan
        .segments
        .iter()
        .map(|s| plan.closing_force(s))
        .collect();
    assert_eq!(closing, forces);
    let mut bare = plan.clone();
    bare.segments[0].grip_force = None;
    assert_eq!(
        bare.closing_force(&bare.segments[0]),
        bare.support_grip_force
    );
    assert_eq!(bare.closing_force(&bare.segments[2]), Some(120.5));
    // The model written back carries the same forces (its poses are equal to the last bits:
    // tests/plan_model.rs).
    let back = plan_json(&set.arms, plan);
    let back: Vec<Option<f64>> = back.segments.iter().map(|s| s.grip_force).collect();
    assert_eq!(back, forces);
}

#[test]
fn an_absent_grip_force_is_omitted() {
    let mut file = golden();
    for plan in &mut file.plans {
        for seg in &mut plan.segments {
            seg.grip_force = None;
        }
    }
    let text = file.to_json();
    assert!(!text.contains("\"grip_force\""));
    // … and the golden text has it three times per plan (sup1's, mas1's, sup2's).
    let golden = golden_text();
    assert_eq!(
        golden.matches("\"grip_force\":").count(),
        3 * file.plans.len()
    );
}

/// The golden chair plan with `plans[0].segments[seg].grip_force` set to the JSON `value`.
fn with(seg: usize, value: &str) -> String {
    let mut v: serde_json::Value = serde_json::from_str(&golden_text()).unwrap();
    v["plans"][0]["segments"][seg]["grip_force"] = serde_json::Value::Null;
    let text = serde_json::to_string(&v).unwrap();
    text.replace("\"grip_force\":null", &format!("\"grip_force\":{value}"))
}

fn refusal(seg: usize, value: &str) -> String {
    match PlanFile::from_json_str(&with(seg, value), "bad.json") {
        Ok(_) => panic!("grip_force {value} on segment {seg} was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_bad_grip_force_is_refused_by_its_key() {
    let key = |seg: usize| format!("plans[0].segments[{seg}].grip_force");
    for (seg, value) in [
        (0, "-5.0"),      // negative
        (2, "0.0"),       // no force
        (3, "\"NaN\""),   // not a number
        (2, "1e9"),       // huge
        (0, "1000.5"),    // above any gripper
        (3, "300.0"),     // above the 2F-85's 235 N
        (1, "20.0"),      // rot does not close
        (2, "\"120 N\""), // a string
        (2, "[120.0]"),   // not a number
    ] {
        let e = refusal(seg, value);
        assert!(e.contains(&key(seg)), "{value}: {e}");
    }
    // In range: accepted.
    for (seg, value) in [(0, "20.0"), (2, "235.0"), (3, "0.5")] {
        let file = PlanFile::from_json_str(&with(seg, value), "ok.json")
            .unwrap_or_else(|e| panic!("{value}: {e}"));
        let f: f64 = value.parse().unwrap();
        assert_eq!(file.plans[0].segments[seg].grip_force, Some(f));
    }
}
