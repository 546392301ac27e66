//! A parallel-jaw gripper: rigid parts fixed to the flange (the hand) and two jaws that slide
//! toward each other along one axis, driven by one joint (the second jaw a mimic of the first,
//! as the Franka Hand's `fr3_finger_joint2` follows `fr3_finger_joint1`).
//!
//! Frames: the parts' pieces are given in the flange frame (static parts) or in their jaw's
//! frame (jaw parts). The closing frame C ([`JawGripper::closing_frame`], in the flange frame)
//! turns the flange frame about its `z` so that `x_C` points from the `−x` jaw to the `+x` jaw:
//! the tool points carry that turn, so a grasp pose's `x` is the closing axis for every gripper.
//!
//! The state is the gap between the jaws' inner faces ([`crate::GripperState::Jaws`]); the
//! jaws translate, so the gap is affine in the joint: `gap(j) = gap_zero + gap_rate · j`.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use super::GripperState;
use crate::links::{ConvexPieces, Primitive};

/// One rigid part of a jaw gripper (a link of its description).
#[derive(Clone, Debug, PartialEq)]
pub struct JawPart {
    /// The shape's name (`"gripper_<link>"`).
    pub name: &'static str,
    /// Its convex pieces in its frame (the flange frame, or its jaw's frame).
    pub pieces: &'static ConvexPieces,
    /// The box about the frame's axes holding the pieces.
    pub bounds: Primitive,
}

impl JawPart {
    /// A part from its pieces; `None` when they have no vertex.
    pub fn new(name: &str, pieces: Vec<Vec<Point3<f64>>>) -> Option<JawPart> {
        let (pieces, bounds) = ConvexPieces::leak_boxed(pieces)?;
        Some(JawPart {
            name: Box::leak(format!("gripper_{name}").into_boxed_str()),
            pieces,
            bounds,
        })
    }
}

/// `prim` (a part's box) in the frame `frame` places.
fn moved(frame: &Isometry3<f64>, prim: &Primitive) -> Primitive {
    match prim {
        Primitive::Cuboid { pose, half_extents } => Primitive::Cuboid {
            pose: frame * pose,
            half_extents: *half_extents,
        },
        // Parts are built as boxes (`JawPart::new`).
        other => *other,
    }
}

/// A jaw's inner face in the closing frame C: the rectangle in `y`, `z` over which its
/// innermost vertices lie, at `x` (as placed at joint value 0, or in a state:
/// [`JawGripper::faces_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JawFace {
    /// `x_C` of the face at joint value 0 (m).
    pub x: f64,
    /// Its extent in `y_C` (m).
    pub y: (f64, f64),
    /// Its extent in `z_C` (m).
    pub z: (f64, f64),
}

/// How far (m) a jaw vertex may lie outside the innermost one and still belong to the face.
const FACE_DEPTH: f64 = 5e-4;

/// A parallel-jaw gripper on the flange (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct JawGripper {
    /// Identifies the shapes for caches (the description's key and links).
    pub key: String,
    /// Precision point on flange `z` (m): between the jaw faces' centres.
    pub precision_point_z: f64,
    /// Power point on flange `z` (m): where a bar held deep between the jaws has its axis.
    pub power_point_z: f64,
    /// The grip force the jaws can be set to (N), least and greatest.
    pub grip_force: (f64, f64),
    statics: Vec<JawPart>,
    /// `[+x jaw, −x jaw]` parts.
    jaws: [Vec<JawPart>; 2],
    /// Each jaw's frame in the flange frame at joint value 0.
    jaw_zero: [Isometry3<f64>; 2],
    /// Each jaw's displacement (flange frame) per unit of joint value.
    jaw_rate: [Vector3<f64>; 2],
    /// The joint's limits.
    joint: (f64, f64),
    closing: UnitQuaternion<f64>,
    gap_zero: f64,
    gap_rate: f64,
    faces: [JawFace; 2],
}

/// Why parts and jaw kinematics do not make a parallel-jaw gripper.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum JawError {
    #[error("the jaws do not move opposite each other across the flange axis")]
    NotOpposed,
    #[error("a jaw has no collision geometry")]
    NoGeometry,
}

