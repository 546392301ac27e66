//! The reach problem-set file: one arm among static cuboids, a list of start/goal pairs.
//!
//! ```json
//! { "model": "ur5e",
//!   "obstacles": [ { "cuboid": { "name": "table", "center": [x, y, z],
//!                                "half_extents": [hx, hy, hz], "rpy": [r, p, y] } } ],
//!   "queries": [ { "start": [q1, …, q6], "goal": [q1, …, q6] } ] }
//! ```
//! The arm base is at the world origin with an open Robotiq 2F-85 on its flange. `rpy` is
//! fixed-axis roll, pitch, yaw (`R = Rz(y)·Ry(p)·Rx(r)`, rad, optional); `name` is optional
//! (default `obstacle<i>`). Joint values must lie within the model's joint limits.

use std::path::Path;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_robot::{Gripper2F85, Joints, UrModel, JOINT_NAMES};
use serde_json::{json, Map, Value};
use thiserror::Error;

use pregrasp_collision::ArmModel;
use pregrasp_collision::CollisionWorld;

/// Why a problem file could not be used. Every message names the file and the element.
#[derive(Debug, Error)]
pub enum ProblemError {
    #[error("{file}: cannot read")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: not valid JSON: {message}")]
    Json { file: String, message: String },
    #[error("{file}: {element}: {message}")]
    Invalid {
        file: String,
        element: String,
        message: String,
    },
}

/// A static cuboid of a problem set.
#[derive(Clone, Debug, PartialEq)]
pub struct CuboidSpec {
    pub name: String,
    pub center: Point3<f64>,
    pub half_extents: Vector3<f64>,
    /// Roll, pitch, yaw (rad), fixed axes.
    pub rpy: [f64; 3],
}

impl CuboidSpec {
    /// Box frame → world.
    pub fn pose(&self) -> Isometry3<f64> {
        let [r, p, y] = self.rpy;
        Isometry3::from_parts(
            Translation3::from(self.center.coords),
            UnitQuaternion::from_euler_angles(r, p, y),
        )
    }
}

/// One planning query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReachQuery {
    pub start: Joints,
    pub goal: Joints,
}

/// Largest problem file read: 64 MiB (the committed set is 50 KB).
pub const MAX_PROBLEM_BYTES: u64 = 64 << 20;

/// A parsed, validated problem set.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachProblemSet {
    pub model: UrModel,
    pub obstacles: Vec<CuboidSpec>,
    pub queries: Vec<ReachQuery>,
}

impl ReachProblemSet {
    /// Reads and validates a problem file: a regular file of at most
    /// [`MAX_PROBLEM_BYTES`] (a FIFO or device is refused unread).
    pub fn load(path: &Path) -> Result<Self, ProblemError> {
        let file = path.display().to_string();
        let text =
            pregrasp_limits::read_text_limited(path, MAX_PROBLEM_BYTES).map_err(|source| {
                ProblemError::Io {
                    file: file.clone(),
                    source,
                }
            })?;
        Self::parse(&text, &file)
    }

