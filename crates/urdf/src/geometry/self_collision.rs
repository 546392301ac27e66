//! Which link pairs to check for self-collision: MoveIt Setup Assistant's idea, made
//! deterministic.
//!
//! Start from every pair of links that have pieces and drop:
//!
//! * **adjacent** pairs. Links joined by a fixed joint are one rigid body, and a link without
//!   pieces is merged into its parent's body (so the links on both sides of a geometry-less
//!   link are adjacent, as in MoveIt). Two links are adjacent when they are in the same body
//!   or their bodies are joined by one moving joint. (FR3: `fr3_link7`, `fr3_link8` and
//!   `fr3_hand` are one body, so `fr3_link6`–`fr3_hand` and `fr3_link7`–fingers are adjacent.)
//! * pairs in contact in **always** (at least `always_fraction` of) the sampled
//!   configurations: they touch by construction, and checking them would flag every pose.
//! * pairs **never** in contact in any sampled configuration: the kinematics keeps them
//!   apart (with the usual caveat of sampling: a contact rarer than about 1/`samples` of
//!   the joint space can be missed; MoveIt's default is the same 10 000 samples).
//!
//! Samples: each tree variable uniform in its limits (continuous joints and revolute ones
//! wider than a turn: in `[−π, π)`, which covers every pose), from a SplitMix64 stream
//! seeded with `seed`, so the result is the same on every run. Contact is parry's
//! `intersection_test` on the posed pieces (touching counts), after a bounding-sphere
//! rejection. A pair already seen both in and out of contact (so neither always nor never)
//! is not tested again.

use nalgebra::{Isometry3, Point3};
use parry3d_f64::shape::ConvexPolyhedron;

use super::tree::LinkTree;
use super::types::{ExcludedPair, Exclusion, LinkPieces};
use crate::chain::JointKind;
use crate::rng::SplitMix64;

/// Settings of the always/never sampling.
#[derive(Clone, Debug, PartialEq)]
pub struct SelfCollisionOptions {
    /// Configurations sampled (default 10 000, MoveIt Setup Assistant's default).
    pub samples: usize,
    /// Seed of the sample stream.
    pub seed: u64,
    /// A pair in contact in at least this fraction of the samples is "always" (default 1:
    /// every sample).
    pub always_fraction: f64,
}

impl Default for SelfCollisionOptions {
    fn default() -> Self {
        SelfCollisionOptions {
            samples: 10_000,
            seed: 0x5e1f_c011,
            always_fraction: 1.0,
        }
    }
}

/// The pieces of some links as parry shapes with bounding spheres, for contact tests.
#[derive(Clone)]
pub struct PieceShapes {
    /// Per link: each piece's polyhedron, bounding-sphere centre (link frame) and radius.
    links: Vec<Vec<(ConvexPolyhedron, Point3<f64>, f64)>>,
}

impl PieceShapes {
    /// Builds the polyhedra of `links` (pieces without volume are left out).
    pub fn new(links: &[LinkPieces]) -> PieceShapes {
        let links = links
            .iter()
            .map(|l| {
                l.pieces
                    .iter()
                    .filter_map(|p| {
                        let shape = ConvexPolyhedron::from_convex_hull(p)?;
                        let (lo, hi) = p.iter().fold(
                            (
                                Point3::from([f64::INFINITY; 3]),
                                Point3::from([-f64::INFINITY; 3]),
                            ),
                            |(lo, hi), q| (lo.inf(q), hi.sup(q)),
                        );
                        let c = nalgebra::center(&lo, &hi);
                        let r = p.iter().map(|q| (q - c).norm()).fold(0.0, f64::max);
                        Some((shape, c, r))
                    })
                    .collect()
            })
            .collect();
        PieceShapes { links }
    }

    /// True when a piece of link `a` at pose `pa` touches or overlaps a piece of link `b` at
    /// `pb` (both poses in one common frame).
    pub fn intersect(&self, a: usize, pa: &Isometry3<f64>, b: usize, pb: &Isometry3<f64>) -> bool {
        for (sa, ca, ra) in &self.links[a] {
            let wa = pa * ca;
            for (sb, cb, rb) in &self.links[b] {
                if (wa - pb * cb).norm() > ra + rb {
                    continue;
                }
                if parry3d_f64::query::intersection_test(pa, sa, pb, sb).unwrap_or(true) {
                    return true;
                }
            }
        }
        false
    }
}

/// For each link of `tree` (file order), the index into `links` of the link with that name.
pub(crate) fn tree_index(tree: &LinkTree, links: &[LinkPieces]) -> Vec<Option<usize>> {
    tree.link_names()
        .iter()
        .map(|n| links.iter().position(|l| &l.link == n))
        .collect()
}

