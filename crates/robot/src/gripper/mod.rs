//! The gripper on an arm's flange: the built-in Robotiq 2F-85 ([`Gripper2F85`], an
//! underactuated linkage) or a parallel-jaw gripper taken from a robot description
//! ([`JawGripper`], prismatic jaws such as the Franka Hand's), behind one type ([`Gripper`]).
//!
//! Frames: every shape is given in the flange frame (DH frame 6, [`GRIPPER_FRAME`]). The tool
//! points ([`Gripper::precision_point`], [`Gripper::power_point`]) are frames in the flange
//! frame whose `x` is the closing axis and `z` the approach direction: a grasp pose on the
//! part means the same for every gripper.

use nalgebra::Isometry3;

use crate::fingers::FingerPair;
use crate::links::{ArmGeometry, ConvexPieces, LinkShape, Primitive};

mod jaws;
mod per_shape;
mod robotiq;

pub use jaws::{JawError, JawFace, JawGripper, JawPart};
pub use per_shape::PerShape;
pub use robotiq::Gripper2F85;

/// The Robotiq 2F-85's rated grip force range (N), `docs/hardware-facts.md`.
pub const ROBOTIQ_2F85_GRIP_FORCE: (f64, f64) = (20.0, 235.0);

/// Frame index of the gripper shapes (the flange, DH frame 6).
pub const GRIPPER_FRAME: usize = 6;

/// Finger state of a gripper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GripperState {
    /// Fingers fully open (the 2F-85's driver at its lower limit, pads 85.4 mm apart; a jaw
    /// gripper's jaws at the end of their stroke).
    Open,
    /// The 2F-85's fingers closed to `FingerPair`: on a part, where its closing stopped.
    Closed(FingerPair),
    /// A jaw gripper's jaws with their inner faces `gap` (m) apart.
    Jaws {
        /// Distance between the jaws' inner faces along the closing axis (m).
        gap: f64,
    },
}

impl GripperState {
    /// The 2F-85's parallel fingers with their pad faces `gap` (m) apart.
    pub fn at_gap(gap: f64) -> GripperState {
        GripperState::Closed(FingerPair::at_gap(gap))
    }

    /// The 2F-85 fully closed in the parallel mode (pads touching).
    pub fn fully_closed() -> GripperState {
        static CLOSED: std::sync::OnceLock<GripperState> = std::sync::OnceLock::new();
        *CLOSED.get_or_init(|| GripperState::at_gap(0.0))
    }

    /// The 2F-85's finger joints in this state (a jaw state has none: the open pair).
    pub fn fingers(&self) -> FingerPair {
        match self {
            GripperState::Closed(pair) => *pair,
            GripperState::Open | GripperState::Jaws { .. } => FingerPair::open(),
        }
    }

    /// Whether the fingers are closed (on a part or fully).
    pub fn is_closed(&self) -> bool {
        !matches!(self, GripperState::Open)
    }

    /// Bits identifying the state, for caches (`Open` is its own key).
    pub fn key(&self) -> [u64; 3] {
        match self {
            GripperState::Open => [u64::MAX; 3],
            GripperState::Closed(pair) => pair.key(),
            GripperState::Jaws { gap } => [gap.to_bits(), 0, u64::MAX],
        }
    }
}

/// The gripper on the flange.
#[derive(Clone, Debug, PartialEq)]
pub enum Gripper {
    /// The built-in Robotiq 2F-85.
    Robotiq2F85(Gripper2F85),
    /// A parallel-jaw gripper from a robot description.
    Jaws(std::sync::Arc<JawGripper>),
}

impl Default for Gripper {
    fn default() -> Self {
        Gripper::Robotiq2F85(Gripper2F85::default())
    }
}

impl From<Gripper2F85> for Gripper {
    fn from(g: Gripper2F85) -> Self {
        Gripper::Robotiq2F85(g)
    }
}

impl Gripper {
    /// Identifies the gripper's shapes for caches shared between arms (tool points aside).
    pub fn shape_key(&self) -> &str {
        match self {
            Gripper::Robotiq2F85(_) => "robotiq_2f85",
            Gripper::Jaws(j) => &j.key,
        }
    }

    /// The 2F-85, when the gripper is one.
    pub fn robotiq(&self) -> Option<&Gripper2F85> {
        match self {
            Gripper::Robotiq2F85(g) => Some(g),
            Gripper::Jaws(_) => None,
        }
    }

    /// The jaw gripper, when the gripper is one.
    pub fn jaws(&self) -> Option<&JawGripper> {
        match self {
            Gripper::Robotiq2F85(_) => None,
            Gripper::Jaws(j) => Some(j),
        }
    }

    /// Distance from the flange to the precision point along flange `z` (m).
    pub fn precision_point_z(&self) -> f64 {
        match self {
            Gripper::Robotiq2F85(g) => g.precision_point_z,
            Gripper::Jaws(j) => j.precision_point_z,
        }
    }

    /// Distance from the flange to the power point along flange `z` (m).
    pub fn power_point_z(&self) -> f64 {
        match self {
            Gripper::Robotiq2F85(g) => g.power_point_z,
            Gripper::Jaws(j) => j.power_point_z,
        }
    }

