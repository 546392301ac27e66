//! RRT-Connect (Kuffner & LaValle 2000): two trees, one rooted at the start and one
//! at the goal, alternately extended toward random samples and greedily connected.

use std::time::{Duration, Instant};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::simplify::simplify;
use crate::space::{JointSpace, State};
use crate::validity::{MotionValidator, StateValidator};

/// Settings of [`rrt_connect`].
#[derive(Clone, Debug, PartialEq)]
pub struct RrtConnectSettings {
    /// Deterministic stop: number of sampling iterations before giving up.
    pub max_iterations: usize,
    /// Safety net on wall-clock time. A stop caused by it ([`PlanStatus::Timeout`]) is
    /// *not* reproducible; results that end otherwise are identical for a given seed
    /// whatever the time limit.
    pub max_time: Option<Duration>,
    /// Largest extension step, in the space's metric (metres of arm-point travel).
    pub range: f64,
    /// Seed of the ChaCha8 sampler: same seed, same inputs → same path bit for bit.
    pub seed: u64,
    /// Run [`simplify`] on a found path (seeded from `seed`, [`SIMPLIFY_ROUNDS`] rounds).
    pub simplify: bool,
}

/// Random shortcut rounds [`rrt_connect`] uses when `settings.simplify` is set.
pub const SIMPLIFY_ROUNDS: usize = 64;

impl Default for RrtConnectSettings {
    fn default() -> Self {
        Self {
            max_iterations: 10_000,
            max_time: Some(Duration::from_secs(5)),
            range: 0.5,
            seed: 0,
            simplify: true,
        }
    }
}

/// Outcome of a planning query (not an error: all are legitimate answers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PlanStatus {
    /// A valid path from start to goal was found.
    Solved,
    /// The start state is out of bounds or invalid.
    InvalidStart,
    /// The goal state is out of bounds or invalid.
    InvalidGoal,
    /// `max_iterations` reached without connecting the trees (deterministic).
    IterationLimit,
    /// `max_time` elapsed first (not reproducible).
    Timeout,
    /// The caller's stop condition held first ([`rrt_connect_until`]): the answer was no
    /// longer wanted.
    Stopped,
}

/// Counters of one planning query. The check counters cover the search (start, goal,
/// straight connection and tree edges), not the simplification; `time` covers both.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanStats {
    /// Sampling iterations run.
    pub iterations: usize,
    /// States passed to the state validator (including edge sub-states).
    pub states_checked: u64,
    /// Edges passed to the motion validator.
    pub edges_checked: u64,
    /// Total vertices in both trees when the search stopped.
    pub tree_states: usize,
    /// Wall-clock time of the whole query (including simplification).
    pub time: Duration,
}

/// A planning outcome: the status, the path (start … goal, empty unless solved) and
/// statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanResult<const D: usize> {
    /// What happened.
    pub status: PlanStatus,
    /// The path from start to goal (inclusive) when `status == Solved`, else empty.
    pub path: Vec<State<D>>,
    /// Counters.
    pub stats: PlanStats,
}

impl<const D: usize> PlanResult<D> {
    /// Whether a path was found.
    pub fn is_solved(&self) -> bool {
        self.status == PlanStatus::Solved
    }
}

/// A tree stored flat: vertex `k` is `states[k]` with parent `parents[k]`
/// (the root is its own parent).
struct Tree<const D: usize> {
    states: Vec<State<D>>,
    parents: Vec<u32>,
}

impl<const D: usize> Tree<D> {
    fn new(root: State<D>, capacity: usize) -> Self {
        let mut states = Vec::with_capacity(capacity);
        let mut parents = Vec::with_capacity(capacity);
        states.push(root);
        parents.push(0);
        Self { states, parents }
    }

    fn push(&mut self, q: State<D>, parent: usize) -> usize {
        self.states.push(q);
        self.parents.push(parent as u32);
        self.states.len() - 1
    }

    /// Index of the vertex nearest to `q` (linear scan; first minimum wins).
    fn nearest(&self, space: &JointSpace<D>, q: &State<D>) -> (usize, f64) {
        let mut best = (0, f64::INFINITY);
        for (k, s) in self.states.iter().enumerate() {
            let d = space.motion_bound(s, q);
            if d < best.1 {
                best = (k, d);
            }
        }
        best
    }

    /// States from the root to vertex `k`.
    fn branch(&self, mut k: usize) -> Vec<State<D>> {
        let mut out = vec![self.states[k]];
        while k != 0 {
            k = self.parents[k] as usize;
            out.push(self.states[k]);
        }
        out.reverse();
        out
    }
}

enum Extend {
    Trapped,
    Advanced(usize),
    Reached(usize),
}

struct Search<'m, 'a, const D: usize, V: StateValidator<D> + ?Sized> {
    motion: &'m MotionValidator<'a, D, V>,
    range: f64,
    stats: PlanStats,
}

impl<const D: usize, V: StateValidator<D> + ?Sized> Search<'_, '_, D, V> {
    fn edge(&mut self, a: &State<D>, b: &State<D>) -> bool {
        self.stats.edges_checked += 1;
        self.motion
            .check_edge_counted(a, b, &mut self.stats.states_checked)
    }

