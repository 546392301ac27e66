//! Path simplification: greedy and random shortcutting, then waypoint removal.
//!
//! Every edge the simplifier introduces is checked with the same [`MotionValidator`]
//! that validated the input, and a change is kept only when it does not lengthen the
//! path in the space's metric, so the output is valid whenever the input was and
//! `length(out) ≤ length(in)` (the metric is a norm: the triangle inequality holds).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::space::State;
use crate::validity::{MotionValidator, StateValidator};

/// Shortens a valid path.
///
/// 1. Greedy pass (deterministic): from each kept waypoint, jump to the farthest later
///    waypoint reachable by one valid edge.
/// 2. `rounds` random shortcuts (ChaCha8 seeded by `rng_seed`): pick two points on two
///    different edges, `x` on edge `i` and `y` on edge `j > i`, and replace the part
///    between them by the straight edge `x → y` if the three new edges
///    `p_i → x → y → p_{j+1}` are valid and the path gets strictly shorter.
/// 3. `rounds` partial shortcuts (seeded by `rng_seed + 1`): the same for one joint
///    only ([`partial_shortcut`]); this straightens joints that wander while another
///    joint must stay in a narrow passage.
/// 4. Waypoint removal: drop every interior waypoint whose neighbours connect by a
///    valid edge (removes collinear and otherwise unneeded ones).
///
/// Paths with fewer than three states are returned unchanged.
pub fn simplify<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &[State<D>],
    rng_seed: u64,
    rounds: usize,
) -> Vec<State<D>> {
    if path.len() < 3 {
        return path.to_vec();
    }
    let mut out = greedy_shortcut(motion, path);
    random_shortcut(motion, &mut out, rng_seed, rounds);
    partial_shortcut(motion, &mut out, rng_seed.wrapping_add(1), rounds);
    remove_waypoints(motion, &mut out);
    out
}

/// Step 1 of [`simplify`]: from each kept waypoint, the farthest directly reachable one.
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
        while j > i + 1 && !motion.check_edge(&path[i], &path[j]) {
            j -= 1;
        }
        out.push(path[j]);
        i = j;
    }
    out
}

/// Step 2 of [`simplify`]: `rounds` seeded random shortcuts between points on edges.
pub fn random_shortcut<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &mut Vec<State<D>>,
    rng_seed: u64,
    rounds: usize,
) {
    let space = motion.space;
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    for _ in 0..rounds {
        let edges = path.len().saturating_sub(1);
        if edges < 2 {
            return;
        }
        let mut i = rng.random_range(0..edges);
        let mut j = rng.random_range(0..edges - 1);
        if j >= i {
            j += 1;
        }
        if j < i {
            std::mem::swap(&mut i, &mut j);
        }
        let x = space.interpolate(&path[i], &path[i + 1], rng.random());
        let y = space.interpolate(&path[j], &path[j + 1], rng.random());
        let old = space.motion_bound(&x, &path[i + 1])
            + space.path_length(&path[i + 1..=j])
            + space.motion_bound(&path[j], &y);
        let new = space.motion_bound(&x, &y);
        if new >= old * (1.0 - 1e-9) {
            continue;
        }
        // The new edge first: it is the one likely to fail (the others lie along valid edges).
        if motion.check_edge(&x, &y)
            && motion.check_edge(&path[i], &x)
            && motion.check_edge(&y, &path[j + 1])
        {
            // p_0 … p_i, x, y, p_{j+1} …
            path.splice(i + 1..=j, [x, y]);
        }
    }
}

/// Step 3 of [`simplify`]: `rounds` seeded partial (single-joint) shortcuts.
///
/// Picks a joint `c`, a point `x` on edge `i` and `y` on edge `j > i`; the states
/// `x, p_{i+1}, …, p_j, y` keep their other coordinates while coordinate `c` is
/// replaced by the linear interpolation from `x_c` to `y_c` (parameterised by the
/// cumulative length of the sub-path). The weighted L1 length is a per-coordinate sum
/// of total variations, so this never lengthens the path; the change is kept when it
/// shortens it strictly and every new edge `p_i → x' → … → y' → p_{j+1}` is valid.
pub fn partial_shortcut<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &mut Vec<State<D>>,
    rng_seed: u64,
    rounds: usize,
) {
    let space = motion.space;
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    let mut sub: Vec<State<D>> = Vec::new();
    for _ in 0..rounds {
        let edges = path.len().saturating_sub(1);
        if edges < 2 || D == 0 {
            return;
        }
        let c = rng.random_range(0..D);
        let mut i = rng.random_range(0..edges);
        let mut j = rng.random_range(0..edges - 1);
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
        // The moved states' edges first: the end edges lie along valid edges.
        let valid = sub.windows(2).all(|w| motion.check_edge(&w[0], &w[1]))
            && motion.check_edge(&path[i], &sub[0])
            && motion.check_edge(&sub[sub.len() - 1], &path[j + 1]);
        if valid {
            path.splice(i + 1..=j, sub.iter().copied());
        }
    }
}

/// Step 4 of [`simplify`]: drops interior waypoints whose neighbours connect directly.
pub fn remove_waypoints<const D: usize, V: StateValidator<D> + ?Sized>(
    motion: &MotionValidator<D, V>,
    path: &mut Vec<State<D>>,
) {
    let mut k = 1;
    while k + 1 < path.len() {
        if motion.check_edge(&path[k - 1], &path[k + 1]) {
            path.remove(k);
        } else {
            k += 1;
        }
    }
}
