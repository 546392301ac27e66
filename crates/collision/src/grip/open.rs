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

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3};
use pregrasp_robot::{Gripper, GripperState, PerShape, Primitive};

use crate::inside::{box_at_outside, box_outside, depth_in_part_along, ConvexSolid, FreeBox};
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
        static HANDS: PerShape<Arc<OpenHand>> = PerShape::new();
        HANDS.get_or_build(gripper, |g| Arc::new(OpenHand::build(g)))
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
    /// measured without precision ([`depth_in_part`](crate::inside::depth_in_part)).
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
        self.deepest_but(object, flange_in_object, floor, memo, &[])
    }

    /// [`deepest_along`](Self::deepest_along) with the shapes `known_outside` marks (`true`)
    /// known to lie outside the part (missing entries: not known).
    fn deepest_but(
        &self,
        object: &ObjectGeometry,
        flange_in_object: &Isometry3<f64>,
        floor: f64,
        memo: &mut OpenMemo,
        known_outside: &[bool],
    ) -> Option<OpenInside> {
        memo.free.resize(self.shapes.len(), None);
        memo.pieces.resize_with(self.shapes.len(), Vec::new);
        let mut deepest: Option<OpenInside> = None;
        let shapes = self.shapes.iter().zip(&mut memo.free).zip(&mut memo.pieces);
        for (k, ((shape, known), pieces)) in shapes.enumerate() {
            if known_outside.get(k).copied().unwrap_or(false) {
                continue;
            }
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
    let reach = steps as f64 * OPEN_APPROACH_STEP;
    let known_outside = hand.outside_along(object, flange_in_object, reach);
    let mut memo = OpenMemo::default();
    (0..=steps).find_map(|k| {
        let back = k as f64 * OPEN_APPROACH_STEP;
        let at = flange_in_object * Translation3::new(0.0, 0.0, -back);
        hand.deepest_but(object, &at, OPEN_CONTACT_DEPTH, &mut memo, &known_outside)
            .filter(|d| d.depth > OPEN_CONTACT_DEPTH)
            .map(|d| (d, back))
    })
}

impl OpenHand {
    /// Per shape, whether it lies outside the part all along the straight approach: the flange
    /// at `flange_in_object` moved back along its `z` by 0 to `reach` (m). The shape's box,
    /// moved so, sweeps a box of its own axes grown by `reach / 2 · |d|` (`d` the motion's
    /// direction in the box's frame), centred halfway; a swept box that meets no triangle of
    /// the part and lies outside it holds the shape's box outside at every state
    /// ([`box_at_outside`]).
    fn outside_along(
        &self,
        object: &ObjectGeometry,
        flange_in_object: &Isometry3<f64>,
        reach: f64,
    ) -> Vec<bool> {
        let back = flange_in_object.rotation * -nalgebra::Vector3::z();
        self.shapes
            .iter()
            .map(|shape| {
                let pose = flange_in_object * shape.frame;
                let box_pose = pose * Translation3::from(shape.outline.center().coords);
                let d = box_pose.rotation.inverse() * back;
                let half = shape.outline.half() + d.abs() * (0.5 * reach);
                let swept = Isometry3::from_parts(
                    Translation3::from(box_pose.translation.vector + back * (0.5 * reach)),
                    box_pose.rotation,
                );
                box_at_outside(object, &swept, &half, half.norm(), None).0
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Vector3};
    use pregrasp_robot::Gripper;
    use rand::{Rng, SeedableRng};

    use super::*;

    /// The approach judged with the shapes known outside all along skipped gives what judging
    /// every shape at every state gives: the same first state inside, the same link and depth.
    /// The 2F-85 coming down at random onto a frame's bars, its approach tilted up to 0.6 rad.
    #[test]
    fn skipping_shapes_outside_the_whole_approach_changes_no_answer() {
        let mesh = crate::fixtures::frame_mesh(0.3, 0.2, 0.03, 0.025);
        let part = ObjectGeometry::new(&mesh).unwrap();
        let gripper = Gripper::default();
        let hand = OpenHand::of(&gripper);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(50);
        let (mut inside, mut free) = (0, 0);
        for _ in 0..200 {
            let tilt = Vector3::new(
                rng.random_range(-0.6..0.6),
                rng.random_range(-0.6..0.6),
                0.0,
            );
            let turn = nalgebra::UnitQuaternion::from_scaled_axis(tilt)
                * nalgebra::UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
            let at = Point3::new(
                rng.random_range(-0.02..0.32),
                rng.random_range(-0.02..0.22),
                rng.random_range(-0.17..-0.08),
            );
            // The flange above the part, its z (the approach) pointing down into it.
            let flange = Isometry3::from_parts(Translation3::new(at.x, at.y, -at.z), turn);
            let plain = (0..=20).find_map(|k| {
                let back = k as f64 * OPEN_APPROACH_STEP;
                let state = flange * Translation3::new(0.0, 0.0, -back);
                hand.deepest(&part, &state, OPEN_CONTACT_DEPTH)
                    .filter(|d| d.depth > OPEN_CONTACT_DEPTH)
                    .map(|d| (d, back))
            });
            let fast = open_approach_inside(&part, &gripper, &flange);
            assert_eq!(fast, plain, "flange {flange:?}");
            match fast {
                Some(_) => inside += 1,
                None => free += 1,
            }
        }
        assert!(
            inside > 20 && free > 20,
            "{inside} inside, {free} free: both kinds tried"
        );
    }
}
