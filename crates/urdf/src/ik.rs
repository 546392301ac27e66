//! Numerical inverse kinematics for any serial chain: damped least squares
//! (Levenberg–Marquardt) on the geometric Jacobian, joint limits kept by projection, several
//! deterministic starts.
//!
//! # One solve
//!
//! From a start `q`, with `e(q)` the pose error ([`pose_error`]: position in m, rotation
//! vector in rad, base frame), `E = ½|e|²` and `J` the geometric Jacobian (6 × dof), each
//! iteration takes the damped step
//!
//! ```text
//! Δq = Jᵀ (J Jᵀ + λ I₆)⁻¹ e,     λ = μ · (E + w),   w = 10⁻⁸
//! ```
//!
//! (the minimum-norm form of `(JᵀJ + λI)⁻¹ Jᵀ e`, a 6 × 6 Cholesky solve whatever the dof).
//! The damping grows with the error (Sugihara's choice: far from the target the step is a
//! short gradient step, near it Gauss–Newton with quadratic convergence) and `μ` adapts:
//! a step that lowers `E` is kept and `μ` halves (down to 10⁻²); one that does not is
//! dropped and `μ` grows tenfold (the solve gives up past 10¹²: a local minimum). The step is
//! scaled so no joint moves more than `max_step` (rad or m) per iteration.
//!
//! **Limits.** `q + Δq` is clamped into `[lower, upper]`, and a joint sitting on a bound whose
//! step points outward is frozen for that iteration (its column removed, the step solved
//! again), so the step is the damped least-squares step of the joints that can move.
//! Mimic joints follow their master and are not clamped to their own limits.
//!
//! **Convergence**: `|e_p| ≤ 10⁻⁹ m` and `|e_ω| ≤ 10⁻⁹ rad` by default
//! ([`IkOptions::position_tolerance`], [`IkOptions::rotation_tolerance`]).
//!
//! # Several solutions
//!
//! [`SerialChain::ik`] solves from the seed, then from `attempts − 1` starts drawn uniformly
//! within the limits (and `fallback_attempts` more when none converged) by a SplitMix64
//! generator started afresh from
//! [`IkOptions::rng_seed`] (so the output is a pure function of the input, bit for bit). Each
//! converged solution is moved to the `q_i + 2πk` of each rotational joint nearest to the
//! seed that the limits allow (the lower one on a tie, as for a wrist flip half a turn from
//! the seed); solutions within [`IkOptions::distinct_tolerance`] of each other on every
//! joint, modulo 2π on rotational joints, are one branch, reported once. They are sorted by
//! Euclidean joint distance to the seed (ties: lexicographic joint order). Unlike
//! `UrKinematics::ik`, the `±2π` alternates of a branch are not listed separately.
//!
//! # Following a path
//!
//! [`SerialChain::ik_nearest`] never jumps: it moves the target from `fk(seed)` to the goal
//! in straight substeps (position linear, rotation along the geodesic) of at most
//! [`NearestOptions::position_step`] and [`NearestOptions::rotation_step`], and tracks each
//! from the previous solution with small iterations. It returns `None` when a substep does not
//! converge (a singularity, a limit, an unreachable goal) rather than switching branches.

use std::f64::consts::TAU;

use nalgebra::{Isometry3, Matrix6, Matrix6xX, UnitQuaternion, Vector6};

use crate::chain::SerialChain;
use crate::kinematics::{pose_error, rotation_vector};
use crate::rng::SplitMix64;

/// Bias `w` of the damping `λ = μ·(E + w)`.
const DAMPING_BIAS: f64 = 1e-8;
/// Lowest damping multiplier `μ`.
const MU_MIN: f64 = 1e-2;
/// Past this `μ` the solve is stuck in a local minimum.
const MU_MAX: f64 = 1e12;
/// Distances to the seed closer than this are a tie (rad): the solutions themselves are only
/// known to about 1e-9.
const TIE: f64 = 1e-7;

/// Settings of [`SerialChain::ik_with`].
#[derive(Clone, Debug, PartialEq)]
pub struct IkOptions {
    /// Number of starts: the seed, then `attempts − 1` random ones (default 32).
    pub attempts: usize,
    /// More random starts, tried only when none of the first `attempts` converged
    /// (default 96: poses whose few branches have small basins).
    pub fallback_attempts: usize,
    /// Iterations per start (default 200).
    pub max_iterations: usize,
    /// Position residual to reach (m, default 1e-9).
    pub position_tolerance: f64,
    /// Rotation residual to reach (rad, default 1e-9).
    pub rotation_tolerance: f64,
    /// Largest change of one joint in one iteration (rad or m, default 0.5).
    pub max_step: f64,
    /// Seed of the random starts (default `0x5EED_1DE5_0F_A2A5`).
    pub rng_seed: u64,
    /// Stop once this many distinct solutions are found (default: no limit).
    pub max_solutions: usize,
    /// Solutions within this on every joint (modulo 2π on rotational joints) are one branch
    /// (rad or m, default 1e-4: near a singularity converged solutions of one branch spread
    /// by `residual / σ_min`, about 1e-6).
    pub distinct_tolerance: f64,
}

