//! Each closing's own grip force (`segments[].grip_force`, issue 48) reaches the cell: URScript's
//! `SET FOR` before each close, the CSV's `grip_force` column, the ROS 2 files' gripper comment;
//! a plan without the key exports as before.

mod common;

use pregrasp_export::urscript::force_register;
use pregrasp_export::{Format, Options};
use pregrasp_io::plan_file::{PlanFile, SegmentName};

/// The chair plan with its own forces on every closing: sup1 50 N (not the pinch's
/// recommended 20 N), mas1 120 N, sup2 60 N.
fn with_forces() -> PlanFile {
    let (file, _) = common::chair_side();
    let mut file = file.clone();
    for seg in &mut file.plans[0].segments {
        seg.grip_force = match seg.name {
            SegmentName::Sup1 => Some(50.0),
            SegmentName::Rot => None,
            SegmentName::Mas1 => Some(120.0),
            SegmentName::Sup2 => Some(60.0),
        };
    }
    file
}

/// The chair plan as a file without the key (its `physics` kept).
fn without_forces() -> PlanFile {
    let (file, _) = common::chair_side();
    let mut file = file.clone();
    for seg in &mut file.plans[0].segments {
        seg.grip_force = None;
    }
    file
}

fn texts(file: &PlanFile, format: Format, options: &Options) -> Vec<(String, String)> {
    common::export_file(file, 0, &[format], options, None)
        .unwrap()
        .into_iter()
        .map(|f| (f.name, String::from_utf8(f.bytes).unwrap()))
        .collect()
}

/// `(segment, SET FOR register)` of every close, over both programs, sorted by segment.
fn close_forces(file: &PlanFile, options: &Options) -> Vec<(String, u8)> {
    let mut out = Vec::new();
    for (_, text) in texts(file, Format::UrScript, options) {
        let body = text.split("# ---- start ---").nth(1).unwrap();
        let (mut segment, mut force) = (String::new(), None);
        for line in body.lines().map(str::trim) {
            if let Some(rest) = line.strip_prefix("# ---- segment ") {
                segment = rest.split(' ').next().unwrap().to_string();
            } else if let Some(rest) = line.strip_prefix("pg_grip_set(\"SET FOR ") {
                force = Some(rest.trim_end_matches("\")").parse::<u8>().unwrap());
            } else if line.starts_with("pg_grip_close(") {
                out.push((segment.clone(), force.expect("SET FOR before a close")));
            }
        }
    }
    out.sort();
    out
}

fn expect(sup1: u8, mas1: u8, sup2: u8) -> Vec<(String, u8)> {
    let mut v = vec![
        ("sup1".to_string(), sup1),
        ("mas1".to_string(), mas1),
        ("sup2".to_string(), sup2),
    ];
    v.sort();
    v
}

#[test]
fn the_planner_gives_every_closing_its_force() {
    let (file, _) = common::chair_side();
    let plan = &file.plans[0];
    let recommended = plan.physics.as_ref().unwrap().grip_force_recommended;
    assert!(recommended.is_some());
    for seg in &plan.segments {
        // The pinch its recommended force, the power grasps the 2F-85's largest (the carry
        // check finds the chair side carried), `rot` none (it closes nothing).
        let want = match seg.name {
            SegmentName::Sup1 => recommended,
            SegmentName::Mas1 | SegmentName::Sup2 => Some(235.0),
            SegmentName::Rot => None,
        };
        assert_eq!(seg.grip_force, want, "{}", seg.name);
    }
}

#[test]
fn urscript_closes_each_gripper_with_its_segments_force() {
    let file = with_forces();
    let (r50, r120, r60) = (
        force_register(50.0),
        force_register(120.0),
        force_register(60.0),
    );
    assert_eq!((r50, r120, r60), (36, 119, 48));
    assert_eq!(
        close_forces(&file, &Options::default()),
        expect(r50, r120, r60)
    );
    // The user's registers still override the plan, each for its grasp.
    let support_only = Options {
        support_grip_force: Some(17),
        ..Options::default()
    };
    assert_eq!(close_forces(&file, &support_only), expect(17, r120, r60));
    let both = Options {
        support_grip_force: Some(17),
        power_grip_force: Some(200),
        grip_force: 200,
        ..Options::default()
    };
    assert_eq!(close_forces(&file, &both), expect(17, 200, 200));
    // `grip_force` alone is the fallback of the closes the plan gives no force.
    let fallback = Options {
        grip_force: 90,
        ..Options::default()
    };
    assert_eq!(close_forces(&file, &fallback), expect(r50, r120, r60));
}

