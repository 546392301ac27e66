//! The arms a plan file was planned for, as the planner uses them: a built-in model by its
//! name, or the arm of the robot description the plan names (`robots[].model = "urdf"`),
//! loaded as the scene loaded it (`pregrasp_urdf::describe_arm`, the same joints held).

use std::path::{Path, PathBuf};

use pregrasp_robot::{ArmDescription, Gripper, Gripper2F85};
use pregrasp_urdf::{describe_arm_from, describe_gripper, GeometryOptions, LazyGeometry, UrdfArm};

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
        self.per_robot(plan_path, |robot, scene| {
            arm_of(robot, &Source::read(robot, scene, arm_described(robot))?)
        })
    }

    /// Both arms' grippers, with the file's tool points: the Robotiq 2F-85, or (`gripper =
    /// "urdf"`) the jaws of the robot's description, found as [`PlanFile::arm_descriptions`]
    /// finds it.
    pub fn grippers(&self, plan_path: Option<&Path>) -> Result<[Gripper; 2], String> {
        self.per_robot(plan_path, |robot, scene| {
            gripper_of(
                robot,
                &Source::read(robot, scene, gripper_described(robot))?,
            )
        })
    }

    /// Both robots' arms and grippers ([`PlanFile::arm_descriptions`], [`PlanFile::grippers`]),
    /// each robot's description read once for both.
    pub fn arms_and_grippers(
        &self,
        plan_path: Option<&Path>,
    ) -> Result<([ArmDescription; 2], [Gripper; 2]), String> {
        let [a, b] = self.per_robot(plan_path, |robot, scene| {
            let wanted = arm_described(robot) || gripper_described(robot);
            let source = Source::read(robot, scene, wanted)?;
            Ok((arm_of(robot, &source)?, gripper_of(robot, &source)?))
        })?;
        Ok(([a.0, b.0], [a.1, b.1]))
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

/// The robot description a `robots[]` entry names, read when its arm or its gripper comes
/// from it: the arm from its base link to its tool link, where it was found, and its collision
/// geometry (loaded once, when first needed).
struct Source {
    described: Option<(UrdfArm, PathBuf)>,
    geometry: LazyGeometry,
}

impl Source {
    /// `robot`'s description, located from the scene at `scene`, when `wanted` (it names one).
    fn read(robot: &RobotJson, scene: &Path, wanted: bool) -> Result<Source, String> {
        let described = match (&robot.urdf, wanted) {
            (Some(urdf), true) => {
                let path = description_path(scene, &urdf.file);
                let arm = UrdfArm::load(&path, Some(&urdf.base_link), Some(&urdf.tool_link))
                    .map_err(|e| e.to_string())?;
                Some((arm, path))
            }
            _ => None,
        };
        let geometry = match &described {
            Some((arm, _)) => LazyGeometry::for_arm(arm, GeometryOptions::default()),
            None => LazyGeometry::new(GeometryOptions::default()),
        };
        Ok(Source {
            described,
            geometry,
        })
    }
}

/// Whether `robot`'s arm comes from its description.
fn arm_described(robot: &RobotJson) -> bool {
    robot.model == RobotModel::Described
}

/// Whether `robot`'s gripper comes from its description.
fn gripper_described(robot: &RobotJson) -> bool {
    robot.gripper.as_deref() == Some("urdf")
}

/// The gripper of one `robots[]` entry, its description (if any) read into `source`.
fn gripper_of(robot: &RobotJson, source: &Source) -> Result<Gripper, String> {
    let (precision, power) = (robot.precision_point.xyz[2], robot.power_point.xyz[2]);
    match robot.gripper.as_deref() {
        None | Some("robotiq_2f85") => Ok(Gripper2F85 {
            precision_point_z: precision,
            power_point_z: power,
        }
        .into()),
        Some("urdf") => {
            let Some((arm, _)) = &source.described else {
                return Err("gripper is \"urdf\" but the robot names no description".into());
            };
            let jaws = describe_gripper(arm, Some(precision), Some(power), &source.geometry)
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

/// The arm of one `robots[]` entry, its description (if any) read into `source`.
fn arm_of(robot: &RobotJson, source: &Source) -> Result<ArmDescription, String> {
    match robot.model {
        RobotModel::Builtin(model) => Ok(ArmDescription::ur(model)),
        RobotModel::Described => {
            let (Some(urdf), Some((arm, path))) = (&robot.urdf, &source.described) else {
                return Err("model is \"urdf\" but the robot names no description (urdf)".into());
            };
            let held: Vec<(&str, f64)> = urdf.held.iter().map(|(j, v)| (j.as_str(), *v)).collect();
            let allowed: Vec<(&str, &str)> = urdf
                .allow_collisions
                .iter()
                .map(|[a, b]| (a.as_str(), b.as_str()))
                .collect();
            let described = describe_arm_from(arm, &held, &allowed, &source.geometry)
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
