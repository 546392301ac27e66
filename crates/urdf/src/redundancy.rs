//! Redundant arms (7 or more joints): solutions across the self-motion, and continuity along
//! a path.
//!
//! A 7-DoF arm reaches a tool pose along a one-parameter family of configurations (the
//! self-motion). Fixing one joint `r` — the redundancy parameter, e.g. the Franka's joint 3
//! (index 2), which turns the elbow about the shoulder–wrist line — leaves a 6-DoF problem
//! with finitely many solutions, its branches (shoulder, elbow, wrist flips). So:
//!
//! * [`SerialChain::ik_redundant`] samples `q_r` over a grid across its limits (plus the
//!   seed's own value) and, for each value, solves the other joints from several starts with
//!   `q_r` held: the union over the grid shows every branch the limits allow;
//! * [`SerialChain::ik_follow`] tracks a moving target with `q_r` held at the seed's value,
//!   so the arm stays on the seed's branch and its elbow does not drift: the 6-DoF problem's
//!   solutions are isolated, and the continuation of [`SerialChain::ik_nearest`] stays on the
//!   one it starts on.

use nalgebra::Isometry3;

use crate::chain::SerialChain;
use crate::ik::{sort_by_distance, IkOptions, NearestOptions, Solver};

/// Settings of [`SerialChain::ik_redundant`].
#[derive(Clone, Debug, PartialEq)]
pub struct RedundancyOptions {
    /// The redundancy parameter: a chain variable index.
    pub joint: usize,
    /// Grid values of that joint across its limits (default 16): `lo + (k + ½)·(hi − lo)/samples`.
    pub samples: usize,
    /// The solve per grid value (default: [`IkOptions::default`] with 6 attempts).
    pub ik: IkOptions,
}

impl RedundancyOptions {
    /// Default settings with `joint` as the redundancy parameter.
    pub fn new(joint: usize) -> Self {
        RedundancyOptions {
            joint,
            samples: 16,
            ik: IkOptions {
                attempts: 6,
                ..IkOptions::default()
            },
        }
    }
}

impl SerialChain {
    /// Solutions for `target` across the redundancy parameter: for the seed's value of
    /// `opts.joint` and each grid value, the other joints solved with it held (see the module
    /// documentation). Distinct solutions, sorted by distance to `seed`.
    pub fn ik_redundant(
        &self,
        target: &Isometry3<f64>,
        seed: &[f64],
        opts: &RedundancyOptions,
    ) -> Vec<Vec<f64>> {
        self.check_len(seed);
        let r = opts.joint;
        assert!(r < self.dof(), "redundancy joint {r} out of range");
        let solver = Solver::new(self);
        let (lo, hi) = solver.sample_range(r);
        let seed = solver.clamp(seed);
        let mut locked = vec![false; self.dof()];
        locked[r] = true;
        let mut values = vec![seed[r]];
        values.extend(
            (0..opts.samples).map(|k| lo + (k as f64 + 0.5) * (hi - lo) / opts.samples as f64),
        );
        let mut sols = Vec::new();
        for v in values {
            let mut s = seed.clone();
            s[r] = v;
            self.multi_start(target, &s, &locked, &opts.ik, &mut sols);
        }
        sort_by_distance(&mut sols, &seed);
        sols
    }

    /// The continuity helper: the solution for `target` (near `fk(seed)`) on the seed's
    /// branch, with `joint` held at `seed[joint]` and the rest tracked from the seed
    /// ([`SerialChain::ik_nearest_with`], default [`NearestOptions`]). `None` when the
    /// branch cannot reach `target` with that value (a limit or a singularity in between).
    pub fn ik_follow(
        &self,
        target: &Isometry3<f64>,
        seed: &[f64],
        joint: usize,
    ) -> Option<Vec<f64>> {
        self.ik_nearest_with(target, seed, &[joint], &NearestOptions::default())
    }
}
