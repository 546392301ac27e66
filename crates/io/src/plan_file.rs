//! The plan file (`plan.json`, format `pregrasp.plan/1`): serde types that mirror
//! `docs/plan-format.md` field for field, plus atomic writing; reading and
//! validating is [`crate::plan_read`].
//!
//! Field order here is the order in the file; keep it stable, plans must be byte-for-byte
//! reproducible.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use serde::{Deserialize, Serialize};

pub use crate::output::OutputError;
pub use crate::plan_terms::{
    GraspKind, GripVerdict, Outcome, PlanStatus, RobotModel, RotationDirection, SegmentKind,
    SegmentName,
};

/// The `format` value of every plan file this crate writes.
pub const PLAN_FORMAT: &str = "pregrasp.plan/1";

/// A pose in JSON: `{ "xyz": [x, y, z], "quat_xyzw": [x, y, z, w] }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoseJson {
    pub xyz: [f64; 3],
    pub quat_xyzw: [f64; 4],
}

impl From<&Isometry3<f64>> for PoseJson {
    /// Quaternions are written with `w >= 0` so that equal rotations serialise equally.
    fn from(pose: &Isometry3<f64>) -> Self {
        let (xyz, quat_xyzw) = pregrasp_model::pose_numbers(pose);
        PoseJson { xyz, quat_xyzw }
    }
}

impl PoseJson {
    /// The pose as an isometry (the quaternion is normalised).
    pub fn to_isometry(&self) -> Isometry3<f64> {
        let [x, y, z, w] = self.quat_xyzw;
        let q = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
        Isometry3::from_parts(Translation3::new(self.xyz[0], self.xyz[1], self.xyz[2]), q)
    }
}

/// The whole plan file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanFile {
    pub format: String,
    pub scene: SceneRef,
    #[serde(with = "crate::plan_terms::word")]
    pub status: PlanStatus,
    pub reason: Option<String>,
    pub support_height: f64,
    pub planner: PlannerJson,
    pub object: ObjectJson,
    pub robots: Vec<RobotJson>,
    pub grasps: GraspsJson,
    pub candidates: Vec<CandidateJson>,
    pub plans: Vec<PlanJson>,
    /// Wall-clock milliseconds per stage: `axes`, `poses`, `paths`, `total` (more keys allowed).
    pub timing_ms: std::collections::BTreeMap<String, f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneRef {
    pub name: Option<String>,
    /// The scene file as it was given (relative to the directory the planner ran in).
    pub file: String,
    /// (Extension) The same file relative to the folder of the plan file, as the command that
    /// wrote the plan saw it ([`PlanFile::locate_inputs`]): readers try it when `file` does not
    /// exist as given, so a plan moved together with its scene and mesh, or opened from another
    /// folder, finds them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file_from_plan: Option<String>,
}

/// Every `[planner]` key of the scene format with the value used.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannerJson {
    pub support_distance: f64,
    pub min_axis_length: f64,
    pub step_deg: f64,
    pub max_angle_deg: f64,
    pub weight_length: f64,
    pub weight_angle: f64,
    pub extra_steps: u32,
    pub min_grasp_axis_distance: f64,
    pub lift: f64,
    pub approach_distance: f64,
    pub max_joint_step_deg: f64,
    pub seed: u64,
    /// Clearance of arm links and grippers from everything they must not touch (m). Absent in
    /// plans of older versions (then the default, 0.005, applies).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub link_clearance: Option<f64>,
    /// Clearance of a grasping gripper from the support (m); absent in older plans (0.002).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finger_support_clearance: Option<f64>,
    /// (Extension) `[planner] robustness_samples` and its error level, when the ranking by
    /// robustness was on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robustness_samples: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robustness_pos: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robustness_yaw_deg: Option<f64>,
    /// (Extension) `[planner] power_hold` when it is not `"auto"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub power_hold: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectJson {
    pub mesh: String,
    /// (Extension) `mesh` relative to the plan file's folder (see [`SceneRef::file_from_plan`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh_from_plan: Option<String>,
    pub scale: f64,
    /// P_init, including the lift.
    pub initial_pose: PoseJson,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotJson {
    pub name: String,
    #[serde(with = "crate::plan_terms::word")]
    pub model: RobotModel,
    pub base: PoseJson,
    pub joint_names: Vec<String>,
    pub start: [f64; 6],
    /// In the flange frame.
    pub precision_point: PoseJson,
    /// In the flange frame.
    pub power_point: PoseJson,
    /// The robot description the arm was read from, when the scene names one (extension).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<UrdfJson>,
    /// The gripper (extension): `"urdf"` for the jaw gripper of the description in `urdf`;
    /// absent for the Robotiq 2F-85.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gripper: Option<String>,
}

