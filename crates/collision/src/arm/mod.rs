//! One arm of the world: kinematics, base placement, gripper, and its collision primitives
//! cached in their DH link frames, ready to be posed at a configuration.

use std::sync::Arc;

use nalgebra::Isometry3;
use pregrasp_robot::{
    flange_sweep_radii_of, group_sweep_radii_of, ArmDescription, ArmKinematics, Gripper,
    GripperState, Joints, LinkShape, Primitive, UrModel, SHAPE_GROUPS,
};

use crate::error::CollisionError;
use crate::shape::{Bounded, Placed};
use crate::tight::Tight;

/// Most primitives (arm links + gripper parts) one arm may have; the posed arm lives in a
/// fixed-size buffer so that a collision check never touches the heap. (Defined in
/// `pregrasp-robot`, so that describing an arm and loading a scene can keep to it.)
pub use pregrasp_robot::{MAX_ARM_SHAPES, MAX_GRIPPER_SHAPES};

// `PosedArm::placed` holds one bit per shape.
const _: () = assert!(MAX_ARM_SHAPES <= 64);

/// Self-collision pairs of link shapes (indices) between two DH frames `(frame_a, frame_b)`.
pub(crate) type PairGroup = ((u8, u8), Vec<(u8, u8)>);

/// The primitives of an arm with its gripper (links first, then gripper). The list, its names
/// and pairs are the same in every gripper state; only the finger shapes move.
#[derive(Clone, Debug)]
pub(crate) struct ShapeSet {
    /// `(DH frame index 0..=6, primitive in that frame)` of the arm links.
    pub parts: Vec<(usize, Primitive)>,
    /// The arm links as posed in their own frames ([`Local`]), in the order of `parts`.
    pub local_parts: Vec<Local>,
    /// Per arm link (same order as `parts`), its exact pieces where it has them.
    pub tight: TightSet,
    /// The gripper's shapes when open.
    pub open_gripper: GripperPose,
    /// The gripper's shapes in the finger states it is known to hold the part in (see
    /// [`ArmModel::with_held_fingers`]); other states are computed when posed.
    pub held_grippers: Vec<GripperPose>,
    /// Per gripper shape, its exact pieces (the finger links'; none for the housing).
    pub gripper_tight: Arc<Vec<Option<Tight>>>,
    /// `"<arm>/<link>"` for every part.
    pub names: Vec<String>,
    /// Whether the part belongs to the gripper (may touch a grasped part).
    pub is_gripper: Vec<bool>,
    /// The link shapes no gripper shape may touch (every link but the one carrying it).
    pub gripper_forbidden: Vec<u8>,
    /// A sphere (centre in the flange frame, radius) holding every gripper shape at any
    /// opening: one test culls the whole gripper.
    pub gripper_sphere: (nalgebra::Point3<f64>, f64),
    /// Per DH frame 0..=6, a sphere (centre in that frame, radius) holding the frame's link
    /// shapes (radius 0 for a frame with none).
    pub frame_spheres: [(nalgebra::Point3<f64>, f64); 7],
    /// The link shapes' self-collision pairs grouped by their two frames, so a whole group is
    /// culled by one test of the frame spheres.
    pub link_pair_groups: Vec<PairGroup>,
    /// Shape groups: the link shapes of each DH frame 0..=6, then (group 7) the gripper's.
    pub group_members: [Vec<u8>; 8],
    /// The group of every shape.
    pub group_of: Vec<u8>,
    /// Per joint and shape group, the group's largest distance from the joint axis (m), see
    /// [`pregrasp_robot::group_sweep_radii`].
    pub group_radii: [[f64; SHAPE_GROUPS]; 6],
    /// Per joint, the flange origin's largest distance from the joint axis (m).
    pub flange_radii: Joints,
}

/// The gripper's shapes in one finger state, in the flange frame.
#[derive(Clone, Debug)]
pub(crate) struct GripperPose {
    /// [`GripperState::key`] of the state.
    pub key: [u64; 3],
    pub prims: Vec<Primitive>,
    /// `prims` ready to be posed.
    pub locals: Vec<Local>,
    /// Per shape, the frame its pieces are given in (flange frame for the housing, the link
    /// frame for a finger link), in G.
    pub frames: Vec<Isometry3<f64>>,
}

