//! The serial chain between a base link and a tool link of a URDF.
//!
//! # Frames
//!
//! Every pose is expressed in the **base link frame**. URDF gives each joint an `<origin>`:
//! the pose of the joint frame (= the child link frame at joint value 0) in the parent link
//! frame, with `rpy` = fixed-axis roll about x, then pitch about y, then yaw about z, i.e.
//! `R = Rz(yaw)·Ry(pitch)·Rx(roll)`. A moving joint then moves its child by
//! `M(q) = Rot(axis, q)` (revolute, continuous) or `Trans(q·axis)` (prismatic), with `axis`
//! in the joint frame. So the child link frame of joint `j` is
//! `T_child = T_parent · origin_j · M_j(q_j)`.
//!
//! Fixed joints are folded: [`ChainJoint::origin`] is the product of the origins of every
//! fixed joint since the previous moving joint (or the base link) and of the joint's own
//! origin, and [`SerialChain::tip_offset`] the product of the fixed origins after the last
//! moving joint. With `n` moving joints the tool pose is
//!
//! ```text
//! T_tip(q) = origin_1·M_1(q_1) · origin_2·M_2(q_2) ··· origin_n·M_n(q_n) · tip_offset
//! ```
//!
//! # Joints of the chain
//!
//! The chain's variables are its **actuated** joints: the moving joints on the path that do
//! not mimic another. A mimic joint on the path moves with its master (which must be an
//! actuated joint of the same chain): its value is `multiplier·q_master + offset`. Mimic
//! relations elsewhere in the file (e.g. a gripper's second finger) are listed by
//! [`SerialChain::mimics`].

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use crate::error::UrdfError;
use crate::model::{Mimic, UrdfModel};

/// How a moving joint moves its child link.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JointKind {
    /// Rotation about the axis, within position limits (rad).
    Revolute,
    /// Rotation about the axis without position limits (rad).
    Continuous,
    /// Translation along the axis, within position limits (m).
    Prismatic,
}

impl JointKind {
    /// True for revolute and continuous joints.
    pub fn is_rotational(self) -> bool {
        !matches!(self, JointKind::Prismatic)
    }
}

/// Fastest joint speed a description may give (rad/s or m/s): ten times the fastest
/// industrial arm joint's. A `<limit velocity="1e300">` would time every motion at zero
/// seconds.
pub const MAX_JOINT_SPEED: f64 = 100.0;

/// Longest travel either way of a prismatic joint (m).
pub const MAX_PRISMATIC_TRAVEL: f64 = 100.0;

/// A number short enough for a message: `1e308`, not 309 digits.
pub(crate) fn number(v: f64) -> String {
    if v.is_finite() && v.abs() >= 1e6 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A joint's limits from its `<limit>` element. Continuous joints have infinite position
/// limits (and an infinite velocity when the element is absent).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Lowest position (rad or m), may be −∞.
    pub lower: f64,
    /// Highest position (rad or m), may be +∞.
    pub upper: f64,
    /// Speed limit (rad/s or m/s).
    pub velocity: f64,
    /// Effort limit (N·m or N).
    pub effort: f64,
}

impl JointLimits {
    /// `q` clamped into `[lower, upper]`.
    #[inline]
    pub fn clamp(&self, q: f64) -> f64 {
        q.max(self.lower).min(self.upper)
    }

    /// True when `lower ≤ q ≤ upper`.
    #[inline]
    pub fn contains(&self, q: f64) -> bool {
        q >= self.lower && q <= self.upper
    }
}

/// What sets a moving joint's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drive {
    /// The chain variable of that index (`0..dof`).
    Actuated(usize),
    /// `multiplier · q[master] + offset`, `master` a chain variable index.
    Mimic {
        /// Chain variable index of the master joint.
        master: usize,
        /// Factor on the master's value.
        multiplier: f64,
        /// Added after scaling.
        offset: f64,
    },
}

/// A moving joint of the chain.
#[derive(Clone, Debug)]
pub struct ChainJoint {
    /// The URDF joint name.
    pub name: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// Joint frame at value 0 in the previous moving joint's child frame (the base frame for
    /// the first joint), the fixed joints in between folded in.
    pub origin: Isometry3<f64>,
    /// Unit axis in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// Position, velocity and effort limits.
    pub limits: JointLimits,
    /// Actuated (a chain variable) or mimic.
    pub drive: Drive,
    /// The URDF child link (its frame is the joint frame moved by the joint).
    pub child_link: String,
}

