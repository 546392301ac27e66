//! An arm as a scene names it: a URDF file, the link the arm stands on and the link the
//! gripper is mounted to, resolved once into a [`SerialChain`] and, for a Universal Robots
//! arm, its analytic model ([`UrMatch`]).
//!
//! Defaults, so that a plain robot description needs no link names: the base link is the
//! file's root link (a well-formed URDF has one); the tool link is `tool0` when the file has
//! one (the ROS-Industrial name of the flange frame, used by every UR and many other
//! descriptions), else `flange`, else the chain's only leaf below the base.

use std::path::Path;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::chain::SerialChain;
use crate::error::UrdfError;
use crate::model::UrdfModel;
use crate::ur::{recognise_ur, UrMatch};

/// Tool link names tried in order when the scene gives none.
pub const DEFAULT_TOOL_LINKS: [&str; 2] = ["tool0", "flange"];

/// A URDF arm from its base link to its tool link.
#[derive(Clone, Debug)]
pub struct UrdfArm {
    /// The whole description.
    pub model: UrdfModel,
    /// The base link's name (given or defaulted).
    pub base_link: String,
    /// The tool link's name (given or defaulted).
    pub tool_link: String,
    /// The serial chain from the base link to the tool link.
    pub chain: SerialChain,
    /// The UR model whose analytic kinematics the chain has, if it is one; its `base` with
    /// the description's round-off taken out (a half turn is exactly a half turn).
    pub ur: Option<UrMatch>,
}

impl UrdfArm {
    /// Loads `path` and extracts the chain from `base_link` to `tool_link` (defaults: see
    /// the module documentation).
    pub fn load(
        path: &Path,
        base_link: Option<&str>,
        tool_link: Option<&str>,
    ) -> Result<UrdfArm, UrdfError> {
        UrdfArm::from_model(UrdfModel::from_file(path)?, base_link, tool_link)
    }

    /// [`UrdfArm::load`] of a description already parsed.
    pub fn from_model(
        model: UrdfModel,
        base_link: Option<&str>,
        tool_link: Option<&str>,
    ) -> Result<UrdfArm, UrdfError> {
        let base_link = match base_link {
            Some(b) => b.to_string(),
            None => match model.root_links().as_slice() {
                [one] => one.to_string(),
                roots => {
                    return Err(UrdfError::AmbiguousLink {
                        file: model.source().to_string(),
                        role: "base link",
                        candidates: roots.iter().map(|s| s.to_string()).collect(),
                    })
                }
            },
        };
        let tool_link = match tool_link {
            Some(t) => t.to_string(),
            None => default_tool_link(&model, &base_link)?,
        };
        let chain = model.chain(&base_link, &tool_link)?;
        let ur = recognise_ur(&chain).map(|m| UrMatch {
            base: snapped(&m.base),
            ..m
        });
        Ok(UrdfArm {
            model,
            base_link,
            tool_link,
            chain,
            ur,
        })
    }
}

/// Largest change [`snapped`] makes to a quaternion component or a coordinate.
const SNAP: f64 = 1e-9;

/// `pose` with each quaternion component within [`SNAP`] of 0, ±½, ±√½ or ±1, and each
/// coordinate within [`SNAP`] of 0, made exactly that, when the result is still a unit
/// quaternion to the last bit's order. A description writes π as 3.1415926535897931 and
/// π/2 as 1.570796327, so the base of a UR description comes out as a half turn give or take
/// 1e-16; snapped, the arm it describes is the built-in arm bit for bit.
fn snapped(pose: &Isometry3<f64>) -> Isometry3<f64> {
    let levels = [0.0, 0.5, std::f64::consts::FRAC_1_SQRT_2, 1.0];
    let snap = |c: f64| {
        levels
            .iter()
            .find(|l| (c.abs() - **l).abs() <= SNAP)
            .map_or(c, |l| l.copysign(c))
    };
    let q = pose.rotation.quaternion();
    let s = Quaternion::new(snap(q.w), snap(q.i), snap(q.j), snap(q.k));
    let rotation = if (s.norm() - 1.0).abs() <= 4.0 * f64::EPSILON {
        UnitQuaternion::new_unchecked(s)
    } else {
        pose.rotation
    };
    let t = pose
        .translation
        .vector
        .map(|c| if c.abs() <= SNAP { 0.0 } else { c });
    Isometry3::from_parts(Translation3::from(t), rotation)
}

/// `tool0`, else `flange`, else the only leaf link the base link reaches.
fn default_tool_link(model: &UrdfModel, base_link: &str) -> Result<String, UrdfError> {
    if let Some(name) = DEFAULT_TOOL_LINKS.iter().find(|n| model.has_link(n)) {
        return Ok(name.to_string());
    }
    let leaves: Vec<&str> = model
        .leaf_links()
        .into_iter()
        .filter(|leaf| model.chain(base_link, leaf).is_ok())
        .collect();
    match leaves.as_slice() {
        [one] => Ok(one.to_string()),
        many => Err(UrdfError::AmbiguousLink {
            file: model.source().to_string(),
            role: "tool link",
            candidates: many.iter().map(|s| s.to_string()).collect(),
        }),
    }
}
