//! The scene file (`*.toml`, `docs/scene-format.md`): the planner's input.
//!
//! [`Scene::load`] reads and validates a whole scene and refuses anything unusable with one
//! [`SceneError`] whose message names the file and the key (`robot[1].model: ...`). Keys the
//! format does not list are not errors: they are returned as [`Scene::warnings`].
//!
//! Everything is stored in SI units: metres, radians, kilograms. Where the file may use a
//! `_deg` spelling (`rpy_deg`, `step_deg`, ...) the value is converted on load; the plain
//! spelling (`rpy`, `step`, ...) is in radians. Giving both spellings of one key is an error.
//!
//! Every number is checked for range as well as type: lengths lie within
//! ±[`MAX_COORDINATE`] of the origin, start joint angles within the model's joint limits
//! (the arm's `joint_limits`), gripper points between the 2F-85's palm and fingertips, and
//! every `[planner]` key within the range `docs/scene-format.md` gives it.
//!
//! The mesh itself is not read here (see [`crate::mesh_io::load_mesh`]); the scene only resolves
//! its path relative to the scene file's directory.
//!
//! Reading is two steps: `raw.rs` deserializes the text into structs that mirror the file
//! (type errors named by key path, unknown keys collected), and `validate.rs` turns those into
//! a [`Scene`] (missing keys, spellings given twice, ranges), where [`Scene::load`] and
//! [`Scene::from_str`] live.

mod described;
mod raw;
mod validate;

use std::path::PathBuf;

use nalgebra::Isometry3;
use pregrasp_robot::ArmDescription;

use crate::plan_file::PlannerJson;

/// The robot models with built-in kinematics and geometry.
pub const ROBOT_MODELS: [&str; 5] = ["ur3e", "ur5e", "ur10e", "ur16e", "ur5"];
/// The grippers: the built-in Robotiq 2F-85, or (`"urdf"`, only with `urdf`) the parallel-jaw
/// gripper the robot description carries below its tool link.
pub const GRIPPERS: [&str; 2] = ["robotiq_2f85", "urdf"];
/// Flange-to-precision-point distance of the Robotiq 2F-85 (m).
pub const DEFAULT_PRECISION_POINT_Z: f64 = 0.150;
/// Flange-to-power-point distance of the Robotiq 2F-85 (m).
pub const DEFAULT_POWER_POINT_Z: f64 = 0.115;
/// Range of `precision_point_z` and `power_point_z` for the Robotiq 2F-85 (m): from the top
/// of the palm (0.1008) to the fingertips of the closed gripper (0.1735), the span in which
/// fingers can hold anything (`docs/hardware-facts.md`).
pub const GRIPPER_POINT_RANGE: (f64, f64) = (0.1008, 0.1735);
/// Largest magnitude (m) of a world or object coordinate and of `support.height`. The arms
/// reach at most 1.3 m; a coordinate beyond this is a scene written in millimetres.
pub const MAX_COORDINATE: f64 = 100.0;

/// A validated scene. Poses map the child frame into the parent (`p_world = pose * p_object`).
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene file as given to the loader.
    pub file: PathBuf,
    pub name: Option<String>,
    /// World `z` of the support plane (m).
    pub support_height: f64,
    pub object: ObjectSpec,
    pub grasps: Grasps,
    /// `[[robot]]` entries in file order: `robots[0]` owns `grasps.power[0]`.
    pub robots: [RobotSpec; 2],
    pub planner: PlannerParams,
    /// `[physics]`: the quasi-static grip check of the rotation (every key optional).
    pub physics: PhysicsParams,
    /// One line per ignored key, e.g. `scene.toml: object.colour: unknown key (ignored)`, in
    /// key order (each table's keys alphabetically, depth first).
    pub warnings: Vec<String>,
}

/// `[object]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSpec {
    /// The scene file's directory joined with the `mesh` entry (not canonicalised).
    pub mesh_path: PathBuf,
    /// The `mesh` entry exactly as written in the file.
    pub mesh_entry: String,
    /// Mesh units to metres, > 0.
    pub scale: f64,
    /// The object frame in world as given (P_init is this raised by `planner.lift`).
    pub pose: Isometry3<f64>,
    /// kg, > 0, if given.
    pub mass: Option<f64>,
}

