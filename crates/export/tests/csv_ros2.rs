//! The CSV and ROS 2 YAML files, parsed back and compared with the plan.

// Joint loops index several arrays at once (`for j in 0..6`): clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

mod common;

use pregrasp_export::{Format, Options};

fn files(format: Format, options: &Options) -> Vec<(String, String)> {
    let (file, _) = common::chair_side();
    common::export_file(file, 0, &[format], options, None)
        .unwrap()
        .into_iter()
        .map(|f| (f.name, String::from_utf8(f.bytes).unwrap()))
        .collect()
}

fn read_csv(text: &str) -> Vec<(f64, [f64; 6], u8)> {
    let mut lines = text.lines();
    // The plan gives sup1 its pinch's grip force: a last column `grip_force` (tests/grip_forces.rs).
    assert_eq!(lines.next(), Some("t,q1,q2,q3,q4,q5,q6,gripper,grip_force"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 9, "{l}");
            let q = std::array::from_fn(|i| f[i + 1].parse::<f64>().unwrap());
            (f[0].parse().unwrap(), q, f[7].parse().unwrap())
        })
        .collect()
}

/// Linear interpolation of the CSV rows at `t`.
fn csv_at(rows: &[(f64, [f64; 6], u8)], t: f64) -> [f64; 6] {
    let i = rows.partition_point(|r| r.0 <= t).max(1) - 1;
    if i + 1 >= rows.len() || rows[i].0 == t {
        return rows[i].1;
    }
    let (a, b) = (&rows[i], &rows[i + 1]);
    let s = (t - a.0) / (b.0 - a.0);
    std::array::from_fn(|j| a.1[j] + (b.1[j] - a.1[j]) * s)
}

#[test]
fn csv_round_trips_to_the_plan() {
    let (file, _) = common::chair_side();
    let points = common::plan_points(file, 0);
    let duration = points.last().unwrap().0;
    let csvs = files(Format::Csv, &Options::default());
    assert_eq!(csvs.len(), 2);
    for (name, text) in &csvs {
        let robot = name.trim_end_matches(".csv");
        let rows = read_csv(text);
        // Times: strictly increasing from 0 to the plan's end; every 1/125 s grid time is
        // there (or a plan point within 1 ns of it).
        assert_eq!(rows[0].0, 0.0);
        assert!((rows.last().unwrap().0 - duration).abs() < 1e-9);
        assert!(
            rows.windows(2).all(|w| w[1].0 > w[0].0),
            "{name}: times grow"
        );
        let n = (duration * 125.0).floor() as usize;
        for k in 0..=n {
            let t = k as f64 / 125.0;
            let i = rows.partition_point(|r| r.0 < t - 1e-9);
            assert!((rows[i].0 - t).abs() <= 1e-9, "{name}: no row at {t}");
        }
        // Every row is on the plan, and the plan's points are on the CSV's interpolation:
        // both arms' points (the other arm's points are times at which this arm holds).
        for r in &rows {
            let q = common::plan_q(file, 0, robot, r.0);
            for j in 0..6 {
                assert!((r.1[j] - q[j]).abs() < 1e-9, "{name} at {}", r.0);
            }
        }
        for (t, who, q) in &points {
            let c = csv_at(&rows, *t);
            let expect = if who == robot {
                *q
            } else {
                common::plan_q(file, 0, robot, *t)
            };
            for j in 0..6 {
                assert!((c[j] - expect[j]).abs() < 1e-9, "{name}: plan point at {t}");
            }
        }
        // Gripper: open at 0; closed exactly from the end of each of its reach/regrasp
        // segments until the next one of its segments opens it.
        let plan = &file.plans[0];
        let mut t0 = 0.0;
        let mut events = Vec::new();
        for seg in &plan.segments {
            let t1 = t0 + seg.points.last().unwrap().t;
            if seg.robot == robot && seg.kind.closes_at_end() {
                events.push((t0, 0u8));
                events.push((t1, 1u8));
            }
            t0 = t1;
        }
        for r in &rows {
            let expect = events.iter().rev().find(|e| e.0 <= r.0).map_or(0, |e| e.1);
            assert_eq!(r.2, expect, "{name}: gripper at {}", r.0);
        }
        assert!(rows.iter().any(|r| r.2 == 1), "{name}: the gripper closes");
    }
}

