//! The collision world: support, static cuboids, the part, and two arms with grippers.
//!
//! Pairs checked (each with the optional safety margin):
//! - every arm part vs the support half-space `z ≤ support_height`, except parts rigid with
//!   the arm base (DH frame 0: mounted there);
//! - every arm part vs every static cuboid obstacle (same base exception);
//! - the arm's self-collision pairs (non-adjacent links; gripper vs the links it must not
//!   touch, see `pregrasp_robot`);
//! - every part of one arm vs every part of the other (base vs base excepted: both static);
//! - every arm part vs the part (object), except the gripper of an arm whose `grasping`
//!   flag is set; the object at its fixed pose or attached to a flange;
//! - an attached object vs the static cuboids.
//!
//! Never checked: the object vs the support (it rests and pivots on it), and pairs of static
//! things (a fixed object vs obstacles, obstacles vs support): no configuration changes them.

use std::ops::ControlFlow;
use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_motion::Doubts;
use pregrasp_robot::{GripperState, Joints};

use crate::arm::{ArmModel, PosedArm};
use crate::distance::aabb_aabb_sq;
use crate::error::CollisionError;
use crate::object::ObjectGeometry;
use crate::shape::{
    pair_distance, pair_intersects, pair_may_intersect, plane_distance, Bounded, Placed,
};
use crate::sweep::Grows;
use crate::tight::{self, Part};

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
    shape: Bounded,
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

/// Identifies one side of a pair, resolved to a name only when reported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Id {
    Arm(usize, usize),
    /// A whole shape group of an arm (DH frame 0..=6, 7 = the gripper): only for culling by
    /// bounding spheres, never reported.
    Group(usize, usize),
    Support,
    Obstacle(usize),
    Object,
}

/// Support, obstacles, part and two arms. Immutable; queries take a [`WorldState`] and
/// allocate nothing unless they report a contact by name.
#[derive(Clone, Debug)]
pub struct CollisionWorld {
    support: Option<f64>,
    /// The part's geometry, shared by the worlds made for one part (its BVH is built once).
    object: Option<Arc<ObjectGeometry>>,
    arms: [ArmModel; 2],
    active: [bool; 2],
    obstacles: Vec<Obstacle>,
    margin: f64,
    grasp_support_margin: f64,
    /// Identifies this world's arms for the per-thread cache of the arm that stands still.
    id: u64,
}

/// Source of [`CollisionWorld`] ids.
static NEXT_WORLD_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// Key of a posed arm in the cache: world id, arm, joint bits, gripper gap bits (open: `u64::MAX`).
type PoseKey = (u64, usize, [u64; 6], [u64; 3]);

/// Both arms as last posed on this thread, with the keys they were posed for.
type PosedPair = ([Option<PoseKey>; 2], [PosedArm; 2]);

thread_local! {
    /// Both arms as last posed on this thread: queries pose into it without copying, and an arm
    /// whose key has not changed (the arm that stands still while the other moves, in every
    /// query of a motion) is not posed again.
    static POSED: std::cell::RefCell<PosedPair> =
        const { std::cell::RefCell::new(([None, None], [PosedArm::EMPTY, PosedArm::EMPTY])) };
}

impl CollisionWorld {
    /// A world with the support plane at `z = support_height`, the part's mesh (object
    /// frame, if any) and two arms.
    ///
    /// # Panics
    /// If the mesh is unusable (no triangles, bad indices, non-finite vertices); use
    /// [`CollisionWorld::try_new`] to get the error instead.
    pub fn new(support_height: f64, object_mesh: Option<&Mesh>, arms: [ArmModel; 2]) -> Self {
        match Self::try_new(Some(support_height), object_mesh, arms) {
            Ok(w) => w,
            Err(e) => panic!("{e}"),
        }
    }

    /// Like [`CollisionWorld::new`], reporting a bad mesh; `support_height = None` means
    /// no support plane.
    pub fn try_new(
        support_height: Option<f64>,
        object_mesh: Option<&Mesh>,
        arms: [ArmModel; 2],
    ) -> Result<Self, CollisionError> {
        let object = object_mesh.map(ObjectGeometry::new).transpose()?;
        Ok(Self::with_part(support_height, object.map(Arc::new), arms))
    }

    /// [`CollisionWorld::try_new`] with the part's geometry already built (say, by another
    /// world of the same part: [`part`](Self::part)).
    pub fn with_part(
        support_height: Option<f64>,
        object: Option<Arc<ObjectGeometry>>,
        arms: [ArmModel; 2],
    ) -> Self {
        CollisionWorld {
            support: support_height,
            object,
            arms,
            active: [true; 2],
            obstacles: Vec::new(),
            margin: 0.0,
            grasp_support_margin: 0.0,
            id: NEXT_WORLD_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        }
    }

    /// A world with one arm only (as arm 0; `WorldState::q[1]` is ignored), an optional
    /// support plane and an optional part. For single-arm benchmarks.
    pub fn single_arm(
        support_height: Option<f64>,
        object_mesh: Option<&Mesh>,
        arm: ArmModel,
    ) -> Result<Self, CollisionError> {
        let mut w = Self::try_new(support_height, object_mesh, [arm.clone(), arm])?;
        w.active = [true, false];
        Ok(w)
    }

