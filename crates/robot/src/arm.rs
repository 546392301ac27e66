//! The kinematics the planner drives: any arm with six actuated joints, behind one trait, so
//! that the stages ask an arm for poses and joint vectors and never what arm it is.
//!
//! # Frames
//!
//! Every pose is in the arm's base frame. [`ArmKinematics::fk_frames`] returns seven frames,
//! the standard-DH convention the built-in UR arms use, stated so that any chain can give
//! them:
//!
//! - frame `i` (`0 ≤ i ≤ 5`) is rigid with the link that joints `1..=i` move (frame 0 with the
//!   base), and its **origin lies on the axis of joint `i + 1`**;
//! - frame 6 is the flange (tool0: the frame the gripper is mounted to), rigid with the last
//!   link.
//!
//! A link shape given in frame `f` therefore moves only with joints `1..=f`, and the distance
//! from joint `i + 1`'s axis to frame `i + 1`'s origin never changes: it is at most
//! [`ArmKinematics::frame_offsets`]`[i]` (the distance between the two origins). Summing
//! them bounds how far any point of the arm is from any joint axis, which is what the swept
//! collision checks need ([`crate::group_sweep_radii`]).

use std::sync::{Arc, OnceLock};

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use crate::fk::UrKinematics;
use crate::links::{arm_geometry, ArmGeometry};
use crate::model::{Joints, UrModel, JOINT_NAMES};

/// Kinematics and limits of an arm with six actuated joints (see the module documentation
/// for the frames).
pub trait ArmKinematics: Send + Sync + std::fmt::Debug {
    /// Short name for reports (`"ur5e"`, `"fr3"`).
    fn name(&self) -> &str;

    /// Flange pose in the base frame.
    fn fk(&self, q: &Joints) -> Isometry3<f64>;

    /// Frames 0..=6 in the base frame (frame 6 the flange).
    fn fk_frames(&self, q: &Joints) -> [Isometry3<f64>; 7];

    /// Every inverse kinematics solution found for the flange pose `flange`, within the
    /// joint limits, sorted by joint distance to `seed` (nearest first).
    fn ik(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints>;

    /// One solution per geometrically distinct one (angles equal modulo 2π): of each, the
    /// variant nearest to `seed`, in [`ArmKinematics::ik`]'s order. The variants share one
    /// geometry, so collision-checking one of each is enough.
    fn ik_distinct(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        crate::distinct_solutions(self.ik(flange, seed))
    }

    /// The solution on `seed`'s branch (a small motion from `seed` continues it), if any.
    fn ik_nearest(&self, flange: &Isometry3<f64>, seed: &Joints) -> Option<Joints>;

    /// Position limits `(lower, upper)` (rad).
    fn joint_limits(&self) -> [(f64, f64); 6];

    /// Speed limits (rad/s).
    fn max_joint_speed(&self) -> Joints;

    /// Acceleration limits (rad/s²).
    fn max_joint_accel(&self) -> Joints;

    /// Per joint `i` (0-based), the distance from frame `i`'s origin to frame `i + 1`'s: a
    /// constant of the arm, since frame `i`'s origin is on the axis joint `i + 1` turns about.
    fn frame_offsets(&self) -> [f64; 6];

    /// The chain as a drawing or an animation builds it: frame 0 in the base frame, and per
    /// joint `i` (0-based) its axis in frame `i` and frame `i + 1` in frame `i` turned about
    /// that axis, so that `frame_{i+1} = frame_i · Rot(axis_i, q_i) · link_i`
    /// ([`chain_frames`] composes them; the result is [`ArmKinematics::fk_frames`]).
    fn chain_steps(&self) -> ChainSteps;
}

/// Frame 0 and the six joint steps of an arm (see [`ArmKinematics::chain_steps`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainSteps {
    /// Frame 0 in the base frame.
    pub frame0: Isometry3<f64>,
    /// Per joint, its axis in the frame before it.
    pub axes: [Unit<Vector3<f64>>; 6],
    /// Per joint, the next frame in the frame before it turned by the joint.
    pub links: [Isometry3<f64>; 6],
}

/// The frames 0..=6 of `steps` at `q`: `frame_{i+1} = frame_i · Rot(axis_i, q_i) · link_i`.
pub fn chain_frames(steps: &ChainSteps, q: &Joints) -> [Isometry3<f64>; 7] {
    let mut frames = [steps.frame0; 7];
    for i in 0..6 {
        let turn = UnitQuaternion::from_axis_angle(&steps.axes[i], q[i]);
        frames[i + 1] =
            frames[i] * Isometry3::from_parts(Default::default(), turn) * steps.links[i];
    }
    frames
}

impl ArmKinematics for UrKinematics {
    fn name(&self) -> &str {
        self.model().name()
    }

    fn fk(&self, q: &Joints) -> Isometry3<f64> {
        UrKinematics::fk(self, q)
    }