/// `[grasps]`, all in the object frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Grasps {
    /// G_p1 (for `robots[0]`) and G_p2 (for `robots[1]`).
    pub power: [Isometry3<f64>; 2],
    /// G_s, reached by whichever arm supports.
    pub support: Isometry3<f64>,
    /// (Extension) `mode = "auto"`: the grasps not given are found from the mesh
    /// (`pregrasp_planner::auto_grasps`); until then they are identity placeholders. `None`:
    /// hand-placed grasps (the default).
    pub auto: Option<AutoGrasps>,
}

/// Which grasps an auto scene pins (gives by hand).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AutoGrasps {
    /// `support` was given.
    pub support_pinned: bool,
    /// `power` was given (both poses).
    pub power_pinned: bool,
}

/// One `[[robot]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotSpec {
    pub name: String,
    /// The arm: a built-in model, or one from the robot description `urdf` names.
    pub arm: ArmDescription,
    /// The arm base frame in world: the controller's Base frame (DH frame 0). For an arm from
    /// a URDF, the scene's `base` (the base link's pose) composed with the base link → DH
    /// Base transform the URDF has.
    pub base: Isometry3<f64>,
    /// The robot description the arm was read from, when the scene names one (`urdf`).
    pub urdf: Option<UrdfRef>,
    /// Start joint angles (rad).
    pub start: [f64; 6],
    /// One of [`GRIPPERS`].
    pub gripper: String,
    /// The description's jaw gripper (`gripper = "urdf"`), its tool points those below.
    pub jaws: Option<std::sync::Arc<pregrasp_robot::JawGripper>>,
    /// Flange-to-precision-point distance along flange `z` (m).
    pub precision_point_z: f64,
    /// Flange-to-power-point distance along flange `z` (m).
    pub power_point_z: f64,
}

impl RobotSpec {
    /// The gripper on the flange, with this robot's tool points.
    pub fn gripper_model(&self) -> pregrasp_robot::Gripper {
        match &self.jaws {
            Some(j) => pregrasp_robot::Gripper::Jaws(j.clone()),
            None => pregrasp_robot::Gripper2F85 {
                precision_point_z: self.precision_point_z,
                power_point_z: self.power_point_z,
            }
            .into(),
        }
    }
}

/// A `[[robot]]`'s robot description: the URDF and the links the arm runs between, resolved
/// to a built-in model whose kinematics it has (`pregrasp_urdf::recognise_ur`).
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfRef {
    /// The scene file's directory joined with the `urdf` entry.
    pub path: PathBuf,
    /// The `urdf` entry exactly as written in the file.
    pub entry: String,
    /// The link the arm stands on (given, or the file's root link).
    pub base_link: String,
    /// The link the gripper is mounted to (given, or `tool0` / `flange` / the only leaf).
    pub tool_link: String,
    /// The names of the six joints the planner drives, base to tool.
    pub joint_names: Vec<String>,
    /// Joints held still (`hold`), with their values (rad), in chain order.
    pub held: Vec<(String, f64)>,
    /// Link pairs not checked for self-collision (`allow_collisions`).
    pub allowed: Vec<[String; 2]>,
}

/// How the power grasps of a 2F-85 hold their bars (`[planner] power_hold`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PowerHold {
    /// The pads' pinch at the fingertips where it squeezes the bar; the wraps where the pinch
    /// cannot carry the part at the gripper's force (the default).
    #[default]
    Auto,
    /// The pads' pinch at the fingertips wherever it squeezes the bar.
    Fingertips,
    /// The wraps, seated on the palm; the fingertips only where the wrap cages the bar or
    /// closes on one side.
    Wraps,
}

impl PowerHold {
    /// The scene file's spelling.
    pub fn name(self) -> &'static str {
        match self {
            PowerHold::Auto => "auto",
            PowerHold::Fingertips => "fingertips",
            PowerHold::Wraps => "wraps",
        }
    }

    /// The hold spelled `name` in a scene file.
    pub fn from_name(name: &str) -> Option<PowerHold> {
        [PowerHold::Auto, PowerHold::Fingertips, PowerHold::Wraps]
            .into_iter()
            .find(|h| h.name() == name)
    }
}