impl GripperPose {
    fn new(gripper: &Gripper, state: GripperState) -> Self {
        let mut prims = Vec::with_capacity(gripper.shape_count());
        gripper.for_each_shape(state, |_, _, p| prims.push(p));
        GripperPose {
            key: state.key(),
            locals: prims.iter().map(|p| Local::new(p, 0.0)).collect(),
            prims,
            frames: gripper.shape_frames(state),
        }
    }
}

mod pieces;
mod posed;

use pieces::{frame_spheres, gripper_sphere, gripper_tight, tight_pieces, TightSet};
use posed::place;
pub(crate) use posed::{Local, PosedArm};

/// An arm in the world: an arm ([`ArmDescription`]: a built-in UR model or one from a robot
/// description) at `base` with a gripper on its flange (the Robotiq 2F-85, or a jaw gripper
/// from a description).
///
/// Frames: `base` maps the arm's base frame into the world; link primitives live in the
/// frames of [`ArmKinematics::fk_frames`] (the DH frames of a UR) and gripper primitives in
/// the flange frame.
#[derive(Clone, Debug)]
pub struct ArmModel {
    /// Name used in contact reports (`"left"` → `"left/forearm"`).
    pub name: String,
    /// Kinematics of the arm (base frame).
    pub kin: Arc<dyn ArmKinematics>,
    /// What the arm is built from.
    description: ArmDescription,
    /// Arm base frame in the world.
    pub base: Isometry3<f64>,
    /// The gripper on the flange.
    pub gripper: Gripper,
    shapes: ShapeSet,
}

impl ArmModel {
    /// Builds the arm and caches its link and gripper primitives.
    ///
    /// # Panics
    /// If the robot model has more than [`MAX_ARM_SHAPES`] primitives (a programming error in
    /// the built-in geometry); [`ArmModel::try_new`] reports it instead.
    pub fn new(
        name: &str,
        model: UrModel,
        base: Isometry3<f64>,
        gripper: impl Into<Gripper>,
    ) -> Self {
        match Self::try_new(name, model, base, gripper) {
            Ok(arm) => arm,
            Err(e) => panic!("{e}"),
        }
    }

    /// Builds the arm, reporting an over-large geometry as an error.
    pub fn try_new(
        name: &str,
        model: UrModel,
        base: Isometry3<f64>,
        gripper: impl Into<Gripper>,
    ) -> Result<Self, CollisionError> {
        Self::from_description(name, ArmDescription::ur(model), base, gripper)
    }

