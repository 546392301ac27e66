//! Path simplification: greedy and random shortcutting, then waypoint removal.
//!
//! Every edge the simplifier introduces is checked with the same [`MotionValidator`]
//! that validated the input (one that ends at a waypoint of the path without that
//! waypoint, [`MotionValidator::check_edge_between_valid`]), and a change is kept only when
//! it lowers the path's [`PathCost`] (by default its length in the space's metric), so the
//! output is valid whenever the input was and `cost(out) ≤ cost(in)`. Greedy shortcuts and
//! waypoint removal replace two or more edges by one, which never costs more when the edge
//! cost satisfies the triangle inequality (length does, being a norm; so does [`RestToRest`]
//! duration); random and partial shortcuts compare costs before they check any edge, so a
//! change that would not pay costs no collision check.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::space::{JointSpace, State};
use crate::timing::rest_to_rest_duration;
use crate::validity::{MotionValidator, StateValidator};

/// What simplification lowers: a cost that adds up over a path's edges, with
/// `edge(a, c) ≤ edge(a, b) + edge(b, c)` (the triangle inequality).
pub trait PathCost<const D: usize> {
    /// The cost of the straight edge `a → b`.
    fn edge(&self, a: &State<D>, b: &State<D>) -> f64;

    /// The cost of a polyline: the sum over its edges.
    fn path(&self, path: &[State<D>]) -> f64 {
        path.windows(2).map(|w| self.edge(&w[0], &w[1])).sum()
    }
}

/// Length in the space's metric ([`JointSpace::motion_bound`]).
impl<const D: usize> PathCost<D> for JointSpace<D> {
    fn edge(&self, a: &State<D>, b: &State<D>) -> f64 {
        self.motion_bound(a, b)
    }
}

/// Duration when every edge is run rest to rest under per-joint speed and acceleration
/// limits, as [`time_parameterize`](crate::time_parameterize) times it: each waypoint is
/// a stop, so a shortcut that saves length but adds a waypoint may well cost time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestToRest<const D: usize> {
    /// Speed limit per joint (> 0).
    pub vmax: [f64; D],
    /// Acceleration limit per joint (> 0).
    pub amax: [f64; D],
}

impl<const D: usize> PathCost<D> for RestToRest<D> {
    fn edge(&self, a: &State<D>, b: &State<D>) -> f64 {
        rest_to_rest_duration(a, b, &self.vmax, &self.amax)
    }
}

/// Shortens a valid path in the space's metric: [`simplify_by`] with
/// `motion.space` as the cost.
pub fn simplify<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &[State<D>],
    rng_seed: u64,
    rounds: usize,
) -> Vec<State<D>> {
    simplify_by(motion, path, rng_seed, rounds, motion.space)
}

/// Lowers the cost of a valid path.
///
/// 1. Greedy pass (deterministic): from each kept waypoint, jump to the farthest later
///    waypoint reachable by one valid edge.
/// 2. `rounds` random shortcuts (ChaCha8 seeded by `rng_seed`): pick two points on two
///    different edges, `x` on edge `i` and `y` on edge `j > i`, and replace the part
///    `p_i … p_{j+1}` by `p_i → x → y → p_{j+1}` if that costs strictly less and the
///    three new edges are valid; where it does not (under a duration, every waypoint is a
///    stop), by the cheaper of `p_i → y → p_{j+1}` and `p_i → x → p_{j+1}` if that does.
///    Drawn in batches, the best valid one of each applied ([`random_shortcut`]).
/// 3. `rounds` partial shortcuts (seeded by `rng_seed + 1`): the same for one joint
///    only ([`partial_shortcut`]); this straightens joints that wander while another
///    joint must stay in a narrow passage.
/// 4. Waypoint removal: drop every interior waypoint whose neighbours connect by a
///    valid edge (removes collinear and otherwise unneeded ones).
///
/// Paths with fewer than three states are returned unchanged.
pub fn simplify_by<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &[State<D>],
    rng_seed: u64,
    rounds: usize,
    cost: &impl PathCost<D>,
) -> Vec<State<D>> {
    if path.len() < 3 {
        return path.to_vec();
    }
    let mut out = greedy_shortcut(motion, path);
    random_shortcut(motion, &mut out, rng_seed, rounds, cost);
    partial_shortcut(motion, &mut out, rng_seed.wrapping_add(1), rounds, cost);
    remove_waypoints(motion, &mut out);
    out
}

