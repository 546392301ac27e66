//! Swept queries: one check that stands for every state within a motion bound of it.
//!
//! # The bound
//! The distance between two bodies changes by at most the sum of their points' displacements.
//! So if at a state every pair keeps its clearance `m` *plus* `δ_a + δ_b`, where `δ_a` bounds
//! how far any point of body `a` moves to any other state considered, every one of those
//! states keeps `m` (the test is [`CollisionWorld::is_free_within`]). Bodies:
//! - a shape group of an arm (the link shapes of one DH frame, or the gripper): along joint
//!   motions within `|Δq_i| ≤ r_i` every point of group g moves at most `Σ_i L[i][g] r_i`,
//!   `L[i][g]` its lever about joint axis `i`: the group's distance from the axis at the
//!   checked configuration plus how far the later joints may move it, never more than the
//!   configuration-free bound `R[i][g]` ([`pregrasp_robot::group_sweep_radii`]). The upper
//!   arm moves far less than the gripper, and a bent arm's levers are much shorter than a
//!   stretched one's;
//! - the part, fixed at a pose per state: its bounding sphere's centre moves `|Δc|` and the
//!   rest turns by the rotation angle `α` about it, so a point moves at most
//!   `|Δc| + 2 sin(α/2)·r`;
//!   attached to a flange: `Σ_i (F[i] + ρ) r_i` for `ρ` its reach from the flange origin;
//! - the support and the static cuboids do not move.
//!
//! # Sequences
//! [`CollisionWorld::first_contact_in`] finds the first state of a sequence (the states of a
//! motion at its check resolution) that [`CollisionWorld::check`] would reject, and returns
//! exactly what checking them one by one returns; but, going along the sequence, the next
//! states are accepted by one swept check about their middle when the bodies keep room for
//! their motion — the range doubles after a success (unless the check before failed) and
//! halves after a failure, down to single states checked as before. Far from everything a
//! whole motion costs a few checks. Motion bounds along the sequence are prefix sums of the
//! steps' bounds (the triangle inequality), so a range's bound costs O(1).
//!
//! A grasping gripper works millimetres above the support (a fingertip pinch), where no range
//! of the whole world would pass: that pair is left out of the swept checks and tested on its
//! own first, with the gripper posed by its flange only and ranges passed where the gripper's
//! height above the clearance exceeds how far it may move vertically.

use pregrasp_motion::Doubts;
use pregrasp_robot::{Joints, SHAPE_GROUPS};

pub use crate::world::Sweep;
use crate::world::{
    first_tilting_joint, shapes_among, CollisionWorld, FirstContact, Grows, ObjectPlacement,
    WorldState,
};

impl CollisionWorld {
    /// Whether every state whose bodies lie within `sweep` of theirs in `state` is free — in
    /// the sense of [`check`](Self::check), or of [`check_arm`](Self::check_arm) when `only`
    /// is given — grasping grippers against the support included (grown like every pair).
    pub fn is_free_within(&self, only: Option<usize>, state: &WorldState, sweep: &Sweep) -> bool {
        self.free_within(only, state, sweep, SweptUse::Answer)
    }

    /// Arm `arm` anywhere in the joint box `q ± reach` about its configuration in `state`
    /// (a part attached to it moving along), everything else as in `state`: is every such
    /// state free in the sense of [`check_arm`](Self::check_arm)?
    pub fn is_arm_free_within(&self, arm: usize, state: &WorldState, reach: &Joints) -> bool {
        let mut sweep = Sweep::default();
        sweep.reach[arm] = *reach;
        self.free_within(Some(arm), state, &sweep, SweptUse::Answer)
    }

    /// [`is_arm_free_within`](Self::is_arm_free_within) by the shapes' primitives alone: `true`
    /// only where every state of the box is free, but a pair whose primitives come within its
    /// grown clearance counts as touching without its exact pieces being asked. For a box
    /// whose failure only splits it, down to states checked exactly (edges certified by
    /// [`pregrasp_motion::MotionValidator`]): the edge's answer is the same, for less.
    pub fn is_arm_clear_within(&self, arm: usize, state: &WorldState, reach: &Joints) -> bool {
        let mut sweep = Sweep::default();
        sweep.reach[arm] = *reach;
        self.free_within(Some(arm), state, &sweep, SweptUse::Box)
    }

