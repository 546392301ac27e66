//! From the file's shape (`raw.rs`) to a [`Scene`]: what types cannot check — missing keys,
//! two spellings of one key, ranges — section by section, each refusal naming the key. Also
//! the loader's entry points, [`Scene::load`] and [`Scene::from_str`].

use std::f64::consts::PI;
use std::fmt::Display;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use pregrasp_robot::{ArmDescription, UrModel};
use toml::Value;

use super::raw::{self, Flag, Int, Num, Nums, PosePair, RawError, RawScene, Robots, Str, Table};
use super::raw::{RawGrasps, RawObject, RawPhysics, RawPlanner, RawPose, RawRobot};
use super::PowerHold;
use super::{AutoGrasps, Grasps, ObjectSpec, PhysicsParams, PlannerParams, RobotSpec, Scene};
use super::{SceneError, GRIPPERS, GRIPPER_POINT_RANGE, MAX_COORDINATE, ROBOT_MODELS};
use super::{DEFAULT_POWER_POINT_Z, DEFAULT_PRECISION_POINT_Z};
use crate::ranges::check_physics_value;

/// Slack (rad) allowed beyond a joint limit, so that `start_deg = [360, ...]` (which converts
/// to 2π give or take one ulp) is inside ±2π.
const JOINT_LIMIT_SLACK: f64 = 1e-9;

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
        let cx = Cx(file.display().to_string());
        let (raw, unknown) = raw::parse(text).map_err(|e| match e {
            RawError::Syntax(message) => SceneError::Syntax {
                file: cx.0.clone(),
                message,
            },
            RawError::Key { key, message } => cx.err(&key, message),
        })?;
        let warnings = unknown
            .iter()
            .map(|key| format!("{}: {key}: unknown key (ignored)", cx.0))
            .collect();
        cx.scene(raw, file, warnings)
    }
}

/// The validation, with the file name for its messages.
pub(super) struct Cx(String);

impl Cx {
    pub(super) fn err(&self, key: &str, message: impl Display) -> SceneError {
        SceneError::Key {
            file: self.0.clone(),
            key: key.to_string(),
            message: message.to_string(),
        }
    }

    /// Refuses the value at `key` unless `ok`.
    fn ensure(&self, ok: bool, key: &str, message: impl Display) -> Result<(), SceneError> {
        match ok {
            true => Ok(()),
            false => Err(self.err(key, message)),
        }
    }

    fn need<T>(&self, value: Option<T>, key: &str) -> Result<T, SceneError> {
        value.ok_or_else(|| self.err(key, "missing key"))
    }

    fn scene(
        &self,
        raw: RawScene,
        file: &Path,
        warnings: Vec<String>,
    ) -> Result<Scene, SceneError> {
        let Table(support) = self.need(raw.support, "support")?;
        let Num(support_height) = self.need(support.height, "support.height")?;
        self.coordinate(support_height, "support.height")?;
        let Table(object) = self.need(raw.object, "object")?;
        let object = self.object(object, file)?;
        let Table(grasps) = self.need(raw.grasps, "grasps")?;
        let grasps = self.grasps(grasps)?;
        let Some(Robots([r0, r1])) = raw.robot else {
            return Err(self.err("robot", "missing: exactly two [[robot]] tables are needed"));
        };
        let robots = [
            self.robot(r0, "robot[0]", file)?,
            self.robot(r1, "robot[1]", file)?,
        ];
        let name = &robots[1].name;
        let message = format!("duplicate robot name {name:?}");
        self.ensure(robots[0].name != *name, "robot[1].name", message)?;
        Ok(Scene {
            file: file.to_path_buf(),
            name: raw.name.map(|Str(s)| s),
            support_height,
            object,
            grasps,
            robots,
            planner: match raw.planner {
                None => PlannerParams::default(),
                Some(Table(p)) => self.planner(p)?,
            },
            physics: match raw.physics {
                None => PhysicsParams::default(),
                Some(Table(p)) => self.physics(p)?,
            },
            warnings,
        })
    }

    /// Checks a length that places something in the world or on the object (m).
    fn coordinate(&self, x: f64, key: &str) -> Result<(), SceneError> {
        let message = format!(
            "{x} m is more than {MAX_COORDINATE} m from the origin (lengths are in metres)"
        );
        self.ensure(x.abs() <= MAX_COORDINATE, key, message)
    }