/// Whether `new` is a strict improvement on `old` (beyond round-off).
fn cheaper(new: f64, old: f64) -> bool {
    new < old * (1.0 - 1e-9)
}

/// Step 1 of [`simplify_by`]: from each kept waypoint, the farthest directly reachable one.
pub fn greedy_shortcut<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &[State<D>],
) -> Vec<State<D>> {
    let Some(&first) = path.first() else {
        return Vec::new();
    };
    let mut out = vec![first];
    let mut i = 0;
    while i + 1 < path.len() {
        // The original edge i → i+1 is known valid, so the search always ends at i+1.
        let mut j = path.len() - 1;
        while j > i + 1 && !motion.check_edge_between_valid(&path[i], &path[j]) {
            j -= 1;
        }
        out.push(path[j]);
        i = j;
    }
    out
}

/// Random shortcuts are drawn in batches of this many: each batch's candidates are ranked by
/// what they save and checked best first, and only the first valid one is applied.
pub const SHORTCUT_BATCH: usize = 8;

/// One drawn shortcut: replace `p_{i+1} … p_j` by `keep` (one or two states), saving `gain`.
struct Candidate<const D: usize> {
    gain: f64,
    i: usize,
    j: usize,
    keep: [State<D>; 2],
    len: usize,
}

/// Step 2 of [`simplify_by`]: `rounds` seeded random shortcuts between points on edges, drawn
/// in batches of [`SHORTCUT_BATCH`] on the current path; in each batch the candidates that pay
/// are checked from the largest saving down, and the first valid one is applied. A shortcut
/// that is kept costs the certification of its new edges, usually long ones that graze what
/// the path went around; ranking first spends that on the best of a batch rather than on each
/// improvement in turn.
pub fn random_shortcut<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &mut Vec<State<D>>,
    rng_seed: u64,
    rounds: usize,
    cost: &impl PathCost<D>,
) {
    let space = motion.space;
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    let mut left = rounds;
    let mut batch: Vec<Candidate<D>> = Vec::with_capacity(SHORTCUT_BATCH);
    while left > 0 {
        let n = path.len().saturating_sub(1);
        if n < 2 {
            return;
        }
        batch.clear();
        for _ in 0..left.min(SHORTCUT_BATCH) {
            let mut i = rng.random_range(0..n);
            let mut j = rng.random_range(0..n - 1);
            if j >= i {
                j += 1;
            }
            if j < i {
                std::mem::swap(&mut i, &mut j);
            }
            let x = space.interpolate(&path[i], &path[i + 1], rng.random());
            let y = space.interpolate(&path[j], &path[j + 1], rng.random());
            let old = cost.path(&path[i..=j + 1]);
            let (p, q) = (path[i], path[j + 1]);
            // p_i → x → y → p_{j+1}; where that does not pay (a stop costs time), the cheaper
            // of p_i → y → p_{j+1} and p_i → x → p_{j+1}, if it does. Under length the first
            // always pays when anything does (the triangle inequality).
            let via_both = cost.edge(&p, &x) + cost.edge(&x, &y) + cost.edge(&y, &q);
            let via_y = cost.edge(&p, &y) + cost.edge(&y, &q);
            let via_x = cost.edge(&p, &x) + cost.edge(&x, &q);
            let (new, keep, len) = if cheaper(via_both, old) {
                (via_both, [x, y], 2)
            } else if cheaper(via_y, old) && via_y <= via_x {
                (via_y, [y, y], 1)
            } else if cheaper(via_x, old) {
                (via_x, [x, x], 1)
            } else {
                continue;
            };
            batch.push(Candidate {
                gain: old - new,
                i,
                j,
                keep,
                len,
            });
        }
        left -= left.min(SHORTCUT_BATCH);
        // Largest saving first; ties in the order drawn (a stable sort).
        batch.sort_by(|a, b| b.gain.total_cmp(&a.gain));
        for c in &batch {
            let (p, q) = (path[c.i], path[c.j + 1]);
            let keep = &c.keep[..c.len];
            // The new edge first: it is the one likely to fail (the others lie along valid
            // edges).
            let valid = match keep {
                [x, y] => {
                    motion.check_edge(x, y)
                        && motion.check_edge(&p, x)
                        && motion.check_edge_between_valid(y, &q)
                }
                [z] => motion.check_edge(&p, z) && motion.check_edge_between_valid(z, &q),
                _ => unreachable!("one or two states"),
            };
            if valid {
                // p_0 … p_i, keep…, p_{j+1} …
                path.splice(c.i + 1..=c.j, keep.iter().copied());
                break;
            }
        }
    }
}

