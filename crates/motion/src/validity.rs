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
mod tests {
    use super::*;
    use std::sync::Mutex;

    fn line() -> JointSpace<1> {
        JointSpace::new([-10.0], [10.0], [1.0]).unwrap()
    }

    #[test]
    fn edge_checks_every_state_once_in_spread_order() {
        let space = line();
        let seen = Mutex::new(Vec::new());
        let v = |q: &State<1>| {
            seen.lock().unwrap().push(q[0]);
            true
        };
        let mv = MotionValidator::new(&space, &v, 0.1);
        let mut count = 0;
        assert!(mv.check_edge_counted(&[0.0], &[1.0], &mut count));
        let seen = seen.into_inner().unwrap();
        assert_eq!(count, 10);
        assert_eq!(seen.len(), 10);
        assert_eq!(seen[0], 1.0, "end state first");
        assert!((seen[1] - 0.5).abs() < 1e-12, "then the midpoint");
        let mut sorted = seen.clone();
        sorted.sort_by(f64::total_cmp);
        for (k, x) in sorted.iter().enumerate() {
            assert!((x - (k + 1) as f64 * 0.1).abs() < 1e-12);
        }
    }

    #[test]
    fn every_sub_state_is_checked_exactly_once_for_any_step_count() {
        let space = line();
        for n in 1..=130usize {
            let seen = Mutex::new(Vec::new());
            let v = |q: &State<1>| {
                seen.lock()
                    .unwrap()
                    .push((q[0] * n as f64).round() as usize);
                true
            };
            let mv = MotionValidator::new(&space, &v, 1.0 / n as f64 + 1e-12);
            assert_eq!(mv.edge_steps(&[0.0], &[1.0]), n);
            assert!(mv.check_edge(&[0.0], &[1.0]));
            let mut ks = seen.into_inner().unwrap();
            assert_eq!(ks[0], n, "end state first");
            ks.sort_unstable();
            assert_eq!(ks, (1..=n).collect::<Vec<_>>(), "n = {n}");
        }
    }

