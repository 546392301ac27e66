//! Analytic inverse kinematics of a UR arm: every joint solution (up to 8) for a flange pose.
//!
//! The closed form follows the arm's structure (joints 2–4 parallel, standard DH as in
//! [`crate::model`]). With `p` the flange position, `x6, y6, z6` the flange axes and
//! `z1 = (sin q1, −cos q1, 0)` the (horizontal) axis of joints 2–4:
//! 1. `o5 = p − d6·z6` satisfies `o5·z1 = d4`; with `o5 = r(cos φ, sin φ, ·)`,
//!    `q1 = φ + atan2(d4, ±√(r² − d4²))` (no solution when `r < |d4|`; the two branches
//!    merge at the shoulder singularity `r = |d4|`, where `o5 − d4·z1` is on the base z axis).
//! 2. `z1` in flange coordinates is `(cos q6 sin q5, −sin q6 sin q5, cos q5)`, so
//!    `q5 = ±atan2(√((z1·x6)² + (z1·y6)²), z1·z6)` and
//!    `q6 = atan2(−(z1·y6)/sin q5, (z1·x6)/sin q5)`. When `sin q5 ≈ 0` (wrist singularity)
//!    q6 is free: a hint is used (0 in [`UrKinematics::ik_raw`], the seed's q6 in
//!    [`UrKinematics::ik`]) and q4 absorbs the rest, so solutions stay exact.
//! 3. Frame 4 follows: `z4 = −sin q6·x6 − cos q6·y6`,
//!    `x4 = cos q5 (cos q6·x6 − sin q6·y6) − sin q5·z6`, `o4 = o5 − d5·z4`. In frame 1, `o4 = (a2 c2 + a3 c23, a2 s2 + a3 s23, d4)` and
//!    `x4 = (c234, s234, 0)`: a planar two-link problem gives q3 (elbow up/down), q2 and q4.
//!
//! Every candidate is checked by forward kinematics (position and rotation residual below
//! [`IK_RESIDUAL_TOL`]) and dropped otherwise, so no NaN or approximate solution escapes.

use std::f64::consts::{PI, TAU};

use nalgebra::{Isometry3, Matrix3, Vector3};

use crate::angle::{angle_of, atan2, wrap_angle};
use crate::fk::UrKinematics;
use crate::model::Joints;

/// Maximum accepted FK residual of an IK solution: metres for the position, radians for the
/// rotation.
pub const IK_RESIDUAL_TOL: f64 = 1e-9;

/// How much larger (rad²) a joint's squared distance to the seed may be than its nearest
/// alternate's and still rank first in a sum of six ([`UrKinematics::ik_distinct`]): far above
/// the sum's rounding (about 1e-13 for six terms up to (3π)²). Two alternates 2π apart differ
/// in their squares by 4π·|v − seed ∓ π|, within this slack only for a seed 1e-10 rad from
/// half a turn away, where both are kept and ranked.
const TIE_SLACK: f64 = 1e-9;

/// Below this `|sin q5|` the wrist is treated as singular and q6 is taken from the hint.
const WRIST_SINGULAR_EPS: f64 = 1e-10;

/// Up to eight IK solutions, stored inline (no heap).
#[derive(Clone, Copy, Debug, Default)]
pub struct IkSolutions {
    sols: [Joints; 8],
    len: usize,
}

impl IkSolutions {
    /// The solutions found.
    pub fn as_slice(&self) -> &[Joints] {
        &self.sols[..self.len]
    }
    /// Number of solutions.
    pub fn len(&self) -> usize {
        self.len
    }
    /// True when the pose is unreachable (or every candidate failed validation).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// Iterates over the solutions.
    pub fn iter(&self) -> std::slice::Iter<'_, Joints> {
        self.as_slice().iter()
    }
    fn push_unique(&mut self, q: Joints) {
        // Same angle modulo 2π (inputs in (−π, π], so a difference of 2π is the same angle).
        let same = |a: f64, b: f64| {
            let d = (a - b).abs();
            d < 1e-12 || (d - TAU).abs() < 1e-12
        };
        let dup = self
            .as_slice()
            .iter()
            .any(|s| s.iter().zip(q.iter()).all(|(&a, &b)| same(a, b)));
        if !dup && self.len < 8 {
            self.sols[self.len] = q;
            self.len += 1;
        }
    }
}

impl<'a> IntoIterator for &'a IkSolutions {
    type Item = &'a Joints;
    type IntoIter = std::slice::Iter<'a, Joints>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl UrKinematics {
    /// Every analytic solution, each joint in (−π, π]; no NaN; empty when unreachable.
    /// At the wrist singularity q6 = 0 is chosen.
    pub fn ik_raw(&self, flange: &Isometry3<f64>) -> IkSolutions {
        self.ik_raw_with_q6_hint(flange, 0.0)
    }

