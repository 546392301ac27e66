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
//! ([`UrModel::joint_limits`]), gripper points between the 2F-85's palm and fingertips, and
//! every `[planner]` key within the range `docs/scene-format.md` gives it.
//!
//! The mesh itself is not read here (see [`crate::mesh_io::load_mesh`]); the scene only resolves
//! its path relative to the scene file's directory.

use std::f64::consts::PI;
use std::fmt::Display;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use pregrasp_robot::{UrModel, JOINT_NAMES};
use toml::{Table, Value};

use crate::plan_file::PlannerJson;

/// The robot models with built-in kinematics and geometry.
pub const ROBOT_MODELS: [&str; 5] = ["ur3e", "ur5e", "ur10e", "ur16e", "ur5"];
/// The grippers with built-in geometry.
pub const GRIPPERS: [&str; 1] = ["robotiq_2f85"];
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
/// Slack (rad) allowed beyond a joint limit, so that `start_deg = [360, ...]` (which converts
/// to 2π give or take one ulp) is inside ±2π.
const JOINT_LIMIT_SLACK: f64 = 1e-9;

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
    /// One line per ignored key, e.g. `scene.toml: object.colour: unknown key (ignored)`.
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
    pub model: UrModel,
    /// The arm base frame in world.
    pub base: Isometry3<f64>,
    /// Start joint angles (rad).
    pub start: [f64; 6],
    /// One of [`GRIPPERS`].
    pub gripper: String,
    /// Flange-to-precision-point distance along flange `z` (m).
    pub precision_point_z: f64,
    /// Flange-to-power-point distance along flange `z` (m).
    pub power_point_z: f64,
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
    /// `reject` (default true): the planner rejects a candidate whose rotation the gripper
    /// cannot hold or that slides at the support. `false` keeps such plans and only reports.
    pub reject: bool,
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
            reject: true,
        }
    }
}

/// The keys of `[physics]` that hold numbers.
pub const PHYSICS_NUMBER_KEYS: [&str; 5] = [
    "mu_pad",
    "mu_support",
    "safety_factor",
    "pad_torsion_radius",
    "density",
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
    /// Reads and validates the scene file at `path`.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let read = |error| SceneError::Read {
            file: path.display().to_string(),
            error,
        };
        let bytes =
            crate::limits::read_limited(path, crate::limits::MAX_SCENE_BYTES).map_err(read)?;
        let text = String::from_utf8(bytes).map_err(|_| {
            read(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                "not UTF-8 text (a scene file is TOML)",
            ))
        })?;
        Scene::from_str(&text, path)
    }

    /// Parses and validates scene text; `file` is used for messages and to resolve the mesh path.
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(text: &str, file: &Path) -> Result<Scene, SceneError> {
        let mut cx = Cx {
            file: file.display().to_string(),
            warnings: Vec::new(),
        };
        let root: Table = text.parse::<Table>().map_err(|e| SceneError::Syntax {
            file: cx.file.clone(),
            // TOML quotes the offending line: a line of a binary or minified file can be
            // hundreds of kilobytes, so each quoted line is clipped.
            message: e
                .to_string()
                .trim_end()
                .lines()
                .map(|line| crate::text::clip(line, 160))
                .collect::<Vec<_>>()
                .join(" | "),
        })?;
        cx.unknown(
            &root,
            "",
            &[
                "name", "support", "object", "grasps", "robot", "planner", "physics",
            ],
        );

        let name = match root.get("name") {
            None => None,
            Some(v) => Some(cx.string(v, "name")?),
        };
        let support = cx.table(&root, "", "support")?;
        cx.unknown(support, "support", &["height"]);
        let support_height = cx.req_f64(support, "support", "height")?;
        cx.coordinate(support_height, "support.height")?;

        let object = cx.object(&root, file)?;
        let grasps = cx.grasps(&root)?;
        let robots = cx.robots(&root)?;
        let planner = match root.get("planner") {
            None => PlannerParams::default(),
            Some(v) => cx.planner(cx.as_table(v, "planner")?)?,
        };
        let physics = match root.get("physics") {
            None => PhysicsParams::default(),
            Some(v) => cx.physics(cx.as_table(v, "physics")?)?,
        };
        Ok(Scene {
            file: file.to_path_buf(),
            name,
            support_height,
            object,
            grasps,
            robots,
            planner,
            physics,
            warnings: cx.warnings,
        })
    }

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