/// The adjacency relation of the module documentation, as a matrix over `links`.
pub(crate) fn adjacency(tree: &LinkTree, links: &[LinkPieces]) -> Vec<Vec<bool>> {
    let of = tree_index(tree, links);
    let n = tree.link_names().len();
    // Union-find over tree links: fixed joints and geometry-less children merge.
    let mut body: Vec<usize> = (0..n).collect();
    fn find(body: &mut [usize], mut i: usize) -> usize {
        while body[i] != i {
            body[i] = body[body[i]];
            i = body[i];
        }
        i
    }
    for (i, own) in of.iter().enumerate() {
        if let Some((p, moving)) = tree.parent_of(i) {
            if !moving || own.is_none() {
                let (ri, rp) = (find(&mut body, i), find(&mut body, p));
                body[ri] = rp;
            }
        }
    }
    let roots: Vec<usize> = (0..n).map(|i| find(&mut body, i)).collect();
    let mut joined = std::collections::HashSet::new();
    for i in 0..n {
        if let Some((p, true)) = tree.parent_of(i) {
            joined.insert((roots[i].min(roots[p]), roots[i].max(roots[p])));
        }
    }
    let m = links.len();
    let mut adj = vec![vec![false; m]; m];
    for i in 0..n {
        for j in 0..n {
            if let (Some(a), Some(b)) = (of[i], of[j]) {
                let (x, y) = (roots[i].min(roots[j]), roots[i].max(roots[j]));
                adj[a][b] |= x == y || joined.contains(&(x, y));
            }
        }
    }
    adj
}

/// The sampling range of a tree variable (see the module documentation).
fn range(kind: JointKind, lower: f64, upper: f64) -> (f64, f64) {
    use std::f64::consts::PI;
    let within_a_turn = upper - lower <= 2.0 * PI; // false for ±∞ (and NaN)
    if kind.is_rotational() && !within_a_turn {
        (-PI, PI)
    } else {
        (lower, upper)
    }
}

/// The pairs to check, and the excluded ones with their reason (both ascending).
pub fn classify_pairs(
    tree: &LinkTree,
    links: &[LinkPieces],
    opts: &SelfCollisionOptions,
) -> (Vec<(usize, usize)>, Vec<ExcludedPair>) {
    let adj = adjacency(tree, links);
    let of = tree_index(tree, links);
    // Tree index of each link of `links`.
    let at: Vec<usize> = (0..links.len())
        .map(|a| {
            of.iter()
                .position(|o| *o == Some(a))
                .expect("every link is in the tree")
        })
        .collect();
    let shapes = PieceShapes::new(links);
    struct Tally {
        a: usize,
        b: usize,
        hits: usize,
        tested: usize,
    }
    let mut tallies: Vec<Tally> = Vec::new();
    let mut excluded = Vec::new();
    for (a, row) in adj.iter().enumerate() {
        for (b, &adjacent) in row.iter().enumerate().skip(a + 1) {
            if adjacent {
                excluded.push(ExcludedPair {
                    a,
                    b,
                    why: Exclusion::Adjacent,
                    hits: 0,
                    samples: 0,
                });
            } else {
                tallies.push(Tally {
                    a,
                    b,
                    hits: 0,
                    tested: 0,
                });
            }
        }
    }
    let ranges: Vec<(f64, f64)> = tree
        .variables()
        .iter()
        .map(|v| range(v.kind, v.limits.lower, v.limits.upper))
        .collect();
    let mut rng = SplitMix64::new(opts.seed);
    let allowed_misses = ((1.0 - opts.always_fraction) * opts.samples as f64).floor() as usize;
    let mut q = vec![0.0; ranges.len()];
    for _ in 0..opts.samples {
        for (v, &(lo, hi)) in q.iter_mut().zip(&ranges) {
            *v = rng.uniform(lo, hi);
        }
        if tallies
            .iter()
            .all(|t| t.hits > 0 && t.tested - t.hits > allowed_misses)
        {
            break;
        }
        let poses = tree.poses(&q);
        for t in &mut tallies {
            if t.hits > 0 && t.tested - t.hits > allowed_misses {
                continue; // sometimes in contact: checked, whatever the other samples say
            }
            t.tested += 1;
            t.hits += shapes.intersect(t.a, &poses[at[t.a]], t.b, &poses[at[t.b]]) as usize;
        }
    }
    let mut pairs = Vec::new();
    for t in tallies {
        let always = t.tested > 0 && t.hits as f64 >= opts.always_fraction * t.tested as f64;
        let why = if t.tested > 0 && t.hits == 0 {
            Exclusion::Never
        } else if always && t.tested == opts.samples {
            Exclusion::Always
        } else {
            pairs.push((t.a, t.b));
            continue;
        };
        excluded.push(ExcludedPair {
            a: t.a,
            b: t.b,
            why,
            hits: t.hits,
            samples: t.tested,
        });
    }
    excluded.sort_by_key(|e| (e.a, e.b));
    (pairs, excluded)
}
