//! State and edge (motion) validity.
//!
//! The planner's only view of the world is a [`StateValidator`]: a predicate on joint
//! states. A [`MotionValidator`] lifts it to straight joint-space edges by checking
//! discrete states spaced so that no point of the arm moves more than `resolution`
//! metres between two checked states (see [`JointSpace::motion_bound`]).

use std::fmt;

use crate::space::{JointSpace, State};

/// A predicate on joint states: `true` when the state is collision free (and
/// otherwise acceptable). Must be `Sync` so planners can run queries in parallel.
pub trait StateValidator<const D: usize>: Sync {
    /// Whether `q` is valid.
    fn is_valid(&self, q: &State<D>) -> bool;

    /// Whether every state `x` within `reach` of `q` (`|x_i − q_i| ≤ reach_i`) that lies in
    /// the space's bounds is valid: one answer for a whole piece of an edge. `false` means
    /// "not shown", never "invalid"; the default shows nothing.
    fn is_valid_around(&self, _q: &State<D>, _reach: &State<D>) -> bool {
        false
    }

    /// The largest box worth asking [`is_valid_around`](Self::is_valid_around) about, as the
    /// farthest any state in it may be from its centre in the space's metric
    /// ([`JointSpace::motion_bound`]): larger boxes are split without asking (near anything
    /// they fail, and their checks cost the most). `0` (the default): never ask; edges are
    /// then checked state by state.
    fn around_limit(&self) -> f64 {
        0.0
    }

    /// [`is_valid_around`](Self::is_valid_around) asked only about the constraints `among`
    /// (every constraint when `None`), naming those it could not show: `Some(doubts)`, a
    /// subset of `among`, empty when the whole box is valid; `None` when more failed than
    /// [`Doubts`] holds (or the validator does not name its constraints).
    ///
    /// A validator is a conjunction of constraints (pairs of bodies that must keep apart,
    /// say) that it numbers as it likes. What a box shows for one constraint holds for every
    /// state in the box, so the states of a box that failed need only be asked about its
    /// doubts ([`is_valid_among`](Self::is_valid_among)), and so do the smaller boxes within
    /// it. The default names nothing: a box is shown whole or not at all.
    fn doubts_around(
        &self,
        q: &State<D>,
        reach: &State<D>,
        among: Option<&Doubts>,
    ) -> Option<Doubts> {
        if self.is_valid_around(q, reach) {
            Some(Doubts::default())
        } else {
            among.copied()
        }
    }

    /// Whether `q` satisfies the constraints `among`, all others being known to hold there
    /// (a box about it showed them, see [`doubts_around`](Self::doubts_around)). The default
    /// checks the whole state.
    fn is_valid_among(&self, q: &State<D>, _among: &Doubts) -> bool {
        self.is_valid(q)
    }
}

/// The constraints a box check could not show (see [`StateValidator::doubts_around`]), in
/// the validator's own numbering: at most [`Doubts::CAPACITY`] of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Doubts {
    ids: [u32; Doubts::CAPACITY],
    len: u8,
}

impl Doubts {
    /// The most constraints a `Doubts` names: past a dozen a box is near too much for the
    /// names to save work.
    pub const CAPACITY: usize = 12;

    /// Adds `id` (once); `false` when it is full and `id` is not in it.
    #[inline]
    pub fn insert(&mut self, id: u32) -> bool {
        if self.contains(id) {
            return true;
        }
        if self.len as usize == Self::CAPACITY {
            return false;
        }
        self.ids[self.len as usize] = id;
        self.len += 1;
        true
    }

    /// Whether `id` is one of them.
    #[inline]
    pub fn contains(&self, id: u32) -> bool {
        self.as_slice().contains(&id)
    }

    /// The constraints, in the order they were added.
    #[inline]
    pub fn as_slice(&self) -> &[u32] {
        &self.ids[..self.len as usize]
    }

    /// Whether there are none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl<const D: usize, F: Fn(&State<D>) -> bool + Sync> StateValidator<D> for F {
    #[inline]
    fn is_valid(&self, q: &State<D>) -> bool {
        self(q)
    }
}

/// Largest number of sub-steps one edge is cut into (guards against a zero or
/// non-finite `resolution`).
const MAX_EDGE_STEPS: usize = 1 << 30;

