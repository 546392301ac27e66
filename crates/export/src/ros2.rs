//! ROS 2 trajectories (`<name>_<segment>.yaml`, per arm and segment it moves in): a
//! `trajectory_msgs/msg/JointTrajectory` in the YAML that `ros2 topic pub` and action clients
//! (`ros2 action send_goal … FollowJointTrajectory`) take.
//!
//! `joint_names` are ur_robot_driver's for a built-in arm, the plan's (its description's) for an
//! arm from a robot description, with an optional prefix. `time_from_start` counts from
//! the segment's first point. `velocities` are the finite differences of the plan's linear
//! interpolation: at an inner point the time-weighted mean of the slopes of its two intervals,
//! `(q[k+1] − q[k−1]) / (t[k+1] − t[k−1])`, and zero at the segment's ends (the arm stops
//! there; the next segment may belong to the other arm).
//!
//! A trajectory carries no gripper command: a segment that closes its gripper (`sup1`, `mas1`,
//! `sup2`) says so in a comment line after the header comment, with the grip force (N) to
//! close with when the plan gives one, for the `max_effort` of a `control_msgs/GripperCommand`
//! sent after the trajectory.

use pregrasp_model::timeline::Segment;
use pregrasp_model::{PlanSet, Timeline};

use crate::{float, Options, OutFile};

/// ur_robot_driver's joint names, base to flange.
pub const ROS_JOINT_NAMES: [&str; 6] = [
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
];

/// Velocities at the points of `seg`, as documented in the module.
pub fn velocities(seg: &Segment) -> Vec<[f64; 6]> {
    let p = &seg.points;
    let n = p.len();
    (0..n)
        .map(|k| {
            if k == 0 || k + 1 == n {
                [0.0; 6]
            } else {
                let dt = p[k + 1].0 - p[k - 1].0;
                std::array::from_fn(|j| (p[k + 1].1[j] - p[k - 1].1[j]) / dt)
            }
        })
        .collect()
}

/// `(sec, nanosec)` of a duration in seconds (nanoseconds rounded; `nanosec` < 10⁹).
pub fn sec_nanosec(t: f64) -> (i64, u32) {
    let total = (t * 1e9).round() as i64;
    (
        total.div_euclid(1_000_000_000),
        total.rem_euclid(1_000_000_000) as u32,
    )
}

fn list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| float(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// The YAML text of one segment of `set`'s plan.
pub fn segment_yaml(set: &PlanSet, seg: &Segment, prefix: &str) -> String {
    let arm = &set.arms[seg.arm];
    let mut s = format!(
        "# pregrasp plan: arm {} ({}), segment {} ({}), {} points, {} s\n",
        arm.name,
        arm.model,
        seg.name,
        seg.kind,
        seg.points.len(),
        float(seg.t_end() - seg.t0)
    );
    if seg.kind.closes_at_end() {
        if let Some(f) = seg.grip_force {
            s.push_str(&format!(
                "# gripper: opens at the first point, closes on the part at the last with \
                 grip force {} N (control_msgs/GripperCommand max_effort)\n",
                float(f)
            ));
        }
    }
    s.push_str("header:\n  stamp: {sec: 0, nanosec: 0}\n  frame_id: ''\njoint_names:\n");
    // A built-in arm is driven by ur_robot_driver; any other by the names its description
    // gives (the plan's `joint_names`).
    let names: Vec<&str> = match arm.model.builtin() {
        Some(_) => ROS_JOINT_NAMES.to_vec(),
        None => arm.joint_names.iter().map(String::as_str).collect(),
    };
    for n in names {
        s.push_str(&format!("  - {prefix}{n}\n"));
    }
    s.push_str("points:\n");
    for ((t, q), v) in seg.points.iter().zip(velocities(seg)) {
        let (sec, nanosec) = sec_nanosec(t - seg.t0);
        s.push_str(&format!("  - positions: {}\n", list(q)));
        s.push_str(&format!("    velocities: {}\n", list(&v)));
        s.push_str("    accelerations: []\n    effort: []\n");
        s.push_str(&format!(
            "    time_from_start: {{sec: {sec}, nanosec: {nanosec}}}\n"
        ));
    }
    s
}

/// One file per (arm, segment it moves in).
pub fn export(set: &PlanSet, timeline: &Timeline, options: &Options) -> Vec<OutFile> {
    timeline
        .segments
        .iter()
        .map(|seg| OutFile {
            name: format!("{}_{}.yaml", timeline.arms[seg.arm].name, seg.name),
            bytes: segment_yaml(set, seg, &options.ros_prefix).into_bytes(),
        })
        .collect()
}
