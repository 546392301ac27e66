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

use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_motion::Doubts;
use pregrasp_robot::GripperState;

use crate::arm::ArmModel;
use crate::error::CollisionError;
use crate::object::ObjectGeometry;
use crate::shape::{Bounded, Placed};

mod grows;
mod pairs;
mod sink;
mod state;

pub use grows::attached_reach;
pub(crate) use grows::{first_tilting_joint, Grows};
use sink::MinDistance;
pub(crate) use sink::{shapes_among, FirstContact, Sink};
pub use state::{Contact, ObjectPlacement, Obstacle, Sweep, WorldState};

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

impl CollisionWorld {
    /// A world with the support plane at `z = support_height` (`None`: no support plane), the
    /// part's mesh (object frame, if any) and two arms; an error for an unusable mesh (no
    /// triangles, bad indices, non-finite vertices).
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
}