/// Checks straight joint-space edges at a guaranteed spatial resolution.
///
/// An edge `a → b` is cut into `n = ⌈motion_bound(a, b) / resolution⌉` equal steps
/// (at least 1), so between neighbouring checked states every arm point moves at most
/// `Σ_i w_i |Δq_i| / n ≤ resolution` metres. The states `k/n`, `k = 1..=n` are checked
/// `b` first and then in bit-reversed (van der Corput) order — midpoint, quarter
/// points, … — so a collision anywhere on the edge is usually found after few checks;
/// the check stops at the first invalid state. `a` is assumed valid (it is the end of
/// the previous edge or a checked start state).
///
/// With a validator that [certifies boxes](StateValidator::around_limit), a range of
/// states is accepted at once when the box about its middle state that holds them all is
/// valid, and split in halves (middle state checked) otherwise: the answer is the same,
/// and an edge far from obstacles costs a few checks instead of one per step. Where the
/// validator names the constraints a box failed ([`StateValidator::doubts_around`]), the
/// middle state and the halves are asked about those alone: the box showed the rest for
/// every state in it.
pub struct MotionValidator<'a, const D: usize, V: StateValidator<D> + ?Sized> {
    /// The joint space (bounds and metric).
    pub space: &'a JointSpace<D>,
    /// The state validator.
    pub validator: &'a V,
    /// Largest displacement (metres, in the space's metric) between checked states.
    pub resolution: f64,
}

/// An edge `a → b` cut into `n` steps.
struct Edge<'e, const D: usize> {
    a: &'e State<D>,
    b: &'e State<D>,
    n: usize,
}

/// Added to every box half-width: the states are computed in floating point.
const REACH_ROUNDING: f64 = 1e-12;

impl<const D: usize, V: StateValidator<D> + ?Sized> Clone for MotionValidator<'_, D, V> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<const D: usize, V: StateValidator<D> + ?Sized> Copy for MotionValidator<'_, D, V> {}

impl<const D: usize, V: StateValidator<D> + ?Sized> fmt::Debug for MotionValidator<'_, D, V> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MotionValidator")
            .field("space", self.space)
            .field("resolution", &self.resolution)
            .finish_non_exhaustive()
    }
}

impl<'a, const D: usize, V: StateValidator<D> + ?Sized> MotionValidator<'a, D, V> {
    /// A motion validator checking edges every `resolution` metres.
    pub fn new(space: &'a JointSpace<D>, validator: &'a V, resolution: f64) -> Self {
        Self {
            space,
            validator,
            resolution,
        }
    }

    /// Whether `q` lies within the joint bounds and is valid.
    #[inline]
    pub fn check_state(&self, q: &State<D>) -> bool {
        self.space.contains(q) && self.validator.is_valid(q)
    }

    /// Number of sub-steps `n` an edge `a → b` is cut into (≥ 1).
    #[inline]
    pub fn edge_steps(&self, a: &State<D>, b: &State<D>) -> usize {
        let n = (self.space.motion_bound(a, b) / self.resolution).ceil();
        // `as` saturates (NaN → 0), so this is total.
        (n as usize).clamp(1, MAX_EDGE_STEPS)
    }

    /// Whether the straight edge `a → b` is valid (`a` assumed valid, `b` checked).
    #[inline]
    pub fn check_edge(&self, a: &State<D>, b: &State<D>) -> bool {
        let mut checked = 0;
        self.check_edge_counted(a, b, &mut checked)
    }

    /// [`Self::check_edge`], adding the number of checks made to `states_checked` (a box
    /// check of a whole range counts as one).
    pub fn check_edge_counted(&self, a: &State<D>, b: &State<D>, states_checked: &mut u64) -> bool {
        *states_checked += 1;
        self.check_state(b) && self.check_between(a, b, states_checked)
    }

    /// [`Self::check_edge`] where `b` is known valid too (a waypoint of a valid path, say):
    /// only the states between the ends are checked.
    pub fn check_edge_between_valid(&self, a: &State<D>, b: &State<D>) -> bool {
        let mut checked = 0;
        self.check_between(a, b, &mut checked)
    }

    /// Whether the states strictly between `a` and `b` are valid.
    fn check_between(&self, a: &State<D>, b: &State<D>, states_checked: &mut u64) -> bool {
        let n = self.edge_steps(a, b);
        if n == 1 {
            return true;
        }
        let limit = self.validator.around_limit();
        if limit > 0.0 {
            let edge = Edge { a, b, n };
            return self.certify(&edge, 1, n - 1, limit, states_checked);
        }
        let inv_n = 1.0 / n as f64;
        for k in spread(n) {
            *states_checked += 1;
            let q = self.space.interpolate(a, b, k as f64 * inv_n);
            if !self.validator.is_valid(&q) {
                return false;
            }
        }
        true
    }