    /// One step of at most `range` from the nearest vertex toward `target`.
    fn extend(&mut self, tree: &mut Tree<D>, target: &State<D>) -> Extend {
        let space = self.motion.space;
        let (near, d) = tree.nearest(space, target);
        let near_q = tree.states[near];
        let (q_new, reached) = if d <= self.range {
            (*target, true)
        } else {
            (space.interpolate(&near_q, target, self.range / d), false)
        };
        if !self.edge(&near_q, &q_new) {
            return Extend::Trapped;
        }
        let k = tree.push(q_new, near);
        if reached {
            Extend::Reached(k)
        } else {
            Extend::Advanced(k)
        }
    }

    /// Repeated extensions toward `target` until reached or trapped.
    fn connect(&mut self, tree: &mut Tree<D>, target: &State<D>) -> Option<usize> {
        loop {
            match self.extend(tree, target) {
                Extend::Trapped => return None,
                Extend::Reached(k) => return Some(k),
                Extend::Advanced(_) => {}
            }
        }
    }
}

/// Plans a path from `start` to `goal` with RRT-Connect.
///
/// 1. `start` and `goal` are checked ([`PlanStatus::InvalidStart`] / `InvalidGoal`).
/// 2. The straight edge start → goal is tried first.
/// 3. Each iteration samples `q_rand` uniformly in the bounds, extends tree A one step
///    (≤ `range`) toward it and, if that added a vertex `q_new`, greedily connects
///    tree B toward `q_new`; then the trees swap roles.
///
/// Every tree edge is checked by `motion`, so the returned path is valid at its
/// resolution. Nearest neighbours use the weighted L1 metric with a linear scan.
/// With `settings.simplify` the path is shortened by [`simplify`].
pub fn rrt_connect<const D: usize, V: StateValidator<D> + ?Sized>(
    space: &JointSpace<D>,
    motion: &MotionValidator<D, V>,
    start: &State<D>,
    goal: &State<D>,
    settings: &RrtConnectSettings,
) -> PlanResult<D> {
    rrt_connect_until(space, motion, start, goal, settings, &|| false)
}

/// [`rrt_connect`] that also ends, with [`PlanStatus::Stopped`], where `stop` holds before an
/// iteration: a caller that learns its answer is no longer wanted (another thread refused what
/// it was for) stops the search. Until `stop` holds, the same search and path as
/// [`rrt_connect`]'s.
pub fn rrt_connect_until<const D: usize, V: StateValidator<D> + ?Sized>(
    space: &JointSpace<D>,
    motion: &MotionValidator<D, V>,
    start: &State<D>,
    goal: &State<D>,
    settings: &RrtConnectSettings,
    stop: &dyn Fn() -> bool,
) -> PlanResult<D> {
    let t0 = Instant::now();
    let mut search = Search {
        motion,
        range: settings.range.max(f64::MIN_POSITIVE),
        stats: PlanStats::default(),
    };
    let finish = |status, path: Vec<State<D>>, mut stats: PlanStats| {
        stats.time = t0.elapsed();
        PlanResult {
            status,
            path,
            stats,
        }
    };

    search.stats.states_checked += 1;
    if !motion.check_state(start) {
        return finish(PlanStatus::InvalidStart, Vec::new(), search.stats);
    }
    search.stats.states_checked += 1;
    if !motion.check_state(goal) {
        return finish(PlanStatus::InvalidGoal, Vec::new(), search.stats);
    }
    if search.edge(start, goal) {
        return finish(PlanStatus::Solved, vec![*start, *goal], search.stats);
    }

    let mut rng = ChaCha8Rng::seed_from_u64(settings.seed);
    let cap = settings.max_iterations.min(4096) + 1;
    let mut a = Tree::new(*start, cap);
    let mut b = Tree::new(*goal, cap);
    // `a_is_start`: whether tree `a` is currently the one rooted at the start.
    let mut a_is_start = true;
    let mut status = PlanStatus::IterationLimit;
    let mut joined: Option<(usize, usize)> = None;

    while search.stats.iterations < settings.max_iterations {
        if let Some(limit) = settings.max_time {
            if t0.elapsed() >= limit {
                status = PlanStatus::Timeout;
                break;
            }
        }
        if stop() {
            status = PlanStatus::Stopped;
            break;
        }
        search.stats.iterations += 1;
        let q_rand = space.sample(&mut rng);
        let new = match search.extend(&mut a, &q_rand) {
            Extend::Trapped => None,
            Extend::Advanced(k) | Extend::Reached(k) => Some(k),
        };
        if let Some(ka) = new {
            let target = a.states[ka];
            if let Some(kb) = search.connect(&mut b, &target) {
                joined = Some((ka, kb));
                status = PlanStatus::Solved;
                break;
            }
        }
        std::mem::swap(&mut a, &mut b);
        a_is_start = !a_is_start;
    }
    search.stats.tree_states = a.states.len() + b.states.len();

    let Some((ka, kb)) = joined else {
        return finish(status, Vec::new(), search.stats);
    };
    // Both branches end at the same state; drop the duplicate.
    let (from_start, from_goal) = if a_is_start {
        (a.branch(ka), b.branch(kb))
    } else {
        (b.branch(kb), a.branch(ka))
    };
    let mut path = from_start;
    path.extend(from_goal.iter().rev().skip(1));
    if settings.simplify {
        path = simplify(motion, &path, settings.seed, SIMPLIFY_ROUNDS);
    }
    finish(PlanStatus::Solved, path, search.stats)
}