    /// [`is_arm_free_within`](Self::is_arm_free_within) asked only about the pairs `among`
    /// (all when `None`), naming those that do not keep room for the box: `Some` of them
    /// (empty: the box is free), or `None` when more fail than [`Doubts`] holds. A pair named
    /// is one of `among`; a pair not named keeps apart in every state of the box.
    pub fn is_arm_doubted_within(
        &self,
        arm: usize,
        state: &WorldState,
        reach: &Joints,
        among: Option<&Doubts>,
    ) -> Option<Doubts> {
        let mut sweep = Sweep::default();
        sweep.reach[arm] = *reach;
        self.with_posed_shapes(state, among.map_or([u64::MAX; 2], shapes_among), |posed| {
            let groups = among.map_or([u8::MAX; 2], |d| groups_among(self, d));
            let grows = Grows::new(self, state, &sweep, false, &posed, groups);
            let mut sink = FirstContact {
                loose_filter: among.is_some(),
                ..FirstContact::swept(self.margin(), &grows).collecting(among.is_none())
            };
            let _ = match among {
                Some(among) => self.visit_among(state, posed, among, &mut sink),
                None => self.visit_posed(Some(arm), state, posed, &mut sink),
            };
            sink.doubts()
        })
    }

    fn free_within(
        &self,
        only: Option<usize>,
        state: &WorldState,
        sweep: &Sweep,
        purpose: SweptUse,
    ) -> bool {
        let range = purpose == SweptUse::Range;
        self.with_posed(state, |posed| {
            let grows = Grows::new(self, state, sweep, range, &posed, [u8::MAX; 2]);
            let mut sink = FirstContact::swept(self.margin(), &grows);
            sink.by_primitives = range || purpose == SweptUse::Box;
            let _ = self.visit_posed(only, state, posed, &mut sink);
            sink.ids.is_none()
        })
    }

    /// How much room the grasping grippers (of arm `only` if given) have above the grasp
    /// clearance from the support at `state` (m): the smallest `height − margin`, `∞` when
    /// none grasps. The state keeps that clearance iff it is positive — the one pair
    /// [`check`](Self::check) tests with [`grasp_support_margin`](Self::grasp_support_margin).
    fn grasp_support_room(&self, only: Option<usize>, state: &WorldState) -> f64 {
        let margin = self.grasp_support_margin();
        (0..2)
            .filter(|&i| self.is_active(i) && state.grasping[i] && only.is_none_or(|o| o == i))
            .map(|i| self.gripper_support_distance(i, state) - margin)
            .fold(f64::INFINITY, f64::min)
    }

    /// The first of `states` that [`check`](Self::check) (or [`check_arm`](Self::check_arm)
    /// when `only` is given) rejects, or `None`: the same answer as checking them in order,
    /// with ranges of states accepted by one swept check where the bodies keep room for the
    /// range's motion (see the module docs).
    pub fn first_contact_in(&self, only: Option<usize>, states: &[WorldState]) -> Option<usize> {
        if states.is_empty() {
            return None;
        }
        let path = PathBounds::new(self, states);
        self.first_contact_along(only, states, &path, false)
    }

    /// [`first_contact_in`](Self::first_contact_in) (`first_contact`) and, per arm,
    /// [`closest_grasp_to_support`](Self::closest_grasp_to_support) (`closest_grasp`) over the
    /// same states, from one pass of motion bounds. Where every grasping gripper stays above
    /// the grasp clearance at its closest, no state can fail that pair and its per-state test
    /// is skipped.
    pub fn check_states(&self, only: Option<usize>, states: &[WorldState]) -> StatesCheck {
        if states.is_empty() {
            return StatesCheck::default();
        }
        let path = PathBounds::new(self, states);
        let closest_grasp = [0, 1].map(|arm| {
            (self.is_active(arm) && self.support_height().is_some())
                .then(|| self.closest_grasp_along(arm, states, &path))
                .flatten()
        });
        let margin = self.grasp_support_margin();
        let clear = (0..2)
            .filter(|&i| only.is_none_or(|o| o == i))
            .all(|i| closest_grasp[i].is_none_or(|d| d - margin > 0.0));
        StatesCheck {
            first_contact: self.first_contact_along(only, states, &path, clear),
            closest_grasp,
        }
    }

    /// [`first_contact_in`](Self::first_contact_in) with the bounds of `states` (not empty);
    /// `grasps_clear`: no grasping gripper comes within the grasp clearance of the support.
    fn first_contact_along(
        &self,
        only: Option<usize>,
        states: &[WorldState],
        path: &PathBounds,
        grasps_clear: bool,
    ) -> Option<usize> {
        // The grasping grippers vs the support first: cheap, and they work nearest.
        let limit = if grasps_clear {
            states.len()
        } else {
            self.grasp_support_fails(only, states, path, 0, states.len() - 1)
                .unwrap_or(states.len())
        };
        if limit > 0 {
            if let Some(k) = self.certify(only, states, path, 0, limit - 1) {
                return Some(k);
            }
        }
        // The state whose gripper came too near the support fails its full check.
        (limit < states.len()).then_some(limit)
    }