    /// Whether the states `k/n`, `k ∈ lo..=hi`, of `edge` are all valid.
    ///
    /// The range is cut into the fewest chunks whose boxes (about their middle states) are small
    /// enough to be worth asking about, visited in bisection order so that an obstacle anywhere
    /// along the edge is met early. A chunk is accepted by one box check; where the box fails,
    /// its middle state is checked exactly and both halves are queued (breadth first, coarse to
    /// fine). Too long a range is thus never checked at its middle state before its boxes are
    /// asked: on an edge through free space that check would be spent for nothing. A failed
    /// box hands its doubts down: its middle state and both halves are asked about them only.
    fn certify(
        &self,
        edge: &Edge<D>,
        lo: usize,
        hi: usize,
        limit: f64,
        states_checked: &mut u64,
    ) -> bool {
        let inv_n = 1.0 / edge.n as f64;
        let length = self.space.motion_bound(edge.a, edge.b);
        // A box reaching `s` states either side of its middle spans at most `s / n · length`.
        let half = if length > 0.0 {
            ((limit / (inv_n * length)).floor() as usize).min(hi - lo)
        } else {
            hi - lo
        };
        let per = 2 * half + 1;
        let chunks = (hi - lo + 1).div_ceil(per);
        let mut queue = std::collections::VecDeque::with_capacity(chunks.min(64) + 16);
        for c in spread(chunks + 1) {
            let from = lo + (c - 1) * per;
            queue.push_back((from, (from + per - 1).min(hi), None));
        }
        // Each range carries the constraints its enclosing boxes left in doubt (`None`: all).
        while let Some((lo, hi, among)) = queue.pop_front() {
            let mid = lo + (hi - lo) / 2;
            let q = self.space.interpolate(edge.a, edge.b, mid as f64 * inv_n);
            let span = (mid - lo).max(hi - mid) as f64 * inv_n;
            let mut doubts: Option<Doubts> = among;
            if hi > lo && span * length <= limit {
                let reach: State<D> =
                    std::array::from_fn(|i| (edge.b[i] - edge.a[i]).abs() * span + REACH_ROUNDING);
                *states_checked += 1;
                doubts = self.validator.doubts_around(&q, &reach, among.as_ref());
                if doubts.is_some_and(|d| d.is_empty()) {
                    continue;
                }
            }
            *states_checked += 1;
            let valid = match &doubts {
                None => self.validator.is_valid(&q),
                Some(d) => self.validator.is_valid_among(&q, d),
            };
            if !valid {
                return false;
            }
            if mid > lo {
                queue.push_back((lo, mid - 1, doubts));
            }
            if mid < hi {
                queue.push_back((mid + 1, hi, doubts));
            }
        }
        true
    }

    /// Whether the whole polyline is valid: its first state and every edge.
    /// An empty path is invalid.
    pub fn check_path(&self, path: &[State<D>]) -> bool {
        match path.first() {
            None => false,
            Some(first) => {
                self.check_state(first) && path.windows(2).all(|w| self.check_edge(&w[0], &w[1]))
            }
        }
    }

    /// The same validator with a different resolution (e.g. finer, to re-check paths).
    pub fn with_resolution(&self, resolution: f64) -> Self {
        Self {
            resolution,
            ..*self
        }
    }
}

/// The integers `1..n`, each once, in bisection order: `n/2`, then `n/4` and `3n/4`, … (the
/// midpoints of coarser levels first), so that something anywhere in `1..n` is met after few.
///
/// With `M = 2^K ≥ n`, the values `k(i) = ⌊i n / M⌋` for `i = 1..M` cover every `k` in `1..n`;
/// enumerating `i` in bit-reversed order visits the midpoints level by level. Since
/// `n / M > 1/2`, at most two neighbouring `i` share a `k`; one of them is odd and comes later in
/// that order, so an odd `i` whose neighbour shares its `k` is skipped.
fn spread(n: usize) -> impl Iterator<Item = usize> {
    let m = n.max(1).next_power_of_two() as u64;
    let shift = u64::BITS - m.trailing_zeros();
    let n64 = n as u64;
    let k_of = move |i: u64| i * n64 / m;
    (1..m).filter_map(move |j| {
        let i = j.reverse_bits() >> shift;
        let k = k_of(i);
        if k == 0 || (i % 2 == 1 && (k_of(i - 1) == k || k_of(i + 1) == k)) {
            None
        } else {
            Some(k as usize)
        }
    })
}

#[cfg(test)]
mod tests;
