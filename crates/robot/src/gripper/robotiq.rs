//! Robotiq 2F-85 gripper on the flange: tool points and collision shapes in any finger state.
//!
//! Gripper frame G = flange frame (tool0): z is the approach direction, x the closing axis
//! (pads at ±x), y the finger-width direction. The housing and coupling never move; the
//! fingers are the underactuated linkage of [`crate::FingerLinkage`] in the state
//! [`FingerPair`]: *open*, the pads 85.4 mm apart; *closed* on a part, where the closing of
//! [`crate::close_fingers`] left them (parallel for a pinch, curled around a bar for an
//! encompassing power grasp).
//!
//! Each finger link is a box holding its convex pieces ([`FingerSolids`]); the pieces are the
//! exact tier the collision crate tests where a box comes close. Neither has a margin:
//! clearances are the planner's and the checker's (`[planner]` keys), not part of the shapes.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::{GripperState, GRIPPER_FRAME};
use crate::finger::{BoxJson, FingerKinematics};
use crate::fingers::{FingerPair, FingerSolids, FINGER_SHAPES, LINKS_PER_FINGER};
use crate::links::{ArmGeometry, LinkShape, Primitive};

/// Robotiq 2F-85 mounted on the flange (gripper frame = flange frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gripper2F85 {
    /// Precision point on flange z (m): between the pad centres. Where the pads really are
    /// depends on the width the gripper closes on (0.1416 open … 0.1547 closed); 0.150 suits
    /// 20–60 mm objects. A scene that declares the true pad centre of its pinch places the
    /// flange exactly so that the pads are centred on the support grasp.
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

/// The names of the shapes [`Gripper2F85::for_each_shape`] produces, in order: the static
/// boxes, then each finger link on the left (`−x`) and on the right (`+x`).
fn shape_names() -> &'static [&'static str] {
    static NAMES: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
    NAMES.get_or_init(|| {
        let mut names: Vec<&'static str> = FingerKinematics::robotiq_2f85_statics()
            .iter()
            .map(|(n, _)| {
                let name = if n.starts_with("gripper_") {
                    n.clone()
                } else {
                    format!("gripper_{n}")
                };
                &*Box::leak(name.into_boxed_str())
            })
            .collect();
        let solids = FingerSolids::robotiq_2f85();
        for (k, solid) in solids.links.iter().enumerate() {
            let side = if k < LINKS_PER_FINGER {
                "left"
            } else {
                "right"
            };
            names.push(Box::leak(
                format!("gripper_{}_{side}", solid.name).into_boxed_str(),
            ));
        }
        names
    })
}

/// The box `b` (in the frame `pose` places) as a primitive.
fn cuboid(pose: Isometry3<f64>, b: &BoxJson) -> Primitive {
    Primitive::Cuboid {
        pose: pose
            * Isometry3::from_parts(
                Translation3::from(Vector3::from(b.center)),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), b.angle),
            ),
        half_extents: Vector3::from(b.half),
    }
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

    /// The finger links as solids (boxes and convex pieces in their link frames).
    pub fn finger_solids(&self) -> &'static FingerSolids {
        FingerSolids::robotiq_2f85()
    }

    /// Number of collision shapes (the same in every state).
    pub fn shape_count(&self) -> usize {
        shape_names().len()
    }

    /// Number of static shapes (housing, coupling), listed before the finger links.
    pub fn static_count(&self) -> usize {
        self.shape_count() - FINGER_SHAPES
    }

    /// The frame in G of every shape in `state` ([`for_each_shape`](Self::for_each_shape)
    /// order): the flange frame for the static shapes, the link frame for the finger links
    /// (in which their pieces are given).
    pub fn shape_frames(&self, state: GripperState) -> Vec<Isometry3<f64>> {
        let mut frames = vec![Isometry3::identity(); self.static_count()];
        frames.extend(state.fingers().link_frames());
        frames
    }

    /// Calls `f(index, name, primitive)` for every collision shape in `state`, in the flange
    /// frame, in a fixed order (static boxes, left finger links, right finger links).
    pub fn for_each_shape(
        &self,
        state: GripperState,
        mut f: impl FnMut(usize, &'static str, Primitive),
    ) {
        let names = shape_names();
        let mut k = 0;
        for (_, b) in FingerKinematics::robotiq_2f85_statics() {
            f(k, names[k], cuboid(Isometry3::identity(), b));
            k += 1;
        }
        let frames = state.fingers().link_frames();
        for (frame, solid) in frames.iter().zip(&self.finger_solids().links) {
            f(k, names[k], cuboid(*frame, &solid.bounds));
            k += 1;
        }
    }

    /// Finger states covering every pose the fingers can take (parallel at 33 driver angles,
    /// and the spring link held anywhere below its free angle while the driver turns on),
    /// for bounds that must hold in any state (sweep radii, the gripper's bounding sphere).
    pub fn sample_states(&self) -> Vec<GripperState> {
        let l = crate::fingers::linkage();
        let (lo, hi) = l.limits.driver;
        let (s_lo, _) = l.limits.spring_link;
        let mut states = vec![GripperState::Open];
        for i in 0..=32 {
            let driver = lo + (hi - lo) * i as f64 / 32.0;
            let free = FingerPair::parallel(driver);
            states.push(GripperState::Closed(free));
            for j in 0..8 {
                let spring = s_lo + (free.spring_link[0] - s_lo) * j as f64 / 8.0;
                let valid = l
                    .assemble(driver, spring)
                    .is_some_and(|c| l.within_limits(&c, 1e-9));
                if valid {
                    states.push(GripperState::Closed(FingerPair {
                        driver,
                        spring_link: [spring; 2],
                    }));
                }
            }
        }
        states
    }

    /// Collision shapes in the flange frame (`frame` = 6), named "gripper_*".
    pub fn shapes(&self, state: GripperState) -> Vec<LinkShape> {
        let mut shapes = Vec::with_capacity(self.shape_count());
        self.for_each_shape(state, |_, name, primitive| {
            shapes.push(LinkShape {
                name,
                frame: GRIPPER_FRAME,
                primitive,
                pieces: None,
            })
        });
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