    /// Parses and validates problem-set JSON; `file` names the source in errors.
    pub fn parse(text: &str, file: &str) -> Result<Self, ProblemError> {
        let value: Value = serde_json::from_str(text).map_err(|e| ProblemError::Json {
            file: file.to_string(),
            message: e.to_string(),
        })?;
        let bad = |element: &str, message: String| ProblemError::Invalid {
            file: file.to_string(),
            element: element.to_string(),
            message,
        };
        let root = value
            .as_object()
            .ok_or_else(|| bad("(root)", "expected an object".into()))?;
        let model_name = root
            .get("model")
            .ok_or_else(|| bad("model", "missing".into()))?
            .as_str()
            .ok_or_else(|| bad("model", "expected a string".into()))?;
        let model = UrModel::from_name(model_name).ok_or_else(|| {
            let known: Vec<&str> = UrModel::ALL.iter().map(|m| m.name()).collect();
            bad(
                "model",
                format!("unknown model {model_name:?} (known: {})", known.join(", ")),
            )
        })?;
        let mut obstacles = Vec::new();
        if let Some(obs) = root.get("obstacles") {
            let arr = obs
                .as_array()
                .ok_or_else(|| bad("obstacles", "expected an array".into()))?;
            for (i, o) in arr.iter().enumerate() {
                let el = format!("obstacles[{i}]");
                let cub = o
                    .as_object()
                    .and_then(|m| m.get("cuboid"))
                    .and_then(Value::as_object)
                    .ok_or_else(|| bad(&el, "expected {\"cuboid\": {...}}".into()))?;
                let el = format!("{el}.cuboid");
                let center = vec3(cub, "center", &el, true).map_err(|m| bad(&m.0, m.1))?;
                let half = vec3(cub, "half_extents", &el, true).map_err(|m| bad(&m.0, m.1))?;
                if half.iter().any(|h| *h <= 0.0) {
                    return Err(bad(
                        &format!("{el}.half_extents"),
                        "every half extent must be > 0".into(),
                    ));
                }
                let rpy = vec3(cub, "rpy", &el, false).map_err(|m| bad(&m.0, m.1))?;
                let name = match cub.get("name") {
                    None => format!("obstacle{i}"),
                    Some(Value::String(s)) => s.clone(),
                    Some(_) => return Err(bad(&format!("{el}.name"), "expected a string".into())),
                };
                obstacles.push(CuboidSpec {
                    name,
                    center: Point3::from(center),
                    half_extents: Vector3::from(half),
                    rpy,
                });
            }
        }
        let queries_v = root
            .get("queries")
            .ok_or_else(|| bad("queries", "missing".into()))?
            .as_array()
            .ok_or_else(|| bad("queries", "expected an array".into()))?;
        if queries_v.is_empty() {
            return Err(bad("queries", "no queries".into()));
        }
        let limits = model.joint_limits();
        let mut queries = Vec::with_capacity(queries_v.len());
        for (i, q) in queries_v.iter().enumerate() {
            let el = format!("queries[{i}]");
            let obj = q
                .as_object()
                .ok_or_else(|| bad(&el, "expected {\"start\": [...], \"goal\": [...]}".into()))?;
            let mut pair = [[0.0; 6]; 2];
            for (slot, key) in pair.iter_mut().zip(["start", "goal"]) {
                let e = format!("{el}.{key}");
                let arr = obj
                    .get(key)
                    .ok_or_else(|| bad(&e, "missing".into()))?
                    .as_array()
                    .filter(|a| a.len() == 6)
                    .ok_or_else(|| bad(&e, "expected an array of 6 joint angles (rad)".into()))?;
                for (j, v) in arr.iter().enumerate() {
                    let x = v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                        bad(&format!("{e}[{j}]"), "expected a finite number".into())
                    })?;
                    let (lo, hi) = limits[j];
                    if x < lo || x > hi {
                        return Err(bad(
                            &format!("{e}[{j}]"),
                            format!(
                                "{x} rad is outside the {} limits [{lo:.4}, {hi:.4}]",
                                JOINT_NAMES[j]
                            ),
                        ));
                    }
                    slot[j] = x;
                }
            }
            queries.push(ReachQuery {
                start: pair[0],
                goal: pair[1],
            });
        }
        Ok(ReachProblemSet {
            model,
            obstacles,
            queries,
        })
    }

    /// The problem set as JSON (the file format above), numbers printed exactly.
    pub fn to_json(&self) -> Value {
        let obstacles: Vec<Value> = self
            .obstacles
            .iter()
            .map(|o| {
                json!({"cuboid": {
                    "name": o.name,
                    "center": [o.center.x, o.center.y, o.center.z],
                    "half_extents": [o.half_extents.x, o.half_extents.y, o.half_extents.z],
                    "rpy": o.rpy,
                }})
            })
            .collect();
        let queries: Vec<Value> = self
            .queries
            .iter()
            .map(|q| json!({"start": q.start, "goal": q.goal}))
            .collect();
        json!({"model": self.model.name(), "obstacles": obstacles, "queries": queries})
    }

    /// The arm of the problem: base at the origin, default 2F-85.
    pub fn arm(&self) -> ArmModel {
        ArmModel::new(
            "arm",
            self.model,
            Isometry3::identity(),
            Gripper2F85::default(),
        )
    }

    /// The single-arm world: no support plane, the cuboids as obstacles.
    pub fn world(&self) -> CollisionWorld {
        let world = CollisionWorld::single_arm(None, None, self.arm())
            .expect("a world without a mesh always builds");
        self.obstacles.iter().fold(world, |w, o| {
            w.with_obstacle_cuboid(&o.name, o.pose(), o.half_extents)
        })
    }
}

