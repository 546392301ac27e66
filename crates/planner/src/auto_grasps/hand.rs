//! What the grasp search needs to know of a parallel gripper: how wide it opens, how thick its
//! fingers are beyond their pads, how wide they are along the bar, and how far its fingertips
//! reach below the precision point at a given width.
//!
//! Frames: the closing frame C of the gripper (flange `z` along the approach, `x` the closing
//! axis; a grasp frame is a C frame placed on the part). The 2F-85's numbers are its finger
//! linkage's ([`pregrasp_robot::FingerKinematics`]); a jaw gripper's are read off its jaw
//! parts in the open state ([`pregrasp_robot::JawGripper`]).

use pregrasp_robot::{FingerKinematics, Gripper, GripperState, JawGripper};

/// The 2F-85's stroke (m): the gap between the open pads.
pub const STROKE_2F85: f64 = 0.085;
/// Thickness (m) of a 2F-85 finger beyond its pad, with a little clearance.
pub const FINGER_THICKNESS_2F85: f64 = 0.012;
/// Half the width of the 2F-85's finger links (m; the pads are 22 mm wide, the links a little
/// more).
pub const HALF_PAD_2F85: f64 = 0.016;
/// Clearance (m) added to a jaw's measured thickness and half width.
const JAW_CLEARANCE: f64 = 0.002;
/// What a bar must leave of the stroke to close on (m).
pub const CLOSING_MARGIN: f64 = 0.005;

/// A parallel gripper's dimensions for the bar search (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub enum BarHand {
    /// The built-in Robotiq 2F-85.
    Robotiq2F85,
    /// A parallel-jaw gripper from a description.
    Jaws {
        /// The gap between the open jaws (m).
        stroke: f64,
        /// A jaw's thickness beyond its inner face, with clearance (m).
        finger_thickness: f64,
        /// Half a jaw's width along the bar, with clearance (m).
        half_pad: f64,
        /// How far (m) along flange `z` the jaws' lowest point lies (the fingertips).
        tip_z: f64,
    },
}

impl BarHand {
    /// The dimensions of `gripper`.
    pub fn of(gripper: &Gripper) -> BarHand {
        match gripper.jaws() {
            None => BarHand::Robotiq2F85,
            Some(j) => Self::of_jaws(j),
        }
    }

    fn of_jaws(j: &JawGripper) -> BarHand {
        let to_c = j.closing_frame().inverse();
        let frames = j.jaw_frames(GripperState::Open);
        let faces = j.faces_at(GripperState::Open);
        let (mut thick, mut half, mut tip) = (0.0_f64, 0.0_f64, f64::NEG_INFINITY);
        for (k, frame) in frames.iter().enumerate() {
            let side = if k == 0 { 1.0 } else { -1.0 };
            let points = j
                .jaw_parts(k)
                .iter()
                .flat_map(|p| p.pieces.pieces.iter().flatten())
                .map(|v| to_c * (frame * v));
            for p in points {
                thick = thick.max(side * (p.x - faces[k].x));
                half = half.max(p.y.abs());
                tip = tip.max(p.z);
            }
        }
        BarHand::Jaws {
            stroke: j.open_gap(),
            finger_thickness: thick + JAW_CLEARANCE,
            half_pad: half + JAW_CLEARANCE,
            tip_z: tip,
        }
    }

    /// The gap between the open pads (jaws) (m).
    pub fn stroke(&self) -> f64 {
        match self {
            BarHand::Robotiq2F85 => STROKE_2F85,
            BarHand::Jaws { stroke, .. } => *stroke,
        }
    }

    /// A finger's thickness beyond its pad (m).
    pub fn finger_thickness(&self) -> f64 {
        match self {
            BarHand::Robotiq2F85 => FINGER_THICKNESS_2F85,
            BarHand::Jaws {
                finger_thickness, ..
            } => *finger_thickness,
        }
    }

    /// Half a finger's width along the bar (m): the bar must be straight, and the air beside
    /// it free, this far to each side of a site.
    pub fn half_pad(&self) -> f64 {
        match self {
            BarHand::Robotiq2F85 => HALF_PAD_2F85,
            BarHand::Jaws { half_pad, .. } => *half_pad,
        }
    }

    /// The widest bar the hand closes on (m): its stroke less [`CLOSING_MARGIN`].
    pub fn max_bar_width(&self) -> f64 {
        self.stroke() - CLOSING_MARGIN
    }

    /// Free space (m) needed beyond each face of a bar of `width` for the open fingers to
    /// come down beside it: from the face to the open pad, plus the finger.
    pub fn finger_room(&self, width: f64) -> f64 {
        (self.stroke() - width) / 2.0 + self.finger_thickness()
    }

    /// How far (m) along flange `z` the fingertips reach with the fingers `width` apart.
    pub fn tip_z(&self, width: f64) -> f64 {
        match self {
            BarHand::Robotiq2F85 => FingerKinematics::robotiq_2f85().at(width).tip_z,
            BarHand::Jaws { tip_z, .. } => *tip_z,
        }
    }

    /// The dimensions both of two hands fit: the smaller stroke, the thicker and wider finger.
    /// A site found with them is a site for either arm.
    pub fn both(a: &BarHand, b: &BarHand) -> BarHand {
        if a == b {
            return a.clone();
        }
        BarHand::Jaws {
            stroke: a.stroke().min(b.stroke()),
            finger_thickness: a.finger_thickness().max(b.finger_thickness()),
            half_pad: a.half_pad().max(b.half_pad()),
            // Not used for sites: the fingertips' depth is asked of each arm's own hand.
            tip_z: a.tip_z(0.0).max(b.tip_z(0.0)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_2f85_opens_85_mm_and_needs_its_fingers_room() {
        let h = BarHand::Robotiq2F85;
        assert_eq!(h.max_bar_width(), 0.080);
        assert!((h.finger_room(0.045) - (0.020 + 0.012)).abs() < 1e-12);
        assert_eq!(BarHand::both(&h, &h), h);
    }
}