#[test]
fn csv_rate_option_sets_the_grid() {
    let o = Options {
        rate: 10.0,
        ..Options::default()
    };
    let rows = read_csv(&files(Format::Csv, &o)[0].1);
    let (file, _) = common::chair_side();
    let points = common::plan_points(file, 0);
    let mut times: Vec<f64> = points.iter().map(|p| p.0).collect();
    times.dedup();
    let grid = (points.last().unwrap().0 * 10.0).floor() as usize + 1;
    assert!(rows.len() <= grid + times.len() + 1 && rows.len() >= times.len());
}

#[derive(serde::Deserialize)]
struct Duration {
    sec: i64,
    nanosec: u32,
}

#[derive(serde::Deserialize)]
struct Point {
    positions: Vec<f64>,
    velocities: Vec<f64>,
    accelerations: Vec<f64>,
    effort: Vec<f64>,
    time_from_start: Duration,
}

#[derive(serde::Deserialize)]
struct Header {
    frame_id: String,
}

#[derive(serde::Deserialize)]
struct JointTrajectory {
    header: Header,
    joint_names: Vec<String>,
    points: Vec<Point>,
}

#[test]
fn ros2_yaml_round_trips_to_the_plan() {
    let (file, _) = common::chair_side();
    let plan = &file.plans[0];
    let o = Options {
        ros_prefix: "left_".into(),
        ..Options::default()
    };
    let yamls = files(Format::Ros2, &o);
    let names: Vec<String> = yamls.iter().map(|y| y.0.clone()).collect();
    let expected: Vec<String> = plan
        .segments
        .iter()
        .map(|s| format!("{}_{}.yaml", s.robot, s.name))
        .collect();
    assert_eq!(names, expected);
    for ((name, text), seg) in yamls.iter().zip(&plan.segments) {
        let msg: JointTrajectory =
            serde_yaml::from_str(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(msg.header.frame_id, "");
        assert_eq!(
            msg.joint_names,
            [
                "left_shoulder_pan_joint",
                "left_shoulder_lift_joint",
                "left_elbow_joint",
                "left_wrist_1_joint",
                "left_wrist_2_joint",
                "left_wrist_3_joint"
            ]
        );
        // Every number is a YAML float (a decimal point), as rosidl's Python setters require.
        for line in text
            .lines()
            .filter(|l| l.contains("positions:") || l.contains("velocities:"))
        {
            let inner = line.split('[').nth(1).unwrap().trim_end_matches(']');
            for x in inner.split(',') {
                assert!(x.contains('.'), "{name}: {x:?} would read as an int");
            }
        }
        assert_eq!(msg.points.len(), seg.points.len(), "{name}");
        let model = file
            .robots
            .iter()
            .find(|r| r.name == seg.robot)
            .unwrap()
            .model
            .builtin()
            .expect("a built-in arm");
        let vmax = model.max_joint_speed();
        let n = seg.points.len();
        for (k, (p, want)) in msg.points.iter().zip(&seg.points).enumerate() {
            assert!(p.accelerations.is_empty() && p.effort.is_empty());
            assert!(p.time_from_start.nanosec < 1_000_000_000);
            let t = p.time_from_start.sec as f64 + p.time_from_start.nanosec as f64 * 1e-9;
            assert!(
                (t - want.t).abs() < 1e-9,
                "{name}: point {k} at {t} vs {}",
                want.t
            );
            for j in 0..6 {
                assert!(
                    (p.positions[j] - want.q[j]).abs() < 1e-9,
                    "{name}: point {k}"
                );
            }
            // Velocities: zero at the ends; inside, the finite difference over the two
            // neighbouring intervals, which lies between their slopes and within the limit.
            for j in 0..6 {
                let v = p.velocities[j];
                if k == 0 || k + 1 == n {
                    assert_eq!(v, 0.0, "{name}: end velocity");
                    continue;
                }
                let (a, b, c) = (&seg.points[k - 1], want, &seg.points[k + 1]);
                let fd = (c.q[j] - a.q[j]) / (c.t - a.t);
                assert!((v - fd).abs() < 1e-9, "{name}: point {k} joint {j}");
                let s0 = (b.q[j] - a.q[j]) / (b.t - a.t);
                let s1 = (c.q[j] - b.q[j]) / (c.t - b.t);
                assert!(v >= s0.min(s1) - 1e-9 && v <= s0.max(s1) + 1e-9);
                assert!(v.abs() <= vmax[j] + 1e-9);
            }
        }
        if let Some(last) = msg.points.last() {
            let dur = seg.points.last().unwrap().t;
            let t = last.time_from_start.sec as f64 + last.time_from_start.nanosec as f64 * 1e-9;
            assert!((t - dur).abs() < 1e-9);
        }
    }
}