    /// The smallest height above the support of arm `arm`'s gripper over the `states` in
    /// which it grasps (`None`: it grasps in none). Exact over the states; ranges whose lower
    /// bound (the height at their middle less how far the gripper may move vertically) cannot
    /// beat the best so far are skipped.
    pub fn closest_grasp_to_support(&self, arm: usize, states: &[WorldState]) -> Option<f64> {
        if states.is_empty() || self.support_height().is_none() {
            return None;
        }
        let path = PathBounds::new(self, states);
        self.closest_grasp_along(arm, states, &path)
    }

    fn closest_grasp_along(
        &self,
        arm: usize,
        states: &[WorldState],
        path: &PathBounds,
    ) -> Option<f64> {
        let mut best = f64::INFINITY;
        let mut stack = vec![(0, states.len() - 1)];
        while let Some((lo, hi)) = stack.pop() {
            let mid = lo + (hi - lo) / 2;
            let state = &states[mid];
            let d = if state.grasping[arm] {
                let d = self.gripper_support_distance(arm, state);
                best = best.min(d);
                d
            } else {
                f64::INFINITY
            };
            if lo == hi {
                continue;
            }
            let bound = if path.run[lo] == path.run[hi] {
                // An arm that does not move over the range is as high at every state of it.
                if !state.grasping[arm] || path.still(arm, lo, hi) {
                    continue;
                }
                d - self.gripper_vertical_sweep(arm, &path.reach(arm, lo, mid, hi))
            } else {
                f64::NEG_INFINITY
            };
            if bound >= best {
                continue;
            }
            if mid < hi {
                stack.push((mid + 1, hi));
            }
            if mid > lo {
                stack.push((lo, mid - 1));
            }
        }
        best.is_finite().then_some(best)
    }

    /// How far arm `arm`'s gripper may move vertically within `reach` of its joints.
    fn gripper_vertical_sweep(&self, arm: usize, reach: &Joints) -> f64 {
        let model = &self.arms()[arm];
        let radii = &model.set().group_radii;
        (first_tilting_joint(model)..6)
            .map(|j| radii[j][SHAPE_GROUPS - 1] * reach[j])
            .sum()
    }

    /// The first state in `lo..=hi` whose grasping gripper comes within the grasp clearance of
    /// the support; a range is passed at once when the room at its middle exceeds how far the
    /// grippers may move vertically over it.
    fn grasp_support_fails(
        &self,
        only: Option<usize>,
        states: &[WorldState],
        path: &PathBounds,
        lo: usize,
        hi: usize,
    ) -> Option<usize> {
        if hi - lo < LEAF_STATES {
            return (lo..=hi).find(|&k| self.grasp_support_room(only, &states[k]) <= 0.0);
        }
        let mid = lo + (hi - lo) / 2;
        let room = self.grasp_support_room(only, &states[mid]);
        if path.run[lo] == path.run[hi] {
            let moves = (0..2)
                .filter(|&i| states[mid].grasping[i] && only.is_none_or(|o| o == i))
                .map(|i| self.gripper_vertical_sweep(i, &path.reach(i, lo, mid, hi)))
                .fold(0.0, f64::max);
            if room > moves {
                return None;
            }
        }
        self.grasp_support_fails(only, states, path, lo, mid - 1)
            .or_else(|| (room <= 0.0).then_some(mid))
            .or_else(|| self.grasp_support_fails(only, states, path, mid + 1, hi))
    }

    /// The first state in `lo..=hi` that is not free (every pair but the grasping grippers vs
    /// the support, which the caller has tested), in order: from the first unchecked state,
    /// a swept check of the next `2w + 1` states (about their middle) passes them all and
    /// doubles `w` (keeps it, right after a failure); a failed one halves it, and at `w = 1`
    /// the state is checked exactly.
    fn certify(
        &self,
        only: Option<usize>,
        states: &[WorldState],
        path: &PathBounds,
        lo: usize,
        hi: usize,
    ) -> Option<usize> {
        let mut k = lo;
        let mut w = FIRST_HALF_WIDTH;
        let mut exact_run = 0;
        // Whether the last swept check failed: a range that passed right after a failure
        // keeps its width (doubled, the next one mostly fails again: in a shelf plan's re-check
        // 642 of 1330 swept checks failed; kept, 384 of 1100).
        let mut failed_last = false;
        while k <= hi {
            if exact_run == 0 {
                let end = (k + 2 * w).min(hi);
                if end > k {
                    let mid = k + (end - k) / 2;
                    // Too wide a motion is not worth a swept check: it halves like a failure.
                    let passed = path.sweep(&states[mid], k, mid, end).is_some_and(|sweep| {
                        self.sweep_bound(&sweep) <= SWEEP_LIMIT
                            && self.free_within(only, &states[mid], &sweep, SweptUse::Range)
                    });
                    if passed {
                        k = end + 1;
                        if !failed_last {
                            w *= 2;
                        }
                        failed_last = false;
                        continue;
                    }
                    failed_last = true;
                    if w > 1 {
                        w /= 2;
                        continue;
                    }
                    exact_run = EXACT_AFTER_FAILURE;
                }
            }
            exact_run = exact_run.saturating_sub(1);
            if !self.state_free(only, &states[k]) {
                return Some(k);
            }
            k += 1;
        }
        None
    }

