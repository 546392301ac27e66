//! Robotiq 2F-85 gripper on the flange: tool points and collision boxes.
//!
//! Gripper frame G = flange frame (tool0): z is the approach direction, x the closing axis
//! (pads at ±x), y the finger-width direction. Numbers from the MuJoCo Menagerie model
//! (`shared/facts/ur5e-2f85.md`): housing x ±0.0424, y ±0.0375, z 0.0068…0.1008 (coupling
//! Ø0.075, z 0…0.0139, inside that footprint); open fingers reach x ±0.0741 and z 0.1603
//! with the pad faces 0.0852 apart; closed fingers reach x ±0.0619 and z 0.1735. Every box
//! is grown by [`LINK_MARGIN`] except on the flange face (z = 0, where the gripper is
//! bolted), on the palm (z = 0.1008, so that a bar held at the power point touches it at
//! most) and on the open pads' inner faces, which stay at ±0.0426 so that the 85 mm
//! stroke is free.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::links::{ArmGeometry, LinkShape, Primitive, LINK_MARGIN};

/// Frame index of the gripper shapes (the flange, DH frame 6).
pub const GRIPPER_FRAME: usize = 6;

/// Half the open gap between the pad inner faces (m): stroke 0.0852 m.
pub const OPEN_PAD_HALF_GAP: f64 = 0.0426;

/// Half the length of a pad along the approach axis z (m): 37.5 mm pads.
pub const PAD_HALF_LENGTH: f64 = 0.01875;

/// Finger state of the gripper.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GripperState {
    /// Fingers fully open (85 mm stroke between the pads).
    Open,
    /// Fingers fully closed (pads touching).
    Closed,
}

/// Robotiq 2F-85 mounted on the flange (gripper frame = flange frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gripper2F85 {
    /// Precision point on flange z (m): between the pad centres (0.1416 open … 0.1547
    /// closed; 0.150 suits 20–60 mm objects).
    pub precision_point_z: f64,
    /// Power point on flange z (m): axis of a Ø≈30 mm bar held against the palm
    /// (palm top 0.101 + D/2).
    pub power_point_z: f64,
}

impl Default for Gripper2F85 {
    fn default() -> Self {
        Gripper2F85 {
            precision_point_z: 0.150,
            power_point_z: 0.115,
        }
    }
}

fn on_z(z: f64) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::new(0.0, 0.0, z), UnitQuaternion::identity())
}

impl Gripper2F85 {
    /// Precision-point frame in the flange frame (same orientation as the flange).
    pub fn precision_point(&self) -> Isometry3<f64> {
        on_z(self.precision_point_z)
    }

    /// Power-point frame in the flange frame (same orientation as the flange).
    pub fn power_point(&self) -> Isometry3<f64> {
        on_z(self.power_point_z)
    }

    /// Collision shapes in the flange frame (`frame` = 6), named "gripper_*".
    pub fn shapes(&self, state: GripperState) -> Vec<LinkShape> {
        let m = LINK_MARGIN;
        let (hy, body_hx, palm) = (0.0375 + m, 0.0424 + m, 0.1008);
        let shape = |name, lo: [f64; 3], hi: [f64; 3]| LinkShape {
            name,
            frame: GRIPPER_FRAME,
            primitive: Primitive::aabb(Vector3::from(lo), Vector3::from(hi)),
        };
        let mut shapes = vec![shape(
            "gripper_body",
            [-body_hx, -hy, 0.0],
            [body_hx, hy, palm],
        )];
        match state {
            GripperState::Open => {
                let (outer, tip) = (0.0741 + m, 0.1603 + m);
                // Outer finger links and pads: from the pad faces outwards.
                shapes.push(shape(
                    "gripper_finger_left",
                    [-outer, -hy, 0.0068],
                    [-OPEN_PAD_HALF_GAP, hy, tip],
                ));
                shapes.push(shape(
                    "gripper_finger_right",
                    [OPEN_PAD_HALF_GAP, -hy, 0.0068],
                    [outer, hy, tip],
                ));
                // Knuckles just above the palm reach in to ±0.031 over z 0.10…0.11.
                shapes.push(shape(
                    "gripper_knuckle_left",
                    [-body_hx, -hy, palm],
                    [-0.031 + m, hy, 0.110 + m],
                ));
                shapes.push(shape(
                    "gripper_knuckle_right",
                    [0.031 - m, -hy, palm],
                    [body_hx, hy, 0.110 + m],
                ));
            }
            GripperState::Closed => {
                // Closed on a part: the pads stop on it, centred on the precision point (the
                // scene's precision_point_z encodes the grasped width, facts table "gap vs pad
                // centre z"), so the fingertips reach half a pad length (18.75 mm) beyond it —
                // never beyond the fully closed fingertips (0.1735). For power grasps on bars
                // 17–55 mm wide the pads sit within 5 mm of that depth, inside LINK_MARGIN.
                let tip = (self.precision_point_z + PAD_HALF_LENGTH).min(0.1735);
                let (outer, tip) = (0.0619 + m, tip + m);
                shapes.push(shape(
                    "gripper_fingers",
                    [-outer, -hy, palm],
                    [outer, hy, tip],
                ));
            }
        }
        shapes
    }

    /// The arm links (indices into `geometry.links`) the gripper must not touch: every
    /// link except wrist_3, which carries it.
    pub fn forbidden_arm_links(geometry: &ArmGeometry) -> Vec<usize> {
        (0..geometry.links.len())
            .filter(|&i| geometry.links[i].frame < GRIPPER_FRAME)
            .collect()
    }
}