/// Parsing context: the file name for messages and the warnings collected so far.
struct Cx {
    file: String,
    warnings: Vec<String>,
}

fn join(parent: &str, key: &str) -> String {
    if parent.is_empty() {
        key.to_string()
    } else {
        format!("{parent}.{key}")
    }
}

fn type_name(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a float",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::Table(_) => "a table",
    }
}

impl Cx {
    fn err(&self, key: &str, message: impl Display) -> SceneError {
        SceneError::Key {
            file: self.file.clone(),
            key: key.to_string(),
            message: message.to_string(),
        }
    }

    /// Records a warning for every key of `table` not in `known`, in sorted order.
    fn unknown(&mut self, table: &Table, path: &str, known: &[&str]) {
        for k in table.keys() {
            if !known.contains(&k.as_str()) {
                self.warnings.push(format!(
                    "{}: {}: unknown key (ignored)",
                    self.file,
                    join(path, k)
                ));
            }
        }
    }

    fn as_table<'t>(&self, v: &'t Value, key: &str) -> Result<&'t Table, SceneError> {
        v.as_table()
            .ok_or_else(|| self.err(key, format!("expected a table, found {}", type_name(v))))
    }

    fn table<'t>(&self, t: &'t Table, path: &str, name: &str) -> Result<&'t Table, SceneError> {
        let key = join(path, name);
        let v = t.get(name).ok_or_else(|| self.err(&key, "missing key"))?;
        self.as_table(v, &key)
    }

    fn string(&self, v: &Value, key: &str) -> Result<String, SceneError> {
        v.as_str()
            .map(str::to_string)
            .ok_or_else(|| self.err(key, format!("expected a string, found {}", type_name(v))))
    }

    /// A finite number; integers are accepted.
    fn number(&self, v: &Value, key: &str) -> Result<f64, SceneError> {
        let x = match v {
            Value::Float(x) => *x,
            Value::Integer(i) => *i as f64,
            _ => return Err(self.err(key, format!("expected a number, found {}", type_name(v)))),
        };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(key, format!("number must be finite, found {x}")))
        }
    }

    fn opt_f64(&self, t: &Table, path: &str, name: &str) -> Result<Option<f64>, SceneError> {
        t.get(name)
            .map(|v| self.number(v, &join(path, name)))
            .transpose()
    }

    fn req_f64(&self, t: &Table, path: &str, name: &str) -> Result<f64, SceneError> {
        self.opt_f64(t, path, name)?
            .ok_or_else(|| self.err(&join(path, name), "missing key"))
    }

    /// Checks a length that places something in the world or on the object (m).
    fn coordinate(&self, x: f64, key: &str) -> Result<(), SceneError> {
        if x.abs() > MAX_COORDINATE {
            return Err(self.err(
                key,
                format!(
                    "{x} m is more than {MAX_COORDINATE} m from the origin (lengths are in metres)"
                ),
            ));
        }
        Ok(())
    }

    fn array<const N: usize>(&self, v: &Value, key: &str) -> Result<[f64; N], SceneError> {
        let a = v.as_array().ok_or_else(|| {
            self.err(
                key,
                format!("expected an array of {N} numbers, found {}", type_name(v)),
            )
        })?;
        if a.len() != N {
            return Err(self.err(key, format!("expected {N} numbers, found {}", a.len())));
        }
        let mut out = [0.0; N];
        for (i, x) in a.iter().enumerate() {
            out[i] = self.number(x, &format!("{key}[{i}]"))?;
        }
        Ok(out)
    }

    /// An angle-like key that may be spelled `name` (radians) or `name_deg` (degrees): the
    /// value in radians, if either is present.
    fn angle(&self, t: &Table, path: &str, name: &str) -> Result<Option<f64>, SceneError> {
        let deg_name = format!("{name}_deg");
        match (t.get(name), t.get(&deg_name)) {
            (Some(_), Some(_)) => Err(self.err(
                &join(path, name),
                format!("give either {name} or {deg_name}, not both"),
            )),
            (Some(v), None) => Ok(Some(self.number(v, &join(path, name))?)),
            (None, Some(v)) => Ok(Some(self.number(v, &join(path, &deg_name))?.to_radians())),
            (None, None) => Ok(None),
        }
    }

    /// `{ xyz = [..], rpy | rpy_deg | quat_xyzw = [..] }`.
    fn pose(&mut self, v: &Value, key: &str) -> Result<Isometry3<f64>, SceneError> {
        let t = self.as_table(v, key)?;
        self.unknown(t, key, &["xyz", "rpy", "rpy_deg", "quat_xyzw"]);
        let xyz_v = t
            .get("xyz")
            .ok_or_else(|| self.err(&join(key, "xyz"), "missing key"))?;
        let xyz: [f64; 3] = self.array(xyz_v, &join(key, "xyz"))?;
        for (i, &x) in xyz.iter().enumerate() {
            self.coordinate(x, &format!("{key}.xyz[{i}]"))?;
        }
        let given: Vec<&str> = ["rpy", "rpy_deg", "quat_xyzw"]
            .into_iter()
            .filter(|k| t.contains_key(*k))
            .collect();
        if given.len() > 1 {
            return Err(self.err(
                key,
                format!("give one rotation, found {}", given.join(" and ")),
            ));
        }
        let rotation = match given.first().copied() {
            None => UnitQuaternion::identity(),
            Some("quat_xyzw") => {
                let k = join(key, "quat_xyzw");
                let [x, y, z, w]: [f64; 4] = self.array(&t["quat_xyzw"], &k)?;
                let q = Quaternion::new(w, x, y, z);
                if q.norm() < 1e-12 {
                    return Err(self.err(&k, "zero quaternion"));
                }
                UnitQuaternion::from_quaternion(q)
            }
            Some(name) => {
                let k = join(key, name);
                let mut rpy: [f64; 3] = self.array(&t[name], &k)?;
                if name == "rpy_deg" {
                    rpy = rpy.map(f64::to_radians);
                }
                // R = Rz(yaw) · Ry(pitch) · Rx(roll), which is nalgebra's convention.
                UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2])
            }
        };
        Ok(Isometry3::from_parts(
            Translation3::new(xyz[0], xyz[1], xyz[2]),
            rotation,
        ))
    }

    fn object(&mut self, root: &Table, file: &Path) -> Result<ObjectSpec, SceneError> {
        let t = self.table(root, "", "object")?;
        self.unknown(t, "object", &["mesh", "scale", "pose", "mass"]);
        let mesh_v = t
            .get("mesh")
            .ok_or_else(|| self.err("object.mesh", "missing key"))?;
        let mesh_entry = self.string(mesh_v, "object.mesh")?;
        if mesh_entry.trim().is_empty() {
            return Err(self.err("object.mesh", "empty path"));
        }
        let mesh_path = match file.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir.join(&mesh_entry),
            _ => PathBuf::from(&mesh_entry),
        };
        let scale = self.opt_f64(t, "object", "scale")?.unwrap_or(1.0);
        if scale <= 0.0 {
            return Err(self.err("object.scale", format!("must be > 0, found {scale}")));
        }
        let pose_v = t
            .get("pose")
            .ok_or_else(|| self.err("object.pose", "missing key"))?;
        let pose = self.pose(pose_v, "object.pose")?;
        let mass = self.opt_f64(t, "object", "mass")?;
        if let Some(m) = mass {
            check_physics_value("mass", m).map_err(|problem| self.err("object.mass", problem))?;
        }
        Ok(ObjectSpec {
            mesh_path,
            mesh_entry,
            scale,
            pose,
            mass,
        })
    }

    fn grasps(&mut self, root: &Table) -> Result<Grasps, SceneError> {
        let t = self.table(root, "", "grasps")?;
        self.unknown(t, "grasps", &["power", "support", "mode"]);
        let auto = match t.get("mode") {
            None => false,
            Some(Value::String(m)) if m == "manual" => false,
            Some(Value::String(m)) if m == "auto" => true,
            Some(v) => {
                return Err(self.err(
                    "grasps.mode",
                    format!("expected \"manual\" or \"auto\", found {v}"),
                ))
            }
        };
        if auto {
            let support = match t.get("support") {
                Some(v) => Some(self.pose(v, "grasps.support")?),
                None => None,
            };
            let power = match t.get("power") {
                Some(_) => Some(self.power_pair(t)?),
                None => None,
            };
            return Ok(Grasps {
                power: power.unwrap_or([Isometry3::identity(); 2]),
                support: support.unwrap_or_else(Isometry3::identity),
                auto: Some(AutoGrasps {
                    support_pinned: support.is_some(),
                    power_pinned: power.is_some(),
                }),
            });
        }
        let [p0, p1] = self.power_pair(t)?;
        let sv = t
            .get("support")
            .ok_or_else(|| self.err("grasps.support", "missing key"))?;
        let support = self.pose(sv, "grasps.support")?;
        Ok(Grasps {
            power: [p0, p1],
            support,
            auto: None,
        })
    }

    /// `grasps.power`: exactly two poses.
    fn power_pair(&mut self, t: &Table) -> Result<[Isometry3<f64>; 2], SceneError> {
        let pv = t
            .get("power")
            .ok_or_else(|| self.err("grasps.power", "missing key"))?;
        let pa = pv.as_array().ok_or_else(|| {
            self.err(
                "grasps.power",
                format!("expected an array of 2 poses, found {}", type_name(pv)),
            )
        })?;
        if pa.len() != 2 {
            return Err(self.err(
                "grasps.power",
                format!("expected exactly 2 poses, found {}", pa.len()),
            ));
        }
        let p0 = self.pose(&pa[0], "grasps.power[0]")?;
        let p1 = self.pose(&pa[1], "grasps.power[1]")?;
        Ok([p0, p1])
    }

    fn robots(&mut self, root: &Table) -> Result<[RobotSpec; 2], SceneError> {
        let v = root
            .get("robot")
            .ok_or_else(|| self.err("robot", "missing: exactly two [[robot]] tables are needed"))?;
        let a = v.as_array().ok_or_else(|| {
            self.err(
                "robot",
                format!("expected [[robot]] tables, found {}", type_name(v)),
            )
        })?;
        if a.len() != 2 {
            return Err(self.err(
                "robot",
                format!("expected exactly two [[robot]] tables, found {}", a.len()),
            ));
        }
        let r0 = self.robot(&a[0], "robot[0]")?;
        let r1 = self.robot(&a[1], "robot[1]")?;
        if r0.name == r1.name {
            return Err(self.err(
                "robot[1].name",
                format!("duplicate robot name {:?}", r1.name),
            ));
        }
        Ok([r0, r1])
    }

    fn robot(&mut self, v: &Value, key: &str) -> Result<RobotSpec, SceneError> {
        let t = self.as_table(v, key)?;
        self.unknown(
            t,
            key,
            &[
                "name",
                "model",
                "base",
                "start",
                "start_deg",
                "gripper",
                "precision_point_z",
                "power_point_z",
            ],
        );
        let name_v = t
            .get("name")
            .ok_or_else(|| self.err(&join(key, "name"), "missing key"))?;
        let name = self.string(name_v, &join(key, "name"))?;
        if name.is_empty() {
            return Err(self.err(&join(key, "name"), "empty name"));
        }
        let model_v = t
            .get("model")
            .ok_or_else(|| self.err(&join(key, "model"), "missing key"))?;
        let model = self.string(model_v, &join(key, "model"))?;
        let Some(ur) = UrModel::ALL.into_iter().find(|m| m.name() == model) else {
            return Err(self.err(
                &join(key, "model"),
                format!(
                    "unknown robot model {model:?} (expected one of {})",
                    ROBOT_MODELS.join(", ")
                ),
            ));
        };
        let base_v = t
            .get("base")
            .ok_or_else(|| self.err(&join(key, "base"), "missing key"))?;
        let base = self.pose(base_v, &join(key, "base"))?;
        let (start, in_degrees) = match (t.get("start"), t.get("start_deg")) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    &join(key, "start"),
                    "give either start or start_deg, not both",
                ))
            }
            (Some(v), None) => (self.array::<6>(v, &join(key, "start"))?, false),
            (None, Some(v)) => (
                self.array::<6>(v, &join(key, "start_deg"))?
                    .map(f64::to_radians),
                true,
            ),
            (None, None) => return Err(self.err(&join(key, "start"), "missing key")),
        };
        self.joint_limits(ur, &start, in_degrees, key, &name)?;
        let gripper = match t.get("gripper") {
            None => GRIPPERS[0].to_string(),
            Some(v) => self.string(v, &join(key, "gripper"))?,
        };
        if !GRIPPERS.contains(&gripper.as_str()) {
            return Err(self.err(
                &join(key, "gripper"),
                format!(
                    "unknown gripper {gripper:?} (expected one of {})",
                    GRIPPERS.join(", ")
                ),
            ));
        }
        let point_z = |name: &str, default: f64| -> Result<f64, SceneError> {
            let z = self.opt_f64(t, key, name)?.unwrap_or(default);
            let (lo, hi) = GRIPPER_POINT_RANGE;
            if !(lo..=hi).contains(&z) {
                return Err(self.err(
                    &join(key, name),
                    format!(
                        "{z} m is outside [{lo}, {hi}] m, the {gripper}'s palm-to-fingertip span"
                    ),
                ));
            }
            Ok(z)
        };
        let precision_point_z = point_z("precision_point_z", DEFAULT_PRECISION_POINT_Z)?;
        let power_point_z = point_z("power_point_z", DEFAULT_POWER_POINT_Z)?;
        if power_point_z > precision_point_z {
            return Err(self.err(
                &join(key, "power_point_z"),
                format!(
                    "{power_point_z} m is beyond precision_point_z = {precision_point_z} m: \
                     the power point lies deeper in the hand (nearer the palm)"
                ),
            ));
        }
        Ok(RobotSpec {
            name,
            model: ur,
            base,
            start,
            gripper,
            precision_point_z,
            power_point_z,
        })
    }

    /// Refuses a start configuration outside `model`'s joint limits, naming the robot and the
    /// joint (`start` in radians; `in_degrees`: the file spelled it `start_deg`).
    fn joint_limits(
        &self,
        model: UrModel,
        start: &[f64; 6],
        in_degrees: bool,
        key: &str,
        name: &str,
    ) -> Result<(), SceneError> {
        for (i, (&q, &(lo, hi))) in start.iter().zip(&model.joint_limits()).enumerate() {
            if q >= lo - JOINT_LIMIT_SLACK && q <= hi + JOINT_LIMIT_SLACK {
                continue;
            }
            let (what, field) = if in_degrees {
                (
                    format!(
                        "{}° is outside the {model} joint limits [{:.0}, {:.0}]°",
                        q.to_degrees(),
                        lo.to_degrees(),
                        hi.to_degrees()
                    ),
                    "start_deg",
                )
            } else {
                (
                    format!("{q} rad is outside the {model} joint limits [{lo:.3}, {hi:.3}]"),
                    "start",
                )
            };
            return Err(self.err(
                &format!("{key}.{field}[{i}]"),
                format!("{what} ({} of robot {name:?})", JOINT_NAMES[i]),
            ));
        }
        Ok(())
    }

    fn planner(&mut self, t: &Table) -> Result<PlannerParams, SceneError> {
        const P: &str = "planner";
        self.unknown(
            t,
            P,
            &[
                "support_distance",
                "min_axis_length",
                "step",
                "step_deg",
                "max_angle",
                "max_angle_deg",
                "weight_length",
                "weight_angle",
                "extra_steps",
                "min_grasp_axis_distance",
                "lift",
                "approach_distance",
                "max_joint_step",
                "max_joint_step_deg",
                "seed",
                "link_clearance",
                "finger_support_clearance",
                "robustness_samples",
                "robustness_pos",
                "robustness_yaw",
                "robustness_yaw_deg",
            ],
        );
        let d = PlannerParams::default();
        let non_negative = |cx: &Cx, name: &str, default: f64| -> Result<f64, SceneError> {
            let x = cx.opt_f64(t, P, name)?.unwrap_or(default);
            if x < 0.0 {
                return Err(cx.err(&join(P, name), format!("must be >= 0, found {x}")));
            }
            Ok(x)
        };
        // An angle in (0, max]; the message names the spelling the file used.
        let positive_angle = |cx: &Cx, name: &str, default: f64, max: f64| {
            let x = cx.angle(t, P, name)?.unwrap_or(default);
            let shown = if t.contains_key(name) {
                name.to_string()
            } else {
                format!("{name}_deg")
            };
            if x <= 0.0 {
                return Err(cx.err(&join(P, &shown), "must be > 0"));
            }
            if x > max + 1e-12 {
                return Err(cx.err(
                    &join(P, &shown),
                    format!(
                        "must be at most {}° ({max:.4} rad), found {}°",
                        max.to_degrees().round(),
                        x.to_degrees()
                    ),
                ));
            }
            Ok((x, shown))
        };
        let integer = |cx: &Cx, name: &str| -> Result<Option<i64>, SceneError> {
            match t.get(name) {
                None => Ok(None),
                Some(Value::Integer(i)) if *i >= 0 => Ok(Some(*i)),
                Some(Value::Integer(i)) => {
                    Err(cx.err(&join(P, name), format!("must be >= 0, found {i}")))
                }
                Some(v) => Err(cx.err(
                    &join(P, name),
                    format!("expected an integer, found {}", type_name(v)),
                )),
            }
        };
        let extra_steps = match integer(self, "extra_steps")? {
            None => d.extra_steps,
            Some(i) => {
                u32::try_from(i).map_err(|_| self.err("planner.extra_steps", "too large"))?
            }
        };
        let (max_angle, _) = positive_angle(self, "max_angle", d.max_angle, PI)?;
        let (step, step_key) = positive_angle(self, "step", d.step, PI)?;
        if step > max_angle {
            return Err(self.err(
                &join(P, &step_key),
                format!(
                    "the step {}° is larger than max_angle {}°",
                    step.to_degrees(),
                    max_angle.to_degrees()
                ),
            ));
        }
        Ok(PlannerParams {
            support_distance: non_negative(self, "support_distance", d.support_distance)?,
            min_axis_length: non_negative(self, "min_axis_length", d.min_axis_length)?,
            step,
            max_angle,
            weight_length: non_negative(self, "weight_length", d.weight_length)?,
            weight_angle: non_negative(self, "weight_angle", d.weight_angle)?,
            extra_steps,
            min_grasp_axis_distance: non_negative(
                self,
                "min_grasp_axis_distance",
                d.min_grasp_axis_distance,
            )?,
            lift: non_negative(self, "lift", d.lift)?,
            approach_distance: non_negative(self, "approach_distance", d.approach_distance)?,
            max_joint_step: positive_angle(self, "max_joint_step", d.max_joint_step, PI)?.0,
            seed: integer(self, "seed")?.map_or(d.seed, |i| i as u64),
            link_clearance: non_negative(self, "link_clearance", d.link_clearance)?,
            finger_support_clearance: non_negative(
                self,
                "finger_support_clearance",
                d.finger_support_clearance,
            )?,
            robustness_samples: match integer(self, "robustness_samples")? {
                None => d.robustness_samples,
                Some(i) if i <= 10_000 => i as u32,
                Some(i) => {
                    return Err(self.err(
                        "planner.robustness_samples",
                        format!("must be at most 10000, found {i}"),
                    ))
                }
            },
            robustness_pos: {
                let x = non_negative(self, "robustness_pos", d.robustness_pos)?;
                if x > 0.5 {
                    return Err(self.err(
                        "planner.robustness_pos",
                        format!("must be at most 0.5 m, found {x}"),
                    ));
                }
                x
            },
            robustness_yaw: match self.angle(t, P, "robustness_yaw")? {
                None => d.robustness_yaw,
                Some(x) if (0.0..=PI).contains(&x) => x,
                Some(x) => {
                    return Err(self.err(
                        "planner.robustness_yaw",
                        format!("must be in [0°, 180°], found {}°", x.to_degrees()),
                    ))
                }
            },
        })
    }

    fn physics(&mut self, t: &Table) -> Result<PhysicsParams, SceneError> {
        const P: &str = "physics";
        let mut known = PHYSICS_NUMBER_KEYS.to_vec();
        known.push("reject");
        self.unknown(t, P, &known);
        let value = |cx: &Cx, name: &str| -> Result<Option<f64>, SceneError> {
            let x = cx.opt_f64(t, P, name)?;
            if let Some(x) = x {
                check_physics_value(name, x).map_err(|m| cx.err(&join(P, name), m))?;
            }
            Ok(x)
        };
        let reject = match t.get("reject") {
            None => true,
            Some(Value::Boolean(b)) => *b,
            Some(v) => {
                return Err(self.err(
                    "physics.reject",
                    format!("expected true or false, found {}", type_name(v)),
                ))
            }
        };
        Ok(PhysicsParams {
            mu_pad: value(self, "mu_pad")?,
            mu_support: value(self, "mu_support")?,
            safety_factor: value(self, "safety_factor")?,
            pad_torsion_radius: value(self, "pad_torsion_radius")?,
            density: value(self, "density")?,
            reject,
        })
    }
}
