//! The fully open gripper against the part: contact, never penetration (plan-format rule 2).
//!
//! At the start of a closing, at every state of the straight approach next to a grasp (its
//! contact zone) and at the start of `sup2`'s retreat, the gripper is fully open and may touch
//! the part, but no link of it — each finger link (a jaw) and the palm/housing — may lie more
//! than [`OPEN_CONTACT_DEPTH`] inside it. How deep a link lies is
//! [`depth_in_part`](crate::inside::depth_in_part) of its convex pieces (the 2F-85's finger
//! links: [`pregrasp_robot::FingerSolids`] placed by the open linkage; its housing and coupling:
//! their boxes; a jaw gripper's parts: their pieces), the deepest piece's depth.
//!
//! Frames: every shape is placed in the flange frame G by [`Gripper::shape_frames`] of the open
//! state, G in the object frame by `flange_in_object`. Along a straight approach the tool moves
//! along its own `z` and the part stands still, so the open hand `s` back from the grasp is at
//! `flange_in_object · Translation(0, 0, −s)`: the approach is a property of the grasp alone.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use nalgebra::{Isometry3, Point3, Translation3};
use pregrasp_robot::{Gripper, GripperState, Primitive};

use crate::inside::{box_outside, depth_in_part_along, ConvexSolid, FreeBox};
use crate::object::ObjectGeometry;

/// How deep (m) an open gripper link may lie in the part it grasps: touching, not inside.
pub const OPEN_CONTACT_DEPTH: f64 = 0.0005;
/// How far back along the approach (m) the open hand is judged at a grasp: the contact zone
/// of the plan's time line (`pregrasp_model::timeline::CONTACT_ZONE`), where the gripper may
/// touch the part; farther back it must keep the link clearance.
pub const OPEN_APPROACH_ZONE: f64 = 0.02;
/// Step (m) between the approach states judged: the plan check's resolution while grasping.
pub const OPEN_APPROACH_STEP: f64 = 0.001;

/// An open gripper link inside the part: its shape's name and how deep (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OpenInside {
    pub link: &'static str,
    pub depth: f64,
}

/// One shape of the open gripper: its name, its frame in G and its convex pieces there.
struct OpenShape {
    name: &'static str,
    frame: Isometry3<f64>,
    pieces: Vec<ConvexSolid>,
    /// All its pieces' points as one solid: its box settles most states.
    outline: ConvexSolid,
}

/// The open gripper's shapes (see the module documentation).
pub struct OpenHand {
    shapes: Vec<OpenShape>,
}

impl OpenHand {
    /// The open hand of `gripper`, built once per gripper shape ([`Gripper::shape_key`]).
    pub fn of(gripper: &Gripper) -> Arc<OpenHand> {
        static HANDS: OnceLock<Mutex<HashMap<String, Arc<OpenHand>>>> = OnceLock::new();
        let hands = HANDS.get_or_init(Default::default);
        let key = gripper.shape_key().to_string();
        if let Some(hand) = hands.lock().ok().and_then(|h| h.get(&key).cloned()) {
            return hand;
        }
        let hand = Arc::new(OpenHand::build(gripper));
        if let Ok(mut h) = hands.lock() {
            h.entry(key).or_insert_with(|| hand.clone());
        }
        hand
    }

    fn build(gripper: &Gripper) -> OpenHand {
        let frames = gripper.shape_frames(GripperState::Open);
        let pieces = gripper.shape_pieces();
        let mut shapes = Vec::with_capacity(frames.len());
        gripper.for_each_shape(GripperState::Open, |k, name, primitive| {
            let shape = match (pieces.get(k).copied().flatten(), frames.get(k)) {
                (Some(p), Some(frame)) => {
                    let all: Vec<Point3<f64>> = p.pieces.iter().flatten().copied().collect();
                    let Some(outline) = ConvexSolid::new(&all) else {
                        return;
                    };
                    OpenShape {
                        name,
                        frame: *frame,
                        pieces: p
                            .pieces
                            .iter()
                            .filter_map(|v| ConvexSolid::new(v))
                            .collect(),
                        outline,
                    }
                }
                // An exact primitive (the 2F-85's housing boxes), in the flange frame.
                _ => match primitive {
                    Primitive::Cuboid { pose, half_extents } => {
                        let Some(outline) = ConvexSolid::cuboid(&half_extents) else {
                            return;
                        };
                        OpenShape {
                            name,
                            frame: pose,
                            pieces: vec![outline.clone()],
                            outline,
                        }
                    }
                    _ => return,
                },
            };
            shapes.push(shape);
        });
        OpenHand { shapes }
    }