    /// Precision-point frame in the flange frame (`x` the closing axis).
    pub fn precision_point(&self) -> Isometry3<f64> {
        match self {
            Gripper::Robotiq2F85(g) => g.precision_point(),
            Gripper::Jaws(j) => j.precision_point(),
        }
    }

    /// Power-point frame in the flange frame (`x` the closing axis).
    pub fn power_point(&self) -> Isometry3<f64> {
        match self {
            Gripper::Robotiq2F85(g) => g.power_point(),
            Gripper::Jaws(j) => j.power_point(),
        }
    }

    /// The grip force it can be set to (N), least and greatest: the 2F-85's rated 20–235 N
    /// (`docs/hardware-facts.md`), a jaw gripper's from its description.
    pub fn grip_force_range(&self) -> (f64, f64) {
        match self {
            Gripper::Robotiq2F85(_) => ROBOTIQ_2F85_GRIP_FORCE,
            Gripper::Jaws(j) => j.grip_force,
        }
    }

    /// Number of collision shapes (the same in every state).
    pub fn shape_count(&self) -> usize {
        match self {
            Gripper::Robotiq2F85(g) => g.shape_count(),
            Gripper::Jaws(j) => j.shape_count(),
        }
    }

    /// Number of static shapes (rigid with the flange), listed before the finger shapes.
    pub fn static_count(&self) -> usize {
        match self {
            Gripper::Robotiq2F85(g) => g.static_count(),
            Gripper::Jaws(j) => j.static_count(),
        }
    }

    /// The frame in the flange frame of every shape in `state`, in which its pieces are given.
    pub fn shape_frames(&self, state: GripperState) -> Vec<Isometry3<f64>> {
        match self {
            Gripper::Robotiq2F85(g) => g.shape_frames(state),
            Gripper::Jaws(j) => j.shape_frames(state),
        }
    }

    /// Calls `f(index, name, primitive)` for every collision shape in `state`, in the flange
    /// frame, in a fixed order (static shapes first).
    pub fn for_each_shape(
        &self,
        state: GripperState,
        f: impl FnMut(usize, &'static str, Primitive),
    ) {
        match self {
            Gripper::Robotiq2F85(g) => g.for_each_shape(state, f),
            Gripper::Jaws(j) => j.for_each_shape(state, f),
        }
    }

    /// Per shape, its exact pieces in its frame ([`Gripper::shape_frames`]); `None` where the
    /// primitive is exact (the 2F-85's housing boxes).
    pub fn shape_pieces(&self) -> Vec<Option<&'static ConvexPieces>> {
        match self {
            Gripper::Robotiq2F85(g) => {
                let mut out: Vec<Option<&'static ConvexPieces>> = vec![None; g.static_count()];
                out.extend(g.finger_solids().links.iter().map(|s| Some(&s.pieces)));
                out
            }
            Gripper::Jaws(j) => j.parts().map(|p| Some(p.pieces)).collect(),
        }
    }

    /// Finger states covering every pose the fingers can take, for bounds that must hold in
    /// any state.
    pub fn sample_states(&self) -> Vec<GripperState> {
        match self {
            Gripper::Robotiq2F85(g) => g.sample_states(),
            Gripper::Jaws(j) => j.sample_states(),
        }
    }

    /// Collision shapes in the flange frame (`frame` = 6), named "gripper_*".
    pub fn shapes(&self, state: GripperState) -> Vec<LinkShape> {
        let mut shapes = Vec::with_capacity(self.shape_count());
        let pieces = self.shape_pieces();
        let statics = self.static_count();
        self.for_each_shape(state, |k, name, primitive| {
            shapes.push(LinkShape {
                name,
                frame: GRIPPER_FRAME,
                primitive,
                // Static pieces are in the flange frame, where the shape is.
                pieces: if k < statics { pieces[k] } else { None },
            })
        });
        shapes
    }

    /// The state with the fingers holding `gap` (m) between them, parallel.
    pub fn at_gap(&self, gap: f64) -> GripperState {
        match self {
            Gripper::Robotiq2F85(_) => GripperState::at_gap(gap),
            Gripper::Jaws(j) => j.at_gap(gap),
        }
    }

    /// Fully closed (pads or jaws touching, or the stroke's end).
    pub fn fully_closed(&self) -> GripperState {
        match self {
            Gripper::Robotiq2F85(_) => GripperState::fully_closed(),
            Gripper::Jaws(j) => j.at_gap(0.0),
        }
    }

    /// The distance between the pad (jaw) faces in `state` (m).
    pub fn gap(&self, state: GripperState) -> f64 {
        match (self, state) {
            (Gripper::Jaws(j), GripperState::Open) => j.open_gap(),
            (_, GripperState::Jaws { gap }) => gap,
            (_, s) => s.fingers().gap(),
        }
    }

    /// The arm links (indices into `geometry.links`) the gripper must not touch: every link
    /// except those of the last frame, which carries it.
    pub fn forbidden_arm_links(geometry: &ArmGeometry) -> Vec<usize> {
        (0..geometry.links.len())
            .filter(|&i| geometry.links[i].frame < GRIPPER_FRAME)
            .collect()
    }
}
