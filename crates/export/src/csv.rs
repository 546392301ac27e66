//! CSV per arm (`<name>.csv`): `t,q1,q2,q3,q4,q5,q6,gripper`.
//!
//! Rows at every multiple of `1 / rate` over the whole plan time line (both arms' segments
//! advance time), plus one row at every plan point of either arm, so that interpolating the
//! rows linearly gives back the plan exactly (a grid time within 1 ns of a plan point is
//! replaced by it). `gripper` is 0 open, 1 closed, with the commands at `t` applied.
//! When the plan gives any closing a grip force, a last column `grip_force` follows: the force
//! (N) the arm's gripper holds the part with — its close's force while closed, empty while open
//! or when the plan gives that close none ([`Timeline::grip_force_at`]); without one the files
//! have no such column. Numbers are written in Rust's shortest round-trip form.

use pregrasp_model::Timeline;

use crate::{float, Options, OutFile};

/// The row times: the rate grid merged with every plan-point time, sorted, unique.
pub fn row_times(timeline: &Timeline, rate: f64) -> Vec<f64> {
    let points = timeline.point_times();
    let n = (timeline.duration * rate + 1e-9).floor() as usize;
    let mut times: Vec<f64> = (0..=n)
        .map(|k| k as f64 / rate)
        .filter(|t| {
            let i = points.partition_point(|p| p < t);
            let near = |j: usize| points.get(j).is_some_and(|p| (p - t).abs() <= 1e-9);
            !(near(i) || (i > 0 && near(i - 1))) && *t <= timeline.duration
        })
        .collect();
    times.extend(points);
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// Whether the plan gives any closing a grip force (then the files have a `grip_force`
/// column).
pub fn has_grip_forces(timeline: &Timeline) -> bool {
    timeline.segments.iter().any(|s| s.grip_force.is_some())
}

/// One CSV text for arm `arm`.
pub fn arm_csv(timeline: &Timeline, arm: usize, rate: f64) -> String {
    let forces = has_grip_forces(timeline);
    let mut s = String::from("t,q1,q2,q3,q4,q5,q6,gripper");
    s.push_str(if forces { ",grip_force\n" } else { "\n" });
    for t in row_times(timeline, rate) {
        let q = timeline.q_at(arm, t);
        let closed = timeline.gripper_at(arm, t).0;
        s.push_str(&float(t));
        for x in q {
            s.push(',');
            s.push_str(&float(x));
        }
        s.push_str(if closed { ",1" } else { ",0" });
        if forces {
            s.push(',');
            if let Some(f) = timeline.grip_force_at(arm, t) {
                s.push_str(&float(f));
            }
        }
        s.push('\n');
    }
    s
}

/// `<name>.csv` for every arm.
pub fn export(timeline: &Timeline, options: &Options) -> Vec<OutFile> {
    (0..timeline.arms.len())
        .map(|a| OutFile {
            name: format!("{}.csv", timeline.arms[a].name),
            bytes: arm_csv(timeline, a, options.rate).into_bytes(),
        })
        .collect()
}
