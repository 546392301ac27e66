//! Robot models for pregrasp: Universal Robots arms (UR3e, UR5e, UR10e, UR16e, UR5) with
//! standard-DH forward kinematics and analytic inverse kinematics, the Robotiq 2F-85
//! gripper with its finger linkage, parallel-jaw grippers from robot descriptions, and
//! collision shapes fitted to them (no margin in them).
//!
//! Frames: every pose is in the arm's controller *Base* frame unless stated otherwise;
//! the flange frame (tool0, DH frame 6) has z out of the flange; gripper shapes are given in
//! it, and the tool points are frames in it whose x is the gripper's closing axis. Units: metres, radians, seconds.

mod angle;
mod arm;
mod closing;
mod finger;
mod finger_box;
mod fingers;
mod fk;
mod gripper;
mod ik;
mod linkage;
mod links;
mod model;
mod pieces_blob;
mod sweep_radii;

pub use angle::{atan2, sin_cos, wrap_angle};
pub use arm::{chain_frames, ArmDescription, ArmKinematics, ChainSteps};
pub use closing::{
    close_fingers, close_fingers_traced, ClosingKind, ClosingWorld, FingerClosing, Touch,
    CONTACT_SLACK, COUPLER, DRIVER, DRIVER_STEP, DRIVER_TOLERANCE, FOLLOWER, PAD, SPRING_LINK,
};
pub use finger::{BoxJson, FingerKinematics, FingerLink, FingerPose};
pub use fingers::{
    linkage, FingerPair, FingerSolid, FingerSolids, FINGER_SHAPES, LINKS_PER_FINGER, SIDES,
};
pub use fk::UrKinematics;
pub use gripper::{
    Gripper, Gripper2F85, GripperState, JawError, JawFace, JawGripper, JawPart, PerShape,
    GRIPPER_FRAME, ROBOTIQ_2F85_GRIP_FORCE,
};
pub use ik::{distinct_solutions, joint_distance, IkSolutions, IK_RESIDUAL_TOL};
pub use linkage::{FingerConfig, FingerLinkage, LinkageLimits, PlanarPose, FINGER_LINKS};
pub use links::{
    arm_geometry, fitted_links_of, point_cylinder_distance, ArmGeometry, Capsule, ConvexPieces,
    Cylinder, FittedLink, LinkShape, Primitive, MAX_ARM_SHAPES, MAX_GRIPPER_SHAPES,
    MAX_LINK_SHAPES, SHAPE_GROUPS,
};
pub use model::{DhParams, Joints, UnknownModel, UrModel, DEFAULT_JOINT_ACCEL, JOINT_NAMES};
pub use sweep_radii::{
    flange_sweep_radii, flange_sweep_radii_of, group_sweep_radii, group_sweep_radii_of,
    joint_sweep_radii, largest_per_joint,
};
