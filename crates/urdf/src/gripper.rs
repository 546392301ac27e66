//! The parallel-jaw gripper a robot description carries below its tool link (the Franka
//! Hand of `fr3.urdf`): [`describe_gripper`] turns it into a `pregrasp_robot::JawGripper`.
//!
//! # What counts as a jaw gripper
//!
//! Below the tool link, every joint is fixed except two prismatic ones, one a `<mimic>` of
//! the other: each moves a jaw (its child link and what is fixed below it). The links fixed to
//! the tool link are the hand. Pieces come from the description's collision geometry
//! ([`UrdfGeometry`]): the hand's in the tool-link (flange) frame, each jaw's in its joint's
//! child frame. A mimic's `offset` shifts its jaw's zero, its `multiplier` scales its motion.
//! The master joint's `<limit effort>` is the grip force (N) the jaws can be set to (the Franka
//! Hand's description says 100 N; its datasheet 70 N continuous, 140 N peak).

use std::collections::BTreeMap;
use std::sync::{Mutex, OnceLock};

use nalgebra::{Isometry3, Translation3, Vector3};
use pregrasp_robot::{JawGripper, JawPart};
use urdf_rs::JointType;

use crate::arm::UrdfArm;
use crate::chain::origin_isometry;
use crate::error::UrdfError;
use crate::geometry::LazyGeometry;

/// Where a link below the tool link hangs: fixed to the hand (`None`) or on jaw `k`, with its
/// pose in the hand's or the jaw's frame.
type Hanging = (Option<usize>, Isometry3<f64>);

/// Longest travel of a jaw (m): a parallel gripper's stroke is centimetres; 0.5 m bounds the
/// tables made over it (a `<limit upper="1e10">` would have them fill the memory).
pub const MAX_JAW_STROKE: f64 = 0.5;

/// Largest force a jaw may press with (N).
pub const MAX_JAW_FORCE: f64 = 10_000.0;