/// `robots[].urdf`: the scene's robot description of the arm (paths as the scene wrote them,
/// relative to the scene file), and the links the arm runs between.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UrdfJson {
    pub file: String,
    pub base_link: String,
    pub tool_link: String,
    /// Joints held still while the planner drives the other six (rad), by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub held: BTreeMap<String, f64>,
    /// Link pairs not checked for self-collision (the scene's `allow_collisions`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub allow_collisions: Vec<[String; 2]>,
}

/// Grasp poses in the object frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraspsJson {
    pub power: [PoseJson; 2],
    pub support: PoseJson,
    /// (Extension) How the grasps were found when the scene asked for `mode = "auto"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub auto: Option<AutoGraspsJson>,
    /// (Extension) How far (m) each power grasp (`power[0]`, `power[1]`) was moved deeper
    /// along its approach from the scene's, so the bar sits against the palm (0: as given);
    /// absent when neither moved. `power` holds the moved grasps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seated: Option<[f64; 2]>,
    /// (Extension) How far (m) each power grasp was moved out along its approach from the
    /// scene's, so that the pads pinch the bar at the fingertips: the planner holds a grasp
    /// there where the pads pinch its bar, and where the closing at the scene's grasp cages the
    /// bar, closes on one side or wraps it only short of the palm (0: not moved); absent when
    /// neither moved. `power` holds the moved grasps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fingertips: Option<[f64; 2]>,
    /// (Extension) How far (m) each power grasp was moved across its bar (its own `x` axis,
    /// the closing direction) from the scene's, onto the bar's mid-plane, so that both pads
    /// meet the bar together: every 2F-85 power grasp more than 2 mm off it, and a grasp held
    /// at the fingertips however little (0: not moved); absent when neither moved. `power`
    /// holds the moved grasps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centred: Option<[f64; 2]>,
    /// (Extension) How far (m) each power grasp was slid along its bar (its own `y` axis) from
    /// the scene's, so that the line through both passes nearer the part's centre of mass: the
    /// scene's grasps could not carry the part, or left its weight hanging more than 0.1 m off
    /// their line. Absent when they were kept. `power` holds the slid grasps (then seated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slid: Option<[f64; 2]>,
}

/// The grasp search of an auto scene (`[grasps] mode = "auto"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AutoGraspsJson {
    /// Graspable bar sites found on the mesh.
    pub sites: usize,
    /// Grasp sets built from them (per rotation axis), how many went through the pipeline
    /// (best ranked first), and how many of those planned.
    pub sets: usize,
    pub tried: usize,
    pub planned: usize,
    /// Index of the chosen set among the tried ones (best plan score), if any planned.
    pub chosen: Option<usize>,
    /// Bar widths (m) across the chosen grasps: support, `power[0]`, `power[1]`.
    pub widths: [f64; 3],
    /// Which grasps the scene pinned.
    pub support_pinned: bool,
    pub power_pinned: bool,
}

