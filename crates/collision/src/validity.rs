//! Glue to `pregrasp_motion`: one moving arm, everything else fixed.
//!
//! # Resolution bound
//! [`joint_space`] weights joint `i` by `w_i` = `pregrasp_robot::joint_sweep_radii`, an upper
//! bound on the distance of any point of the links beyond joint `i` (gripper included, a held
//! part not, see below) from joint axis `i`. Along a straight joint-space edge every point
//! then moves at most `Σ_i w_i |Δq_i|`, and `MotionValidator` checks states no more than
//! `resolution` (m) of such travel apart. Between two checked states each point is within
//! `resolution / 2` of where it was at one of them, so:
//! - against static things (support, cuboids, the part, the fixed other arm) a contact on
//!   the edge implies a checked state closer than `resolution / 2`: with a safety margin
//!   `m ≥ resolution / 2` ([`CollisionWorld::with_margin`]) a valid edge is collision-free
//!   in continuous motion; without margin, only penetrations shallower than `resolution / 2`
//!   can be missed;
//! - for self-collision pairs both sides move, so the bound is `resolution` (margin
//!   `m ≥ resolution` for the continuous guarantee).
//!
//! The reach benchmark uses `resolution = 0.01` m and `margin = 0.005` m
//! (`reach::DEFAULT_RESOLUTION`, `reach::DEFAULT_MARGIN`).
//!
//! A part attached to the moving flange reaches farther than the gripper: its radius is
//! not in `w_i`. [`joint_space_with_payload`] adds the attached part's reach to every weight.

use pregrasp_motion::{Doubts, JointSpace, State, StateValidator};

use crate::arm::ArmModel;
use crate::world::{CollisionWorld, WorldState};

/// State validity for arm `arm` moving while the other arm, its gripper and the part stay
/// as in `base_state` (a part attached to `arm` moves with it). A state is valid when it is
/// within the arm's joint limits and [`CollisionWorld::check_arm`] finds no contact.
#[derive(Clone, Debug)]
pub struct ArmValidity<'a> {
    pub world: &'a CollisionWorld,
    pub arm: usize,
    pub base_state: WorldState,
}

impl<'a> ArmValidity<'a> {
    pub fn new(world: &'a CollisionWorld, arm: usize, base_state: WorldState) -> Self {
        ArmValidity {
            world,
            arm,
            base_state,
        }
    }

    /// Whether `q` is within the arm's joint limits.
    #[inline]
    fn within_limits(&self, q: &State<6>) -> bool {
        let limits = self.world.arms()[self.arm].joint_limits();
        q.iter()
            .zip(limits.iter())
            .all(|(x, (lo, hi))| *x >= *lo && *x <= *hi)
    }

    /// The full world state with arm `arm` at `q`.
    #[inline]
    pub fn state_at(&self, q: &State<6>) -> WorldState {
        let mut s = self.base_state;
        s.q[self.arm] = *q;
        s
    }
}

impl StateValidator<6> for ArmValidity<'_> {
    #[inline]
    fn is_valid(&self, q: &State<6>) -> bool {
        self.within_limits(q) && self.world.is_arm_free(self.arm, &self.state_at(q))
    }

    /// The joint box about `q` is free ([`CollisionWorld::is_arm_free_within`]).
    #[inline]
    fn is_valid_around(&self, q: &State<6>, reach: &State<6>) -> bool {
        self.world
            .is_arm_free_within(self.arm, &self.state_at(q), reach)
    }

    fn around_limit(&self) -> f64 {
        crate::sweep::BOX_LIMIT
    }

    /// The pairs of bodies that do not keep room for the box
    /// ([`CollisionWorld::is_arm_doubted_within`]).
    #[inline]
    fn doubts_around(
        &self,
        q: &State<6>,
        reach: &State<6>,
        among: Option<&Doubts>,
    ) -> Option<Doubts> {
        self.world
            .is_arm_doubted_within(self.arm, &self.state_at(q), reach, among)
    }

    /// Joint limits and the pairs `among` ([`CollisionWorld::is_free_among`]).
    #[inline]
    fn is_valid_among(&self, q: &State<6>, among: &Doubts) -> bool {
        self.within_limits(q) && self.world.is_free_among(&self.state_at(q), among)
    }
}

/// The arm's joint space: its model's joint limits, weights from `joint_sweep_radii` (m/rad)
/// so that `motion_bound` bounds arm-point travel in metres (see the module docs).
pub fn joint_space(arm: &ArmModel) -> JointSpace<6> {
    joint_space_with_payload(arm, 0.0)
}

/// [`joint_space`] for an arm carrying a part that reaches at most `payload_reach` (m) from
/// the flange origin: every weight grows by `payload_reach`, since a rotation about any
/// axis moves a point at distance `≤ w_i + payload_reach` from that axis.
pub fn joint_space_with_payload(arm: &ArmModel, payload_reach: f64) -> JointSpace<6> {
    let limits = arm.joint_limits();
    let radii = arm.joint_sweep_radii();
    let lower = limits.map(|l| l.0);
    let upper = limits.map(|l| l.1);
    let weights = radii.map(|r| r + payload_reach.max(0.0));
    JointSpace {
        lower,
        upper,
        weights,
    }
}