    fn pose(&self, raw: RawPose, key: &str) -> Result<Isometry3<f64>, SceneError> {
        let Nums(xyz) = self.need(raw.xyz, &format!("{key}.xyz"))?;
        for (i, &x) in xyz.iter().enumerate() {
            self.coordinate(x, &format!("{key}.xyz[{i}]"))?;
        }
        let given = [
            ("rpy", raw.rpy.is_some()),
            ("rpy_deg", raw.rpy_deg.is_some()),
            ("quat_xyzw", raw.quat_xyzw.is_some()),
        ];
        let given: Vec<&str> = given.iter().filter(|g| g.1).map(|g| g.0).collect();
        let message = format!("give one rotation, found {}", given.join(" and "));
        self.ensure(given.len() <= 1, key, message)?;
        // R = Rz(yaw) · Ry(pitch) · Rx(roll), which is nalgebra's convention.
        let euler =
            |[roll, pitch, yaw]: [f64; 3]| UnitQuaternion::from_euler_angles(roll, pitch, yaw);
        let rotation = match (raw.rpy, raw.rpy_deg, raw.quat_xyzw) {
            (Some(Nums(rpy)), _, _) => euler(rpy),
            (_, Some(Nums(rpy_deg)), _) => euler(rpy_deg.map(f64::to_radians)),
            (_, _, Some(Nums([x, y, z, w]))) => {
                let q = Quaternion::new(w, x, y, z);
                let key = format!("{key}.quat_xyzw");
                self.ensure(q.norm() >= 1e-12, &key, "zero quaternion")?;
                UnitQuaternion::from_quaternion(q)
            }
            (None, None, None) => UnitQuaternion::identity(),
        };
        let [x, y, z] = xyz;
        Ok(Isometry3::from_parts(Translation3::new(x, y, z), rotation))
    }

    fn object(&self, raw: RawObject, file: &Path) -> Result<ObjectSpec, SceneError> {
        let Str(mesh_entry) = self.need(raw.mesh, "object.mesh")?;
        self.ensure(!mesh_entry.trim().is_empty(), "object.mesh", "empty path")?;
        let mesh_path = match file.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir.join(&mesh_entry),
            _ => PathBuf::from(&mesh_entry),
        };
        let scale = raw.scale.map_or(1.0, |Num(x)| x);
        self.ensure(
            scale > 0.0,
            "object.scale",
            format!("must be > 0, found {scale}"),
        )?;
        let Table(pose) = self.need(raw.pose, "object.pose")?;
        let pose = self.pose(pose, "object.pose")?;
        let mass = raw.mass.map(|Num(m)| m);
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

    fn grasps(&self, raw: RawGrasps) -> Result<Grasps, SceneError> {
        let auto = match &raw.mode {
            None => false,
            Some(Value::String(m)) if m == "manual" => false,
            Some(Value::String(m)) if m == "auto" => true,
            Some(v) => {
                let message = format!("expected \"manual\" or \"auto\", found {v}");
                return Err(self.err("grasps.mode", message));
            }
        };
        let support = |s: Option<Table<RawPose>>| {
            s.map(|Table(p)| self.pose(p, "grasps.support")).transpose()
        };
        let power = |p: Option<PosePair>| {
            let pair = |PosePair([p0, p1])| {
                Ok::<_, SceneError>([
                    self.pose(p0, "grasps.power[0]")?,
                    self.pose(p1, "grasps.power[1]")?,
                ])
            };
            p.map(pair).transpose()
        };
        if !auto {
            return Ok(Grasps {
                power: self.need(power(raw.power)?, "grasps.power")?,
                support: self.need(support(raw.support)?, "grasps.support")?,
                auto: None,
            });
        }
        let support = support(raw.support)?;
        let power = power(raw.power)?;
        Ok(Grasps {
            power: power.unwrap_or([Isometry3::identity(); 2]),
            support: support.unwrap_or_else(Isometry3::identity),
            auto: Some(AutoGrasps {
                support_pinned: support.is_some(),
                power_pinned: power.is_some(),
            }),
        })
    }

