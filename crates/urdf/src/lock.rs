//! Holding joints of a chain still: a chain with some actuated joints fixed at given values is
//! again a [`SerialChain`], with fewer variables.
//!
//! A held joint `j` at value `v` contributes the constant `origin_j · M_j(v)`; it is folded
//! into the next moving joint's origin (or into the tool offset when it is the last), and the
//! links that hung below it hang below the previous moving joint with that constant in their
//! offset. A mimic joint whose master is held is held too, at `multiplier · v + offset`. The
//! chain's tool pose is unchanged for every vector of the remaining variables:
//! `T_held(q_rest) = T(q_rest with v inserted)`.

use nalgebra::Isometry3;

use crate::chain::{ChainLink, Drive, SerialChain};
use crate::error::UrdfError;

impl SerialChain {
    /// This chain with the actuated joints named in `held` fixed at the given values (rad or
    /// m); the remaining actuated joints keep their order. Errors: a name that is not an
    /// actuated joint of the chain, a value outside its limits, or every joint held.
    pub fn with_held(&self, held: &[(&str, f64)]) -> Result<SerialChain, UrdfError> {
        let names = self.joint_names();
        let mut value: Vec<Option<f64>> = vec![None; self.dof()];
        for &(name, v) in held {
            let Some(i) = names.iter().position(|n| *n == name) else {
                return Err(UrdfError::HeldJoint {
                    file: self.source.clone(),
                    joint: name.to_string(),
                    problem: format!(
                        "is not an actuated joint of the chain from `{}` to `{}` (its joints: {})",
                        self.base,
                        self.tip,
                        names.join(", ")
                    ),
                });
            };
            let lim = self.joints[self.actuated[i]].limits;
            if !(v.is_finite() && lim.contains(v)) {
                return Err(UrdfError::HeldJoint {
                    file: self.source.clone(),
                    joint: name.to_string(),
                    problem: format!(
                        "value {v} is outside its limits [{}, {}]",
                        lim.lower, lim.upper
                    ),
                });
            }
            value[i] = Some(v);
        }
        let kept: Vec<usize> = (0..self.dof()).filter(|&i| value[i].is_none()).collect();
        if kept.is_empty() {
            return Err(UrdfError::NoJoints {
                file: self.source.clone(),
                base: self.base.clone(),
                tip: self.tip.clone(),
            });
        }
        // The value a joint is held at, if it is held (directly or through its master).
        let held_value = |drive: Drive| match drive {
            Drive::Actuated(i) => value[i],
            Drive::Mimic {
                master,
                multiplier,
                offset,
            } => value[master].map(|v| multiplier * v + offset),
        };
        let renumber = |i: usize| kept.iter().position(|&k| k == i).expect("a kept joint");
        let mut joints = Vec::new();
        let mut actuated = Vec::new();
        // Per old joint: the new joint its child frame hangs below (if any) and the offset.
        let mut below: Vec<(Option<usize>, Isometry3<f64>)> = Vec::with_capacity(self.joints.len());
        let mut pending = Isometry3::identity();
        for j in &self.joints {
            if let Some(v) = held_value(j.drive) {
                pending = pending * j.origin * j.motion(v);
                below.push((joints.len().checked_sub(1), pending));
                continue;
            }
            let mut joint = j.clone();
            joint.origin = pending * j.origin;
            joint.drive = match j.drive {
                Drive::Actuated(i) => {
                    actuated.push(joints.len());
                    Drive::Actuated(renumber(i))
                }
                Drive::Mimic {
                    master,
                    multiplier,
                    offset,
                } => Drive::Mimic {
                    master: renumber(master),
                    multiplier,
                    offset,
                },
            };
            joints.push(joint);
            below.push((Some(joints.len() - 1), Isometry3::identity()));
            pending = Isometry3::identity();
        }
        let links = self
            .links
            .iter()
            .map(|l| match l.after_joint {
                None => l.clone(),
                Some(j) => {
                    let (after_joint, pre) = below[j];
                    ChainLink {
                        name: l.name.clone(),
                        after_joint,
                        offset: pre * l.offset,
                    }
                }
            })
            .collect();
        Ok(SerialChain {
            source: self.source.clone(),
            base: self.base.clone(),
            tip: self.tip.clone(),
            joints,
            actuated,
            tip_offset: pending * self.tip_offset,
            links,
            mimics: self.mimics.clone(),
        })
    }
}