impl ChainJoint {
    /// The joint's motion `M(value)`: a rotation about [`ChainJoint::axis`] by `value` rad,
    /// or a translation by `value · axis` m.
    #[inline]
    pub fn motion(&self, value: f64) -> Isometry3<f64> {
        if self.kind.is_rotational() {
            Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&self.axis, value),
            )
        } else {
            Isometry3::from_parts(
                Translation3::from(self.axis.into_inner() * value),
                UnitQuaternion::identity(),
            )
        }
    }
}

/// A link on the path from the base link to the tool link.
#[derive(Clone, Debug)]
pub struct ChainLink {
    /// The URDF link name.
    pub name: String,
    /// Index into [`SerialChain::joints`] of the last moving joint above it (`None`: rigid
    /// with the base link).
    pub after_joint: Option<usize>,
    /// Its frame in the child frame of that joint (or in the base frame).
    pub offset: Isometry3<f64>,
}

/// A serial kinematic chain extracted from a URDF: the moving joints from a base link to a
/// tool link, fixed joints folded into the transforms (see the module documentation for the
/// frames).
#[derive(Clone, Debug)]
pub struct SerialChain {
    pub(crate) source: String,
    pub(crate) base: String,
    pub(crate) tip: String,
    pub(crate) joints: Vec<ChainJoint>,
    /// Index into `joints` of each chain variable.
    pub(crate) actuated: Vec<usize>,
    pub(crate) tip_offset: Isometry3<f64>,
    pub(crate) links: Vec<ChainLink>,
    pub(crate) mimics: Vec<Mimic>,
}

impl SerialChain {
    /// Loads `path` and extracts the chain from link `base` down to link `tip`.
    pub fn from_file(
        path: impl AsRef<std::path::Path>,
        base: &str,
        tip: &str,
    ) -> Result<Self, UrdfError> {
        UrdfModel::from_file(path)?.chain(base, tip)
    }

    /// The number of chain variables (actuated joints).
    pub fn dof(&self) -> usize {
        self.actuated.len()
    }

    /// Every moving joint, base to tip, mimic joints included.
    pub fn joints(&self) -> &[ChainJoint] {
        &self.joints
    }

    /// The actuated joints, in chain variable order.
    pub fn actuated_joints(&self) -> impl ExactSizeIterator<Item = &ChainJoint> {
        self.actuated.iter().map(|&i| &self.joints[i])
    }

    /// Names of the chain variables, in order.
    pub fn joint_names(&self) -> Vec<&str> {
        self.actuated_joints().map(|j| j.name.as_str()).collect()
    }

    /// Limits of the chain variables, in order.
    pub fn limits(&self) -> Vec<JointLimits> {
        self.actuated_joints().map(|j| j.limits).collect()
    }

    /// The base link (the frame every pose is expressed in).
    pub fn base_link(&self) -> &str {
        &self.base
    }

    /// The tool link (the frame [`SerialChain::fk`](crate::SerialChain::fk) returns).
    pub fn tip_link(&self) -> &str {
        &self.tip
    }

    /// The tool frame in the last moving joint's child frame (fixed joints folded).
    pub fn tip_offset(&self) -> &Isometry3<f64> {
        &self.tip_offset
    }

    /// Every link on the path, base link first, tool link last.
    pub fn links(&self) -> &[ChainLink] {
        &self.links
    }

    /// Every `<mimic>` relation of the source file (on the chain or not).
    pub fn mimics(&self) -> &[Mimic] {
        &self.mimics
    }

    /// The source file (as given) or label.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The value of every moving joint (mimic joints included), in [`SerialChain::joints`]
    /// order, from the chain variables `q`.
    pub fn joint_values(&self, q: &[f64]) -> Vec<f64> {
        self.check_len(q);
        self.joints.iter().map(|j| value_of(j.drive, q)).collect()
    }

    pub(crate) fn check_len(&self, q: &[f64]) {
        assert_eq!(
            q.len(),
            self.dof(),
            "{} → {}: expected {} joint values, got {}",
            self.base,
            self.tip,
            self.dof(),
            q.len()
        );
    }
}

/// A joint's value from the chain variables.
#[inline]
pub(crate) fn value_of(drive: Drive, q: &[f64]) -> f64 {
    match drive {
        Drive::Actuated(i) => q[i],
        Drive::Mimic {
            master,
            multiplier,
            offset,
        } => multiplier * q[master] + offset,
    }
}