/// Step 3 of [`simplify_by`]: `rounds` seeded partial (single-joint) shortcuts.
///
/// Picks a joint `c`, a point `x` on edge `i` and `y` on edge `j > i`; the states
/// `x, p_{i+1}, …, p_j, y` keep their other coordinates while coordinate `c` is
/// replaced by the linear interpolation from `x_c` to `y_c` (parameterised by the
/// cumulative length of the sub-path). The weighted L1 length is a per-coordinate sum
/// of total variations, so this never lengthens the path; the change is kept when
/// `p_i → x' → … → y' → p_{j+1}` costs strictly less than `p_i … p_{j+1}` and every new
/// edge is valid.
pub fn partial_shortcut<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &mut Vec<State<D>>,
    rng_seed: u64,
    rounds: usize,
    cost: &impl PathCost<D>,
) {
    let space = motion.space;
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    let mut sub: Vec<State<D>> = Vec::new();
    for _ in 0..rounds {
        let n = path.len().saturating_sub(1);
        if n < 2 || D == 0 {
            return;
        }
        let c = rng.random_range(0..D);
        let mut i = rng.random_range(0..n);
        let mut j = rng.random_range(0..n - 1);
        if j >= i {
            j += 1;
        }
        if j < i {
            std::mem::swap(&mut i, &mut j);
        }
        sub.clear();
        sub.push(space.interpolate(&path[i], &path[i + 1], rng.random()));
        sub.extend_from_slice(&path[i + 1..=j]);
        sub.push(space.interpolate(&path[j], &path[j + 1], rng.random()));
        let variation: f64 = sub.windows(2).map(|w| (w[1][c] - w[0][c]).abs()).sum();
        let (x_c, y_c) = (sub[0][c], sub[sub.len() - 1][c]);
        let total = space.path_length(&sub);
        if space.weights[c] * (variation - (y_c - x_c).abs()) <= 1e-9 * total {
            continue;
        }
        let mut run = 0.0;
        for k in 1..sub.len() - 1 {
            // Cumulative length along the original sub-path (sub[0] = x is never modified).
            let prev = if k == 1 { sub[0] } else { path[i + k - 1] };
            run += space.motion_bound(&prev, &path[i + k]);
            let u = if total > 0.0 { run / total } else { 0.0 };
            sub[k][c] = x_c + u * (y_c - x_c);
        }
        let old = cost.path(&path[i..=j + 1]);
        let new = cost.edge(&path[i], &sub[0])
            + cost.path(&sub)
            + cost.edge(&sub[sub.len() - 1], &path[j + 1]);
        if !cheaper(new, old) {
            continue;
        }
        // The moved states' edges first: the end edges lie along valid edges.
        let valid = sub.windows(2).all(|w| motion.check_edge(&w[0], &w[1]))
            && motion.check_edge(&path[i], &sub[0])
            && motion.check_edge_between_valid(&sub[sub.len() - 1], &path[j + 1]);
        if valid {
            path.splice(i + 1..=j, sub.iter().copied());
        }
    }
}

/// Step 4 of [`simplify_by`]: drops interior waypoints whose neighbours connect directly.
pub fn remove_waypoints<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &mut Vec<State<D>>,
) {
    let mut k = 1;
    while k + 1 < path.len() {
        if motion.check_edge_between_valid(&path[k - 1], &path[k + 1]) {
            path.remove(k);
        } else {
            k += 1;
        }
    }
}
