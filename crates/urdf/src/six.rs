//! A URDF arm as the planner drives it: six actuated revolute joints, behind
//! [`pregrasp_robot::ArmKinematics`].
//!
//! A six-joint arm (xArm6, a UR, a Kinova Gen3 lite …) is taken as it is. A seven-joint arm
//! (FR3, Gen3, iiwa) is driven with one joint **held** at a chosen value
//! ([`SerialChain::with_held`]): the planner's motions are then those of a six-joint arm, and
//! every joint vector it reports is completed with the held value
//! ([`SixJointArm::full_joints`]). This gives up the redundancy during a plan (the pose of the
//! elbow is fixed by the choice), not any reachable flange pose near the chosen posture.
//!
//! # Frames
//!
//! With the chain written `T(q) = origin_1·M_1(q_1) ··· origin_6·M_6(q_6) · tip_offset`
//! ([`crate::chain`]), frame `i` of [`ArmKinematics::fk_frames`] is the frame of joint
//! `i + 1` before it turns, `origin_1·M_1(q_1) ··· origin_{i+1}`: rigid with the link joints
//! `1..=i` move, its origin on joint `i + 1`'s axis (a URDF joint turns about an axis through
//! its frame's origin). Frame 6 is the tool link (the flange). The distance between the
//! origins of frames `i` and `i + 1` is `|origin_{i+2}.translation|` (`|tip_offset|` for the
//! last), whatever the joints.

use nalgebra::Isometry3;
use pregrasp_robot::{ArmKinematics, ChainSteps, Joints, DEFAULT_JOINT_ACCEL};

use crate::chain::{Drive, SerialChain};
use crate::error::UrdfError;

/// Position limit given to a continuous joint (rad): two turns either way, as the built-in
/// UR arms have.
const CONTINUOUS_RANGE: f64 = 2.0 * std::f64::consts::TAU;

/// A URDF arm with six actuated joints (some of its joints held; see the module
/// documentation).
#[derive(Clone, Debug)]
pub struct SixJointArm {
    name: String,
    /// The chain with the held joints folded in: six actuated revolute joints.
    chain: SerialChain,
    /// Names of the original chain's actuated joints.
    full_names: Vec<String>,
    /// `(index in the original joint vector, value)` of each held joint, in order.
    held: Vec<(usize, f64)>,
    limits: [(f64, f64); 6],
    speed: Joints,
    offsets: [f64; 6],
}

impl SixJointArm {
    /// The arm `chain` with the joints in `held` fixed at their values; `name` for reports.
    /// Errors: a held joint that cannot be held ([`SerialChain::with_held`]), or a chain that
    /// then does not have exactly six actuated revolute joints and no mimic joint.
    pub fn new(
        name: &str,
        chain: &SerialChain,
        held: &[(&str, f64)],
    ) -> Result<SixJointArm, UrdfError> {
        let reduced = chain.with_held(held)?;
        let full_names: Vec<String> = chain.joint_names().iter().map(|s| s.to_string()).collect();
        let six = reduced.dof() == 6
            && reduced.joints().len() == 6
            && reduced
                .joints()
                .iter()
                .all(|j| j.kind.is_rotational() && matches!(j.drive, Drive::Actuated(_)));
        if !six {
            let hint = if reduced.dof() == 7 {
                ": hold one joint (`hold = { <joint> = <rad> }`), e.g. the elbow of a 7-joint arm"
            } else if reduced.dof() > 7 {
                ": hold the joints beyond six, or pick a tool link nearer the base"
            } else {
                " revolute joints, no prismatic or mimic joint on the arm"
            };
            return Err(UrdfError::NotSixJoints {
                file: chain.source().to_string(),
                chain: format!("from `{}` to `{}`", chain.base_link(), chain.tip_link()),
                dof: reduced.dof(),
                joints: reduced.joint_names().join(", "),
                hint,
            });
        }
        let mut held_at: Vec<(usize, f64)> = held
            .iter()
            .map(|&(n, v)| {
                let i = full_names.iter().position(|f| f == n).expect("checked");
                (i, v)
            })
            .collect();
        held_at.sort_by_key(|&(i, _)| i);
        let lim = reduced.limits();
        let limits = std::array::from_fn(|i| {
            let (lo, hi) = (lim[i].lower, lim[i].upper);
            (lo.max(-CONTINUOUS_RANGE), hi.min(CONTINUOUS_RANGE))
        });
        // Continuous joints without a `<limit velocity>` have an infinite one: the planner
        // times every motion by these speeds, so each must be given.
        if let Some(i) = (0..6).find(|&i| !lim[i].velocity.is_finite()) {
            return Err(UrdfError::BadLimit {
                file: chain.source().to_string(),
                joint: reduced.joint_names()[i].to_string(),
                problem: "no velocity: give <limit velocity=\"..\"> (rad/s), motions are timed \
                          by it"
                    .to_string(),
            });
        }
        let speed = std::array::from_fn(|i| lim[i].velocity);
        let joints = reduced.joints();
        let offsets = std::array::from_fn(|i| match joints.get(i + 1) {
            Some(next) => next.origin.translation.vector.norm(),
            None => reduced.tip_offset().translation.vector.norm(),
        });
        Ok(SixJointArm {
            name: name.to_string(),
            chain: reduced,
            full_names,
            held: held_at,
            limits,
            speed,
            offsets,
        })
    }