/// `<origin xyz rpy>` as an isometry: translation `xyz`, rotation `Rz(y)·Ry(p)·Rx(r)`.
pub fn origin_isometry(pose: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = pose.xyz.0;
    let [r, p, yw] = pose.rpy.0;
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(r, p, yw),
    )
}

impl UrdfModel {
    /// The serial chain from link `base` down to link `tip` (a descendant of `base`).
    ///
    /// Errors: an unknown link, `tip` not below `base`, a floating/planar/spherical joint on
    /// the path, a revolute or prismatic joint without limits, a bad axis or origin, a mimic
    /// joint whose master is not an actuated joint of the chain, no moving joint at all.
    pub fn chain(&self, base: &str, tip: &str) -> Result<SerialChain, UrdfError> {
        let file = || self.source().to_string();
        for (link, role) in [(base, "base link"), (tip, "tool link")] {
            if !self.has_link(link) {
                return Err(UrdfError::UnknownLink {
                    file: file(),
                    link: link.to_string(),
                    context: format!("asked for as the {role}"),
                });
            }
        }
        // Walk up from the tip; the parent relation is a function (checked on load), so the
        // walk either meets `base`, ends at a root, or loops (more steps than links).
        let mut path: Vec<&urdf_rs::Joint> = Vec::new();
        let mut link = tip;
        while link != base {
            let Some(j) = self.parent_joint(link) else {
                return Err(UrdfError::NoPath {
                    file: file(),
                    base: base.to_string(),
                    tip: tip.to_string(),
                    tip_root: link.to_string(),
                });
            };
            if path.len() > self.robot().links.len() {
                return Err(UrdfError::NotSerial {
                    file: file(),
                    link: link.to_string(),
                    problem: "is its own ancestor (the parent joints form a loop)".to_string(),
                });
            }
            path.push(j);
            link = &j.parent.link;
        }
        path.reverse();

        let mut joints: Vec<ChainJoint> = Vec::new();
        let mut actuated = Vec::new();
        let mut links = vec![ChainLink {
            name: base.to_string(),
            after_joint: None,
            offset: Isometry3::identity(),
        }];
        let mut pending = Isometry3::identity();
        for j in &path {
            let origin = origin_isometry(&j.origin);
            if !(origin.translation.vector.iter().all(|v| v.is_finite())
                && origin.rotation.coords.iter().all(|v| v.is_finite()))
            {
                return Err(UrdfError::BadOrigin {
                    file: file(),
                    joint: j.name.clone(),
                });
            }
            pending *= origin;
            let kind = match j.joint_type {
                urdf_rs::JointType::Fixed => {
                    links.push(ChainLink {
                        name: j.child.link.clone(),
                        after_joint: joints.len().checked_sub(1),
                        offset: pending,
                    });
                    continue;
                }
                urdf_rs::JointType::Revolute => JointKind::Revolute,
                urdf_rs::JointType::Continuous => JointKind::Continuous,
                urdf_rs::JointType::Prismatic => JointKind::Prismatic,
                ref other => {
                    return Err(UrdfError::UnsupportedJoint {
                        file: file(),
                        joint: j.name.clone(),
                        kind: format!("{other:?}").to_lowercase(),
                    })
                }
            };
            let axis = self.axis_of(j)?;
            let limits = self.limits_of(j, kind)?;
            let drive = if j.mimic.is_some() {
                // Resolved below, once every actuated joint has its index.
                Drive::Mimic {
                    master: usize::MAX,
                    multiplier: 1.0,
                    offset: 0.0,
                }
            } else {
                actuated.push(joints.len());
                Drive::Actuated(actuated.len() - 1)
            };
            joints.push(ChainJoint {
                name: j.name.clone(),
                kind,
                origin: pending,
                axis,
                limits,
                drive,
                child_link: j.child.link.clone(),
            });
            links.push(ChainLink {
                name: j.child.link.clone(),
                after_joint: Some(joints.len() - 1),
                offset: Isometry3::identity(),
            });
            pending = Isometry3::identity();
        }
        if joints.is_empty() {
            return Err(UrdfError::NoJoints {
                file: file(),
                base: base.to_string(),
                tip: tip.to_string(),
            });
        }
        let mimics = self.mimic_joints();
        let names: Vec<String> = joints.iter().map(|j| j.name.clone()).collect();
        for joint in &mut joints {
            if !matches!(joint.drive, Drive::Mimic { .. }) {
                continue;
            }
            let m = mimics
                .iter()
                .find(|m| m.joint == joint.name)
                .expect("a mimic joint has its relation");
            let master = actuated.iter().position(|&a| names[a] == m.master);
            let Some(master) = master else {
                return Err(UrdfError::MimicOutsideChain {
                    file: file(),
                    joint: joint.name.clone(),
                    master: m.master.clone(),
                    base: base.to_string(),
                    tip: tip.to_string(),
                });
            };
            joint.drive = Drive::Mimic {
                master,
                multiplier: m.multiplier,
                offset: m.offset,
            };
        }
        Ok(SerialChain {
            source: file(),
            base: base.to_string(),
            tip: tip.to_string(),
            joints,
            actuated,
            tip_offset: pending,
            links,
            mimics,
        })
    }