    fn robot(&self, raw: RawRobot, key: &str, file: &Path) -> Result<RobotSpec, SceneError> {
        let at = |name: &str| format!("{key}.{name}");
        let Str(name) = self.need(raw.name, &at("name"))?;
        self.ensure(!name.is_empty(), &at("name"), "empty name")?;
        let held: Vec<(String, f64)> = raw.hold.map_or_else(Vec::new, |Table(h)| {
            h.into_iter().map(|(joint, Num(v))| (joint, v)).collect()
        });
        let allowed: Vec<[String; 2]> = raw.allow_collisions.map_or_else(Vec::new, |p| p.0);
        let described = match raw.urdf {
            Some(Str(entry)) => {
                let links = (raw.base_link, raw.tool_link);
                let keep = (&held[..], &allowed[..]);
                Some(self.urdf_arm(entry, links, keep, key, file)?)
            }
            None => {
                for (given, name) in [
                    (raw.base_link.is_some(), "base_link"),
                    (raw.tool_link.is_some(), "tool_link"),
                    (!held.is_empty(), "hold"),
                    (!allowed.is_empty(), "allow_collisions"),
                ] {
                    let message = "only with `urdf` (the links of the robot description)";
                    self.ensure(!given, &at(name), message)?;
                }
                None
            }
        };
        let arm = match (raw.model, &described) {
            (Some(Str(model)), _) => {
                let Some(ur) = UrModel::ALL.into_iter().find(|m| m.name() == model) else {
                    let expected = ROBOT_MODELS.join(", ");
                    let message =
                        format!("unknown robot model {model:?} (expected one of {expected})");
                    return Err(self.err(&at("model"), message));
                };
                if let Some((_, found, _, _)) = &described {
                    let message = format!("{model:?}, but the arm of `urdf` is a {}", found.name());
                    self.ensure(found.ur == Some(ur), &at("model"), message)?;
                }
                ArmDescription::ur(ur)
            }
            (None, Some((_, found, _, _))) => found.clone(),
            (None, None) => return Err(self.err(&at("model"), "missing key")),
        };
        let Table(base) = self.need(raw.base, &at("base"))?;
        let mut base = self.pose(base, &at("base"))?;
        let (urdf, source) = match described {
            Some((urdf, _, to_dh_base, source)) => {
                // `base` places the description's base link; the arm's base is its DH Base.
                base *= to_dh_base;
                (Some(urdf), Some(source))
            }
            None => (None, None),
        };
        let (start, in_degrees) = match (raw.start, raw.start_deg) {
            (Some(_), Some(_)) => {
                let message = "give either start or start_deg, not both";
                return Err(self.err(&at("start"), message));
            }
            (Some(Nums(start)), None) => (start, false),
            (None, Some(Nums(start_deg))) => (start_deg.map(f64::to_radians), true),
            (None, None) => return Err(self.err(&at("start"), "missing key")),
        };
        self.joint_limits(&arm, &start, in_degrees, key, &name)?;
        let gripper = raw
            .gripper
            .map_or_else(|| GRIPPERS[0].to_string(), |Str(g)| g);
        let expected = GRIPPERS.join(", ");
        let message = format!("unknown gripper {gripper:?} (expected one of {expected})");
        self.ensure(
            GRIPPERS.contains(&gripper.as_str()),
            &at("gripper"),
            message,
        )?;
        // The jaws a description carries below its tool link (`gripper = "urdf"`).
        let jaws = match (gripper.as_str(), source) {
            ("urdf", Some(source)) => {
                let given = |z: &Option<Num>| z.as_ref().map(|Num(z)| *z);
                Some(self.urdf_jaws(
                    source,
                    given(&raw.precision_point_z),
                    given(&raw.power_point_z),
                    &at("gripper"),
                )?)
            }
            ("urdf", None) => {
                let message = "\"urdf\" takes the gripper from the robot description: give `urdf`";
                return Err(self.err(&at("gripper"), message));
            }
            _ => None,
        };
        let (range, (default_precision, default_power)) = match &jaws {
            // Along the jaws' inner faces, where a jaw gripper can hold anything.
            Some(j) => {
                let f = j.faces();
                let range = (f[0].z.0.min(f[1].z.0), f[0].z.1.max(f[1].z.1));
                (range, (j.precision_point_z, j.power_point_z))
            }
            None => (
                GRIPPER_POINT_RANGE,
                (DEFAULT_PRECISION_POINT_Z, DEFAULT_POWER_POINT_Z),
            ),
        };
        let point_z = |name: &str, z: Option<Num>, default: f64| {
            let z = z.map_or(default, |Num(z)| z);
            let (lo, hi) = range;
            let span = match jaws {
                Some(_) => "the jaws' inner faces".to_string(),
                None => format!("the {gripper}'s palm-to-fingertip span"),
            };
            let message = format!("{z} m is outside [{lo}, {hi}] m, {span}");
            self.ensure((lo..=hi).contains(&z), &at(name), message)?;
            Ok(z)
        };
        let precision_point_z = point_z(
            "precision_point_z",
            raw.precision_point_z,
            default_precision,
        )?;
        let power_point_z = point_z("power_point_z", raw.power_point_z, default_power)?;
        let message = format!(
            "{power_point_z} m is beyond precision_point_z = {precision_point_z} m: \
             the power point lies deeper in the hand (nearer the palm)"
        );
        self.ensure(
            power_point_z <= precision_point_z,
            &at("power_point_z"),
            message,
        )?;
        let spec = RobotSpec {
            name,
            arm,
            base,
            urdf,
            start,
            gripper,
            jaws,
            precision_point_z,
            power_point_z,
        };
        self.shapes_fit(&spec, key)?;
        Ok(spec)
    }