impl Default for IkOptions {
    fn default() -> Self {
        IkOptions {
            attempts: 32,
            fallback_attempts: 96,
            max_iterations: 200,
            position_tolerance: 1e-9,
            rotation_tolerance: 1e-9,
            max_step: 0.5,
            rng_seed: 0x5EED_1DE5_0FA2_A5A5,
            max_solutions: usize::MAX,
            distinct_tolerance: 1e-4,
        }
    }
}

/// Settings of [`SerialChain::ik_nearest_with`].
#[derive(Clone, Debug, PartialEq)]
pub struct NearestOptions {
    /// Largest target translation per substep (m, default 0.01).
    pub position_step: f64,
    /// Largest target rotation per substep (rad, default 0.02).
    pub rotation_step: f64,
    /// Iterations per substep (default 60).
    pub max_iterations: usize,
    /// Largest change of one joint in one iteration (rad or m, default 0.1).
    pub max_step: f64,
    /// Final position residual (m, default 1e-9); substeps stop at 1e-7.
    pub position_tolerance: f64,
    /// Final rotation residual (rad, default 1e-9); substeps stop at 1e-7.
    pub rotation_tolerance: f64,
}

impl Default for NearestOptions {
    fn default() -> Self {
        NearestOptions {
            position_step: 0.01,
            rotation_step: 0.02,
            max_iterations: 60,
            max_step: 0.1,
            position_tolerance: 1e-9,
            rotation_tolerance: 1e-9,
        }
    }
}

/// Euclidean distance between two joint vectors.
pub fn joint_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// One damped least-squares solve: its limits and scratch space.
pub(crate) struct Solver<'a> {
    chain: &'a SerialChain,
    lower: Vec<f64>,
    upper: Vec<f64>,
    rotational: Vec<bool>,
    jac: Matrix6xX<f64>,
}

/// Stopping rule of one solve.
#[derive(Clone, Copy)]
pub(crate) struct Stop {
    pub max_iterations: usize,
    pub max_step: f64,
    pub position_tolerance: f64,
    pub rotation_tolerance: f64,
}

impl<'a> Solver<'a> {
    pub(crate) fn new(chain: &'a SerialChain) -> Self {
        let limits = chain.limits();
        Solver {
            chain,
            lower: limits.iter().map(|l| l.lower).collect(),
            upper: limits.iter().map(|l| l.upper).collect(),
            rotational: chain
                .actuated_joints()
                .map(|j| j.kind.is_rotational())
                .collect(),
            jac: Matrix6xX::zeros(chain.dof()),
        }
    }

    /// `q` clamped into the limits.
    pub(crate) fn clamp(&self, q: &[f64]) -> Vec<f64> {
        q.iter()
            .enumerate()
            .map(|(i, &v)| v.max(self.lower[i]).min(self.upper[i]))
            .collect()
    }

    /// The interval random starts of joint `i` are drawn from: the limits where finite,
    /// else `[−π, π]` for a rotation and `[−1, 1]` m for a translation (a half-infinite
    /// range is cut one such width from its finite end).
    pub(crate) fn sample_range(&self, i: usize) -> (f64, f64) {
        let w = if self.rotational[i] { TAU } else { 2.0 };
        match (self.lower[i].is_finite(), self.upper[i].is_finite()) {
            (true, true) => (self.lower[i], self.upper[i]),
            (true, false) => (self.lower[i], self.lower[i] + w),
            (false, true) => (self.upper[i] - w, self.upper[i]),
            (false, false) => (-w / 2.0, w / 2.0),
        }
    }

