//! Serial arms from URDF for pregrasp: load a robot description, extract the serial chain
//! between a base link and a tool link, and compute its forward and inverse kinematics.
//!
//! * [`UrdfModel`] parses a URDF (with `urdf-rs`) and indexes its kinematic tree;
//!   [`UrdfModel::chain`] extracts a [`SerialChain`]: the moving joints (revolute,
//!   continuous, prismatic) from the base link down to the tool link, fixed joints folded into
//!   the transforms, mimic joints driven by their master. Errors ([`UrdfError`]) name the
//!   file and the element.
//! * [`SerialChain::fk`], [`SerialChain::link_frames`], [`SerialChain::jacobian`]: forward
//!   kinematics in the base link frame ([`chain`] documents the frames,
//!   [`kinematics`] the Jacobian).
//! * [`SerialChain::ik`]: every solution found by damped least squares from the seed and from
//!   deterministic random starts, within the joint limits, sorted by distance to the seed;
//!   [`SerialChain::ik_nearest`]: the solution reached by tracking the target from the seed
//!   (for following a path) ([`ik`] documents the method).
//! * Redundant arms: [`SerialChain::ik_redundant`] samples a redundancy joint over a grid to
//!   find every branch; [`SerialChain::ik_follow`] keeps it fixed to stay on a branch
//!   ([`redundancy`]).
//! * [`UrdfArm`]: an arm as a scene names it (file, base link, tool link, with defaults),
//!   resolved into its chain and, for a UR arm, its analytic model.
//! * [`SixJointArm`]: the arm as the planner drives it, six actuated joints (a 7-joint arm
//!   with one held still, [`SerialChain::with_held`]), behind `pregrasp_robot::ArmKinematics`
//!   ([`six`] documents its frames).
//! * [`recognise_ur`]: whether a chain is a Universal Robots arm (standard DH up to fixed base
//!   and tool transforms), so the analytic solver of `pregrasp-robot` can be used
//!   ([`ur`]).
//!
//! * [`geometry`]: collision geometry from the `<collision>` elements — meshes resolved and
//!   read, one convex piece per element in the link frame, self-collision pairs from
//!   deterministic sampling — derived once and cached on disk ([`UrdfGeometry::load`]).
//!
//! Units: metres, radians. A joint vector `q` lists the chain's actuated joints base to tip
//! ([`SerialChain::joint_names`]), `q.len() == dof()`.

mod arm;
pub mod chain;
mod describe;
mod error;
pub mod geometry;
mod gripper;
pub mod ik;
pub mod kinematics;
pub mod limits;
mod lock;
mod merge;
mod model;
pub mod redundancy;
mod rng;
pub mod six;
pub mod ur;

pub use arm::{UrdfArm, DEFAULT_TOOL_LINKS};
pub use chain::{
    origin_isometry, ChainJoint, ChainLink, Drive, JointKind, JointLimits, SerialChain,
};
pub use describe::{describe_arm, describe_arm_from};
pub use error::UrdfError;
pub use geometry::{
    CacheDir, CacheOutcome, GeometryOptions, LazyGeometry, LinkPieces, Loaded,
    SelfCollisionOptions, UrdfGeometry,
};
pub use gripper::describe_gripper;
pub use ik::{joint_distance, IkOptions, NearestOptions};
pub use kinematics::{pose_distance, pose_error, rotation_vector};
pub use model::{Mimic, UrdfModel};
pub use redundancy::RedundancyOptions;
pub use six::SixJointArm;
pub use ur::{recognise_ur, recognise_ur_with_tolerance, UrMatch, UR_MATCH_TOLERANCE};