    /// Builds any arm ([`ArmDescription`]) with its link and gripper primitives cached.
    pub fn from_description(
        name: &str,
        description: ArmDescription,
        base: Isometry3<f64>,
        gripper: impl Into<Gripper>,
    ) -> Result<Self, CollisionError> {
        let gripper: Gripper = gripper.into();
        let geometry = &*description.geometry;
        let forbidden = Gripper::forbidden_arm_links(geometry);
        let grip: Vec<LinkShape> = gripper.shapes(GripperState::Open);
        let n_links = geometry.links.len();
        let count = n_links + grip.len();
        if count > MAX_ARM_SHAPES || grip.len() > MAX_GRIPPER_SHAPES {
            return Err(CollisionError::TooManyShapes {
                arm: name.to_string(),
                count,
                max: MAX_ARM_SHAPES,
            });
        }
        let names = geometry
            .links
            .iter()
            .chain(grip.iter())
            .map(|l| format!("{name}/{}", l.name))
            .collect();
        let is_gripper = (0..count).map(|i| i >= n_links).collect();
        let link_pairs: Vec<(u8, u8)> = geometry
            .self_collision_pairs
            .iter()
            .map(|&(i, j)| (i as u8, j as u8))
            .collect();
        let gripper_forbidden = forbidden.iter().map(|&l| l as u8).collect();
        let frame_spheres = frame_spheres(&geometry.links);
        let mut link_pair_groups: Vec<PairGroup> = Vec::new();
        for &(a, b) in &link_pairs {
            let key = (
                geometry.links[a as usize].frame as u8,
                geometry.links[b as usize].frame as u8,
            );
            match link_pair_groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, pairs)) => pairs.push((a, b)),
                None => link_pair_groups.push((key, vec![(a, b)])),
            }
        }
        let tight = tight_pieces(&description.key, &geometry.links);
        let shapes = ShapeSet {
            parts: geometry
                .links
                .iter()
                .map(|l| (l.frame, l.primitive))
                .collect(),
            local_parts: geometry
                .links
                .iter()
                .zip(tight.iter())
                .map(|(l, t)| Local::new(&l.primitive, t.as_ref().map_or(0.0, Tight::slack)))
                .collect(),
            tight,
            open_gripper: GripperPose::new(&gripper, GripperState::Open),
            held_grippers: Vec::new(),
            gripper_tight: gripper_tight(&gripper),
            names,
            is_gripper,
            gripper_forbidden,
            gripper_sphere: gripper_sphere(&gripper),
            frame_spheres,
            link_pair_groups,
            group_members: std::array::from_fn(|g| {
                if g < 7 {
                    (0..n_links)
                        .filter(|&k| geometry.links[k].frame == g)
                        .map(|k| k as u8)
                        .collect()
                } else {
                    (n_links..count).map(|k| k as u8).collect()
                }
            }),
            group_of: (0..count)
                .map(|k| geometry.links.get(k).map_or(7, |l| l.frame as u8))
                .collect(),
            group_radii: group_sweep_radii_of(&description, &gripper),
            flange_radii: flange_sweep_radii_of(&*description.kin),
        };
        Ok(ArmModel {
            name: name.to_string(),
            kin: description.kin.clone(),
            description,
            base,
            gripper,
            shapes,
        })
    }

    /// The same arm with the same gripper named `name` at `base`: what
    /// [`ArmModel::from_description`] would build from this arm's description and gripper, its
    /// link and gripper primitives (which depend on neither name nor base) taken from `self`
    /// rather than computed again.
    pub fn placed(&self, name: &str, base: Isometry3<f64>) -> ArmModel {
        let mut shapes = self.shapes.clone();
        for n in &mut shapes.names {
            // Every name is "<arm>/<link>" (`from_description`).
            let link = &n[self.name.len() + 1..];
            *n = format!("{name}/{link}");
        }
        ArmModel {
            name: name.to_string(),
            kin: self.kin.clone(),
            description: self.description.clone(),
            base,
            gripper: self.gripper.clone(),
            shapes,
        }
    }

    /// Whether this arm is built from `description` with `gripper` (then
    /// [`ArmModel::placed`] gives any other arm of that description and gripper).
    pub fn is_built_from(&self, description: &ArmDescription, gripper: &Gripper) -> bool {
        self.description == *description && self.gripper == *gripper
    }

    /// Caches the gripper's shapes in each of the finger states `held` (the closings on the
    /// part), so that posing the arm holding the part costs no finger kinematics.
    pub fn with_held_fingers(mut self, held: &[GripperState]) -> Self {
        for state in held {
            let key = state.key();
            let known = key == self.shapes.open_gripper.key
                || self.shapes.held_grippers.iter().any(|g| g.key == key);
            if !known {
                let pose = GripperPose::new(&self.gripper, *state);
                self.shapes.held_grippers.push(pose);
            }
        }
        self
    }

    /// The gripper's shapes in `state` if they are prepared.
    fn gripper_pose(&self, state: GripperState) -> Option<&GripperPose> {
        let key = state.key();
        let set = &self.shapes;
        if set.open_gripper.key == key {
            return Some(&set.open_gripper);
        }
        set.held_grippers.iter().find(|g| g.key == key)
    }

    /// What the arm is built from.
    pub fn description(&self) -> &ArmDescription {
        &self.description
    }

    /// The built-in UR model, when the arm is one.
    pub fn ur_model(&self) -> Option<UrModel> {
        self.description.ur
    }

    /// Position limits `(lower, upper)` (rad).
    pub fn joint_limits(&self) -> [(f64, f64); 6] {
        self.kin.joint_limits()
    }

    /// Speed limits (rad/s).
    pub fn max_joint_speed(&self) -> Joints {
        self.kin.max_joint_speed()
    }

    /// Acceleration limits (rad/s²).
    pub fn max_joint_accel(&self) -> Joints {
        self.kin.max_joint_accel()
    }

    /// Per joint, an upper bound on the distance from its axis to any point of the arm beyond
    /// it with the gripper at any opening (m): [`pregrasp_robot::joint_sweep_radii`].
    pub fn joint_sweep_radii(&self) -> Joints {
        pregrasp_robot::largest_per_joint(&self.shapes.group_radii)
    }

    /// Flange pose in the world: `base · fk(q)`.
    pub fn flange_world(&self, q: &Joints) -> Isometry3<f64> {
        self.base * self.kin.fk(q)
    }

    /// Names of the primitives (`"<arm>/<link>"`), links first then the gripper's; the same
    /// in every gripper state.
    pub fn shape_names(&self) -> &[String] {
        &self.shapes.names
    }

    pub(crate) fn set(&self) -> &ShapeSet {
        &self.shapes
    }

    /// Every primitive placed in the world at `q`.
    pub(crate) fn pose(&self, q: &Joints, state: GripperState) -> PosedArm {
        let mut posed = PosedArm::EMPTY;
        self.pose_into(q, state, &mut posed);
        posed
    }

    /// [`pose`](Self::pose) into an existing buffer (no copy of the posed arm).
    pub(crate) fn pose_into(&self, q: &Joints, state: GripperState, posed: &mut PosedArm) {
        self.pose_frames_into(q, state, posed);
        self.place_into(posed, u64::MAX);
    }

    /// The frames, frame spheres and gripper sphere at `q`; no shape placed yet
    /// ([`place_into`](Self::place_into) places them).
    pub(crate) fn pose_frames_into(&self, q: &Joints, state: GripperState, posed: &mut PosedArm) {
        let set = &self.shapes;
        let local = self.kin.fk_frames(q);
        let mut frames = [Isometry3::identity(); 7];
        for (f, l) in frames.iter_mut().zip(local.iter()) {
            *f = self.base * l;
        }
        let (gc, gr) = set.gripper_sphere;
        posed.len = set.names.len();
        posed.links = set.parts.len();
        posed.frames = frames;
        posed.gripper = Bounded::sphere(frames[6] * gc, gr);
        for (f, slot) in posed.frame_spheres.iter_mut().enumerate() {
            let (c, r) = set.frame_spheres[f];
            *slot = Bounded::sphere(frames[f] * c, r);
        }
        posed.gripper_state = state;
        posed.placed = 0;
        posed.bounds.set(None);
        posed.gripper_frames_placed = false;
    }

    /// Places the shapes in `mask` (bit `k`: shape `k`) that are not placed yet.
    pub(crate) fn place_into(&self, posed: &mut PosedArm, mask: u64) {
        let set = &self.shapes;
        let all = if posed.len >= 64 {
            u64::MAX
        } else {
            (1u64 << posed.len) - 1
        };
        let mut todo = mask & all & !posed.placed;
        if todo == 0 {
            return;
        }
        posed.bounds.set(None);
        let (n_links, flange) = (posed.links, posed.frames[6]);
        if todo == all {
            // Every shape: link by link, then the gripper (as one loop each).
            for ((slot, (frame, _)), local) in posed.shapes[..n_links]
                .iter_mut()
                .zip(set.parts.iter())
                .zip(set.local_parts.iter())
            {
                *slot = local.place(&posed.frames[*frame]);
            }
            todo = all & !((1u64 << n_links) - 1);
            posed.placed |= (1u64 << n_links) - 1;
        }
        let prepared = self.gripper_pose(posed.gripper_state);
        if todo >> n_links != 0 && !posed.gripper_frames_placed {
            let computed;
            let frames = match prepared {
                Some(g) => &g.frames,
                None => {
                    computed = self.gripper.shape_frames(posed.gripper_state);
                    &computed
                }
            };
            for (slot, f) in posed.gripper_frames.iter_mut().zip(frames) {
                *slot = flange * f;
            }
            posed.gripper_frames_placed = true;
        }
        if prepared.is_none() && todo >> n_links != 0 {
            // A finger state without prepared shapes: the gripper is placed whole.
            let slots = &mut posed.shapes[n_links..];
            self.gripper
                .for_each_shape(posed.gripper_state, |k, _, prim| {
                    slots[k] = Bounded::new(place(&flange, &prim));
                });
            posed.placed |= all & !((1u64 << n_links) - 1);
            todo &= (1u64 << n_links) - 1;
        }
        while todo != 0 {
            let k = todo.trailing_zeros() as usize;
            todo &= todo - 1;
            posed.shapes[k] = if k < n_links {
                set.local_parts[k].place(&posed.frames[set.parts[k].0])
            } else {
                prepared.expect("prepared gripper shapes").locals[k - n_links].place(&flange)
            };
            posed.placed |= 1 << k;
        }
    }

    /// World height of the lowest point of the gripper at `q` (m). Only the flange is posed,
    /// and of each box only what its height needs: the world `z` row of its rotation.
    pub(crate) fn gripper_lowest(&self, q: &Joints, state: GripperState) -> f64 {
        let flange = self.base * self.kin.fk(q);
        let row = crate::distance::world_up_in(&flange);
        let tz = flange.translation.vector.z;
        let lowest = |prim: &Primitive| match prim {
            Primitive::Cuboid { pose, half_extents } => {
                let r = pose.rotation.to_rotation_matrix();
                let z = r.matrix().transpose() * row;
                let ext = z.x.abs() * half_extents.x
                    + z.y.abs() * half_extents.y
                    + z.z.abs() * half_extents.z;
                row.dot(&pose.translation.vector) + tz - ext
            }
            other => crate::shape::plane_distance(&place(&flange, other), 0.0),
        };
        let statics = self.gripper.static_count();
        let frames;
        let (prims, shape_frames) = match self.gripper_pose(state) {
            Some(g) => (&g.prims, &g.frames),
            None => {
                let g = GripperPose::new(&self.gripper, state);
                frames = g;
                (&frames.prims, &frames.frames)
            }
        };
        let mut best = prims[..statics]
            .iter()
            .map(lowest)
            .fold(f64::INFINITY, f64::min);
        // The finger links by their pieces' lowest vertex, asked only of the links whose box
        // (which holds the pieces) reaches below the best so far, lowest box first.
        let tight = &self.shapes.gripper_tight;
        let mut boxes = [(f64::INFINITY, 0usize); MAX_GRIPPER_SHAPES];
        let n = prims.len() - statics;
        for (slot, k) in boxes.iter_mut().zip(statics..prims.len()) {
            *slot = (lowest(&prims[k]), k);
        }
        let boxes = &mut boxes[..n];
        boxes.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(box_low, k) in boxes.iter() {
            if box_low >= best {
                break;
            }
            let frame = flange * shape_frames[k];
            let exact = match &tight[k] {
                Some(t) => t.lowest(&frame),
                None => box_low,
            };
            best = best.min(exact);
        }
        best
    }

    /// Every primitive of the arm placed in the world at `q` (for viewers and debugging):
    /// `(name, primitive)`.
    pub fn placed_shapes(&self, q: &Joints, state: GripperState) -> Vec<(String, Placed)> {
        let posed = self.pose(q, state);
        let set = self.set();
        posed
            .shapes()
            .iter()
            .zip(set.names.iter())
            .map(|(b, n)| (n.clone(), b.shape))
            .collect()
    }

    /// Whether primitive `i` is rigidly attached to the base (DH frame 0): its pose never
    /// depends on `q`, so it is mounted, not moving.
    pub(crate) fn is_base_part(&self, i: usize) -> bool {
        self.shapes.parts.get(i).is_some_and(|p| p.0 == 0)
    }
}