/// `[planner]`, SI units (angles in radians). Paper symbols in code spans.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannerParams {
    /// `Δd_s`: max distance of a hull edge's endpoints from the support at P_init (m).
    pub support_distance: f64,
    /// `Δl`: shorter hull edges are not rotation axes (m).
    pub min_axis_length: f64,
    /// `Δφ`: rotation increment (rad), > 0.
    pub step: f64,
    /// `φ_obj`: limit angle of a rotation (rad), > 0.
    pub max_angle: f64,
    /// `ω_l`: score per metre of axis length.
    pub weight_length: f64,
    /// `ω_m`: score per radian of θ_max.
    pub weight_angle: f64,
    /// `n_ext`: rotations past the first collision-free step.
    pub extra_steps: u32,
    /// `Δd_a`: skip an axis when a power grasp's origin is closer than this to the axis line (m).
    pub min_grasp_axis_distance: f64,
    /// P_init = object pose raised by this much along world `z` (m).
    pub lift: f64,
    /// Stand-off before the straight final approach to a grasp (m).
    pub approach_distance: f64,
    /// Largest joint change between neighbouring points of μ_rot (rad), > 0.
    pub max_joint_step: f64,
    /// Seed of the motion planner's random generator.
    pub seed: u64,
    /// Clearance (m) every arm link and gripper keeps from the support, the other arm, its own
    /// links and the part — the cell's safety margin. The link shapes enclose the real links
    /// with no margin of their own.
    pub link_clearance: f64,
    /// Clearance (m) a gripper keeps from the support while it grasps: holding the part, and
    /// within the last 2 cm of an approach to a grasp or the first 2 cm of a retreat from one —
    /// where a fingertip pinch sits a few millimetres above the table.
    pub finger_support_clearance: f64,
    /// (Extension) Rank plans by how often their rotation axis plans again when the part lies
    /// up to `robustness_pos` / `robustness_yaw` off (this many samples per plan; 0: off).
    pub robustness_samples: u32,
    /// Largest placement error along world x and y for that ranking (m).
    pub robustness_pos: f64,
    /// Largest yaw error for that ranking (rad).
    pub robustness_yaw: f64,
    /// (Extension) How the power grasps hold their bars.
    pub power_hold: PowerHold,
}

/// `[physics]`: what the quasi-static check of `μ_rot` (crate `pregrasp-physics`) needs beyond
/// the mesh and `object.mass`. `None`: the check's default (see `docs/physics.md`).
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicsParams {
    /// Coulomb friction coefficient pad–part, in (0, 10].
    pub mu_pad: Option<f64>,
    /// Coulomb friction coefficient part–support, in [0, 10].
    pub mu_support: Option<f64>,
    /// Grip force to set = this × the largest minimum grip force along `rot`, in [1, 100].
    pub safety_factor: Option<f64>,
    /// Torsion radius of a pad contact (m), in [0, 0.1]; 0: point contacts.
    pub pad_torsion_radius: Option<f64>,
    /// Density (kg/m³) of a part without `object.mass`, in (0, 30000].
    pub density: Option<f64>,
    /// Largest twist arm (m) of a rotation: the moment per newton of weight only a twist of the
    /// pads holds, in [0, 1]; 1 turns the rule off.
    pub max_twist_arm: Option<f64>,
    /// `reject` (default true): the planner rejects a candidate whose rotation the gripper
    /// cannot hold or that slides at the support, or whose power grasps cannot lift the part at
    /// the gripper's largest force (the carry check). `false` keeps such plans and only reports.
    pub reject: bool,
    /// `reject_uncarried` (default false): the planner also rejects a candidate whose power
    /// grasps lift the part only without the safety factor, or that no force lifts. `false`
    /// keeps such plans and says so in their `physics.warnings`.
    pub reject_uncarried: bool,
}

impl Default for PhysicsParams {
    /// No table: every value the check's default, unsafe rotations rejected.
    fn default() -> Self {
        PhysicsParams {
            mu_pad: None,
            mu_support: None,
            safety_factor: None,
            pad_torsion_radius: None,
            density: None,
            max_twist_arm: None,
            reject: true,
            reject_uncarried: false,
        }
    }
}

/// The keys of `[physics]` that hold numbers.
pub const PHYSICS_NUMBER_KEYS: [&str; 6] = [
    "mu_pad",
    "mu_support",
    "safety_factor",
    "pad_torsion_radius",
    "density",
    "max_twist_arm",
];

