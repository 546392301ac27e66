//! Is a plan file a plan file? The format's shape and value ranges, checked before any motion
//! is judged: a malformed file is refused with the JSON path of the offending field, and no
//! value can size a loop (a joint angle of 1e29 rad would otherwise be interpolated at the
//! checker's resolution for ever). [`crate::plan_file::PlanFile::read`] applies it, so every
//! command that reads a plan (`check`, `view`, `export`, `physics`, `replan`, Python) gets a
//! validated file or one error naming the field.

use crate::plan_file::{PhysicsJson, PlanFile, PoseJson, SegmentJson};

/// Largest magnitude of a joint value (rad) a plan may hold: no UR joint turns beyond ±2π, so
/// anything past ±20 rad is not a joint angle (values between the limits and this bound are
/// judged by rule 1).
pub const MAX_JOINT_VALUE: f64 = 20.0;
/// Largest magnitude of a coordinate (m).
pub const MAX_COORDINATE: f64 = 1.0e3;
/// Largest time stamp (s): a day.
pub const MAX_TIME: f64 = 86_400.0;

/// The first field of `file` that does not follow the plan format, as `path: problem`.
pub fn validate(file: &PlanFile) -> Result<(), String> {
    if file.format != "pregrasp.plan/1" {
        return Err(format!(
            "format: {:?} is not \"pregrasp.plan/1\"",
            file.format
        ));
    }
    number("support_height", file.support_height, MAX_COORDINATE)?;
    pose("object.initial_pose", &file.object.initial_pose)?;
    if !(file.object.scale.is_finite() && file.object.scale > 0.0) {
        return Err(format!(
            "object.scale: {} is not a positive number",
            file.object.scale
        ));
    }
    if let Some(m) = file.object.mass {
        crate::ranges::check_physics_value("mass", m).map_err(|p| format!("object.mass: {p}"))?;
    }
    if file.robots.len() != 2 {
        return Err(format!("robots: {} robots, expected 2", file.robots.len()));
    }
    for (i, r) in file.robots.iter().enumerate() {
        pose(&format!("robots[{i}].base"), &r.base)?;
        pose(&format!("robots[{i}].precision_point"), &r.precision_point)?;
        pose(&format!("robots[{i}].power_point"), &r.power_point)?;
        joints(&format!("robots[{i}].start"), &r.start)?;
    }
    pose("grasps.support", &file.grasps.support)?;
    for (i, g) in file.grasps.power.iter().enumerate() {
        pose(&format!("grasps.power[{i}]"), g)?;
    }
    for (c, cand) in file.candidates.iter().enumerate() {
        for (e, p) in cand.axis.iter().enumerate() {
            for (k, x) in p.iter().enumerate() {
                number(
                    &format!("candidates[{c}].axis[{e}][{k}]"),
                    *x,
                    MAX_COORDINATE,
                )?;
            }
        }
    }
    for (k, plan) in file.plans.iter().enumerate() {
        pose(
            &format!("plans[{k}].object_goal_pose"),
            &plan.object_goal_pose,
        )?;
        for (s, seg) in plan.segments.iter().enumerate() {
            let at = format!("plans[{k}].segments[{s}]");
            // Each segment of the format has one kind and one grasp (plan-format.md).
            let (kind, grasp) = (seg.name.kind(), seg.name.grasp());
            if seg.kind != kind {
                return Err(format!(
                    "{at}.kind: \"{}\", but segment {} is always \"{kind}\"",
                    seg.kind, seg.name
                ));
            }
            if seg.grasp != grasp {
                return Err(format!(
                    "{at}.grasp: \"{}\", but segment {} always ends at the {grasp} grasp",
                    seg.grasp, seg.name
                ));
            }
            if let Some(w) = seg.grip_width {
                number(&format!("{at}.grip_width"), w, 1.0)?;
            }
            if let Some(f) = seg.grip_force {
                grip_force(file, &at, seg, f)?;
            }
            if let Some(c) = &seg.pad_contact {
                for (i, x) in c.center.iter().enumerate() {
                    number(&format!("{at}.pad_contact.center[{i}]"), *x, 1.0)?;
                }
                let e = c.torsion_radius;
                number(&format!("{at}.pad_contact.torsion_radius"), e, 0.05)?;
                if e < 0.0 {
                    return Err(format!("{at}.pad_contact.torsion_radius: {e} is negative"));
                }
                for (i, a) in c.area.iter().enumerate() {
                    number(&format!("{at}.pad_contact.area[{i}]"), *a, 0.01)?;
                    if *a < 0.0 {
                        return Err(format!("{at}.pad_contact.area[{i}]: {a} is negative"));
                    }
                }
            }
            if let Some(f) = &seg.fingers {
                number(&format!("{at}.fingers.driver"), f.driver, 1.0)?;
                for (i, q) in f.spring_link.iter().enumerate() {
                    number(&format!("{at}.fingers.spring_link[{i}]"), *q, 1.0)?;
                }
            }
            for (p, point) in seg.points.iter().enumerate() {
                number(&format!("{at}.points[{p}].t"), point.t, MAX_TIME)?;
                joints(&format!("{at}.points[{p}].q"), &point.q)?;
                if let Some(o) = &point.object_pose {
                    pose(&format!("{at}.points[{p}].object_pose"), o)?;
                }
            }
        }
        if let Some(p) = &plan.physics {
            // The 2F-85's force range binds its plans; a jaw gripper's is its description's.
            let robotiq = file
                .robots
                .iter()
                .find(|r| r.name == plan.supportive)
                .is_none_or(|r| r.gripper.as_deref().is_none_or(|g| g == "robotiq_2f85"));
            physics(&format!("plans[{k}].physics"), p, robotiq)?;
        }
        if let Some(r) = &plan.robustness {
            for (l, level) in r.levels.iter().enumerate() {
                let at = format!("plans[{k}].robustness.levels[{l}]");
                number(&format!("{at}.pos"), level.pos, MAX_COORDINATE)?;
                number(&format!("{at}.yaw_deg"), level.yaw_deg, 360.0)?;
                if !(0.0..=1.0).contains(&level.share) {
                    return Err(format!("{at}.share: {} is not in [0, 1]", level.share));
                }
            }
        }
    }
    Ok(())
}