/// One (axis, direction) pair of Algorithm 1, with what became of it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CandidateJson {
    pub id: usize,
    /// World endpoints at P_init.
    pub axis: [[f64; 3]; 2],
    /// `ccw`: positive rotation about `axis[1] - axis[0]` (right-hand rule); `cw`: negative.
    #[serde(with = "crate::plan_terms::word")]
    pub direction: RotationDirection,
    pub length: f64,
    pub theta_max: f64,
    pub score: f64,
    pub theta_goal: Option<f64>,
    pub outcome: Outcome,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanJson {
    pub candidate: usize,
    pub score: f64,
    pub master: String,
    pub supportive: String,
    pub object_goal_pose: PoseJson,
    pub segments: Vec<SegmentJson>,
    /// (Extension) The quasi-static check of `rot`: will the pinch hold the part? Absent in
    /// files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physics: Option<PhysicsJson>,
    /// (Extension) How this plan's rotation axis survives placement errors of the part
    /// (`pregrasp robustness --write-plan`, or `[planner] robustness_samples`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robustness: Option<RobustnessJson>,
}

/// A plan's `robustness` object: Monte-Carlo over placement errors, each sample re-planned.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobustnessJson {
    /// Samples per level and the seed they were drawn with.
    pub samples: usize,
    pub seed: u64,
    pub levels: Vec<RobustnessLevelJson>,
    /// `[pos (m), yaw (degrees)]`: the largest position error and the largest yaw error among
    /// the tested levels at which the plan's axis planned again in every sample; `null` when
    /// there is no such level.
    pub tolerance: Option<[f64; 2]>,
}

/// One placement error level: offsets uniform in ±`pos` (m) along world x and y and ±`yaw_deg`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobustnessLevelJson {
    pub pos: f64,
    pub yaw_deg: f64,
    /// Share of the samples in which the plan's rotation axis planned again.
    pub share: f64,
}

/// A plan's `physics` object: the quasi-static check of its rotation (`docs/physics.md`). Forces
/// in newtons; friction use is |tangential force| / (μ · normal force), 1 = at the cone's edge.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicsJson {
    #[serde(with = "crate::plan_terms::word")]
    pub verdict: GripVerdict,
    /// The part's mass (kg) and where it comes from.
    pub mass: f64,
    pub mass_source: String,
    pub mu_pad: f64,
    pub mu_support: f64,
    pub safety_factor: f64,
    /// The largest minimum grip force over the states of `rot` (N), when every state is held.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grip_force_min: Option<f64>,
    /// `safety_factor × grip_force_min` (N).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grip_force_required: Option<f64>,
    /// The 2F-85 force to set for the support grasp: `grip_force_required` clamped to
    /// [20, 235] N; absent when the plan does not hold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grip_force_recommended: Option<f64>,
    /// Largest friction use at the pads, squeezing with the recommended force (with 235 N when
    /// the plan does not hold).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad_friction_use: Option<f64>,
    /// Largest friction use at the support contacts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support_friction_use: Option<f64>,
    /// Largest total normal force of the support on the part (N).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support_normal_max: Option<f64>,
    /// Time into `rot` (s) and rotation from P_init (degrees) of the worst state.
    pub worst_t: f64,
    pub worst_theta_deg: f64,
    /// States checked (the points of `rot` and the ones interpolated between them).
    pub states: usize,
    /// What the verdict alone does not say (e.g. the edge slides 5.8 mm along the support).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentJson {
    #[serde(with = "crate::plan_terms::word")]
    pub name: SegmentName,
    pub robot: String,
    #[serde(with = "crate::plan_terms::word")]
    pub kind: SegmentKind,
    #[serde(with = "crate::plan_terms::word")]
    pub grasp: GraspKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retreat_to: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach_from: Option<usize>,
    /// Gap (m) between the pad faces of this segment's gripper once it has closed on the part
    /// (at its last point; throughout `rot`): the width of the part it holds. Informative — the
    /// checker measures it again from the mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grip_width: Option<f64>,
    /// The grip force (N) a closing segment (`sup1`, `mas1`, `sup2`) closes its gripper with,
    /// the safety factor included: for `sup1` the pinch's `physics.grip_force_recommended`.
    /// Exporters command it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grip_force: Option<f64>,
    /// Where this segment's gripper fingers stopped closing on the part (same instants as
    /// `grip_width`): informative, for viewers and exporters to draw and command the fingers
    /// as they really hold it (curled around a bar in a power grasp).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fingers: Option<FingersJson>,
    /// Where the pads bear on the part once closed (`rot`): informative, for the grip check.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad_contact: Option<PadContactJson>,
    pub points: Vec<PointJson>,
}