/// Reads `key` of `obj` as three finite numbers (`[0; 3]` when absent and not required).
fn vec3(
    obj: &Map<String, Value>,
    key: &str,
    el: &str,
    required: bool,
) -> Result<[f64; 3], (String, String)> {
    let e = format!("{el}.{key}");
    let Some(v) = obj.get(key) else {
        return if required {
            Err((e, "missing".into()))
        } else {
            Ok([0.0; 3])
        };
    };
    let arr = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or_else(|| (e.clone(), "expected an array of 3 numbers".into()))?;
    let mut out = [0.0; 3];
    for (i, x) in arr.iter().enumerate() {
        out[i] = x
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| (format!("{e}[{i}]"), "expected a finite number".into()))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"{"model": "ur5e",
        "obstacles": [{"cuboid": {"center": [0.5, 0, -0.1], "half_extents": [0.5, 0.5, 0.09], "rpy": [0, 0, 0.3]}}],
        "queries": [{"start": [0, -1.57, 1.57, 0, 0, 0], "goal": [1, -1.2, 1.0, 0, 0.5, 0]}]}"#;

    #[test]
    fn parses_and_round_trips() {
        let p = ReachProblemSet::parse(GOOD, "good.json").unwrap();
        assert_eq!(p.model, UrModel::Ur5e);
        assert_eq!(p.obstacles[0].name, "obstacle0");
        assert_eq!(p.queries[0].goal[4], 0.5);
        let again = ReachProblemSet::parse(&p.to_json().to_string(), "again.json").unwrap();
        assert_eq!(p, again);
    }

    fn err(text: &str) -> String {
        ReachProblemSet::parse(text, "p.json")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn errors_name_file_and_element() {
        assert!(err("{").starts_with("p.json: not valid JSON"));
        assert_eq!(
            err(&GOOD.replace("ur5e", "ur7")),
            "p.json: model: unknown model \"ur7\" (known: ur3e, ur5e, ur10e, ur16e, ur5)"
        );
        assert_eq!(
            err(&GOOD.replace("[0.5, 0.5, 0.09]", "[0.5, 0, 0.09]")),
            "p.json: obstacles[0].cuboid.half_extents: every half extent must be > 0"
        );
        assert_eq!(
            err(&GOOD.replace(
                "\"goal\": [1, -1.2, 1.0, 0, 0.5, 0]",
                "\"goal\": [1, -1.2, 1.0, 0, 0.5]"
            )),
            "p.json: queries[0].goal: expected an array of 6 joint angles (rad)"
        );
        assert!(err(&GOOD.replace("1.57, 0, 0, 0]", "3.5, 0, 0, 0]"))
            .starts_with("p.json: queries[0].start[2]: 3.5 rad is outside the elbow limits"));
        assert_eq!(
            err(&GOOD.replace("[0.5, 0, -0.1]", "[0.5, \"x\", -0.1]")),
            "p.json: obstacles[0].cuboid.center[1]: expected a finite number"
        );
        assert_eq!(
            err(r#"{"model": "ur5", "queries": []}"#),
            "p.json: queries: no queries"
        );
    }

    #[test]
    fn missing_file_names_it() {
        let e = ReachProblemSet::load(Path::new("/nonexistent/problems.json"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("/nonexistent/problems.json: cannot read"),
            "{e}"
        );
    }
}
