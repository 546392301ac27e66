//! The arms a plan file was planned for, as the planner uses them: a built-in model by its
//! name, or the arm of the robot description the plan names (`robots[].model = "urdf"`),
//! loaded as the scene loaded it (`pregrasp_urdf::describe_arm`, the same joints held).

use std::path::{Path, PathBuf};

use pregrasp_robot::{ArmDescription, Gripper, Gripper2F85};
use pregrasp_urdf::{describe_arm, describe_gripper, GeometryOptions, UrdfArm};

use crate::plan_file::{PlanFile, RobotJson, RobotModel};

impl PlanFile {
    /// Both arms of the file. `plan_path`, where the file was read from, finds a robot
    /// description as the scene named it (relative to the scene's folder, the scene found as
    /// [`PlanFile::scene_path`] finds it); without it the scene path is taken as given.
    /// Errors name the robot and what could not be loaded.
    pub fn arm_descriptions(
        &self,
        plan_path: Option<&Path>,
    ) -> Result<[ArmDescription; 2], String> {
        self.per_robot(plan_path, arm_of)
    }

    /// Both arms' grippers, with the file's tool points: the Robotiq 2F-85, or (`gripper =
    /// "urdf"`) the jaws of the robot's description, found as [`PlanFile::arm_descriptions`]
    /// finds it.
    pub fn grippers(&self, plan_path: Option<&Path>) -> Result<[Gripper; 2], String> {
        self.per_robot(plan_path, gripper_of)
    }

    /// `build(robot, scene path)` of both robots, errors prefixed by the robot.
    fn per_robot<T>(
        &self,
        plan_path: Option<&Path>,
        build: impl Fn(&RobotJson, &Path) -> Result<T, String>,
    ) -> Result<[T; 2], String> {
        if self.robots.len() != 2 {
            return Err(format!("expected 2 robots, found {}", self.robots.len()));
        }
        let scene = match plan_path {
            Some(p) => self.scene_path(p),
            None => PathBuf::from(&self.scene.file),
        };
        let one =
            |i: usize| build(&self.robots[i], &scene).map_err(|e| format!("robots[{i}]: {e}"));
        Ok([one(0)?, one(1)?])
    }
}

/// The gripper of one `robots[]` entry; `scene` locates its description.
pub fn gripper_of(robot: &RobotJson, scene: &Path) -> Result<Gripper, String> {
    let (precision, power) = (robot.precision_point.xyz[2], robot.power_point.xyz[2]);
    match robot.gripper.as_deref() {
        None | Some("robotiq_2f85") => Ok(Gripper2F85 {
            precision_point_z: precision,
            power_point_z: power,
        }
        .into()),
        Some("urdf") => {
            let Some(urdf) = &robot.urdf else {
                return Err("gripper is \"urdf\" but the robot names no description".into());
            };
            let arm = UrdfArm::load(
                &description_path(scene, &urdf.file),
                Some(&urdf.base_link),
                Some(&urdf.tool_link),
            )
            .map_err(|e| e.to_string())?;
            let jaws = describe_gripper(
                &arm,
                Some(precision),
                Some(power),
                &GeometryOptions::default(),
            )
            .map_err(|e| e.to_string())?;
            Ok(Gripper::Jaws(std::sync::Arc::new(jaws)))
        }
        Some(other) => Err(format!(
            "unknown gripper {other:?} (expected \"robotiq_2f85\" or \"urdf\")"
        )),
    }
}

/// The path of a description `file` named relative to the folder of `scene`.
fn description_path(scene: &Path, file: &str) -> PathBuf {
    match scene.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(file),
        _ => PathBuf::from(file),
    }
}

/// The arm of one `robots[]` entry; `scene` locates its description.
fn arm_of(robot: &RobotJson, scene: &Path) -> Result<ArmDescription, String> {
    match robot.model {
        RobotModel::Builtin(model) => Ok(ArmDescription::ur(model)),
        RobotModel::Described => {
            let Some(urdf) = &robot.urdf else {
                return Err("model is \"urdf\" but the robot names no description (urdf)".into());
            };
            let path = description_path(scene, &urdf.file);
            let arm = UrdfArm::load(&path, Some(&urdf.base_link), Some(&urdf.tool_link))
                .map_err(|e| e.to_string())?;
            let held: Vec<(&str, f64)> = urdf.held.iter().map(|(j, v)| (j.as_str(), *v)).collect();
            let allowed: Vec<(&str, &str)> = urdf
                .allow_collisions
                .iter()
                .map(|[a, b]| (a.as_str(), b.as_str()))
                .collect();
            let described = describe_arm(&arm, &held, &allowed, &GeometryOptions::default())
                .map_err(|e| e.to_string())?;
            if described.joint_names.as_slice() != robot.joint_names.as_slice() {
                return Err(format!(
                    "joint_names {:?} are not the driven joints of {} ({:?})",
                    robot.joint_names,
                    path.display(),
                    described.joint_names
                ));
            }
            Ok(described)
        }
    }
}