impl JawGripper {
    /// The gripper from its static parts (flange frame), its jaws' parts (each in its jaw's
    /// frame), each jaw's frame at joint value 0 and its displacement per unit joint value
    /// (both in the flange frame), and the joint's limits. The jaws must move opposite each
    /// other, across the flange `z` axis.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        key: String,
        statics: Vec<JawPart>,
        jaws: [Vec<JawPart>; 2],
        jaw_zero: [Isometry3<f64>; 2],
        jaw_rate: [Vector3<f64>; 2],
        joint: (f64, f64),
        precision_point_z: f64,
        power_point_z: f64,
    ) -> Result<JawGripper, JawError> {
        if jaws.iter().any(|j| j.is_empty()) {
            return Err(JawError::NoGeometry);
        }
        let apart = jaw_rate[0] - jaw_rate[1];
        let opposed = (jaw_rate[0] + jaw_rate[1]).norm() <= 1e-9 * apart.norm()
            && apart.z.abs() <= 1e-9 * apart.norm()
            && apart.norm() > 0.0;
        if !opposed {
            return Err(JawError::NotOpposed);
        }
        // x_C along the separation, pointing at jaw 0 when jaw 0 is on its +x side.
        let u = Vector3::new(apart.x, apart.y, 0.0).normalize();
        let centre = |k: usize| {
            let pts: Vec<Point3<f64>> = jaws[k]
                .iter()
                .flat_map(|p| p.pieces.pieces.iter().flatten())
                .map(|v| jaw_zero[k] * v)
                .collect();
            pts.iter().map(|p| p.coords.dot(&u)).sum::<f64>() / pts.len() as f64
        };
        let (jaws, jaw_zero, jaw_rate, u) = if centre(0) >= centre(1) {
            (jaws, jaw_zero, jaw_rate, u)
        } else {
            let [a, b] = jaws;
            (
                [b, a],
                [jaw_zero[1], jaw_zero[0]],
                [jaw_rate[1], jaw_rate[0]],
                u,
            )
        };
        let closing = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), u.y.atan2(u.x));
        let to_c = closing.inverse();
        let faces: [JawFace; 2] = [0, 1].map(|k| {
            let side = if k == 0 { 1.0 } else { -1.0 };
            let pts: Vec<Point3<f64>> = jaws[k]
                .iter()
                .flat_map(|p| p.pieces.pieces.iter().flatten())
                .map(|v| to_c * (jaw_zero[k] * v))
                .collect();
            // The innermost `x` (least on the +x jaw, greatest on the −x jaw).
            let inner = pts.iter().map(|p| side * p.x).fold(f64::INFINITY, f64::min);
            let on_face: Vec<&Point3<f64>> = pts
                .iter()
                .filter(|p| side * p.x <= inner + FACE_DEPTH)
                .collect();
            let span = |f: &dyn Fn(&Point3<f64>) -> f64| {
                on_face
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(f(p)), hi.max(f(p)))
                    })
            };
            JawFace {
                x: side * inner,
                y: span(&|p| p.y),
                z: span(&|p| p.z),
            }
        });
        let gap_zero = faces[0].x - faces[1].x;
        let gap_rate = (to_c * (jaw_rate[0] - jaw_rate[1])).x;
        Ok(JawGripper {
            key,
            precision_point_z,
            power_point_z,
            grip_force: (0.0, f64::INFINITY),
            statics,
            jaws,
            jaw_zero,
            jaw_rate,
            joint,
            closing,
            gap_zero,
            gap_rate,
            faces,
        })
    }

    /// The gripper with its grip force range `(least, greatest)` (N); unbounded until set.
    pub fn with_grip_force(mut self, range: (f64, f64)) -> JawGripper {
        self.grip_force = range;
        self
    }

    /// The closing frame C in the flange frame (a turn about flange `z`).
    pub fn closing_frame(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::identity(), self.closing)
    }

    fn on_z(&self, z: f64) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::new(0.0, 0.0, z), self.closing)
    }

    /// Precision-point frame in the flange frame (`x` the closing axis).
    pub fn precision_point(&self) -> Isometry3<f64> {
        self.on_z(self.precision_point_z)
    }

    /// Power-point frame in the flange frame (`x` the closing axis).
    pub fn power_point(&self) -> Isometry3<f64> {
        self.on_z(self.power_point_z)
    }

    /// The joint value at which the jaws' faces are `gap` apart (not clamped).
    fn joint_at(&self, gap: f64) -> f64 {
        (gap - self.gap_zero) / self.gap_rate
    }

    /// The gap (m) at joint value `j`.
    fn gap_at(&self, j: f64) -> f64 {
        self.gap_zero + self.gap_rate * j
    }

    /// The widest gap (m): the open jaws.
    pub fn open_gap(&self) -> f64 {
        self.gap_at(self.joint.0).max(self.gap_at(self.joint.1))
    }

    /// The narrowest gap the stroke allows (m).
    pub fn closed_gap(&self) -> f64 {
        self.gap_at(self.joint.0).min(self.gap_at(self.joint.1))
    }

    /// The jaws `gap` apart, clamped to the stroke.
    pub fn at_gap(&self, gap: f64) -> GripperState {
        GripperState::Jaws {
            gap: gap.clamp(self.closed_gap(), self.open_gap()),
        }
    }

    /// The gap of `state` (the open gap for anything but a jaw state).
    pub fn gap(&self, state: GripperState) -> f64 {
        match state {
            GripperState::Jaws { gap } => gap,
            _ => self.open_gap(),
        }
    }

    /// Each jaw's frame in the flange frame in `state`.
    pub fn jaw_frames(&self, state: GripperState) -> [Isometry3<f64>; 2] {
        let j = self.joint_at(self.gap(state));
        [0, 1].map(|k| Translation3::from(self.jaw_rate[k] * j) * self.jaw_zero[k])
    }

    /// Each jaw's inner face in C at joint value 0 (`x` moves by half the gap change).
    pub fn faces(&self) -> &[JawFace; 2] {
        &self.faces
    }

    /// Each jaw's inner face in C in `state`.
    pub fn faces_at(&self, state: GripperState) -> [JawFace; 2] {
        let to_c = self.closing.inverse();
        let j = self.joint_at(self.gap(state));
        [0, 1].map(|k| JawFace {
            x: self.faces[k].x + (to_c * self.jaw_rate[k]).x * j,
            ..self.faces[k]
        })
    }

    /// The static parts, then the `+x` jaw's, then the `−x` jaw's.
    pub fn parts(&self) -> impl Iterator<Item = &JawPart> {
        self.statics.iter().chain(self.jaws.iter().flatten())
    }

    /// The parts of jaw `k` (0: `+x`, 1: `−x`).
    pub fn jaw_parts(&self, k: usize) -> &[JawPart] {
        &self.jaws[k]
    }

    /// Number of collision shapes.
    pub fn shape_count(&self) -> usize {
        self.statics.len() + self.jaws[0].len() + self.jaws[1].len()
    }

    /// Number of static shapes.
    pub fn static_count(&self) -> usize {
        self.statics.len()
    }

    /// The frame of every shape in `state` (identity for static parts).
    pub fn shape_frames(&self, state: GripperState) -> Vec<Isometry3<f64>> {
        let jaws = self.jaw_frames(state);
        let mut frames = vec![Isometry3::identity(); self.statics.len()];
        for (k, parts) in self.jaws.iter().enumerate() {
            frames.extend(parts.iter().map(|_| jaws[k]));
        }
        frames
    }

    /// Calls `f(index, name, primitive)` for every shape in `state`, in the flange frame.
    pub fn for_each_shape(
        &self,
        state: GripperState,
        mut f: impl FnMut(usize, &'static str, Primitive),
    ) {
        let frames = self.shape_frames(state);
        for (k, (part, frame)) in self.parts().zip(&frames).enumerate() {
            f(k, part.name, moved(frame, &part.bounds));
        }
    }

    /// Open, and 16 gaps evenly over the stroke.
    pub fn sample_states(&self) -> Vec<GripperState> {
        let (lo, hi) = (self.closed_gap(), self.open_gap());
        let mut states = vec![GripperState::Open];
        states.extend((0..=16).map(|i| GripperState::Jaws {
            gap: lo + (hi - lo) * i as f64 / 16.0,
        }));
        states
    }
}