    /// Refuses a start configuration outside `model`'s joint limits, naming the robot and the
    /// joint (`start` in radians; `in_degrees`: the file spelled it `start_deg`).
    fn joint_limits(
        &self,
        arm: &ArmDescription,
        start: &[f64; 6],
        in_degrees: bool,
        key: &str,
        name: &str,
    ) -> Result<(), SceneError> {
        let limits = arm.kin.joint_limits();
        let model = arm.name();
        for (i, (&q, &(lo, hi))) in start.iter().zip(&limits).enumerate() {
            if q >= lo - JOINT_LIMIT_SLACK && q <= hi + JOINT_LIMIT_SLACK {
                continue;
            }
            let (what, field) = if in_degrees {
                let [q, lo, hi] = [q, lo, hi].map(f64::to_degrees);
                let what = format!("{q}° is outside the {model} joint limits [{lo:.0}, {hi:.0}]°");
                (what, "start_deg")
            } else {
                let what =
                    format!("{q} rad is outside the {model} joint limits [{lo:.3}, {hi:.3}]");
                (what, "start")
            };
            let joint = &arm.joint_names[i];
            let message = format!("{what} ({joint} of robot {name:?})");
            return Err(self.err(&format!("{key}.{field}[{i}]"), message));
        }
        Ok(())
    }

    /// A `[planner]` angle spelled `name` (radians) or `name_deg` (degrees): the value in
    /// radians if given, and the key as the file spelled it (`planner.step_deg` if neither).
    fn angle(&self, name: &str, rad: Option<Num>, deg: Option<Num>) -> Result<Angle, SceneError> {
        match (rad, deg) {
            (Some(_), Some(_)) => {
                let message = format!("give either {name} or {name}_deg, not both");
                Err(self.err(&format!("planner.{name}"), message))
            }
            (Some(Num(x)), None) => Ok((Some(x), format!("planner.{name}"))),
            (None, deg) => Ok((
                deg.map(|Num(x)| x.to_radians()),
                format!("planner.{name}_deg"),
            )),
        }
    }

    /// An angle in (0°, 180°], `default` if not given.
    fn positive_angle(&self, (x, key): Angle, default: f64) -> Result<(f64, String), SceneError> {
        let x = x.unwrap_or(default);
        self.ensure(x > 0.0, &key, "must be > 0")?;
        let (max, found) = (PI.to_degrees().round(), x.to_degrees());
        let message = format!("must be at most {max}° ({PI:.4} rad), found {found}°");
        self.ensure(x <= PI + 1e-12, &key, message)?;
        Ok((x, key))
    }

