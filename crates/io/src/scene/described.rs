//! A `[[robot]]` given by its robot description (`urdf`): the arm as the planner uses it.

use std::path::{Path, PathBuf};

use nalgebra::Isometry3;
use pregrasp_robot::{ArmDescription, GripperState, MAX_ARM_SHAPES, MAX_GRIPPER_SHAPES};
use pregrasp_urdf::{
    describe_arm_from, describe_gripper, GeometryOptions, LazyGeometry, UrdfArm, UrdfError,
    UR_MATCH_TOLERANCE,
};

use super::raw::Str;
use super::validate::Cx;
use super::{RobotSpec, SceneError, UrdfRef};

/// A robot description as the scene read it, kept for its gripper (`gripper = "urdf"`): the
/// arm, and its collision geometry if describing the arm loaded it.
pub(super) struct Source {
    arm: UrdfArm,
    geometry: LazyGeometry,
}

impl Cx {
    /// The arm of robot description `entry` (relative to the scene's folder) from its base
    /// link to its tool link, the joints `held` still: its reference, the arm, and the base
    /// link → arm base transform, and the description read ([`Source`]). A Universal Robots
    /// arm is the built-in model (its base the
    /// DH Base, the gripper at the DH flange); any other six-joint arm (or seven-joint arm
    /// with one joint held) is taken from the description, its collision geometry from the
    /// meshes (`pregrasp_urdf::describe_arm`), the gripper at the tool link.
    pub(super) fn urdf_arm(
        &self,
        entry: String,
        (base_link, tool_link): (Option<Str>, Option<Str>),
        (held, allowed): (&[(String, f64)], &[[String; 2]]),
        key: &str,
        file: &Path,
    ) -> Result<(UrdfRef, ArmDescription, Isometry3<f64>, Source), SceneError> {
        let at = format!("{key}.urdf");
        let path = match file.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir.join(&entry),
            _ => PathBuf::from(&entry),
        };
        let arm = UrdfArm::load(
            &path,
            base_link.as_ref().map(|Str(b)| b.as_str()),
            tool_link.as_ref().map(|Str(t)| t.as_str()),
        )
        .map_err(|e| self.err(&at, e.to_string()))?;
        let Some(ur) = arm.ur else {
            let held: Vec<(&str, f64)> = held.iter().map(|(j, v)| (j.as_str(), *v)).collect();
            let pairs: Vec<(&str, &str)> = allowed
                .iter()
                .map(|[a, b]| (a.as_str(), b.as_str()))
                .collect();
            let geometry = LazyGeometry::for_arm(&arm, GeometryOptions::default());
            let described = describe_arm_from(&arm, &held, &pairs, &geometry).map_err(|e| {
                let at = match e {
                    UrdfError::HeldJoint { .. } => format!("{key}.hold"),
                    UrdfError::UnknownLink { .. } => format!("{key}.allow_collisions"),
                    _ => at.clone(),
                };
                self.err(&at, e.to_string())
            })?;
            let urdf = UrdfRef {
                path,
                entry,
                joint_names: described.joint_names.to_vec(),
                held: held.iter().map(|(j, v)| (j.to_string(), *v)).collect(),
                allowed: allowed.to_vec(),
                base_link: arm.base_link.clone(),
                tool_link: arm.tool_link.clone(),
            };
            let source = Source { arm, geometry };
            return Ok((urdf, described, Isometry3::identity(), source));
        };
        if !allowed.is_empty() {
            let message = format!(
                "{}: the arm is a {}, whose self-collision pairs are built in",
                path.display(),
                ur.model
            );
            return Err(self.err(&format!("{key}.allow_collisions"), message));
        }
        if let Some((joint, _)) = held.first() {
            let message = format!(
                "{}: {joint}: the arm is a {} (six joints, all driven): nothing to hold",
                path.display(),
                ur.model
            );
            return Err(self.err(&format!("{key}.hold"), message));
        }
        let flange_offset = ur
            .tool
            .translation
            .vector
            .norm()
            .max(ur.tool.rotation.angle());
        if flange_offset > UR_MATCH_TOLERANCE {
            let message = format!(
                "{}: the gripper goes on the flange (tool0), but tool link {} is {:.4} m / \
                 {:.4} rad from it; give tool_link = \"tool0\"",
                path.display(),
                arm.tool_link,
                ur.tool.translation.vector.norm(),
                ur.tool.rotation.angle()
            );
            return Err(self.err(&at, message));
        }
        let urdf = UrdfRef {
            path,
            entry,
            joint_names: arm
                .chain
                .joint_names()
                .iter()
                .map(|n| n.to_string())
                .collect(),
            held: Vec::new(),
            allowed: Vec::new(),
            base_link: arm.base_link.clone(),
            tool_link: arm.tool_link.clone(),
        };
        let (model, base) = (ur.model, ur.base);
        let source = Source {
            geometry: LazyGeometry::for_arm(&arm, GeometryOptions::default()),
            arm,
        };
        Ok((urdf, ArmDescription::ur(model), base, source))
    }

    /// The jaw gripper below the tool link of the description the scene read (`source`), its
    /// tool points at `precision` and `power` (flange `z`; defaults: the jaws' faces' middle).
    /// Errors at `at`.
    pub(super) fn urdf_jaws(
        &self,
        source: Source,
        precision: Option<f64>,
        power: Option<f64>,
        at: &str,
    ) -> Result<std::sync::Arc<pregrasp_robot::JawGripper>, SceneError> {
        describe_gripper(&source.arm, precision, power, &source.geometry)
            .map(std::sync::Arc::new)
            .map_err(|e| self.err(at, e.to_string()))
    }

    /// Refuses a robot whose arm and gripper have more collision shapes than an arm of the
    /// collision model holds ([`MAX_ARM_SHAPES`], the gripper at most [`MAX_GRIPPER_SHAPES`]),
    /// naming the robot and the first shape that does not fit: planning it could not start.
    /// (A description's arm is merged down to fit, `pregrasp_urdf::describe_arm`; a gripper
    /// of many parts can still be too many.)
    pub(super) fn shapes_fit(&self, robot: &RobotSpec, key: &str) -> Result<(), SceneError> {
        let model = robot.gripper_model();
        let links = &robot.arm.geometry.links;
        // Counted first: the shapes are posed only to name the one that does not fit.
        let grips = model.shape_count();
        let count = links.len() + grips;
        let (over, max, whose) = if grips > MAX_GRIPPER_SHAPES {
            (
                links.len() + MAX_GRIPPER_SHAPES,
                MAX_GRIPPER_SHAPES,
                "gripper",
            )
        } else if count > MAX_ARM_SHAPES {
            (MAX_ARM_SHAPES, MAX_ARM_SHAPES, "arm with its gripper")
        } else {
            return Ok(());
        };
        let gripper = model.shapes(GripperState::Open);
        let names: Vec<&str> = links.iter().chain(&gripper).map(|l| l.name).collect();
        let at = match (whose, &robot.urdf) {
            ("gripper", _) => "gripper",
            (_, Some(_)) => "urdf",
            (_, None) => "model",
        };
        let message = format!(
            "robot `{}`: the {whose} has {} collision shapes, at most {max} are supported \
             (`{}` is one too many)",
            robot.name,
            if whose == "gripper" {
                gripper.len()
            } else {
                names.len()
            },
            names[over]
        );
        Err(self.err(&format!("{key}.{at}"), message))
    }
}