    /// Adds a static cuboid named `name` (box frame → world `pose`, half extents in m).
    pub fn with_obstacle_cuboid(
        mut self,
        name: &str,
        pose: Isometry3<f64>,
        half_extents: Vector3<f64>,
    ) -> Self {
        let shape = Bounded::new(Placed::Cuboid {
            pose,
            half: half_extents,
        });
        self.obstacles.push(Obstacle {
            name: name.to_string(),
            shape,
        });
        self
    }

    /// Builds now what the queries would otherwise build on their first heavy use (the link
    /// pieces' hull graphs, shared by every world of the same robot model): for a world that
    /// is to serve many queries, so none of them pays for it. Answers do not change.
    pub fn prepare(&self) {
        for arm in &self.arms {
            for tight in arm.set().tight.iter().flatten() {
                tight.prepare();
            }
        }
    }

    /// Safety margin (m) for [`check`](Self::check) and [`check_arm`](Self::check_arm):
    /// a pair collides when its distance is at most `margin`. Clearance ignores it.
    ///
    /// Also sets the gripper–support clearance of a grasping gripper to the same value; call
    /// [`with_grasp_support_margin`](Self::with_grasp_support_margin) after this to set it apart.
    pub fn with_margin(mut self, margin: f64) -> Self {
        self.margin = margin.max(0.0);
        self.grasp_support_margin = self.margin;
        self
    }

    /// Clearance (m) between the support and the gripper of an arm whose `grasping` flag is
    /// set — it holds the part, or is within the last centimetres of closing on it or the
    /// first of letting go, where a fingertip pinch sits a few millimetres above the table.
    pub fn with_grasp_support_margin(mut self, margin: f64) -> Self {
        self.grasp_support_margin = margin.max(0.0);
        self
    }

    /// The gripper–support clearance of a grasping gripper (m).
    pub fn grasp_support_margin(&self) -> f64 {
        self.grasp_support_margin
    }

    /// Lowest height (m) of arm `arm`'s gripper above the support at `state` (signed; `∞`
    /// without a support).
    pub fn gripper_support_distance(&self, arm: usize, state: &WorldState) -> f64 {
        match self.support {
            None => f64::INFINITY,
            Some(h) => self.arms[arm].gripper_lowest(&state.q[arm], state.gripper[arm]) - h,
        }
    }

    /// The safety margin (m).
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// Caches each arm's gripper shapes in the finger states it holds the part in — see
    /// [`ArmModel::with_held_fingers`].
    pub fn with_held_fingers(mut self, held: [&[GripperState]; 2]) -> Self {
        let [a0, a1] = self.arms.clone();
        self.arms = [a0.with_held_fingers(held[0]), a1.with_held_fingers(held[1])];
        self
    }

    /// Both arms (for a single-arm world, arm 1 is an inactive copy of arm 0).
    pub fn arms(&self) -> &[ArmModel; 2] {
        &self.arms
    }

    /// Whether arm `i` takes part in queries (false only for arm 1 of a single-arm world).
    pub fn is_active(&self, arm: usize) -> bool {
        self.active[arm]
    }

    /// Height of the support plane, if any.
    pub fn support_height(&self) -> Option<f64> {
        self.support
    }

    /// The part's geometry, if any.
    pub fn object(&self) -> Option<&ObjectGeometry> {
        self.object.as_deref()
    }

    /// The part's geometry, to share with another world of the same part.
    pub fn part(&self) -> Option<Arc<ObjectGeometry>> {
        self.object.clone()
    }

    /// The static cuboids.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// World pose of the part in `state` (None when absent or the world has no part mesh).
    pub fn object_pose(&self, state: &WorldState) -> Option<Isometry3<f64>> {
        self.object.as_ref()?;
        match state.object {
            ObjectPlacement::Absent => None,
            ObjectPlacement::Fixed(p) => Some(p),
            ObjectPlacement::Attached {
                arm,
                flange_to_object,
            } => Some(self.arms[arm].flange_world(&state.q[arm]) * flange_to_object),
        }
    }

    /// Collision-free, or the first colliding pair by name (fixed, deterministic order:
    /// support, self, obstacles, other arm, part — per arm — then the attached part).
    pub fn check(&self, state: &WorldState) -> Result<(), Contact> {
        match self.first_contact(None, state) {
            None => Ok(()),
            Some(ids) => Err(self.contact(ids)),
        }
    }

    /// Like [`check`](Self::check), restricted to pairs that involve arm `arm` or the part
    /// when attached to it; the other arm is an obstacle. Used by planners.
    pub fn check_arm(&self, arm: usize, state: &WorldState) -> Result<(), Contact> {
        match self.first_contact(Some(arm), state) {
            None => Ok(()),
            Some(ids) => Err(self.contact(ids)),
        }
    }

    /// `check_arm(arm, state).is_ok()` without building names.
    #[inline]
    pub fn is_arm_free(&self, arm: usize, state: &WorldState) -> bool {
        self.first_contact(Some(arm), state).is_none()
    }

    /// `check(state).is_ok()` without building names.
    #[inline]
    pub fn is_free(&self, state: &WorldState) -> bool {
        self.first_contact(None, state).is_none()
    }

    /// Minimum distance (m) over every checked pair, with the pair's names. `≤ 0` means
    /// contact (capsule pairs report a negative penetration estimate). `(∞, "", "")` when
    /// the world has no pair to measure.
    pub fn clearance(&self, state: &WorldState) -> (f64, String, String) {
        self.clearance_of(None, state)
    }