    /// The farthest any point of an arm or the part may move in `sweep` (m).
    fn sweep_bound(&self, sweep: &Sweep) -> f64 {
        let arm = |i: usize| -> f64 {
            let radii = &self.arms()[i].set().group_radii;
            (0..6)
                .map(|j| radii[j].iter().copied().fold(0.0, f64::max) * sweep.reach[i][j])
                .sum()
        };
        arm(0).max(arm(1)).max(sweep.object)
    }

    fn state_free(&self, only: Option<usize>, state: &WorldState) -> bool {
        match only {
            Some(arm) => self.is_arm_free(arm, state),
            None => self.is_free(state),
        }
    }
}

/// What a swept check ([`CollisionWorld::free_within`]) answers for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SweptUse {
    /// An answer in its own right (a box of joint space about a state): a pair with exact
    /// pieces is decided by them.
    Answer,
    /// A box about a state of an edge ([`CollisionWorld::is_arm_clear_within`]): the
    /// primitives decide, every pair asked.
    Box,
    /// A range of a sequence ([`CollisionWorld::first_contact_in`]): a failure only splits the
    /// range, down to states checked exactly, so a pair whose primitives come within its grown
    /// clearance counts as touching without its pieces being asked (in a shelf plan's re-check
    /// the pieces touched too in 650 of 1062 such pairs, and asking them cost a fifth of the
    /// re-check), and the grasping grippers vs the support are tested apart.
    Range,
}

/// What [`CollisionWorld::check_states`] finds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StatesCheck {
    /// The first state in contact.
    pub first_contact: Option<usize>,
    /// Per arm, the smallest height of its gripper above the support over the states in which
    /// it grasps (`None`: it grasps in none, or there is no support).
    pub closest_grasp: [Option<f64>; 2],
}

/// The largest motion bound (m) a swept check is tried for: past a few centimetres the
/// arms' own links (a wrist beside its forearm) and the part rarely leave room, and a check
/// with wide margins costs the most. Wider ranges are split without trying.
pub const SWEEP_LIMIT: f64 = 0.16;

/// The largest motion bound (m, in the joint space's metric) of a joint box asked about as a
/// whole when an edge is certified ([`crate::ArmValidity`]'s `around_limit`). Smaller than
/// [`SWEEP_LIMIT`]: the boxes hand the pairs they could not show to their halves, so a failed
/// box costs little and a small one passes more often (bench reach: 0.16 → 0.12 m, −2 % of
/// the instructions; 0.10 is as good on the whole set, 5 % worse on the direct edges).
pub const BOX_LIMIT: f64 = 0.12;

/// The half-width (states) of the first swept check of a sequence.
const FIRST_HALF_WIDTH: usize = 8;

/// States checked one by one after a swept check of three states failed, before the next try.
const EXACT_AFTER_FAILURE: usize = 2;

/// Ranges of fewer states than this (minus one) are checked state by state: a swept check
/// that fails there would cost more than it could save.
const LEAF_STATES: usize = 2;

/// Prefix sums of the motion bounds along a sequence of states: per arm and joint the path
/// length `Σ|Δq|`, and for a part at a fixed pose per state the displacement bound of its
/// points. Between states `k ≤ l` joint `j` moved at most `Q[l] − Q[k]` and the part at most
/// `O[l] − O[k]` (triangle inequality).
struct PathBounds {
    q: Vec<[Joints; 2]>,
    object: Vec<f64>,
    /// States with equal run numbers agree on grippers, grasping flags and how the part is
    /// placed (absent / fixed / attached to the same flange the same way).
    run: Vec<u32>,
}