    /// The largest distance (m) of a point of the open hand from the flange frame's origin:
    /// a turn of the flange by `a` (rad) moves no point of it farther than `a` times this.
    pub fn reach(&self) -> f64 {
        self.shapes
            .iter()
            .map(|s| s.outline.reach(&s.frame))
            .fold(0.0, f64::max)
    }

    /// The deepest link of the open hand in the part, the flange at `flange_in_object` (G →
    /// object frame): `None` if no link overlaps it. Depths at or below `floor` (m) are
    /// measured without precision ([`depth_in_part`]).
    pub fn deepest(
        &self,
        object: &ObjectGeometry,
        flange_in_object: &Isometry3<f64>,
        floor: f64,
    ) -> Option<OpenInside> {
        self.deepest_along(object, flange_in_object, floor, &mut OpenMemo::default())
    }

    /// [`deepest`](Self::deepest) at one state of a motion, `memo` carried from its earlier
    /// states: where a shape's box met no surface before, a box that meets none now and whose
    /// centre it holds is on the same side (the answers are the same as without it).
    pub fn deepest_along(
        &self,
        object: &ObjectGeometry,
        flange_in_object: &Isometry3<f64>,
        floor: f64,
        memo: &mut OpenMemo,
    ) -> Option<OpenInside> {
        memo.free.resize(self.shapes.len(), None);
        memo.pieces.resize_with(self.shapes.len(), Vec::new);
        let mut deepest: Option<OpenInside> = None;
        let shapes = self.shapes.iter().zip(&mut memo.free).zip(&mut memo.pieces);
        for ((shape, known), pieces) in shapes {
            let pose = flange_in_object * shape.frame;
            let (outside, free) = box_outside(object, &shape.outline, &pose, *known);
            *known = free.or(*known);
            if outside {
                continue;
            }
            pieces.resize(shape.pieces.len(), None);
            for (piece, free) in shape.pieces.iter().zip(pieces.iter_mut()) {
                let known = deepest.map_or(0.0, |d| d.depth);
                let depth = depth_in_part_along(object, piece, &pose, floor.max(known), free);
                if depth > known {
                    deepest = Some(OpenInside {
                        link: shape.name,
                        depth,
                    });
                }
            }
        }
        deepest
    }
}

/// What [`OpenHand::deepest_along`] carries from one state of a motion to the next: per shape,
/// the last box of it found free of the part's surface, and the same of each of its pieces.
#[derive(Clone, Debug, Default)]
pub struct OpenMemo {
    free: Vec<Option<FreeBox>>,
    pieces: Vec<Vec<Option<FreeBox>>>,
}

/// The open hand's deepest link in the part with the flange at `flange_in_object`, when it is
/// more than [`OPEN_CONTACT_DEPTH`] inside; `memo` as [`OpenHand::deepest_along`] takes it.
pub fn open_inside(
    object: &ObjectGeometry,
    gripper: &Gripper,
    flange_in_object: &Isometry3<f64>,
    memo: &mut OpenMemo,
) -> Option<OpenInside> {
    OpenHand::of(gripper)
        .deepest_along(object, flange_in_object, OPEN_CONTACT_DEPTH, memo)
        .filter(|d| d.depth > OPEN_CONTACT_DEPTH)
}

/// The first state of the straight approach to the grasp `flange_in_object` (at the grasp,
/// then every [`OPEN_APPROACH_STEP`] back along G's `z` through [`OPEN_APPROACH_ZONE`]) at
/// which the open hand is more than [`OPEN_CONTACT_DEPTH`] inside the part, with how far
/// back it is (m).
pub fn open_approach_inside(
    object: &ObjectGeometry,
    gripper: &Gripper,
    flange_in_object: &Isometry3<f64>,
) -> Option<(OpenInside, f64)> {
    let hand = OpenHand::of(gripper);
    let steps = (OPEN_APPROACH_ZONE / OPEN_APPROACH_STEP).round() as usize;
    let mut memo = OpenMemo::default();
    (0..=steps).find_map(|k| {
        let back = k as f64 * OPEN_APPROACH_STEP;
        let at = flange_in_object * Translation3::new(0.0, 0.0, -back);
        hand.deepest_along(object, &at, OPEN_CONTACT_DEPTH, &mut memo)
            .filter(|d| d.depth > OPEN_CONTACT_DEPTH)
            .map(|d| (d, back))
    })
}