    #[test]
    fn spread_visits_each_once_coarse_first() {
        for n in 1..=300usize {
            let ks: Vec<usize> = spread(n).collect();
            let mut sorted = ks.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (1..n).collect::<Vec<_>>(), "n = {n}");
            if n >= 4 {
                assert_eq!(ks[0], n / 2, "n = {n}: the midpoint first");
            }
        }
    }

    #[test]
    fn step_bound_respects_resolution() {
        let space = JointSpace::new([-5.0; 3], [5.0; 3], [0.3, 0.2, 0.1]).unwrap();
        let v = |_: &State<3>| true;
        let mv = MotionValidator::new(&space, &v, 0.01);
        let (a, b) = ([0.0, 1.0, -2.0], [1.5, -0.5, 2.0]);
        let n = mv.edge_steps(&a, &b);
        assert!(space.motion_bound(&a, &b) / n as f64 <= 0.01);
        assert!(space.motion_bound(&a, &b) / (n - 1) as f64 > 0.01);
    }

    #[test]
    fn thin_wall_is_found_and_stops_early() {
        let space = line();
        // A wall thinner than the edge but thicker than the resolution.
        let v = |q: &State<1>| !(q[0] > 0.42 && q[0] < 0.47);
        let mv = MotionValidator::new(&space, &v, 0.04);
        let mut count = 0;
        assert!(!mv.check_edge_counted(&[0.0], &[1.0], &mut count));
        assert!(count < mv.edge_steps(&[0.0], &[1.0]) as u64);
        // Coarser than the wall: may be missed — that is the documented contract.
        assert!(mv.with_resolution(0.5).check_edge(&[0.0], &[1.0]));
    }

    /// A wall on a line, with exact box answers: the interval `q ± r` misses it.
    struct Wall {
        from: f64,
        to: f64,
        limit: f64,
    }

    impl StateValidator<1> for Wall {
        fn is_valid(&self, q: &State<1>) -> bool {
            !(q[0] > self.from && q[0] < self.to)
        }
        fn is_valid_around(&self, q: &State<1>, r: &State<1>) -> bool {
            q[0] + r[0] <= self.from || q[0] - r[0] >= self.to
        }
        fn around_limit(&self) -> f64 {
            self.limit
        }
    }

    #[test]
    fn edges_checked_by_boxes_give_the_answers_of_state_by_state_with_fewer_checks() {
        let space = JointSpace::new([-10.0], [10.0], [1.0]).unwrap();
        let mut fewer = 0;
        for (k, from) in [0.0, 0.123, 0.42, 0.5, 0.97, 2.0].iter().enumerate() {
            let wall = Wall {
                from: *from,
                to: from + 0.013 * (k + 1) as f64,
                limit: [0.05, 0.2, 5.0][k % 3],
            };
            let plain = |q: &State<1>| wall.is_valid(q);
            for (a, b) in [
                (-0.3, 1.4),
                (1.4, -0.3),
                (0.6, 0.9),
                (0.2, 0.45),
                (2.5, 3.0),
            ] {
                for resolution in [0.001, 0.007, 0.04] {
                    let boxes = MotionValidator::new(&space, &wall, resolution);
                    let states = MotionValidator::new(&space, &plain, resolution);
                    let (mut n1, mut n2) = (0, 0);
                    let by_boxes = boxes.check_edge_counted(&[a], &[b], &mut n1);
                    let one_by_one = states.check_edge_counted(&[a], &[b], &mut n2);
                    assert_eq!(
                        by_boxes, one_by_one,
                        "wall {from}, {a} → {b} at {resolution}"
                    );
                    // With both ends valid, the states between them decide alone.
                    if states.check_state(&[a]) && states.check_state(&[b]) {
                        assert_eq!(boxes.check_edge_between_valid(&[a], &[b]), one_by_one);
                        assert_eq!(states.check_edge_between_valid(&[a], &[b]), one_by_one);
                    }
                    if by_boxes && states.edge_steps(&[a], &[b]) > 20 {
                        assert!(n1 < n2, "{n1} checks with boxes, {n2} without");
                        fewer += 1;
                    }
                }
            }
        }
        assert!(fewer > 10);
    }

    /// Several walls on a line, each a constraint of its own, counting how often each is asked.
    struct Walls {
        walls: Vec<(f64, f64)>,
        asked: Mutex<usize>,
    }

    impl Walls {
        fn free(&self, w: usize, q: f64, r: f64) -> bool {
            *self.asked.lock().unwrap() += 1;
            let (from, to) = self.walls[w];
            q + r <= from || q - r >= to
        }
    }

    impl StateValidator<1> for Walls {
        fn is_valid(&self, q: &State<1>) -> bool {
            (0..self.walls.len()).all(|w| self.free(w, q[0], 0.0))
        }
        fn is_valid_around(&self, q: &State<1>, r: &State<1>) -> bool {
            (0..self.walls.len()).all(|w| self.free(w, q[0], r[0]))
        }
        fn around_limit(&self) -> f64 {
            0.2
        }
        fn doubts_around(
            &self,
            q: &State<1>,
            r: &State<1>,
            among: Option<&Doubts>,
        ) -> Option<Doubts> {
            let mut doubts = Doubts::default();
            for w in 0..self.walls.len() {
                let asked = among.is_none_or(|d| d.contains(w as u32));
                if asked && !self.free(w, q[0], r[0]) && !doubts.insert(w as u32) {
                    return None;
                }
            }
            Some(doubts)
        }
        fn is_valid_among(&self, q: &State<1>, among: &Doubts) -> bool {
            among
                .as_slice()
                .iter()
                .all(|&w| self.free(w as usize, q[0], 0.0))
        }
    }

    /// The same walls, box checks whole (the default `doubts_around`).
    struct Whole<'a>(&'a Walls);

    impl StateValidator<1> for Whole<'_> {
        fn is_valid(&self, q: &State<1>) -> bool {
            self.0.is_valid(q)
        }
        fn is_valid_around(&self, q: &State<1>, r: &State<1>) -> bool {
            self.0.is_valid_around(q, r)
        }
        fn around_limit(&self) -> f64 {
            self.0.around_limit()
        }
    }

    #[test]
    fn doubts_handed_down_give_the_same_answers_for_fewer_questions() {
        let space = JointSpace::new([-10.0], [10.0], [1.0]).unwrap();
        let mut rng_state = 7u64;
        let mut next = || {
            rng_state = rng_state.wrapping_mul(6364136223846793005).wrapping_add(1);
            (rng_state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut named, mut whole) = (0, 0);
        for case in 0..200 {
            // Up to 20 thin walls, some grazed by the edge, some across it.
            let count = 1 + case % 20;
            let walls = Walls {
                walls: (0..count)
                    .map(|_| {
                        let from = next() * 4.0 - 1.0;
                        (from, from + 0.001 + 0.02 * next())
                    })
                    .collect(),
                asked: Mutex::new(0),
            };
            let (a, b) = (next() * 3.0 - 1.0, next() * 3.0 - 1.0);
            let plain = |q: &State<1>| walls.walls.iter().all(|&(f, t)| q[0] <= f || q[0] >= t);
            for resolution in [0.002, 0.01] {
                let truth = MotionValidator::new(&space, &plain, resolution).check_edge(&[a], &[b]);
                *walls.asked.lock().unwrap() = 0;
                let by_doubts =
                    MotionValidator::new(&space, &walls, resolution).check_edge(&[a], &[b]);
                named += *walls.asked.lock().unwrap();
                *walls.asked.lock().unwrap() = 0;
                let by_boxes =
                    MotionValidator::new(&space, &Whole(&walls), resolution).check_edge(&[a], &[b]);
                whole += *walls.asked.lock().unwrap();
                assert_eq!(by_doubts, truth, "case {case}: {a} → {b} at {resolution}");
                assert_eq!(by_boxes, truth, "case {case}: {a} → {b} at {resolution}");
            }
        }
        // Walls asked about: a box near one wall no longer asks the others again.
        assert!(2 * named < whole, "{named} with doubts, {whole} without");
    }

    #[test]
    fn doubts_hold_each_constraint_once_up_to_capacity() {
        let mut d = Doubts::default();
        assert!(d.is_empty());
        for id in 0..Doubts::CAPACITY as u32 {
            assert!(d.insert(id));
            assert!(d.insert(id), "already in");
        }
        assert_eq!(d.as_slice().len(), Doubts::CAPACITY);
        assert!(!d.insert(99), "full");
        assert!(d.contains(3) && !d.contains(99));
    }

    #[test]
    fn end_state_outside_bounds_is_invalid() {
        let space = line();
        let v = |_: &State<1>| true;
        let mv = MotionValidator::new(&space, &v, 0.1);
        assert!(!mv.check_edge(&[0.0], &[11.0]));
        assert!(mv.check_path(&[[0.0], [1.0], [-3.0]]));
        assert!(!mv.check_path(&[]));
    }

    #[test]
    fn zero_resolution_does_not_hang_on_zero_length_edge() {
        let space = line();
        let v = |_: &State<1>| true;
        let mv = MotionValidator::new(&space, &v, 0.0);
        assert!(mv.check_edge(&[1.0], &[1.0]));
    }
}