impl PathBounds {
    fn new(world: &CollisionWorld, states: &[WorldState]) -> Self {
        let n = states.len();
        let mut q = Vec::with_capacity(n);
        let mut object = Vec::with_capacity(n);
        let mut run = Vec::with_capacity(n);
        let (mut qs, mut os, mut r) = ([[0.0; 6]; 2], 0.0, 0u32);
        let sphere = |s: &WorldState| match (s.object, world.object()) {
            (ObjectPlacement::Fixed(p), Some(obj)) => {
                let (c, radius) = obj.world_sphere(&p);
                Some((c, p.rotation, radius))
            }
            _ => None,
        };
        let mut prev_sphere = states.first().and_then(sphere);
        for (k, s) in states.iter().enumerate() {
            if k > 0 {
                let p = &states[k - 1];
                for (i, arm) in qs.iter_mut().enumerate() {
                    for (j, total) in arm.iter_mut().enumerate() {
                        *total += (s.q[i][j] - p.q[i][j]).abs();
                    }
                }
                // A part that stays put (a reach segment) costs nothing to follow.
                let still = matches!((p.object, s.object),
                    (ObjectPlacement::Fixed(a), ObjectPlacement::Fixed(b)) if a == b);
                if !still {
                    let this = sphere(s);
                    if let (Some((c0, r0, radius)), Some((c1, r1, _))) = (prev_sphere, this) {
                        // A turn by α moves a point at distance r by the chord 2·sin(α/2)·r,
                        // and sin(α/2) is the length of the relative rotation's vector part.
                        let chord = 2.0 * (r0.inverse() * r1).imag().norm();
                        os += (c1 - c0).norm() + chord * radius;
                    }
                    prev_sphere = this;
                }
                if !same_run(p, s) {
                    r += 1;
                }
            }
            q.push(qs);
            object.push(os);
            run.push(r);
        }
        PathBounds { q, object, run }
    }

    /// Whether arm `i` keeps its joints over states `lo..=hi` (no joint moved at all).
    fn still(&self, i: usize, lo: usize, hi: usize) -> bool {
        self.q[lo][i] == self.q[hi][i]
    }

    /// How far each joint of arm `i` may be from state `mid` in states `lo..=hi` (rad).
    fn reach(&self, i: usize, lo: usize, mid: usize, hi: usize) -> Joints {
        std::array::from_fn(|j| {
            let (a, m, b) = (self.q[lo][i][j], self.q[mid][i][j], self.q[hi][i][j]);
            (m - a).max(b - m) + REACH_ROUNDING
        })
    }

    /// The sweep that covers every state of `lo..=hi` from `state` (state `mid`), or `None`
    /// when the range crosses a change of grippers, grasp flags or the part's placement.
    fn sweep(&self, state: &WorldState, lo: usize, mid: usize, hi: usize) -> Option<Sweep> {
        if self.run[lo] != self.run[hi] {
            return None;
        }
        let mut sweep = Sweep {
            reach: [self.reach(0, lo, mid, hi), self.reach(1, lo, mid, hi)],
            object: 0.0,
        };
        if let ObjectPlacement::Fixed(_) = state.object {
            let (a, m, b) = (self.object[lo], self.object[mid], self.object[hi]);
            sweep.object = (m - a).max(b - m) + REACH_ROUNDING;
        }
        Some(sweep)
    }
}

/// Per arm, the shape groups of the shapes the pairs `among` name (bit `g`: group `g`).
fn groups_among(world: &CollisionWorld, among: &Doubts) -> [u8; 2] {
    let shapes = shapes_among(among);
    std::array::from_fn(|i| {
        let group_of = &world.arms()[i].set().group_of;
        let mut bits = shapes[i];
        let mut groups = 0u8;
        while bits != 0 {
            let k = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            groups |= 1 << group_of[k];
        }
        groups
    })
}

/// Added to every bound: the states are computed in floating point.
const REACH_ROUNDING: f64 = 1e-12;

/// Whether two states agree on everything but the joints and a fixed part's pose.
fn same_run(a: &WorldState, b: &WorldState) -> bool {
    let placement = match (a.object, b.object) {
        (ObjectPlacement::Absent, ObjectPlacement::Absent)
        | (ObjectPlacement::Fixed(_), ObjectPlacement::Fixed(_)) => true,
        (
            ObjectPlacement::Attached {
                arm: a1,
                flange_to_object: f1,
            },
            ObjectPlacement::Attached {
                arm: a2,
                flange_to_object: f2,
            },
        ) => a1 == a2 && f1 == f2,
        _ => false,
    };
    let grippers = a
        .gripper
        .iter()
        .zip(&b.gripper)
        .all(|(x, y)| x.key() == y.key());
    placement && grippers && a.grasping == b.grasping
}