    /// As [`UrKinematics::ik_raw`], choosing `q6_hint` for q6 when the wrist is singular.
    pub fn ik_raw_with_q6_hint(&self, flange: &Isometry3<f64>, q6_hint: f64) -> IkSolutions {
        let mut out = IkSolutions::default();
        let dh = self.dh;
        let rm = flange.rotation.to_rotation_matrix();
        let m = rm.matrix();
        let x6 = Vector3::new(m[(0, 0)], m[(1, 0)], m[(2, 0)]);
        let y6 = Vector3::new(m[(0, 1)], m[(1, 1)], m[(2, 1)]);
        let z6 = Vector3::new(m[(0, 2)], m[(1, 2)], m[(2, 2)]);
        let p = flange.translation.vector;
        if !(p.iter().all(|v| v.is_finite()) && m.iter().all(|v| v.is_finite())) {
            return out;
        }
        let o5 = p - dh.d6 * z6;

        // q1: o5 · z1 = d4 with z1 = (s1, −c1, 0); q1 = φ + β, sin β = d4/r, cos β = ±√(r² − d4²)/r.
        let r2 = o5.x * o5.x + o5.y * o5.y;
        let disc = r2 - dh.d4 * dh.d4;
        if disc < -1e-12 * (r2 + dh.d4 * dh.d4) || r2 == 0.0 {
            return out;
        }
        let r = r2.sqrt();
        let root = disc.max(0.0).sqrt();
        let inv_r = 1.0 / r;
        let (cphi, sphi) = (o5.x * inv_r, o5.y * inv_r);
        let q6_hint = wrap_angle(q6_hint);
        for sign1 in [1.0, -1.0] {
            let (sb, cb) = (dh.d4 * inv_r, sign1 * root * inv_r);
            let (s1, c1) = (sphi * cb + cphi * sb, cphi * cb - sphi * sb);
            let q1 = angle_of(s1, c1);
            let z1 = Vector3::new(s1, -c1, 0.0);
            // z1 in flange coordinates is (c6 s5, −s6 s5, c5).
            let (a, b, c5) = (z1.dot(&x6), z1.dot(&y6), z1.dot(&z6));
            let s5_abs = (a * a + b * b).sqrt();
            let singular = s5_abs < WRIST_SINGULAR_EPS;
            // The second wrist branch is q5 → −q5, q6 → q6 + π.
            let q5_pos = atan2(s5_abs, c5);
            let (q6_pos, s6_pos, c6_pos) = if singular {
                let (s, c) = crate::angle::sin_cos(q6_hint);
                (q6_hint, s, c)
            } else {
                let inv = 1.0 / s5_abs;
                (angle_of(-b, a), -b * inv, a * inv)
            };
            for sign5 in [1.0, -1.0] {
                let s5 = sign5 * s5_abs;
                let q5 = sign5 * q5_pos;
                let (s6, c6) = (sign5 * s6_pos, sign5 * c6_pos);
                let q6 = if sign5 > 0.0 {
                    q6_pos
                } else {
                    wrap_angle(q6_pos + PI)
                };
                let z4 = -s6 * x6 - c6 * y6;
                let x4 = c5 * (c6 * x6 - s6 * y6) - s5 * z6;
                let o4 = o5 - dh.d5 * z4;
                // Planar problem in frame 1 (origin (0, 0, d1), x1 = (c1, s1, 0), y1 = z0).
                let px = c1 * o4.x + s1 * o4.y;
                let py = o4.z - dh.d1;
                let rho2 = px * px + py * py;
                let c3 = (rho2 - dh.a2 * dh.a2 - dh.a3 * dh.a3) / (2.0 * dh.a2 * dh.a3);
                if !(-1.0 - 1e-9..=1.0 + 1e-9).contains(&c3) || rho2 == 0.0 {
                    continue;
                }
                let c3 = c3.clamp(-1.0, 1.0);
                let s3_abs = (1.0 - c3 * c3).sqrt();
                let q3_pos = atan2(s3_abs, c3);
                let (c234, s234) = (c1 * x4.x + s1 * x4.y, x4.z);
                let q234 = atan2(s234, c234);
                let inv234 = 1.0 / (c234 * c234 + s234 * s234).sqrt();
                let (c234, s234) = (c234 * inv234, s234 * inv234);
                let inv_rho2 = 1.0 / rho2;
                for sign3 in [1.0, -1.0] {
                    let s3 = sign3 * s3_abs;
                    let q3 = sign3 * q3_pos;
                    // (px, py) = Rz(q2)·(a2 + a3 c3, a3 s3).
                    let (u, v) = (dh.a2 + dh.a3 * c3, dh.a3 * s3);
                    let (c2, s2) = ((px * u + py * v) * inv_rho2, (py * u - px * v) * inv_rho2);
                    let (c23, s23) = (c2 * c3 - s2 * s3, s2 * c3 + c2 * s3);
                    let (s4, c4) = (s234 * c23 - c234 * s23, c234 * c23 + s234 * s23);
                    let sc = [(s1, c1), (s2, c2), (s3, c3), (s4, c4), (s5, c5), (s6, c6)];
                    if self.residual_ok(&sc, m, &p) {
                        let q2 = angle_of(s2, c2);
                        let q4 = wrap_angle(q234 - q2 - q3);
                        out.push_unique([q1, q2, wrap_angle(q3), q4, wrap_angle(q5), q6]);
                    }
                    if s3_abs == 0.0 {
                        break;
                    }
                }
                if singular {
                    break;
                }
            }
            if root == 0.0 {
                break;
            }
        }
        out
    }

