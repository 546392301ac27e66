//! The arms a plan file was planned for, as the planner uses them: a built-in model by its
//! name, or the arm of the robot description the plan names (`robots[].model = "urdf"`),
//! loaded as the scene loaded it (`pregrasp_urdf::describe_arm`, the same joints held).

use std::path::{Path, PathBuf};

use pregrasp_robot::ArmDescription;
use pregrasp_urdf::{describe_arm, GeometryOptions, UrdfArm};

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
        if self.robots.len() != 2 {
            return Err(format!("expected 2 robots, found {}", self.robots.len()));
        }
        let scene = match plan_path {
            Some(p) => self.scene_path(p),
            None => PathBuf::from(&self.scene.file),
        };
        let one =
            |i: usize| arm_of(&self.robots[i], &scene).map_err(|e| format!("robots[{i}]: {e}"));
        Ok([one(0)?, one(1)?])
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
            let path = match scene.parent() {
                Some(dir) if !dir.as_os_str().is_empty() => dir.join(&urdf.file),
                _ => PathBuf::from(&urdf.file),
            };
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