    pub(crate) fn axis_of(&self, j: &urdf_rs::Joint) -> Result<Unit<Vector3<f64>>, UrdfError> {
        let [x, y, z] = j.axis.xyz.0;
        let v = Vector3::new(x, y, z);
        let n = v.norm();
        if !(n.is_finite() && n > 1e-12) {
            return Err(UrdfError::BadAxis {
                file: self.source().to_string(),
                joint: j.name.clone(),
                axis: format!("{x} {y} {z}"),
            });
        }
        Ok(Unit::new_normalize(v))
    }

    pub(crate) fn limits_of(
        &self,
        j: &urdf_rs::Joint,
        kind: JointKind,
    ) -> Result<JointLimits, UrdfError> {
        let l = &j.limit;
        let bad = |problem: String| UrdfError::BadLimit {
            file: self.source().to_string(),
            joint: j.name.clone(),
            problem,
        };
        if l.lower.is_nan() || l.upper.is_nan() || l.velocity.is_nan() || l.effort.is_nan() {
            return Err(bad("a value is NaN".to_string()));
        }
        if l.velocity < 0.0 || l.effort < 0.0 {
            return Err(bad(format!(
                "negative velocity {} or effort {}",
                l.velocity, l.effort
            )));
        }
        let absent = l.lower == 0.0 && l.upper == 0.0 && l.velocity == 0.0;
        if kind == JointKind::Continuous {
            if l.velocity > MAX_JOINT_SPEED {
                return Err(bad(format!(
                    "velocity {}: a joint's speed must be at most {MAX_JOINT_SPEED} rad/s",
                    number(l.velocity)
                )));
            }
            let unset = |v: f64| if v > 0.0 { v } else { f64::INFINITY };
            return Ok(JointLimits {
                lower: f64::NEG_INFINITY,
                upper: f64::INFINITY,
                velocity: unset(l.velocity),
                effort: unset(l.effort),
            });
        }
        if absent {
            return Err(UrdfError::MissingLimit {
                file: self.source().to_string(),
                joint: j.name.clone(),
                kind: if kind == JointKind::Revolute {
                    "revolute"
                } else {
                    "prismatic"
                },
            });
        }
        if l.lower > l.upper {
            return Err(bad(format!("lower {} > upper {}", l.lower, l.upper)));
        }
        // A joint the planner drives must move at a finite, non-zero speed between finite
        // bounds: motions are timed by `velocity`, configurations sampled between the bounds.
        if !(l.velocity > 0.0 && l.velocity <= MAX_JOINT_SPEED) {
            return Err(bad(format!(
                "velocity {}: a joint's speed must be above 0 and at most {MAX_JOINT_SPEED} ({})",
                number(l.velocity),
                if kind == JointKind::Prismatic {
                    "m/s"
                } else {
                    "rad/s"
                }
            )));
        }
        let reach = if kind == JointKind::Prismatic {
            MAX_PRISMATIC_TRAVEL
        } else {
            f64::MAX
        };
        if !(l.lower.is_finite() && l.upper.is_finite())
            || l.lower.abs() > reach
            || l.upper.abs() > reach
        {
            return Err(bad(format!(
                "lower {} / upper {}: the bounds must be finite{}",
                number(l.lower),
                number(l.upper),
                if kind == JointKind::Prismatic {
                    format!(" and within ±{MAX_PRISMATIC_TRAVEL} m")
                } else {
                    String::new()
                }
            )));
        }
        Ok(JointLimits {
            lower: l.lower,
            upper: l.upper,
            velocity: l.velocity,
            effort: l.effort,
        })
    }
}