    /// True when FK from the joints' `(sin, cos)` reproduces the flange rotation `m` and
    /// position `p` within [`IK_RESIDUAL_TOL`]. Rotation: a rotation error θ moves some
    /// column by at least `√(2/3)·2 sin(θ/2)`, so columns within `tol/2` keep θ < tol. The
    /// angles returned are `atan2` of these same pairs (a few ulp away); the tests check the
    /// FK of the returned angles directly.
    fn residual_ok(&self, sc: &[(f64, f64); 6], m: &Matrix3<f64>, p: &Vector3<f64>) -> bool {
        let (r, t) = self.fk_sin_cos(sc);
        let dp = (t - p).norm_squared();
        let dr = (0..3)
            .map(|j| (r.column(j) - m.column(j)).norm_squared())
            .fold(0.0, f64::max);
        let tol2 = IK_RESIDUAL_TOL * IK_RESIDUAL_TOL;
        dp < tol2 && dr < 0.25 * tol2
    }

    /// Every solution wrapped into `model().joint_limits()`, plus the ±2π alternates the
    /// limits allow, sorted by Euclidean joint distance to `seed` (ties broken by
    /// lexicographic joint order). At the wrist singularity q6 continues the seed's q6.
    pub fn ik(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        let limits = self.model().joint_limits();
        let raw = self.ik_raw_with_q6_hint(flange, seed[5]);
        let mut all: Vec<(f64, Joints)> = Vec::new();
        for sol in raw.iter() {
            let alts: [Alternates; 6] = std::array::from_fn(|j| Alternates::new(sol[j], limits[j]));
            all.extend(combinations(&alts).map(|q| (joint_distance(&q, seed), q)));
        }
        all.sort_by(by_distance_then_joints);
        all.into_iter().map(|(_, q)| q).collect()
    }

    /// One configuration per geometrically distinct solution: of each analytic solution's
    /// ±2π alternates within the limits, the one nearest to `seed`, sorted as
    /// [`UrKinematics::ik`] sorts. The same list, bit for bit, as [`distinct_solutions`] of
    /// [`UrKinematics::ik`] (whose first variant of each solution is its nearest), without
    /// enumerating the alternates: the squared distance separates per joint, so only the
    /// alternates within `TIE_SLACK` (1e-9 rad²) of a joint's nearest can be first; their
    /// combinations (one, but at a seed half a turn from a solution) are ranked as `ik` ranks
    /// them. At most a few candidates per solution where `ik` sorts up to 8 · 3⁶.
    pub fn ik_distinct(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        let limits = self.model().joint_limits();
        let raw = self.ik_raw_with_q6_hint(flange, seed[5]);
        let mut nearest: Vec<(f64, Joints)> = Vec::with_capacity(raw.len());
        for sol in raw.iter() {
            // Per joint, the alternates that may be first: within TIE_SLACK of the nearest.
            let near: [Alternates; 6] = std::array::from_fn(|j| {
                Alternates::new(sol[j], limits[j]).nearest(seed[j], TIE_SLACK)
            });
            let best = combinations(&near)
                .map(|q| (joint_distance(&q, seed), q))
                .min_by(by_distance_then_joints);
            nearest.extend(best);
        }
        nearest.sort_by(by_distance_then_joints);
        distinct_solutions(nearest.into_iter().map(|(_, q)| q))
    }