/// The jaw gripper below `arm`'s tool link with its tool points on flange `z` (defaults: the
/// middle of the jaws' inner faces, for both), its pieces from `geometry` (the description's,
/// loaded only once the links below the tool link are found to be jaws).
pub fn describe_gripper(
    arm: &UrdfArm,
    precision_point_z: Option<f64>,
    power_point_z: Option<f64>,
    geometry: &LazyGeometry,
) -> Result<JawGripper, UrdfError> {
    let model = &arm.model;
    let fail = |reason: String| UrdfError::NotAJawGripper {
        file: model.source().to_string(),
        tool_link: arm.tool_link.clone(),
        reason,
    };
    // Walk the tree below the tool link: every link's place, and the two jaw joints.
    let mut hanging: Vec<(String, Hanging)> =
        vec![(arm.tool_link.clone(), (None, Isometry3::identity()))];
    let mut jaw_joints: Vec<(String, Isometry3<f64>, Vector3<f64>)> = Vec::new();
    let mut k = 0;
    while k < hanging.len() {
        let (link, (jaw, pose)) = hanging[k].clone();
        k += 1;
        for joint in model
            .robot()
            .joints
            .iter()
            .filter(|j| j.parent.link == link)
        {
            let origin = pose * origin_isometry(&joint.origin);
            let child = joint.child.link.clone();
            match joint.joint_type {
                JointType::Fixed => hanging.push((child, (jaw, origin))),
                JointType::Prismatic if jaw.is_none() => {
                    let axis = origin.rotation * Vector3::from(joint.axis.xyz.0);
                    hanging.push((child, (Some(jaw_joints.len()), Isometry3::identity())));
                    jaw_joints.push((joint.name.clone(), origin, axis));
                }
                _ => {
                    return Err(fail(format!(
                        "joint `{}` is {:?}; a jaw gripper has two prismatic jaws and fixed \
                         joints only",
                        joint.name, joint.joint_type
                    )))
                }
            }
        }
    }
    let [(a_name, a_origin, a_axis), (b_name, b_origin, b_axis)] =
        <[_; 2]>::try_from(jaw_joints)
            .map_err(|j: Vec<_>| fail(format!("{} prismatic joints, not two jaws", j.len())))?;
    // The master joint and the mimic's multiplier and offset.
    let mimic_of = |name: &str| model.mimic_joints().into_iter().find(|m| m.joint == name);
    let (master, rates, zeros) = match (mimic_of(&a_name), mimic_of(&b_name)) {
        (None, Some(m)) if m.master == a_name => (
            a_name.clone(),
            [a_axis, b_axis * m.multiplier],
            [a_origin, Translation3::from(b_axis * m.offset) * b_origin],
        ),
        (Some(m), None) if m.master == b_name => (
            b_name.clone(),
            [a_axis * m.multiplier, b_axis],
            [Translation3::from(a_axis * m.offset) * a_origin, b_origin],
        ),
        _ => {
            return Err(fail(format!(
                "jaw joints `{a_name}` and `{b_name}`: one must mimic the other"
            )))
        }
    };
    let limit = &model.joint(&master).expect("a joint of the tree").limit;
    let stroke = limit.upper - limit.lower;
    if !(limit.lower.is_finite() && stroke > 0.0 && stroke <= MAX_JAW_STROKE) {
        return Err(fail(format!(
            "jaw joint `{master}`: <limit lower=\"{}\" upper=\"{}\">: a jaw travels more than \
             0 and at most {MAX_JAW_STROKE} m",
            crate::chain::number(limit.lower),
            crate::chain::number(limit.upper)
        )));
    }
    if !(limit.effort > 0.0 && limit.effort <= MAX_JAW_FORCE) {
        return Err(fail(format!(
            "jaw joint `{master}`: <limit effort=\"{}\">: the force a jaw presses with must be \
             above 0 and at most {MAX_JAW_FORCE} N",
            crate::chain::number(limit.effort)
        )));
    }
    let joint = (limit.lower, limit.upper);
    // The jaw joint's effort limit is the force a jaw can press with.
    let force = (0.0, limit.effort);
    let geometry = geometry.get(model)?;
    let key = format!("jaws:{}:{}", geometry.key, arm.tool_link);
    let (statics, jaws) = jaw_parts(&key, geometry, &hanging);
    let build = |precision: f64, power: f64| {
        JawGripper::new(
            key.clone(),
            statics.clone(),
            jaws.clone(),
            zeros,
            rates,
            joint,
            precision,
            power,
        )
        .map(|j| j.with_grip_force(force))
        .map_err(|e| fail(e.to_string()))
    };
    // The faces' middle, for the tool points not given.
    let probe = build(0.0, 0.0)?;
    let middle = probe
        .faces()
        .iter()
        .map(|f| 0.5 * (f.z.0 + f.z.1))
        .sum::<f64>()
        / 2.0;
    let precision = precision_point_z.unwrap_or(middle);
    build(precision, power_point_z.unwrap_or(precision))
}

/// The hand's and each jaw's parts: each link with collision pieces, moved into its hand or
/// jaw frame. A part's name and pieces are `&'static` (`JawPart::new` leaks them), so they
/// are made once per distinct `key` for the life of the process, as `describe_arm` keeps its
/// arms: loading the same description again (a batch, a long-running Python session) costs
/// no memory.
fn jaw_parts(
    key: &str,
    geometry: &crate::geometry::UrdfGeometry,
    hanging: &[(String, Hanging)],
) -> (Vec<JawPart>, [Vec<JawPart>; 2]) {
    type Parts = (Vec<JawPart>, [Vec<JawPart>; 2]);
    static KNOWN: OnceLock<Mutex<BTreeMap<String, Parts>>> = OnceLock::new();
    let known = KNOWN.get_or_init(Default::default);
    if let Some(parts) = known.lock().unwrap_or_else(|e| e.into_inner()).get(key) {
        return parts.clone();
    }
    let mut statics = Vec::new();
    let mut jaws: [Vec<JawPart>; 2] = [Vec::new(), Vec::new()];
    for (link, (jaw, pose)) in hanging {
        let Some(lp) = geometry.links.iter().find(|l| &l.link == link) else {
            continue;
        };
        let Some(part) = JawPart::new(link, lp.placed(pose)) else {
            continue;
        };
        match jaw {
            None => statics.push(part),
            Some(k) => jaws[*k].push(part),
        }
    }
    let parts = (statics, jaws);
    known
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key.to_string(), parts.clone());
    parts
}