    fn planner(&self, raw: RawPlanner) -> Result<PlannerParams, SceneError> {
        let d = PlannerParams::default();
        let err = |name: &str, message: String| self.err(&format!("planner.{name}"), message);
        // A key's name is its field's: `non_negative!(lift)` reads and checks `planner.lift`.
        macro_rules! non_negative {
            ($key:ident) => {
                match raw.$key.map_or(d.$key, |Num(x)| x) {
                    x if x < 0.0 => {
                        return Err(err(stringify!($key), format!("must be >= 0, found {x}")))
                    }
                    x => x,
                }
            };
        }
        macro_rules! count {
            ($key:ident) => {
                match raw.$key {
                    Some(Int(i)) if i < 0 => {
                        return Err(err(stringify!($key), format!("must be >= 0, found {i}")))
                    }
                    i => i.map(|Int(i)| i),
                }
            };
        }
        macro_rules! angle {
            ($key:ident, $deg:ident) => {
                self.angle(stringify!($key), raw.$key, raw.$deg)?
            };
        }
        let extra_steps = match count!(extra_steps) {
            None => d.extra_steps,
            Some(i) => u32::try_from(i).map_err(|_| err("extra_steps", "too large".into()))?,
        };
        let (max_angle, _) = self.positive_angle(angle!(max_angle, max_angle_deg), d.max_angle)?;
        let (step, step_key) = self.positive_angle(angle!(step, step_deg), d.step)?;
        let (step_deg, max_deg) = (step.to_degrees(), max_angle.to_degrees());
        let message = format!("the step {step_deg}° is larger than max_angle {max_deg}°");
        self.ensure(step <= max_angle, &step_key, message)?;
        Ok(PlannerParams {
            support_distance: non_negative!(support_distance),
            min_axis_length: non_negative!(min_axis_length),
            step,
            max_angle,
            weight_length: non_negative!(weight_length),
            weight_angle: non_negative!(weight_angle),
            extra_steps,
            min_grasp_axis_distance: non_negative!(min_grasp_axis_distance),
            lift: non_negative!(lift),
            approach_distance: non_negative!(approach_distance),
            max_joint_step: {
                let max_joint_step = angle!(max_joint_step, max_joint_step_deg);
                self.positive_angle(max_joint_step, d.max_joint_step)?.0
            },
            seed: count!(seed).map_or(d.seed, |i| i as u64),
            link_clearance: non_negative!(link_clearance),
            finger_support_clearance: non_negative!(finger_support_clearance),
            robustness_samples: match count!(robustness_samples) {
                None => d.robustness_samples,
                Some(i) if i <= 10_000 => i as u32,
                Some(i) => {
                    let message = format!("must be at most 10000, found {i}");
                    return Err(err("robustness_samples", message));
                }
            },
            robustness_pos: match non_negative!(robustness_pos) {
                x if x > 0.5 => {
                    let message = format!("must be at most 0.5 m, found {x}");
                    return Err(err("robustness_pos", message));
                }
                x => x,
            },
            robustness_yaw: match angle!(robustness_yaw, robustness_yaw_deg).0 {
                None => d.robustness_yaw,
                Some(x) if (0.0..=PI).contains(&x) => x,
                Some(x) => {
                    let message = format!("must be in [0°, 180°], found {}°", x.to_degrees());
                    return Err(err("robustness_yaw", message));
                }
            },
            power_hold: match raw.power_hold {
                None => d.power_hold,
                Some(Str(name)) => PowerHold::from_name(&name).ok_or_else(|| {
                    let message =
                        format!("must be \"auto\", \"fingertips\" or \"wraps\", found \"{name}\"");
                    err("power_hold", message)
                })?,
            },
        })
    }

    fn physics(&self, raw: RawPhysics) -> Result<PhysicsParams, SceneError> {
        let value = |name: &str, x: Option<Num>| {
            let x = x.map(|Num(x)| x);
            if let Some(x) = x {
                let key = format!("physics.{name}");
                check_physics_value(name, x).map_err(|m| self.err(&key, m))?;
            }
            Ok(x)
        };
        Ok(PhysicsParams {
            mu_pad: value("mu_pad", raw.mu_pad)?,
            mu_support: value("mu_support", raw.mu_support)?,
            safety_factor: value("safety_factor", raw.safety_factor)?,
            pad_torsion_radius: value("pad_torsion_radius", raw.pad_torsion_radius)?,
            density: value("density", raw.density)?,
            max_twist_arm: value("max_twist_arm", raw.max_twist_arm)?,
            reject: raw.reject.is_none_or(|Flag(b)| b),
            reject_uncarried: raw.reject_uncarried.is_some_and(|Flag(b)| b),
        })
    }
}

/// An angle in radians if given, and its key as the file spelled it.
type Angle = (Option<f64>, String);