    /// The six-joint chain (held joints folded in).
    pub fn chain(&self) -> &SerialChain {
        &self.chain
    }

    /// Names of every actuated joint of the arm, held ones included, base to tip.
    pub fn full_joint_names(&self) -> &[String] {
        &self.full_names
    }

    /// The held joints: `(index in the full joint vector, value)`.
    pub fn held(&self) -> &[(usize, f64)] {
        &self.held
    }

    /// The full joint vector (held joints included, [`SixJointArm::full_joint_names`] order)
    /// of the planner's six joints `q`.
    pub fn full_joints(&self, q: &Joints) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.full_names.len());
        let mut free = q.iter();
        let mut held = self.held.iter().peekable();
        for i in 0..self.full_names.len() {
            match held.peek() {
                Some(&&(h, v)) if h == i => {
                    out.push(v);
                    held.next();
                }
                _ => out.push(*free.next().expect("six free joints")),
            }
        }
        out
    }
}

/// A joint vector of the six-joint chain as an array.
fn six(q: Vec<f64>) -> Joints {
    std::array::from_fn(|i| q[i])
}

impl ArmKinematics for SixJointArm {
    fn name(&self) -> &str {
        &self.name
    }

    fn fk(&self, q: &Joints) -> Isometry3<f64> {
        self.chain.fk(q)
    }

    fn fk_frames(&self, q: &Joints) -> [Isometry3<f64>; 7] {
        let mut frames = [Isometry3::identity(); 7];
        let mut t = Isometry3::identity();
        for (i, j) in self.chain.joints().iter().enumerate() {
            let before = t * j.origin;
            frames[i] = before;
            t = before * j.motion(q[i]);
        }
        frames[6] = t * self.chain.tip_offset();
        frames
    }

    fn ik(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        self.chain.ik(flange, seed).into_iter().map(six).collect()
    }

    fn ik_nearest(&self, flange: &Isometry3<f64>, seed: &Joints) -> Option<Joints> {
        self.chain.ik_nearest(flange, seed).map(six)
    }

    fn joint_limits(&self) -> [(f64, f64); 6] {
        self.limits
    }

    fn max_joint_speed(&self) -> Joints {
        self.speed
    }

    fn max_joint_accel(&self) -> Joints {
        [DEFAULT_JOINT_ACCEL; 6]
    }

    fn frame_offsets(&self) -> [f64; 6] {
        self.offsets
    }

    /// Frame 0 is joint 1's origin; joint `i` turns about its URDF axis (given in its own
    /// frame, frame `i − 1`), and `link_i` is the next joint's origin (the tool offset last).
    fn chain_steps(&self) -> ChainSteps {
        let joints = self.chain.joints();
        ChainSteps {
            frame0: joints[0].origin,
            axes: std::array::from_fn(|i| joints[i].axis),
            links: std::array::from_fn(|i| match joints.get(i + 1) {
                Some(next) => next.origin,
                None => *self.chain.tip_offset(),
            }),
        }
    }
}