    /// The solution closest to `seed` (same branch continuation), if any: the first element
    /// of [`UrKinematics::ik`], computed without enumerating the alternates (the distance
    /// separates per joint, so each joint takes its nearest allowed alternate).
    pub fn ik_nearest(&self, flange: &Isometry3<f64>, seed: &Joints) -> Option<Joints> {
        let limits = self.model().joint_limits();
        let raw = self.ik_raw_with_q6_hint(flange, seed[5]);
        let mut best: Option<(f64, Joints)> = None;
        'solutions: for sol in raw.iter() {
            let mut q = [0.0; 6];
            for j in 0..6 {
                match nearest_alternate(sol[j], seed[j], limits[j]) {
                    Some(v) => q[j] = v,
                    None => continue 'solutions,
                }
            }
            let d = joint_distance(&q, seed);
            let better = match &best {
                None => true,
                Some((bd, bq)) => d < *bd || (d == *bd && lex_less(&q, bq)),
            };
            if better {
                best = Some((d, q));
            }
        }
        best.map(|(_, q)| q)
    }
}

/// The order of [`UrKinematics::ik`]: by distance to the seed, ties by lexicographic joint
/// order.
fn by_distance_then_joints(
    (da, qa): &(f64, Joints),
    (db, qb): &(f64, Joints),
) -> std::cmp::Ordering {
    da.total_cmp(db).then_with(|| {
        qa.iter()
            .zip(qb.iter())
            .map(|(a, b)| a.total_cmp(b))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    })
}

/// Of `solutions` in order, the first of each geometrically distinct one: a solution whose
/// angles, wrapped to (−π, π], all lie within 1e-9 rad of an earlier kept one's is dropped.
/// Applied to a list sorted by distance to a seed, it keeps each solution's nearest ±2π
/// variant.
pub fn distinct_solutions(solutions: impl IntoIterator<Item = Joints>) -> Vec<Joints> {
    let mut seen: Vec<Joints> = Vec::new();
    solutions
        .into_iter()
        .filter(|q| {
            let wrapped = q.map(wrap_angle);
            let new = !seen
                .iter()
                .any(|s| (0..6).all(|j| (s[j] - wrapped[j]).abs() < 1e-9));
            if new {
                seen.push(wrapped);
            }
            new
        })
        .collect()
}

/// Euclidean distance between two joint vectors (rad).
pub fn joint_distance(a: &Joints, b: &Joints) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn lex_less(a: &Joints, b: &Joints) -> bool {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        == Some(std::cmp::Ordering::Less)
}

/// The value `q + 2πk` (k ∈ {−1, 0, 1}) inside `[lo, hi]` nearest to `target` (the lower
/// one on a tie), if any.
#[inline]
fn nearest_alternate(q: f64, target: f64, (lo, hi): (f64, f64)) -> Option<f64> {
    let mut best: Option<(f64, f64)> = None;
    for v in [q - TAU, q, q + TAU] {
        if v >= lo && v <= hi {
            let d = (v - target).abs();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, v));
            }
        }
    }
    best.map(|(_, v)| v)
}

/// The values `q + 2πk` (k ∈ {−1, 0, 1}) inside `[lo, hi]`, for `q` in (−π, π] and limits
/// within ±3π.
struct Alternates {
    vals: [f64; 3],
    len: usize,
}

impl Alternates {
    fn new(q: f64, (lo, hi): (f64, f64)) -> Self {
        let mut vals = [0.0; 3];
        let mut len = 0;
        for v in [q - TAU, q, q + TAU] {
            if v >= lo && v <= hi {
                vals[len] = v;
                len += 1;
            }
        }
        Alternates { vals, len }
    }

    fn as_slice(&self) -> &[f64] {
        &self.vals[..self.len]
    }

    /// Those whose squared distance to `target` is within `slack` (rad²) of the least, in
    /// order.
    fn nearest(&self, target: f64, slack: f64) -> Alternates {
        let d = |v: f64| (v - target) * (v - target);
        let min = self
            .as_slice()
            .iter()
            .map(|&v| d(v))
            .fold(f64::INFINITY, f64::min);
        let mut kept = Alternates {
            vals: [0.0; 3],
            len: 0,
        };
        for &v in self.as_slice() {
            if d(v) <= min + slack {
                kept.vals[kept.len] = v;
                kept.len += 1;
            }
        }
        kept
    }
}

/// Every joint vector taking one of `alts[j]` at each joint `j`, joint 0 varying fastest.
fn combinations(alts: &[Alternates; 6]) -> impl Iterator<Item = Joints> + '_ {
    let count: usize = alts.iter().map(|a| a.len).product();
    (0..count).map(move |mut idx| {
        std::array::from_fn(|j| {
            let v = alts[j].vals[idx % alts[j].len];
            idx /= alts[j].len;
            v
        })
    })
}