pub use crate::ranges::{check_physics_value, MAX_MASS};

/// Default of `[planner] link_clearance` (m).
pub const DEFAULT_LINK_CLEARANCE: f64 = 0.005;
/// Default of `[planner] finger_support_clearance` (m).
pub const DEFAULT_FINGER_SUPPORT_CLEARANCE: f64 = 0.002;

impl Default for PlannerParams {
    /// The defaults of `scene-format.md`.
    fn default() -> Self {
        PlannerParams {
            support_distance: 0.01,
            min_axis_length: 0.05,
            step: 1.0f64.to_radians(),
            max_angle: 90.0f64.to_radians(),
            weight_length: 1.0,
            weight_angle: 1.0,
            extra_steps: 3,
            min_grasp_axis_distance: 0.10,
            lift: 0.001,
            approach_distance: 0.05,
            max_joint_step: 10.0f64.to_radians(),
            seed: 0,
            link_clearance: DEFAULT_LINK_CLEARANCE,
            finger_support_clearance: DEFAULT_FINGER_SUPPORT_CLEARANCE,
            robustness_samples: 0,
            robustness_pos: 0.005,
            robustness_yaw: 2.0f64.to_radians(),
            power_hold: PowerHold::Auto,
        }
    }
}

impl PlannerParams {
    /// The plan file's `planner` object: angles in degrees, as the scene file spells them.
    pub fn to_json(&self) -> PlannerJson {
        PlannerJson {
            support_distance: self.support_distance,
            min_axis_length: self.min_axis_length,
            step_deg: deg(self.step),
            max_angle_deg: deg(self.max_angle),
            weight_length: self.weight_length,
            weight_angle: self.weight_angle,
            extra_steps: self.extra_steps,
            min_grasp_axis_distance: self.min_grasp_axis_distance,
            lift: self.lift,
            approach_distance: self.approach_distance,
            max_joint_step_deg: deg(self.max_joint_step),
            seed: self.seed,
            link_clearance: Some(self.link_clearance),
            finger_support_clearance: Some(self.finger_support_clearance),
            robustness_samples: (self.robustness_samples > 0).then_some(self.robustness_samples),
            robustness_pos: (self.robustness_samples > 0).then_some(self.robustness_pos),
            robustness_yaw_deg: (self.robustness_samples > 0).then(|| deg(self.robustness_yaw)),
            power_hold: (self.power_hold != PowerHold::Auto)
                .then(|| self.power_hold.name().to_string()),
        }
    }
}

/// Radians to degrees, snapped to 12 significant decimals so `1.0` deg read from a file is
/// written back as `1.0` and not `0.9999999999999999`.
fn deg(rad: f64) -> f64 {
    let d = rad.to_degrees();
    let snapped = (d * 1e9).round() / 1e9;
    if (snapped - d).abs() <= 1e-12 * d.abs().max(1.0) {
        snapped
    } else {
        d
    }
}

/// A scene that cannot be used. Every message starts with the file name.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{file}: cannot read scene file: {error}")]
    Read { file: String, error: std::io::Error },
    #[error("{file}: not valid TOML: {message}")]
    Syntax { file: String, message: String },
    /// A key is missing, has the wrong type or an unusable value.
    #[error("{file}: {key}: {message}")]
    Key {
        file: String,
        key: String,
        message: String,
    },
}

impl SceneError {
    /// The dotted key the error is about (`robot[1].model`), if any.
    pub fn key(&self) -> Option<&str> {
        match self {
            SceneError::Key { key, .. } => Some(key),
            _ => None,
        }
    }
}

impl Scene {
    /// This scene with the grasps a plan file used (e.g. the ones an auto scene's search
    /// chose), as hand-placed grasps: re-planning and robustness follow the plan's grasps.
    pub fn with_grasps_of(&self, grasps: &crate::plan_file::GraspsJson) -> Scene {
        let mut s = self.clone();
        s.grasps = Grasps {
            power: [grasps.power[0].to_isometry(), grasps.power[1].to_isometry()],
            support: grasps.support.to_isometry(),
            auto: None,
        };
        s
    }

    /// P_init: the object pose raised by `planner.lift` along world `z`.
    pub fn initial_object_pose(&self) -> Isometry3<f64> {
        let mut p = self.object.pose;
        p.translation.vector.z += self.planner.lift;
        p
    }
}
