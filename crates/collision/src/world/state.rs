//! What the world is asked about: where the part is, both arms' joints and grippers, and what
//! a query reports (a named contact); the static cuboid obstacles.

use nalgebra::{Isometry3, Vector3};
use pregrasp_robot::{GripperState, Joints};

use crate::shape::{Bounded, Placed};

/// Where the part is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ObjectPlacement {
    /// No part in the world.
    Absent,
    /// The part at a fixed pose (object frame → world).
    Fixed(Isometry3<f64>),
    /// The part moves with the flange of arm `arm`: `object = flange_world(q[arm]) · flange_to_object`.
    Attached {
        arm: usize,
        flange_to_object: Isometry3<f64>,
    },
}

/// Everything that changes between queries: both arms' joints and grippers, the part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldState {
    /// Joint angles of arm 0 and arm 1 (rad).
    pub q: [Joints; 2],
    /// Gripper state of each arm.
    pub gripper: [GripperState; 2],
    /// Where the part is.
    pub object: ObjectPlacement,
    /// Gripper `i` may touch the part (it grasps, closes on or releases it).
    pub grasping: [bool; 2],
}

impl WorldState {
    /// Both grippers open, no part, nothing grasped.
    pub fn new(q: [Joints; 2]) -> Self {
        WorldState {
            q,
            gripper: [GripperState::Open; 2],
            object: ObjectPlacement::Absent,
            grasping: [false; 2],
        }
    }
}

/// The first colliding pair found, by name (`"left/forearm"`, `"support"`, `"object"`, an
/// obstacle's name). `a` is the moving side when one side is static.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contact {
    pub a: String,
    pub b: String,
}

impl std::fmt::Display for Contact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} touches {}", self.a, self.b)
    }
}

/// A named static cuboid.
#[derive(Clone, Debug)]
pub struct Obstacle {
    pub name: String,
    pub(super) shape: Bounded,
}

impl Obstacle {
    /// Box frame → world pose and half extents (m).
    pub fn cuboid(&self) -> (Isometry3<f64>, Vector3<f64>) {
        match self.shape.shape {
            Placed::Cuboid { pose, half } => (pose, half),
            Placed::Capsule { .. } | Placed::Cylinder { .. } => {
                unreachable!("obstacles are cuboids")
            }
        }
    }
}

/// How far each body may move from a checked state: per arm, how far each joint may turn
/// (rad); a part at a fixed pose, how far any of its points may move (m). A part attached to a
/// flange moves with its arm's joints.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sweep {
    pub reach: [Joints; 2],
    pub object: f64,
}