    /// Damped least squares from `q` (inside the limits) towards `target`; `locked` joints
    /// keep their value. True when the residual reached the tolerances (`q` then holds the
    /// solution; otherwise the last iterate).
    pub(crate) fn solve(
        &mut self,
        target: &Isometry3<f64>,
        q: &mut [f64],
        locked: &[bool],
        stop: Stop,
    ) -> bool {
        let n = q.len();
        let converged = |e: &Vector6<f64>| {
            e.fixed_rows::<3>(0).norm() <= stop.position_tolerance
                && e.fixed_rows::<3>(3).norm() <= stop.rotation_tolerance
        };
        let mut e = pose_error(target, &self.chain.fk_jacobian(q, &mut self.jac));
        let mut err = 0.5 * e.norm_squared();
        let mut mu = 1.0;
        let mut free = vec![true; n];
        let mut dq = vec![0.0; n];
        let mut trial = vec![0.0; n];
        for _ in 0..stop.max_iterations {
            if converged(&e) {
                return true;
            }
            for (f, &l) in free.iter_mut().zip(locked) {
                *f = !l;
            }
            let lambda = mu * (err + DAMPING_BIAS);
            // Active set: at most n passes, each freezing at least one more joint.
            for _ in 0..=n {
                self.step(&e, lambda, &free, &mut dq);
                let scale = stop.max_step / dq.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
                if scale < 1.0 {
                    dq.iter_mut().for_each(|d| *d *= scale);
                }
                let mut frozen = false;
                for i in 0..n {
                    let out = (q[i] <= self.lower[i] && dq[i] < 0.0)
                        || (q[i] >= self.upper[i] && dq[i] > 0.0);
                    if free[i] && out {
                        free[i] = false;
                        frozen = true;
                    }
                }
                if !frozen {
                    break;
                }
            }
            for i in 0..n {
                trial[i] = (q[i] + dq[i]).max(self.lower[i]).min(self.upper[i]);
            }
            let e_trial = pose_error(target, &self.chain.fk(&trial));
            let err_trial = 0.5 * e_trial.norm_squared();
            if err_trial < err {
                q.copy_from_slice(&trial);
                e = pose_error(target, &self.chain.fk_jacobian(q, &mut self.jac));
                err = 0.5 * e.norm_squared();
                mu = (mu * 0.5).max(MU_MIN);
            } else {
                mu *= 10.0;
                if mu > MU_MAX {
                    return converged(&e);
                }
            }
        }
        converged(&e)
    }

    /// `dq = Jᵀ (J Jᵀ + λI)⁻¹ e` over the free columns (zero elsewhere).
    fn step(&self, e: &Vector6<f64>, lambda: f64, free: &[bool], dq: &mut [f64]) {
        let mut a = Matrix6::identity() * lambda;
        for (i, col) in self.jac.column_iter().enumerate() {
            if free[i] {
                a += col * col.transpose();
            }
        }
        // λ > 0 makes `a` positive definite; a failure means non-finite input.
        let y = match a.cholesky() {
            Some(c) => c.solve(e),
            None => Vector6::zeros(),
        };
        for (i, col) in self.jac.column_iter().enumerate() {
            dq[i] = if free[i] { col.dot(&y) } else { 0.0 };
        }
    }

    /// Each rotational joint of `q` moved by a multiple of 2π to the value nearest to
    /// `seed[i]` that its limits allow, the lower one when two are within [`TIE`] of a tie
    /// (`locked` joints untouched).
    pub(crate) fn nearest_equivalent(&self, q: &mut [f64], seed: &[f64], locked: &[bool]) {
        for i in 0..q.len() {
            if !self.rotational[i] || locked[i] || !seed[i].is_finite() {
                continue;
            }
            let k = ((seed[i] - q[i]) / TAU).round();
            let mut best = q[i];
            for dk in [-1.0, 0.0, 1.0] {
                let v = q[i] + (k + dk) * TAU;
                if !(v >= self.lower[i] && v <= self.upper[i]) {
                    continue;
                }
                let (dv, db) = ((v - seed[i]).abs(), (best - seed[i]).abs());
                // A branch half a turn from the seed (a wrist flip) ties: take the lower value.
                if dv < db - TIE || (dv <= db + TIE && v < best) {
                    best = v;
                }
            }
            q[i] = best;
        }
    }
}

/// Sorts solutions by distance to `seed`, ties by lexicographic joint order.
pub(crate) fn sort_by_distance(sols: &mut [Vec<f64>], seed: &[f64]) {
    sols.sort_by(|a, b| {
        joint_distance(a, seed)
            .total_cmp(&joint_distance(b, seed))
            .then_with(|| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| x.total_cmp(y))
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            })
    });
}

/// Adds `q` to `sols` unless one is within `tol` on every joint (modulo 2π on the joints
/// marked `rotational`: one branch is reported once); true when added.
pub(crate) fn push_distinct(
    sols: &mut Vec<Vec<f64>>,
    q: Vec<f64>,
    rotational: &[bool],
    tol: f64,
) -> bool {
    let close = |a: f64, b: f64, rot: bool| {
        let d = a - b;
        let d = if rot { d - TAU * (d / TAU).round() } else { d };
        d.abs() <= tol
    };
    let same = |s: &Vec<f64>| {
        s.iter()
            .zip(&q)
            .zip(rotational)
            .all(|((&a, &b), &r)| close(a, b, r))
    };
    if sols.iter().any(same) {
        return false;
    }
    sols.push(q);
    true
}