/// Where the two pads of a closed gripper bear on the part: the patches of their contact faces
/// that lie on its surface. `center`: midway between the two patches' centroids, in the frame
/// of the segment's grasp (the tool point: the precision point for `support`), m;
/// `torsion_radius`: the smaller patch's mean distance from its centroid (m), the `e` of the
/// soft-finger model (twist about the pad normal ≤ μ·N·e); `area`: each patch's area (m²),
/// `[+x pad, −x pad]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PadContactJson {
    pub center: [f64; 3],
    pub torsion_radius: f64,
    pub area: [f64; 2],
}

impl SegmentJson {
    /// The state `gripper` holds the part with in this segment, as the file records it: its
    /// `fingers` (the 2F-85's), else `gripper` closed in parallel to its `grip_width`; `None`
    /// if it records neither.
    pub fn held_fingers(
        &self,
        gripper: &pregrasp_robot::Gripper,
    ) -> Option<pregrasp_robot::GripperState> {
        use pregrasp_robot::{FingerPair, GripperState};
        match (&self.fingers, self.grip_width) {
            (Some(f), _) => Some(GripperState::Closed(FingerPair {
                driver: f.driver,
                spring_link: f.spring_link,
            })),
            (None, Some(w)) => Some(gripper.at_gap(w)),
            (None, None) => None,
        }
    }
}

/// The 2F-85's finger joints holding the part (rad, MuJoCo Menagerie's joint angles): the
/// common driver (outer knuckle) angle and each finger's spring-link (inner knuckle) angle,
/// `[+x finger, −x finger]` of the tool frame. Equal spring-link angles on the coupler's stop
/// are the parallel closing; smaller ones mean the finger tips curled around the part.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FingersJson {
    pub driver: f64,
    pub spring_link: [f64; 2],
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointJson {
    pub t: f64,
    pub q: [f64; 6],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object_pose: Option<PoseJson>,
}

/// Errors reading or writing a plan file; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum PlanFileError {
    #[error("{path}: cannot read: {error}")]
    Read { path: String, error: std::io::Error },
    #[error("{path}: not a pregrasp plan file: {error}")]
    Parse {
        path: String,
        error: serde_json::Error,
    },
    #[error("{path}: format is {found:?}, expected {PLAN_FORMAT:?}")]
    Format { path: String, found: String },
    #[error("{path}: not a valid plan file: {problem}")]
    Invalid { path: String, problem: String },
}

/// A path a plan file names (`object.mesh`, `scene.file`): as written (relative to the current
/// directory), else relative to the plan file's directory — how `check`, `view`, `export`,
/// `physics`, `replan` and the Python package find a plan's mesh and scene when the file does
/// not say where they are from its own folder ([`PlanFile::scene_path`],
/// [`PlanFile::mesh_path`] try that first).
pub fn resolve_beside(plan_path: &Path, entry: &str) -> PathBuf {
    let given = PathBuf::from(entry);
    if given.is_absolute() || given.exists() {
        return given;
    }
    match plan_path.parent() {
        Some(dir) if dir.join(&given).exists() => dir.join(given),
        _ => given,
    }
}

/// An input of the plan file read from `plan_path`: the path as given when it exists (as
/// before the extension), else its path relative to the plan's folder when the file records
/// one and it exists, else [`resolve_beside`] of the path as given.
fn resolve_input(plan_path: &Path, given: &str, from_plan: Option<&str>) -> PathBuf {
    if Path::new(given).exists() {
        return PathBuf::from(given);
    }
    if let Some(rel) = from_plan {
        let dir = plan_path.parent().unwrap_or(Path::new(""));
        let there = dir.join(rel);
        if there.is_file() {
            return there;
        }
    }
    resolve_beside(plan_path, given)
}