/// Largest grip force (N) a segment's `grip_force` may name: more than any parallel gripper a
/// plan is for squeezes (the 2F-85 235 N, the Franka Hand 140 N).
pub const MAX_GRIP_FORCE: f64 = 1000.0;

/// A segment's `grip_force`: only on a segment that closes its gripper (`sup1`, `mas1`,
/// `sup2`), a finite number in (0, [`MAX_GRIP_FORCE`]] N, and at most the 2F-85's 235 N when the
/// segment's arm carries one.
fn grip_force(file: &PlanFile, at: &str, seg: &SegmentJson, f: f64) -> Result<(), String> {
    let key = format!("{at}.grip_force");
    number(&key, f, MAX_GRIP_FORCE)?;
    if f <= 0.0 {
        return Err(format!("{key}: {f} N is not a positive force"));
    }
    if !seg.kind.closes_at_end() {
        return Err(format!(
            "{key}: segment {} does not close its gripper (only sup1, mas1, sup2 carry a grip force)",
            seg.name
        ));
    }
    let robotiq = file
        .robots
        .iter()
        .find(|r| r.name == seg.robot)
        .is_none_or(|r| r.gripper.as_deref().is_none_or(|g| g == "robotiq_2f85"));
    if robotiq && f > 235.0 {
        return Err(format!("{key}: {f} N is more than the 2F-85's 235 N"));
    }
    Ok(())
}

/// Largest force (N) a plan's `physics` object may name.
const MAX_FORCE: f64 = 1.0e6;

/// The `physics` extension: finite non-negative numbers in range (its verdict is typed); the
/// recommended force within the 2F-85's range when `robotiq` (its supportive gripper is one).
fn physics(path: &str, p: &PhysicsJson, robotiq: bool) -> Result<(), String> {
    let optional = [
        ("grip_force_min", p.grip_force_min),
        ("grip_force_required", p.grip_force_required),
        ("grip_force_recommended", p.grip_force_recommended),
        ("pad_friction_use", p.pad_friction_use),
        ("support_friction_use", p.support_friction_use),
        ("support_normal_max", p.support_normal_max),
    ];
    let given = [
        ("mass", Some(p.mass)),
        ("mu_pad", Some(p.mu_pad)),
        ("mu_support", Some(p.mu_support)),
        ("safety_factor", Some(p.safety_factor)),
        ("worst_t", Some(p.worst_t)),
    ];
    for (key, value) in given.into_iter().chain(optional) {
        if let Some(x) = value {
            number(&format!("{path}.{key}"), x, MAX_FORCE)?;
            if x < 0.0 {
                return Err(format!("{path}.{key}: {x} is negative"));
            }
        }
    }
    number(&format!("{path}.worst_theta_deg"), p.worst_theta_deg, 360.0)?;
    if let Some(f) = p.grip_force_recommended.filter(|_| robotiq) {
        if !(20.0..=235.0).contains(&f) {
            return Err(format!(
                "{path}.grip_force_recommended: {f} N is outside the 2F-85's 20–235 N"
            ));
        }
    }
    Ok(())
}

/// A finite number no larger than `max` in magnitude.
fn number(path: &str, x: f64, max: f64) -> Result<(), String> {
    if !x.is_finite() {
        return Err(format!("{path}: {x} is not a finite number"));
    }
    if x.abs() > max {
        return Err(format!("{path}: {x} is out of range (±{max})"));
    }
    Ok(())
}

fn joints(path: &str, q: &[f64; 6]) -> Result<(), String> {
    for (j, x) in q.iter().enumerate() {
        if !x.is_finite() || x.abs() > MAX_JOINT_VALUE {
            return Err(format!(
                "{path}[{j}]: {x} rad is not a joint angle (|q| ≤ {MAX_JOINT_VALUE} rad)"
            ));
        }
    }
    Ok(())
}

/// Finite coordinates in range and a unit-normalisable quaternion (not zero).
fn pose(path: &str, p: &PoseJson) -> Result<(), String> {
    for (k, x) in p.xyz.iter().enumerate() {
        number(&format!("{path}.xyz[{k}]"), *x, MAX_COORDINATE)?;
    }
    let q = p.quat_xyzw;
    if q.iter().any(|x| !x.is_finite()) {
        return Err(format!("{path}.quat_xyzw: not finite"));
    }
    let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !norm.is_finite() {
        return Err(format!(
            "{path}.quat_xyzw: its norm overflows (write a unit quaternion)"
        ));
    }
    if norm < 1e-9 {
        return Err(format!(
            "{path}.quat_xyzw: a zero quaternion is no rotation"
        ));
    }
    Ok(())
}
