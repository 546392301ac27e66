//! Collision world of pregrasp: the support, the part's real mesh, static cuboids and two UR
//! arms with Robotiq 2F-85 grippers, plus the glue that lets `pregrasp_motion` plan one arm
//! in it (the reach benchmark over it is the crate `pregrasp-reach`).
//!
//! - [`distance`]: closed-form segment/triangle/box distances (the narrow phase).
//! - [`gjk`]: GJK as a yes/no question (within a distance?), stopping once it knows.
//! - [`shape`]: primitives placed in the world ([`Placed`]) and their pair tests.
//! - [`tight`]: the exact tier of the arm links, convex pieces inside their cylinders.
//! - [`object`]: the part as a parry `TriMesh` with its BVH ([`ObjectGeometry`]).
//! - [`grip`]: the width a gripper closes on at a grasp, from the part's mesh.
//! - [`inside`]: how deep a convex piece and the part reach into each other (the open
//!   gripper's rule: contact, never penetration).
//! - [`closing`]: the 2F-85's adaptive closing on the part's mesh and the support
//!   ([`pregrasp_robot::close_fingers`]'s world).
//! - [`arm`]: [`ArmModel`], an arm's kinematics, base and cached link/gripper primitives.
//! - [`world`]: [`CollisionWorld`], [`WorldState`], [`ObjectPlacement`], [`Contact`]:
//!   first contact by name, clearance, single-arm queries.
//! - [`sweep`]: swept checks ([`Sweep`]) that stand for every state within a motion bound,
//!   and [`CollisionWorld::first_contact_in`], a motion's states checked by ranges.
//! - [`validity`]: [`ArmValidity`] (a `StateValidator<6>`) and [`joint_space`] (limits and
//!   sweep-radius weights; the resolution bound is stated there).
//! - [`fixtures`]: meshes for tests and benchmarks (boxes, a frame, a tessellated plate).
//! - [`baked_hulls`]: parry's hulls of the built-in models' fixed point sets, kept in the
//!   repository so that a process does not hull them again.
//!
//! Frames: world `z` up, metres; each arm's base pose maps its controller base frame into
//! the world. The support is the half-space `z ≤ support_height`.

pub mod arm;
pub mod baked_hulls;
pub mod closing;
pub mod distance;
pub mod error;
pub mod fixtures;
pub mod gjk;
pub mod grip;
pub mod inside;
pub mod object;
mod pose_memo;
pub mod shape;
mod solid;
pub mod sweep;
pub mod tight;
pub mod validity;
pub mod world;

pub use arm::{ArmModel, MAX_ARM_SHAPES};
pub use closing::{FingerShapes, PartClosing};
pub use error::CollisionError;
pub use grip::{
    close_on_part, open_approach_inside, open_inside, pad_patches, prepare_closing, Grip,
    GripFailure, OpenHand, OpenInside, OpenMemo, PadPatch, OPEN_CONTACT_DEPTH,
};
pub use object::{check_mesh, ObjectGeometry};
pub use shape::Placed;
pub use sweep::{StatesCheck, Sweep, BOX_LIMIT, SWEEP_LIMIT};
pub use validity::{joint_space, joint_space_with_payload, ArmValidity};
pub use world::{attached_reach, CollisionWorld, Contact, ObjectPlacement, Obstacle, WorldState};