    /// [`clearance`](Self::clearance) restricted as in [`check_arm`](Self::check_arm).
    pub fn clearance_arm(&self, arm: usize, state: &WorldState) -> (f64, String, String) {
        self.clearance_of(Some(arm), state)
    }

    fn clearance_of(&self, only: Option<usize>, state: &WorldState) -> (f64, String, String) {
        let mut sink = MinDistance {
            best: f64::INFINITY,
            ids: None,
        };
        let _ = self.visit(only, state, &mut sink);
        match sink.ids {
            None => (f64::INFINITY, String::new(), String::new()),
            Some(ids) => {
                let c = self.contact(ids);
                (sink.best, c.a, c.b)
            }
        }
    }

    /// Whether the pairs `among` keep apart at `state` (as
    /// [`is_arm_doubted_within`](Self::is_arm_doubted_within) named them for a box holding
    /// it): what [`is_arm_free`](Self::is_arm_free) answers where a box showed every other
    /// pair.
    pub fn is_free_among(&self, state: &WorldState, among: &Doubts) -> bool {
        let mut sink = FirstContact {
            loose_filter: true,
            ..FirstContact::new(self.margin)
        };
        let _ = self.with_posed_shapes(state, shapes_among(among), |posed| {
            self.visit_among(state, posed, among, &mut sink)
        });
        sink.ids.is_none()
    }

    fn first_contact(&self, only: Option<usize>, state: &WorldState) -> Option<(Id, Id)> {
        let mut sink = FirstContact::new(self.margin);
        let _ = self.visit(only, state, &mut sink);
        sink.ids
    }

    fn name(&self, id: Id) -> String {
        match id {
            Id::Arm(i, k) => self.arms[i].shape_names()[k].clone(),
            Id::Group(i, g) => format!("{}/group {g}", self.arms[i].name),
            Id::Support => "support".to_string(),
            Id::Obstacle(o) => self.obstacles[o].name.clone(),
            Id::Object => "object".to_string(),
        }
    }

    fn contact(&self, (a, b): (Id, Id)) -> Contact {
        Contact {
            a: self.name(a),
            b: self.name(b),
        }
    }

    /// Enumerates every pair to check (restricted to arm `only` if given), feeding `sink`.
    pub(crate) fn visit(
        &self,
        only: Option<usize>,
        state: &WorldState,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        self.with_posed(state, |posed| self.visit_posed(only, state, posed, sink))
    }

    /// The pairs `among` (as [`pair_code`] names them, each found by an earlier visit of a
    /// state that differs from `state` in one arm's joints at most), fed to `sink` directly:
    /// each with the test and clearance [`visit_posed`](Self::visit_posed) gives it, none of
    /// the culls that lead there.
    pub(crate) fn visit_among(
        &self,
        state: &WorldState,
        posed: [Option<&PosedArm>; 2],
        among: &Doubts,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let object = self
            .object
            .as_deref()
            .zip(self.object_pose_posed(state, &posed));
        for &code in among.as_slice() {
            let ids = pair_ids(code);
            let part = |id: Id| match id {
                Id::Arm(i, k) => posed[i].map(|p| p.part(self.arms[i].set(), k)),
                Id::Obstacle(o) => Some(Part::plain(&self.obstacles[o].shape)),
                _ => None,
            };
            match ids {
                (Id::Arm(i, k), Id::Support) => {
                    let (Some(h), Some(p)) = (self.support, part(ids.0)) else {
                        continue;
                    };
                    let margin = if state.grasping[i] && self.arms[i].set().is_gripper[k] {
                        if !sink.grasp_support() {
                            continue;
                        }
                        self.grasp_support_margin
                    } else {
                        self.margin
                    };
                    sink.plane(p, h, margin, ids)?;
                }
                (_, Id::Object) | (Id::Object, _) => {
                    let (Some((obj, pose)), Some(p)) = (object, part(ids.0).or(part(ids.1))) else {
                        continue;
                    };
                    sink.object(obj, &pose, p, ids)?;
                }
                (Id::Arm(..), Id::Arm(..) | Id::Obstacle(_)) => {
                    if let (Some(a), Some(b)) = (part(ids.0), part(ids.1)) {
                        sink.pair(a, b, ids)?;
                    }
                }
                _ => unreachable!("not a pair a visit reports: {ids:?}"),
            }
        }
        ControlFlow::Continue(())
    }

    /// Calls `f` with both active arms posed at `state` (from the per-thread buffers).
    pub(crate) fn with_posed<R>(
        &self,
        state: &WorldState,
        f: impl FnOnce([Option<&PosedArm>; 2]) -> R,
    ) -> R {
        self.with_posed_shapes(state, [u64::MAX; 2], f)
    }

    /// [`with_posed`](Self::with_posed) with, of each arm `i`, only the shapes in `shapes[i]`
    /// (bit `k`: shape `k`) sure to be placed: for a query about a few pairs. The frames and
    /// bounding spheres are always posed.
    pub(crate) fn with_posed_shapes<R>(
        &self,
        state: &WorldState,
        shapes: [u64; 2],
        f: impl FnOnce([Option<&PosedArm>; 2]) -> R,
    ) -> R {
        // Both active arms are posed: in a single-arm query the other one is an obstacle.
        POSED.with_borrow_mut(|(keys, buffers)| {
            for i in 0..2 {
                if !self.active[i] {
                    continue;
                }
                let key = self.pose_key(i, state);
                let arm = &self.arms[i];
                if keys[i] != Some(key) {
                    arm.pose_frames_into(&state.q[i], state.gripper[i], &mut buffers[i]);
                    keys[i] = Some(key);
                }
                arm.place_into(&mut buffers[i], shapes[i]);
            }
            let [b0, b1] = &*buffers;
            f([self.active[0].then_some(b0), self.active[1].then_some(b1)])
        })
    }