#[test]
fn without_the_key_urscript_falls_back_as_before() {
    let file = without_forces();
    let recommended = file.plans[0]
        .physics
        .as_ref()
        .and_then(|p| p.grip_force_recommended)
        .unwrap();
    let pinch = force_register(recommended);
    assert_eq!(
        close_forces(&file, &Options::default()),
        expect(pinch, 255, 255)
    );
    // sup1's key equal to the recommended force gives the same program, byte for byte.
    let (planned, _) = common::chair_side();
    assert_eq!(
        texts(planned, Format::UrScript, &Options::default()),
        texts(&file, Format::UrScript, &Options::default())
    );
}

/// `(t, gripper, grip_force)` of each row of a CSV with the `grip_force` column.
fn csv_forces(text: &str) -> Vec<(f64, u8, Option<f64>)> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,q1,q2,q3,q4,q5,q6,gripper,grip_force"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 9, "{l}");
            let force = (!f[8].is_empty()).then(|| f[8].parse::<f64>().unwrap());
            (f[0].parse().unwrap(), f[7].parse().unwrap(), force)
        })
        .collect()
}

#[test]
fn csv_gives_each_rows_grip_force() {
    let file = with_forces();
    let plan = &file.plans[0];
    let csvs = texts(&file, Format::Csv, &Options::default());
    for (name, text) in &csvs {
        let robot = name.trim_end_matches(".csv");
        let rows = csv_forces(text);
        // The forces the arm's closes command, in time order, while closed.
        let mut seen: Vec<f64> = Vec::new();
        for &(t, closed, force) in &rows {
            match (closed, force) {
                (0, f) => assert_eq!(f, None, "{name} t={t}: open with a force"),
                (1, Some(f)) => {
                    if seen.last() != Some(&f) {
                        seen.push(f);
                    }
                }
                (1, None) => panic!("{name} t={t}: closed without the plan's force"),
                _ => unreachable!(),
            }
        }
        let want: Vec<f64> = plan
            .segments
            .iter()
            .filter(|s| s.robot == robot)
            .filter_map(|s| s.grip_force)
            .collect();
        assert_eq!(seen, want, "{name}");
        assert!(!want.is_empty());
    }
    // A plan that gives no closing a force has no such column.
    for (name, text) in texts(&without_forces(), Format::Csv, &Options::default()) {
        assert!(
            text.starts_with("t,q1,q2,q3,q4,q5,q6,gripper\n"),
            "{name}: {}",
            text.lines().next().unwrap()
        );
    }
}

#[test]
fn ros2_files_name_each_closings_force() {
    let file = with_forces();
    let yamls = texts(&file, Format::Ros2, &Options::default());
    let plan = &file.plans[0];
    for ((name, text), seg) in yamls.iter().zip(&plan.segments) {
        let comment = text.lines().find(|l| l.starts_with("# gripper:"));
        match seg.grip_force {
            Some(f) => {
                let line = comment.unwrap_or_else(|| panic!("{name}: no gripper line"));
                assert!(
                    line.contains(&format!("grip force {f:?} N")),
                    "{name}: {line}"
                );
                assert!(line.contains("max_effort"), "{line}");
            }
            None => assert_eq!(comment, None, "{name}"),
        }
        // Still a JointTrajectory YAML: the comment is a comment.
        let v: serde_yaml::Value = serde_yaml::from_str(text).unwrap();
        assert!(v.get("points").is_some(), "{name}");
    }
    assert!(yamls[0].1.contains("grip force 50.0 N"));
    assert!(yamls[2].1.contains("grip force 120.0 N"));
    assert!(yamls[3].1.contains("grip force 60.0 N"));
    for (name, text) in texts(&without_forces(), Format::Ros2, &Options::default()) {
        assert!(!text.contains("# gripper:"), "{name}");
    }
}