/// `path` made absolute against the current directory and normalised lexically (`.` dropped,
/// `..` taken back), without touching the filesystem.
fn lexical_absolute(path: &Path) -> Option<PathBuf> {
    use std::path::Component;
    let absolute = std::path::absolute(path).ok()?;
    let mut out = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    Some(out)
}

/// `target` relative to the folder `from` (both as the current directory sees them), with `/`
/// between components; `None` when there is no such path (another drive) or it is not UTF-8.
fn relative_path(from: &Path, target: &Path) -> Option<String> {
    use std::path::Component;
    let (from, target) = (lexical_absolute(from)?, lexical_absolute(target)?);
    let (a, b): (Vec<Component>, Vec<Component>) =
        (from.components().collect(), target.components().collect());
    if a.first() != b.first() {
        return None;
    }
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut parts: Vec<String> = vec!["..".to_string(); a.len() - common];
    for c in &b[common..] {
        parts.push(c.as_os_str().to_str()?.to_string());
    }
    Some(if parts.is_empty() {
        ".".to_string()
    } else {
        parts.join("/")
    })
}

impl PlanFile {
    /// Records where the scene and the mesh are from the folder the file is about to be written
    /// to (`plan_path`): `scene.file_from_plan`, `object.mesh_from_plan`. Call it with the path
    /// the file will have; the paths it names are taken as the current directory sees them.
    pub fn locate_inputs(&mut self, plan_path: &Path) {
        let dir = match plan_path.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir,
            _ => Path::new("."),
        };
        self.scene.file_from_plan = relative_path(dir, Path::new(&self.scene.file));
        self.object.mesh_from_plan = relative_path(dir, Path::new(&self.object.mesh));
    }

    /// The scene file of a plan read from `plan_path`: as given when it exists, else from the
    /// plan's folder when the file records where, else beside the plan ([`resolve_beside`]).
    pub fn scene_path(&self, plan_path: &Path) -> PathBuf {
        resolve_input(
            plan_path,
            &self.scene.file,
            self.scene.file_from_plan.as_deref(),
        )
    }

    /// The mesh of a plan read from `plan_path`, found as [`PlanFile::scene_path`] finds the
    /// scene.
    pub fn mesh_path(&self, plan_path: &Path) -> PathBuf {
        resolve_input(
            plan_path,
            &self.object.mesh,
            self.object.mesh_from_plan.as_deref(),
        )
    }

    /// The file as pretty JSON with a trailing newline (deterministic for equal values).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("plan file serialises");
        s.push('\n');
        s
    }

    /// Writes the file atomically: to a temporary file beside `path`, then renamed over it,
    /// so a reader never sees half a plan and a failed write leaves nothing behind
    /// ([`crate::output`]: a device is written through, never replaced).
    pub fn write_atomic(&self, path: &Path) -> Result<(), OutputError> {
        write_atomic(path, self.to_json().as_bytes())
    }
}

/// Writes `bytes` to `path` as a command's one output ([`crate::output::write_one`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    crate::output::write_one(path, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_are_lexical_and_walk_up_as_needed() {
        let rel = |from: &str, to: &str| relative_path(Path::new(from), Path::new(to));
        assert_eq!(rel("/a/b", "/a/c/d.toml").as_deref(), Some("../c/d.toml"));
        assert_eq!(rel("/a/b", "/a/b/d.toml").as_deref(), Some("d.toml"));
        assert_eq!(rel("/a/b/c", "/a/x.stl").as_deref(), Some("../../x.stl"));
        assert_eq!(
            rel("/a/./b/../b", "/a/b/m/./n.stl").as_deref(),
            Some("m/n.stl")
        );
        assert_eq!(rel("/a", "/a").as_deref(), Some("."));
        // Relative paths are taken against the current directory, on both sides alike.
        assert_eq!(
            rel("out", "parts/p.toml").as_deref(),
            Some("../parts/p.toml")
        );
    }
}