    /// [`visit`](Self::visit) with both arms posed.
    pub(crate) fn visit_posed(
        &self,
        only: Option<usize>,
        state: &WorldState,
        posed: [Option<&PosedArm>; 2],
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let object = self
            .object
            .as_deref()
            .zip(self.object_pose_posed(state, &posed));
        let attached_to = match state.object {
            ObjectPlacement::Attached { arm, .. } if object.is_some() => Some(arm),
            _ => None,
        };
        if sink.part_first() {
            for (i, pi) in posed.iter().enumerate() {
                if let Some(pi) = pi.filter(|_| self.active[i] && only.is_none_or(|o| o == i)) {
                    self.visit_part(i, pi, state, object, sink)?;
                }
            }
        }
        for i in 0..2 {
            if !self.active[i] || only.is_some_and(|o| o != i) {
                continue;
            }
            let Some(pi) = posed[i] else { continue };
            let arm = &self.arms[i];
            let shapes = pi.shapes();
            let set = arm.set();
            // 1. Support. A gripper that grasps (holds, closes on or releases the part) keeps
            //    its own clearance from the support.
            //    A group whose sphere keeps its clearance is passed whole (the visit order stays
            //    the shapes').
            if let Some(h) = self.support {
                let grasping = |g: usize| state.grasping[i] && g == 7;
                let plane_margin = |g: usize| {
                    if grasping(g) {
                        self.grasp_support_margin
                    } else {
                        self.margin
                    }
                };
                // A grasping gripper the sink leaves out is passed like a clear group.
                let clear: [bool; pregrasp_robot::SHAPE_GROUPS] = std::array::from_fn(|g| {
                    let ids = (Id::Group(i, g), Id::Support);
                    grasping(g) && !sink.grasp_support()
                        || sink.skip_plane(pi.group_sphere(g), h, plane_margin(g), ids)
                });
                for k in 0..shapes.len() {
                    let g = set.group_of[k] as usize;
                    if arm.is_base_part(k) || clear[g] {
                        continue;
                    }
                    let ids = (Id::Arm(i, k), Id::Support);
                    sink.plane(pi.part(set, k), h, plane_margin(g), ids)?;
                }
            }
            // 2. Self-collision pairs. The culls' margin is one per pair of groups.
            for ((fa, fb), pairs) in &set.link_pair_groups {
                let (ga, gb) = (Id::Group(i, *fa as usize), Id::Group(i, *fb as usize));
                let (sa, sb) = (pi.frame_sphere(*fa as usize), pi.frame_sphere(*fb as usize));
                let m = sink.cull_margin((ga, gb));
                if sink.skip_spheres_at(sa, sb, m) {
                    continue;
                }
                for &(a, b) in pairs {
                    let (a, b) = (a as usize, b as usize);
                    if !sink.skip_spheres_at(&shapes[a], &shapes[b], m) {
                        let (sa, sb) = (pi.part(set, a), pi.part(set, b));
                        sink.pair(sa, sb, (Id::Arm(i, a), Id::Arm(i, b)))?;
                    }
                }
            }
            //    The gripper vs the links it must not touch, culled by its enclosing sphere.
            let grip_m: [f64; 7] =
                std::array::from_fn(|f| sink.cull_margin((Id::Group(i, f), Id::Group(i, 7))));
            for &l in &set.gripper_forbidden {
                let l = l as usize;
                let sl = &shapes[l];
                let m = grip_m[set.group_of[l] as usize];
                if sink.skip_spheres_at(sl, pi.gripper_sphere(), m) {
                    continue;
                }
                for g in pi.gripper_range() {
                    if !sink.skip_spheres_at(sl, &shapes[g], m) {
                        let (pl, pg) = (pi.part(set, l), pi.part(set, g));
                        sink.pair(pl, pg, (Id::Arm(i, l), Id::Arm(i, g)))?;
                    }
                }
            }
            // 3. Static cuboids, culled by the spheres' distances from the boxes themselves (a
            //    group's margin is one against every static body).
            let obstacle_m: [f64; 8] = if self.obstacles.is_empty() {
                [0.0; 8]
            } else {
                std::array::from_fn(|g| sink.cull_margin((Id::Group(i, g), Id::Obstacle(0))))
            };
            for (o, obs) in self.obstacles.iter().enumerate() {
                let (pose, half) = obs.cuboid();
                for (g, members) in set.group_members.iter().enumerate() {
                    if members.is_empty() {
                        continue;
                    }
                    let sg = pi.group_sphere(g);
                    let m = obstacle_m[g];
                    if sink.skip_spheres_at(sg, &obs.shape, m)
                        || sink.skip_cuboid_at(&pose, &half, sg, m)
                    {
                        continue;
                    }
                    for &k in members {
                        let (k, s) = (k as usize, &shapes[k as usize]);
                        if !arm.is_base_part(k)
                            && !sink.skip_spheres_at(s, &obs.shape, m)
                            && !sink.skip_cuboid_at(&pose, &half, s, m)
                        {
                            let ids = (Id::Arm(i, k), Id::Obstacle(o));
                            sink.pair(pi.part(set, k), Part::plain(&obs.shape), ids)?;
                        }
                    }
                }
            }
            // 4. The other arm (each unordered pair of arms once).
            let j = 1 - i;
            if let Some(pj) = posed[j] {
                if self.active[j] && (only.is_some() || i < j) {
                    self.arm_vs_arm(i, pi, j, pj, sink)?;
                }
            }
            // 5. The part (visited first instead when the sink asks).
            if !sink.part_first() {
                self.visit_part(i, pi, state, object, sink)?;
            }
        }
        // 6. The attached part vs static cuboids, and (single-arm queries) vs the other arm.
        if let (Some(a), Some((obj, pose))) = (attached_to, &object) {
            if only.is_none_or(|o| o == a) {
                for (o, obs) in self.obstacles.iter().enumerate() {
                    let part = Part::plain(&obs.shape);
                    sink.object(obj, pose, part, (Id::Object, Id::Obstacle(o)))?;
                }
                let j = 1 - a;
                if only.is_some() && self.active[j] {
                    if let Some(pj) = posed[j] {
                        let set = self.arms[j].set();
                        for k in 0..pj.shapes().len() {
                            if state.grasping[j] && set.is_gripper[k] {
                                continue;
                            }
                            sink.object(obj, pose, pj.part(set, k), (Id::Arm(j, k), Id::Object))?;
                        }
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// Arm `i` (posed as `pi`) vs the part at its pose, by groups culled by the part's sphere
    /// and box; the gripper of an arm that grasps is left out.
    fn visit_part(
        &self,
        i: usize,
        pi: &PosedArm,
        state: &WorldState,
        object: Option<(&ObjectGeometry, Isometry3<f64>)>,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let Some((obj, pose)) = object else {
            return ControlFlow::Continue(());
        };
        let set = self.arms[i].set();
        let (c, r) = obj.world_sphere(&pose);
        let part = Bounded::new(Placed::Capsule {
            a: c,
            b: c,
            radius: r,
        });
        for (g, members) in set.group_members.iter().enumerate() {
            let sphere = pi.group_sphere(g);
            let gripper = g == 7;
            if members.is_empty()
                || gripper && state.grasping[i]
                || sink.skip_spheres(sphere, &part, (Id::Group(i, g), Id::Object))
                || sink.skip_object_box(obj, &pose, sphere, (Id::Group(i, g), Id::Object))
            {
                continue;
            }
            for &k in members {
                let k = k as usize;
                sink.object(obj, &pose, pi.part(set, k), (Id::Arm(i, k), Id::Object))?;
            }
        }
        ControlFlow::Continue(())
    }

    /// What arm `i`'s pose at `state` depends on.
    fn pose_key(&self, i: usize, state: &WorldState) -> PoseKey {
        (
            self.id,
            i,
            state.q[i].map(f64::to_bits),
            state.gripper[i].key(),
        )
    }

    /// [`object_pose`](Self::object_pose), reusing the flange of an already posed arm.
    fn object_pose_posed(
        &self,
        state: &WorldState,
        posed: &[Option<&PosedArm>; 2],
    ) -> Option<Isometry3<f64>> {
        match (state.object, self.object.as_deref()) {
            (
                ObjectPlacement::Attached {
                    arm,
                    flange_to_object,
                },
                Some(_),
            ) => match posed[arm] {
                Some(p) => Some(p.flange() * flange_to_object),
                None => self.object_pose(state),
            },
            _ => self.object_pose(state),
        }
    }

    /// Arm `i` vs arm `j`, by groups (the links of one DH frame, or the gripper) culled by
    /// their spheres before their shapes are paired. The two bases are never paired: both are
    /// mounted.
    fn arm_vs_arm(
        &self,
        i: usize,
        pi: &PosedArm,
        j: usize,
        pj: &PosedArm,
        sink: &mut impl Sink,
    ) -> ControlFlow<()> {
        let (lo_i, hi_i) = pi.bounds();
        let (lo_j, hi_j) = pj.bounds();
        if sink.skip_gap_sq(aabb_aabb_sq(&lo_i, &hi_i, &lo_j, &hi_j)) {
            return ControlFlow::Continue(());
        }
        let (set_i, set_j) = (self.arms[i].set(), self.arms[j].set());
        for (gi, members_i) in set_i.group_members.iter().enumerate() {
            let si = pi.group_sphere(gi);
            if members_i.is_empty() {
                continue;
            }
            let r = Vector3::repeat(si.radius);
            if sink.skip_gap_sq(aabb_aabb_sq(
                &(si.center - r),
                &(si.center + r),
                &lo_j,
                &hi_j,
            )) {
                continue;
            }
            for (gj, members_j) in set_j.group_members.iter().enumerate() {
                if members_j.is_empty() {
                    continue;
                }
                // One cull margin for the two groups' pairs; a shape far from the other
                // group's sphere skips its shapes.
                let sj = pj.group_sphere(gj);
                let m = sink.cull_margin((Id::Group(i, gi), Id::Group(j, gj)));
                if sink.skip_spheres_at(si, sj, m) {
                    continue;
                }
                for &k in members_i {
                    let k = k as usize;
                    let a = &pi.shapes()[k];
                    if sink.skip_spheres_at(a, sj, m) {
                        continue;
                    }
                    let base_k = self.arms[i].is_base_part(k);
                    for &l in members_j {
                        let l = l as usize;
                        if base_k && self.arms[j].is_base_part(l) {
                            continue;
                        }
                        if !sink.skip_spheres_at(a, &pj.shapes()[l], m) {
                            let (pa, pb) = (pi.part(set_i, k), pj.part(set_j, l));
                            sink.pair(pa, pb, (Id::Arm(i, k), Id::Arm(j, l)))?;
                        }
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }
}

/// What to do with each candidate pair: stop at the first contact, or track the minimum.
pub(crate) trait Sink {
    /// The clearance within which a pair (`ids`) may matter, for the culls by spheres and boxes:
    /// the same for every pair of bodies of the same two shape groups, and for a group against
    /// any static body (they do not move), so a loop over a group's pairs works it out once. A
    /// margin worked out earlier in a visit may be wider than asking again would give (a sink
    /// that narrows it as it goes), never narrower.
    fn cull_margin(&self, ids: (Id, Id)) -> f64;
    /// Whether bodies in the spheres `s1`, `s2` cannot matter at the cull margin `m`.
    #[inline]
    fn skip_spheres_at(&self, s1: &Bounded, s2: &Bounded, m: f64) -> bool {
        !s1.spheres_near(s2, m)
    }
    /// Whether a pair (`ids`) whose bounding spheres are `s1`, `s2` cannot matter.
    #[inline]
    fn skip_spheres(&self, s1: &Bounded, s2: &Bounded, ids: (Id, Id)) -> bool {
        self.skip_spheres_at(s1, s2, self.cull_margin(ids))
    }
    /// Whether a body (`ids.0`) in the sphere `s` cannot matter against the part's box (its
    /// mesh's bounding box in the object frame) at `pose`.
    fn skip_object_box(
        &self,
        _obj: &ObjectGeometry,
        _pose: &Isometry3<f64>,
        _s: &Bounded,
        _ids: (Id, Id),
    ) -> bool {
        false
    }
    /// Whether a group of bodies (`ids.0`) in the sphere `s` cannot matter against the support
    /// plane `z = height` at clearance `margin` (as [`plane`](Self::plane) would find for each).
    fn skip_plane(&self, _s: &Bounded, _height: f64, _margin: f64, _ids: (Id, Id)) -> bool {
        false
    }
    /// Whether a body in the sphere `s` cannot matter against the cuboid `half` at `pose` (a
    /// static obstacle) at the cull margin `m`.
    fn skip_cuboid_at(
        &self,
        _pose: &Isometry3<f64>,
        _half: &Vector3<f64>,
        _s: &Bounded,
        _m: f64,
    ) -> bool {
        false
    }
    /// Whether a group whose boxes are `sqrt(gap_sq)` apart cannot matter.
    fn skip_gap_sq(&self, gap_sq: f64) -> bool;
    /// Whether the arms are tested against the part before anything else (a swept check, whose
    /// answer does not name the pair, stops soonest where the part is the usual obstacle).
    fn part_first(&self) -> bool {
        false
    }
    /// Whether grasping grippers are tested against the support (a swept query leaves them
    /// to a test at every state: they work millimetres above it).
    fn grasp_support(&self) -> bool {
        true
    }
    /// A solid vs the support plane; `margin` is the clearance this pair must keep.
    fn plane(&mut self, s: Part, height: f64, margin: f64, ids: (Id, Id)) -> ControlFlow<()>;
    /// Two solids.
    fn pair(&mut self, s1: Part, s2: Part, ids: (Id, Id)) -> ControlFlow<()>;
    /// A solid vs the part at `pose`.
    fn object(
        &mut self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: Part,
        ids: (Id, Id),
    ) -> ControlFlow<()>;
}

/// Stops at the first pair within its clearance: the margin, grown for a swept query by
/// how far each of the pair's bodies may move ([`Grows`]).
pub(crate) struct FirstContact<'g> {
    pub margin: f64,
    /// Margin used to cull by bounding spheres and boxes: `margin` plus the largest growth of
    /// any pair.
    pub cull: f64,
    pub grow: Option<&'g Grows<'g>>,
    /// Collecting: every pair in contact goes here (the query goes on) until it is full.
    pub found: Option<Doubts>,
    /// A pair whose primitive comes within its clearance counts as a contact without its
    /// exact pieces being asked (see [`collecting`](Self::collecting)).
    pub by_primitives: bool,
    /// The primitives of a pair with exact pieces filter it loosely (cylinders as their
    /// enclosing capsules, [`pair_may_intersect`]): for pairs known to be near (a box's
    /// doubts), whose exact cylinder test would cost about what the pieces' does and let them
    /// through anyway.
    pub loose_filter: bool,
    /// The last pair found in contact (with `found`: the one that did not fit, if any).
    pub ids: Option<(Id, Id)>,
}

impl<'g> FirstContact<'g> {
    /// A plain query at `margin`.
    pub fn new(margin: f64) -> Self {
        FirstContact {
            margin,
            cull: margin,
            grow: None,
            found: None,
            by_primitives: false,
            loose_filter: false,
            ids: None,
        }
    }

    /// A swept query: every pair's clearance grows by the motion bounds of its two sides.
    pub fn swept(margin: f64, grow: &'g Grows<'g>) -> Self {
        FirstContact {
            cull: margin + grow.most_pair(),
            grow: Some(grow),
            ..Self::new(margin)
        }
    }

    /// Every pair in contact is collected (up to [`Doubts::CAPACITY`]) instead of stopping at
    /// the first; `by_primitives`: by their primitives alone. So a box asked about every pair
    /// names its doubts: they go to smaller boxes, which ask the pieces, and a box near many
    /// things fails for the price of its primitives.
    pub fn collecting(self, by_primitives: bool) -> Self {
        FirstContact {
            found: Some(Doubts::default()),
            by_primitives,
            ..self
        }
    }

    #[inline]
    fn hit(&mut self, hit: bool, ids: (Id, Id)) -> ControlFlow<()> {
        if !hit {
            return ControlFlow::Continue(());
        }
        if let Some(found) = &mut self.found {
            if pair_code(ids).is_some_and(|c| found.insert(c)) {
                return ControlFlow::Continue(());
            }
        }
        self.ids = Some(ids);
        ControlFlow::Break(())
    }

    /// What a collecting query found: the pairs in contact, or `None` when they did not fit.
    pub fn doubts(&self) -> Option<Doubts> {
        match self.ids {
            Some(_) => None,
            None => self.found,
        }
    }

    /// [`margin_of`](Self::margin_of) for two shapes in the spheres `sa`, `sb`, by their own
    /// levers where those are tighter ([`Grows::shapes_pair`]).
    #[inline]
    fn margin_of_shapes(&self, margin: f64, (a, b): (Id, Id), sa: &Bounded, sb: &Bounded) -> f64 {
        match self.grow {
            None => margin,
            Some(g) => margin + g.shapes_pair(a, b, sa, sb),
        }
    }

    /// The clearance pair `ids` must keep: `margin` plus both sides' growth.
    #[inline]
    fn margin_of(&self, margin: f64, (a, b): (Id, Id)) -> f64 {
        match self.grow {
            None => margin,
            Some(g) => margin + g.pair(a, b),
        }
    }
}

/// Per arm, the shapes the pairs `among` name (bit `k`: shape `k`).
pub(crate) fn shapes_among(among: &Doubts) -> [u64; 2] {
    let mut masks = [0u64; 2];
    for &code in among.as_slice() {
        for side in [code >> 16, code & 0xFFFF] {
            if let Id::Arm(i, k) = side_id(side) {
                masks[i] |= 1 << k;
            }
        }
    }
    masks
}

/// The pair [`pair_code`] gave `code`.
fn pair_ids(code: u32) -> (Id, Id) {
    (side_id(code >> 16), side_id(code & 0xFFFF))
}

/// One side of a [`pair_code`] (its 16 bits).
fn side_id(c: u32) -> Id {
    let low = (c & 0x3FFF) as usize;
    match c >> 14 {
        0 | 1 => Id::Arm((c >> 14) as usize, low),
        2 => Id::Obstacle(low),
        _ if c == 0xFFFF => Id::Support,
        _ => Id::Object,
    }
}

/// A pair of bodies as one number (for [`Doubts`]): each side in 16 bits, an arm shape as
/// `arm << 14 | shape`, an obstacle as `2 << 14 | index`, the support and the part as the
/// two largest codes. `None` for whole groups (never reported) and indices too large to
/// code: a collecting query that finds such a pair in contact names none (all stay in doubt).
#[inline(always)]
pub(crate) fn pair_code((a, b): (Id, Id)) -> Option<u32> {
    const LOW: usize = (1 << 14) - 2;
    let side = |id: Id| -> Option<u32> {
        match id {
            Id::Arm(i, k) if i < 2 && k < LOW => Some(((i as u32) << 14) | k as u32),
            Id::Obstacle(o) if o < LOW => Some((2 << 14) | o as u32),
            Id::Support => Some(0xFFFF),
            Id::Object => Some(0xFFFE),
            _ => None,
        }
    };
    Some((side(a)? << 16) | side(b)?)
}

impl Sink for FirstContact<'_> {
    /// The pair's own clearance in a swept query (never more than [`cull`](Self::cull)), the
    /// widest of any pair otherwise.
    #[inline]
    fn cull_margin(&self, ids: (Id, Id)) -> f64 {
        match self.grow {
            None => self.cull,
            Some(_) => self.margin_of(self.margin, ids).min(self.cull),
        }
    }
    #[inline]
    fn skip_object_box(
        &self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: &Bounded,
        ids: (Id, Id),
    ) -> bool {
        !obj.sphere_near_box(pose, s, self.margin_of(self.margin, ids))
    }
    #[inline]
    fn skip_cuboid_at(
        &self,
        pose: &Isometry3<f64>,
        half: &Vector3<f64>,
        s: &Bounded,
        m: f64,
    ) -> bool {
        let reach = s.radius + m;
        s.centre_box_gap_sq(pose, half) > reach * reach
    }
    #[inline]
    fn skip_gap_sq(&self, gap_sq: f64) -> bool {
        gap_sq > self.cull * self.cull
    }
    /// The sphere holds its shapes grown by their slack, so its lowest point above the plane
    /// by more than the pair's clearance passes each shape's test in [`plane`](Sink::plane).
    #[inline]
    fn skip_plane(&self, s: &Bounded, height: f64, margin: f64, ids: (Id, Id)) -> bool {
        s.center.z - s.radius - height > self.margin_of(margin, ids)
    }
    #[inline]
    fn grasp_support(&self) -> bool {
        self.grow.is_none_or(|g| !g.grasp_support_apart)
    }
    #[inline]
    fn part_first(&self) -> bool {
        self.grow.is_some()
    }
    /// The primitive first, with the margin grown by the pieces' slack; the pieces only
    /// where that finds contact (every `FirstContact` test below has this shape).
    #[inline]
    fn plane(&mut self, s: Part, height: f64, margin: f64, ids: (Id, Id)) -> ControlFlow<()> {
        let bound = plane_distance(s.shape(), height);
        // The group's clearance first (no sphere cull came before); where that comes near, the
        // shape's own.
        if bound > self.margin_of(margin, ids) + s.slack() {
            return ControlFlow::Continue(());
        }
        let margin = self.margin_of_shapes(margin, ids, s.bounded, s.bounded);
        let near = bound <= margin + s.slack();
        let hit =
            near && (self.by_primitives || s.plane_distance(height).is_none_or(|d| d <= margin));
        self.hit(hit, ids)
    }
    #[inline]
    fn pair(&mut self, s1: Part, s2: Part, ids: (Id, Id)) -> ControlFlow<()> {
        let margin = self.margin_of_shapes(self.margin, ids, s1.bounded, s2.bounded);
        let plain = s1.tight().is_none() && s2.tight().is_none();
        let (a, b, grown) = (s1.shape(), s2.shape(), margin + s1.slack() + s2.slack());
        // Where the pieces decide, the primitives only filter them (see `by_primitives`). Two
        // boxes go to GJK, which remembers the axis that last kept them apart.
        let boxes = matches!((a, b), (Placed::Cuboid { .. }, Placed::Cuboid { .. }));
        let near = if boxes && plain {
            tight::within(&s1, &s2, grown)
        } else if plain || !self.loose_filter {
            pair_intersects(a, b, grown)
        } else {
            pair_may_intersect(a, b, grown)
        };
        let hit = near && (plain || self.by_primitives || tight::within(&s1, &s2, margin));
        self.hit(hit, ids)
    }
    #[inline]
    fn object(
        &mut self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: Part,
        ids: (Id, Id),
    ) -> ControlFlow<()> {
        let margin = self.margin_of(self.margin, ids);
        let near = obj.intersects(pose, s.bounded, margin + s.slack());
        let hit = near
            && (self.by_primitives
                || s.tight()
                    .is_none_or(|t| obj.pieces_intersect(pose, &t, margin)));
        self.hit(hit, ids)
    }
}

struct MinDistance {
    best: f64,
    ids: Option<(Id, Id)>,
}

impl MinDistance {
    fn offer(&mut self, d: f64, ids: (Id, Id)) -> ControlFlow<()> {
        if d < self.best || self.ids.is_none() {
            self.best = d;
            self.ids = Some(ids);
        }
        ControlFlow::Continue(())
    }
}

impl Sink for MinDistance {
    /// The best distance so far (a culled pair cannot beat it).
    fn cull_margin(&self, _ids: (Id, Id)) -> f64 {
        self.best
    }
    fn skip_spheres_at(&self, s1: &Bounded, s2: &Bounded, m: f64) -> bool {
        (s1.center - s2.center).norm() - s1.radius - s2.radius >= m
    }
    fn skip_cuboid_at(
        &self,
        pose: &Isometry3<f64>,
        half: &Vector3<f64>,
        s: &Bounded,
        m: f64,
    ) -> bool {
        s.centre_box_gap_sq(pose, half).sqrt() - s.radius >= m
    }
    fn skip_gap_sq(&self, gap_sq: f64) -> bool {
        gap_sq.sqrt() >= self.best
    }
    /// Distances of the exact solids; the primitive's distance less the slack (a lower bound)
    /// skips the pieces when it cannot beat the best so far.
    fn plane(&mut self, s: Part, height: f64, _margin: f64, ids: (Id, Id)) -> ControlFlow<()> {
        let bound = plane_distance(s.shape(), height);
        if bound - s.slack() >= self.best && self.ids.is_some() {
            return ControlFlow::Continue(());
        }
        self.offer(s.plane_distance(height).unwrap_or(bound), ids)
    }
    fn pair(&mut self, s1: Part, s2: Part, ids: (Id, Id)) -> ControlFlow<()> {
        let bound = pair_distance(s1.shape(), s2.shape());
        if s1.tight().is_none() && s2.tight().is_none() {
            return self.offer(bound, ids);
        }
        if bound - s1.slack() - s2.slack() >= self.best && self.ids.is_some() {
            return ControlFlow::Continue(());
        }
        self.offer(tight::distance(&s1, &s2), ids)
    }
    fn object(
        &mut self,
        obj: &ObjectGeometry,
        pose: &Isometry3<f64>,
        s: Part,
        ids: (Id, Id),
    ) -> ControlFlow<()> {
        let (c, r) = obj.world_sphere(pose);
        let b = s.bounded;
        if (c - b.center).norm() - r - b.radius - s.slack() >= self.best {
            return ControlFlow::Continue(());
        }
        match s.tight() {
            None => self.offer(obj.distance(pose, b), ids),
            Some(t) => {
                let bound = obj.distance(pose, b);
                if bound - s.slack() >= self.best && self.ids.is_some() {
                    return ControlFlow::Continue(());
                }
                self.offer(obj.pieces_distance(pose, &t), ids)
            }
        }
    }
}