impl SerialChain {
    /// Every distinct solution found for the tool pose `target` (base frame), sorted by
    /// distance to `seed`; empty when none converged. Default [`IkOptions`].
    pub fn ik(&self, target: &Isometry3<f64>, seed: &[f64]) -> Vec<Vec<f64>> {
        self.ik_with(target, seed, &IkOptions::default())
    }

    /// [`SerialChain::ik`] with explicit options.
    pub fn ik_with(
        &self,
        target: &Isometry3<f64>,
        seed: &[f64],
        opts: &IkOptions,
    ) -> Vec<Vec<f64>> {
        self.check_len(seed);
        let locked = vec![false; self.dof()];
        let mut sols = Vec::new();
        self.multi_start(target, seed, &locked, opts, &mut sols);
        sort_by_distance(&mut sols, seed);
        sols
    }

    /// Solves from the seed (clamped) then from random starts, `locked` joints held at the
    /// seed's value; appends new distinct solutions to `sols`.
    pub(crate) fn multi_start(
        &self,
        target: &Isometry3<f64>,
        seed: &[f64],
        locked: &[bool],
        opts: &IkOptions,
        sols: &mut Vec<Vec<f64>>,
    ) {
        let mut solver = Solver::new(self);
        let mut rng = SplitMix64::new(opts.rng_seed);
        let stop = Stop {
            max_iterations: opts.max_iterations,
            max_step: opts.max_step,
            position_tolerance: opts.position_tolerance,
            rotation_tolerance: opts.rotation_tolerance,
        };
        let start_seed = solver.clamp(seed);
        let before = sols.len();
        for attempt in 0..opts.attempts + opts.fallback_attempts {
            if attempt == opts.attempts && sols.len() > before {
                return;
            }
            let mut q = start_seed.clone();
            if attempt > 0 {
                for (i, v) in q.iter_mut().enumerate() {
                    let (lo, hi) = solver.sample_range(i);
                    let r = rng.uniform(lo, hi);
                    if !locked[i] {
                        *v = r;
                    }
                }
            }
            if solver.solve(target, &mut q, locked, stop) {
                solver.nearest_equivalent(&mut q, seed, locked);
                push_distinct(sols, q, &solver.rotational, opts.distinct_tolerance);
                if sols.len() >= opts.max_solutions {
                    return;
                }
            }
        }
    }

    /// The solution reached by following the straight path from `fk(seed)` to `target` from
    /// the seed (same branch, no jump; see the module documentation), default
    /// [`NearestOptions`]. `None` when the tracking fails.
    pub fn ik_nearest(&self, target: &Isometry3<f64>, seed: &[f64]) -> Option<Vec<f64>> {
        self.ik_nearest_with(target, seed, &[], &NearestOptions::default())
    }

    /// [`SerialChain::ik_nearest`] with the chain variables listed in `locked` held at the
    /// seed's value, and explicit options.
    pub fn ik_nearest_with(
        &self,
        target: &Isometry3<f64>,
        seed: &[f64],
        locked: &[usize],
        opts: &NearestOptions,
    ) -> Option<Vec<f64>> {
        self.check_len(seed);
        let mut mask = vec![false; self.dof()];
        for &i in locked {
            mask[i] = true;
        }
        let mut solver = Solver::new(self);
        let mut q = solver.clamp(seed);
        let start = self.fk(&q);
        let dp = target.translation.vector - start.translation.vector;
        let w = rotation_vector(&(target.rotation * start.rotation.inverse()));
        let substeps = (dp.norm() / opts.position_step)
            .max(w.norm() / opts.rotation_step)
            .ceil()
            .max(1.0) as usize;
        for k in 1..=substeps {
            let last = k == substeps;
            let s = k as f64 / substeps as f64;
            let pose = if last {
                *target
            } else {
                Isometry3::from_parts(
                    (start.translation.vector + dp * s).into(),
                    UnitQuaternion::from_scaled_axis(w * s) * start.rotation,
                )
            };
            let tol = |t: f64| if last { t } else { t.max(1e-7) };
            let stop = Stop {
                max_iterations: opts.max_iterations,
                max_step: opts.max_step,
                position_tolerance: tol(opts.position_tolerance),
                rotation_tolerance: tol(opts.rotation_tolerance),
            };
            if !solver.solve(&pose, &mut q, &mask, stop) {
                return None;
            }
        }
        Some(q)
    }
}