    fn fk_frames(&self, q: &Joints) -> [Isometry3<f64>; 7] {
        UrKinematics::fk_frames(self, q)
    }

    fn ik(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        UrKinematics::ik(self, flange, seed)
    }

    fn ik_distinct(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        UrKinematics::ik_distinct(self, flange, seed)
    }

    fn ik_nearest(&self, flange: &Isometry3<f64>, seed: &Joints) -> Option<Joints> {
        UrKinematics::ik_nearest(self, flange, seed)
    }

    fn joint_limits(&self) -> [(f64, f64); 6] {
        self.model().joint_limits()
    }

    fn max_joint_speed(&self) -> Joints {
        self.model().max_joint_speed()
    }

    fn max_joint_accel(&self) -> Joints {
        self.model().max_joint_accel()
    }

    fn frame_offsets(&self) -> [f64; 6] {
        let dh = self.dh();
        std::array::from_fn(|j| {
            let (d, a, _) = dh.row(j);
            a.hypot(d)
        })
    }

    /// DH: every joint turns about its frame's z; `link_i = Tz(d_i)·Tx(a_i)·Rx(α_i)`.
    fn chain_steps(&self) -> ChainSteps {
        let dh = self.dh();
        ChainSteps {
            frame0: Isometry3::identity(),
            axes: [Vector3::z_axis(); 6],
            links: std::array::from_fn(|i| {
                let (d, a, alpha) = dh.row(i);
                Isometry3::from_parts(
                    Translation3::new(a, 0.0, d),
                    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), alpha),
                )
            }),
        }
    }
}

/// An arm as the planner uses it: its kinematics, the collision geometry of its links (in
/// the frames of [`ArmKinematics::fk_frames`]) and the names of its joints, built once and
/// shared.
#[derive(Clone, Debug)]
pub struct ArmDescription {
    /// Names the arm in process-wide caches: the model name for a built-in arm, a digest of
    /// the description for any other (two arms with one key must be the same arm).
    pub key: String,
    /// Kinematics and limits.
    pub kin: Arc<dyn ArmKinematics>,
    /// Link shapes (frames 0..=6) and self-collision pairs.
    pub geometry: Arc<ArmGeometry>,
    /// The built-in model, when the arm is one (URScript export needs it).
    pub ur: Option<UrModel>,
    /// The six driven joints' names, base to flange.
    pub joint_names: [String; 6],
}

impl ArmDescription {
    /// A built-in Universal Robots arm: analytic kinematics, the fitted link geometry (built
    /// once per process and model, then shared).
    pub fn ur(model: UrModel) -> ArmDescription {
        static BUILT: [OnceLock<ArmDescription>; 5] = [const { OnceLock::new() }; 5];
        let i = UrModel::ALL
            .iter()
            .position(|m| *m == model)
            .expect("a model");
        BUILT[i]
            .get_or_init(|| ArmDescription {
                key: model.name().to_string(),
                kin: Arc::new(UrKinematics::new(model)),
                geometry: Arc::new(arm_geometry(model)),
                ur: Some(model),
                joint_names: JOINT_NAMES.map(str::to_string),
            })
            .clone()
    }

    /// The arm's name for messages: the model for a built-in arm, else the kinematics' name.
    pub fn name(&self) -> &str {
        self.kin.name()
    }
}

/// Two descriptions are the same arm when their keys are (see [`ArmDescription::key`]).
impl PartialEq for ArmDescription {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key && self.joint_names == other.joint_names
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::UrModel;

    /// The DH frame origins are as far apart as the trait says, at any joint vector, and each
    /// frame's origin stays on the next joint's axis (its z axis for DH).
    #[test]
    fn ur_frame_offsets_are_origin_distances() {
        for model in UrModel::ALL {
            let kin = UrKinematics::new(model);
            let offsets = ArmKinematics::frame_offsets(&kin);
            for q in [
                [0.0; 6],
                [0.3, -1.2, 1.9, -0.4, 1.1, 2.5],
                [-2.0, -0.2, -2.5, 3.0, -1.5, 0.7],
            ] {
                let f = ArmKinematics::fk_frames(&kin, &q);
                for i in 0..6 {
                    let d = (f[i + 1].translation.vector - f[i].translation.vector).norm();
                    assert!((d - offsets[i]).abs() < 1e-12, "{model} joint {i}: {d}");
                }
                let flange = ArmKinematics::fk(&kin, &q);
                assert!((flange.translation.vector - f[6].translation.vector).norm() < 1e-12);
                let g = chain_frames(&kin.chain_steps(), &q);
                for (a, b) in f.iter().zip(&g) {
                    assert!((a.translation.vector - b.translation.vector).norm() < 1e-12);
                    assert!(a.rotation.angle_to(&b.rotation) < 1e-12);
                }
            }
        }
    }
}
