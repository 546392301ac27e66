//! Toy worlds shared by the integration tests.
#![allow(dead_code)]

use pregrasp_motion::{JointSpace, State};

/// Axis-aligned box obstacle in the first `K` coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Aabb<const K: usize> {
    pub lo: [f64; K],
    pub hi: [f64; K],
}

impl<const K: usize> Aabb<K> {
    pub fn contains<const D: usize>(&self, q: &State<D>) -> bool {
        (0..K).all(|i| q[i] > self.lo[i] && q[i] < self.hi[i])
    }
}

/// The unit-weight square `[-1, 1]²`.
pub fn plane() -> JointSpace<2> {
    JointSpace::new([-1.0; 2], [1.0; 2], [1.0; 2]).unwrap()
}

/// 2-D world: a vertical wall at x ∈ (−0.1, 0.1) with a gap at y ∈ (0.5, 0.6).
pub fn wall_with_gap(q: &State<2>) -> bool {
    wall_with_gap_padded(q, 0.0)
}

/// [`wall_with_gap`] with the wall grown by `pad` (see [`narrow_passage6_padded`]).
pub fn wall_with_gap_padded(q: &State<2>, pad: f64) -> bool {
    let below = Aabb {
        lo: [-0.1 - pad, -2.0],
        hi: [0.1 + pad, 0.5 + pad],
    };
    let above = Aabb {
        lo: [-0.1 - pad, 0.6 - pad],
        hi: [0.1 + pad, 2.0],
    };
    !below.contains(q) && !above.contains(q)
}

/// 2-D world: the goal region x > 0.5 is enclosed by a closed box wall.
pub fn closed_room(q: &State<2>) -> bool {
    let ring_outer = Aabb {
        lo: [0.3, -0.4],
        hi: [0.9, 0.4],
    };
    let ring_inner = Aabb {
        lo: [0.4, -0.3],
        hi: [0.8, 0.3],
    };
    !ring_outer.contains(q) || ring_inner.contains(q)
}

/// `[-1, 1]⁶` with weights 0.2 (so the metric is in "metres" of a 1.2 m-reach arm).
pub fn cube6() -> JointSpace<6> {
    JointSpace::new([-1.0; 6], [1.0; 6], [0.2; 6]).unwrap()
}

/// 6-D narrow passage: a slab |q0| < 0.1 blocks everything except a hole
/// |q1 − 0.3| < 0.12, |q2 + 0.2| < 0.12 (which the straight start–goal line misses).
pub fn narrow_passage6(q: &State<6>) -> bool {
    narrow_passage6_padded(q, 0.0)
}

/// [`narrow_passage6`] with obstacles grown by `pad` in every coordinate.
///
/// Planning against the world padded by `resolution / w` and checking edges every
/// `resolution` guarantees the continuous edges are free in the unpadded world:
/// any state on a checked edge is within `resolution / 2` (weighted L1) of a checked
/// state, so within `resolution / (2 w_i)` in coordinate `i`.
pub fn narrow_passage6_padded(q: &State<6>, pad: f64) -> bool {
    let in_slab = q[0].abs() < 0.1 + pad;
    let in_hole = (q[1] - 0.3).abs() < 0.12 - pad && (q[2] + 0.2).abs() < 0.12 - pad;
    !in_slab || in_hole
}

/// Weighted L1 lower bound on any valid path from [`START6`] to [`GOAL6`] in
/// [`narrow_passage6`]: q1 and q2 must visit the hole, the rest move at least straight.
pub fn narrow_passage6_lower_bound() -> f64 {
    // Shortest |a − x| + |x − b| over x ∈ [lo, hi]: |a − b| plus twice the gap
    // between the intervals [min(a, b), max(a, b)] and [lo, hi].
    let via = |a: f64, lo: f64, hi: f64, b: f64| {
        let gap = (lo - a.max(b)).max(a.min(b) - hi).max(0.0);
        (a - b).abs() + 2.0 * gap
    };
    let d1 = via(START6[1], 0.18, 0.42, GOAL6[1]);
    let d2 = via(START6[2], -0.32, -0.08, GOAL6[2]);
    let rest: f64 = [0, 3, 4, 5]
        .iter()
        .map(|&i| (START6[i] - GOAL6[i]).abs())
        .sum();
    0.2 * (d1 + d2 + rest)
}

pub const START6: State<6> = [-0.8, -0.5, 0.5, 0.3, -0.2, 0.1];
pub const GOAL6: State<6> = [0.8, -0.4, 0.6, -0.3, 0.4, -0.6];
