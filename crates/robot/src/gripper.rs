//! Robotiq 2F-85 gripper on the flange: tool points and collision boxes at any opening.
//!
//! Gripper frame G = flange frame (tool0): z is the approach direction, x the closing axis
//! (pads at ±x), y the finger-width direction. The housing and coupling never move; the
//! fingers follow [`FingerKinematics`]: a gripper *open* has its pads 85.2 mm apart, a gripper
//! *closed* on a part has them at the width it closed on (measured from the part's mesh by the
//! collision crate), with the pads where the real linkage puts them at that width — from
//! 141.6 mm (open) to 154.7 mm (closed) from the flange.
//!
//! The boxes enclose the description meshes with no margin: clearances are the planner's and
//! the checker's (`[planner]` keys), not part of the shapes.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::finger::{BoxJson, FingerKinematics, FingerPose};
use crate::links::{ArmGeometry, LinkShape, Primitive};

/// Frame index of the gripper shapes (the flange, DH frame 6).
pub const GRIPPER_FRAME: usize = 6;

/// Finger state of the gripper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GripperState {
    /// Fingers fully open (85.2 mm between the pads).
    Open,
    /// Fingers closed to `gap` (m) between the pad faces: on a part, the width it closes on;
    /// `0.0` fully closed.
    Closed { gap: f64 },
}

impl GripperState {
    /// Fully closed, pads touching.
    pub const FULLY_CLOSED: GripperState = GripperState::Closed { gap: 0.0 };

    /// The gap between the pad faces in this state (m).
    pub fn gap(&self) -> f64 {
        match self {
            GripperState::Open => FingerKinematics::robotiq_2f85().stroke(),
            GripperState::Closed { gap } => *gap,
        }
    }

    /// Whether the fingers are closed (on a part or fully).
    pub fn is_closed(&self) -> bool {
        matches!(self, GripperState::Closed { .. })
    }
}

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
        let fk = FingerKinematics::robotiq_2f85();
        let mut names: Vec<&'static str> = fk
            .statics
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
        for side in ["left", "right"] {
            for l in &fk.links {
                names.push(Box::leak(
                    format!("gripper_{}_{side}", l.name).into_boxed_str(),
                ));
            }
        }
        names
    })
}

/// The box `b` of a link whose frame is at `pose`; `mirror`: the link is the mirror image
/// `x → −x` of the one `b` was measured on (centre `x` and the box's `y` rotation negate).
fn cuboid(pose: Isometry3<f64>, b: &BoxJson, mirror: bool) -> Primitive {
    let c = Vector3::from(b.center);
    let (c, angle) = if mirror {
        (Vector3::new(-c.x, c.y, c.z), -b.angle)
    } else {
        (c, b.angle)
    };
    Primitive::Cuboid {
        pose: pose
            * Isometry3::from_parts(
                Translation3::from(c),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), angle),
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

    /// The finger linkage of the 2F-85.
    pub fn fingers(&self) -> &'static FingerKinematics {
        FingerKinematics::robotiq_2f85()
    }

    /// Where the fingers are in `state`.
    pub fn finger_pose(&self, state: GripperState) -> FingerPose {
        self.fingers().at(state.gap())
    }

    /// Number of collision shapes (the same in every state).
    pub fn shape_count(&self) -> usize {
        shape_names().len()
    }

    /// Calls `f(index, name, primitive)` for every collision shape in `state`, in the flange
    /// frame, in a fixed order (static boxes, left finger links, right finger links).
    pub fn for_each_shape(
        &self,
        state: GripperState,
        mut f: impl FnMut(usize, &'static str, Primitive),
    ) {
        let fk = self.fingers();
        let names = shape_names();
        let mut k = 0;
        for (_, b) in &fk.statics {
            f(k, names[k], cuboid(Isometry3::identity(), b, false));
            k += 1;
        }
        let pose = fk.at(state.gap());
        for side in [-1.0, 1.0] {
            for (i, link) in fk.links.iter().enumerate() {
                f(
                    k,
                    names[k],
                    cuboid(pose.link_pose(i, side), &link.bounds, side < 0.0),
                );
                k += 1;
            }
        }
    }

    /// Indices (into [`for_each_shape`](Self::for_each_shape)'s order) of the shapes that close
    /// on a part: the pads and the finger tips that carry them, both sides.
    pub fn contact_shapes(&self) -> Vec<usize> {
        let fk = self.fingers();
        let n_static = fk.statics.len();
        let n_links = fk.links.len();
        let mut out = Vec::new();
        for side in 0..2 {
            for (i, l) in fk.links.iter().enumerate() {
                if l.name == "pad" || l.name == "finger_tip" {
                    out.push(n_static + side * n_links + i);
                }
            }
        }
        out
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
