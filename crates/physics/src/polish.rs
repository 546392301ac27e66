//! Newton's method on the optimality conditions of a small conic program, started from the
//! solution of a neighbouring one: the states of one rotation differ by a degree, and their
//! optima by as little. Whatever it returns is checked to be an optimum; anything else is left
//! to the interior-point solver.
//!
//! The program is `min cᵀx subject to A x + s = b, s ∈ K`, `K` a product of zero cones and
//! second-order cones `{(s₀, s̄) : s₀ ≥ ‖s̄‖}` (Clarabel's form). Its
//! optimality conditions, with `z ∈ K*` the multipliers of `A x + s = b` (`K*` is `K` with the
//! zero cones' multipliers free):
//!
//! `Aᵀz + c = 0`, `A x + s − b = 0`, `s ∘ z = 0`, `s ∈ K`, `z ∈ K*`,
//!
//! where `∘` is the cone's Jordan product, `(sᵀz, s₀ z̄ + z₀ s̄)` on a second-order cone, and
//! `s = 0` stands for it on a zero cone. Newton's method solves the three equations;
//! near a strictly complementary solution (each cone's `s` or `z` in its interior, or both on its
//! boundary and nonzero) it converges quadratically. The point it reaches is accepted only if it
//! meets the equations to round-off and lies in `K × K*` up to `CONE_TOLERANCE`: then it is a
//! primal-dual optimum (the duality gap `sᵀz` is zero), exactly what the interior-point solver
//! would have been asked for. A start from the wrong side of a change of active set (a cone
//! that opens or closes between the two problems) converges outside `K`, or not at all, and is
//! refused.

use nalgebra::{DMatrix, DVector};

/// A cone of `K`, by its dimension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Cone {
    Zero(usize),
    SecondOrder(usize),
}

/// `min cᵀx subject to A x + s = b, s ∈ K`, dense.
pub(crate) struct ConicProgram {
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    pub c: DVector<f64>,
    pub cones: Vec<Cone>,
}

/// A primal-dual point `(x, s, z)`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PrimalDual {
    pub x: DVector<f64>,
    pub s: DVector<f64>,
    pub z: DVector<f64>,
}

/// How far outside `K` (or `K*`) an accepted point may lie, in the program's units (here
/// forces in units of the part's weight): the interior-point solver's own feasibility tolerance.
const CONE_TOLERANCE: f64 = 1e-11;
/// The equations' residual (∞-norm, relative to the data's scale) at which Newton stops.
const RESIDUAL_TOLERANCE: f64 = 1e-13;
/// Newton steps before giving up: from a neighbour's optimum it takes two to four.
const MAX_STEPS: usize = 8;

impl ConicProgram {
    /// The optimum reached by Newton's method from `start`, if it is one (module doc).
    pub(crate) fn polish(&self, start: &PrimalDual) -> Option<PrimalDual> {
        let (m, n) = self.a.shape();
        if start.x.len() != n || start.s.len() != m || start.z.len() != m {
            return None;
        }
        let scale = 1.0 + self.b.amax().max(self.c.amax());
        let mut p = start.clone();
        for _ in 0..MAX_STEPS {
            let r = self.residual(&p);
            if r.amax() <= RESIDUAL_TOLERANCE * scale {
                return self.in_cones(&p).then_some(p);
            }
            let step = self.jacobian(&p).lu().solve(&(-r))?;
            if !step.iter().all(|v| v.is_finite()) {
                return None;
            }
            p.x += step.rows(0, n);
            p.s += step.rows(n, m);
            p.z += step.rows(n + m, m);
        }
        let done = self.residual(&p).amax() <= RESIDUAL_TOLERANCE * scale;
        (done && self.in_cones(&p)).then_some(p)
    }

    /// `(Aᵀz + c, A x + s − b, s ∘ z)` stacked.
    fn residual(&self, p: &PrimalDual) -> DVector<f64> {
        let (m, n) = self.a.shape();
        let mut r = DVector::zeros(n + 2 * m);
        r.rows_mut(0, n).copy_from(&(self.a.tr_mul(&p.z) + &self.c));
        r.rows_mut(n, m)
            .copy_from(&(&self.a * &p.x + &p.s - &self.b));
        let mut at = 0;
        for cone in &self.cones {
            match *cone {
                Cone::Zero(k) => {
                    for i in at..at + k {
                        r[n + m + i] = p.s[i];
                    }
                    at += k;
                }
                Cone::SecondOrder(k) => {
                    let (s, z) = (p.s.rows(at, k), p.z.rows(at, k));
                    r[n + m + at] = s.dot(&z);
                    for i in 1..k {
                        r[n + m + at + i] = s[0] * z[i] + z[0] * s[i];
                    }
                    at += k;
                }
            }
        }
        r
    }

    /// The derivative of [`Self::residual`] in `(x, s, z)`.
    fn jacobian(&self, p: &PrimalDual) -> DMatrix<f64> {
        let (m, n) = self.a.shape();
        let mut j = DMatrix::zeros(n + 2 * m, n + 2 * m);
        // Aᵀz + c: d/dz = Aᵀ.
        j.view_mut((0, n + m), (n, m))
            .copy_from(&self.a.transpose());
        // A x + s − b: d/dx = A, d/ds = I.
        j.view_mut((n, 0), (m, n)).copy_from(&self.a);
        for i in 0..m {
            j[(n + i, n + i)] = 1.0;
        }
        // s ∘ z: d/ds = arrow(z), d/dz = arrow(s) (the zero cone: d/ds = I).
        let (ds, dz) = (n, n + m);
        let row = n + m;
        let mut at = 0;
        for cone in &self.cones {
            match *cone {
                Cone::Zero(k) => {
                    for i in at..at + k {
                        j[(row + i, ds + i)] = 1.0;
                    }
                    at += k;
                }
                Cone::SecondOrder(k) => {
                    for (col, v) in [(ds, &p.z), (dz, &p.s)] {
                        // arrow(v) = [[v₀, v̄ᵀ], [v̄, v₀ I]].
                        for i in 0..k {
                            j[(row + at, col + at + i)] = v[at + i];
                        }
                        for i in 1..k {
                            j[(row + at + i, col + at)] = v[at + i];
                            j[(row + at + i, col + at + i)] = v[at];
                        }
                    }
                    at += k;
                }
            }
        }
        j
    }

    /// `s ∈ K` and `z ∈ K*`, up to [`CONE_TOLERANCE`].
    fn in_cones(&self, p: &PrimalDual) -> bool {
        let mut at = 0;
        for cone in &self.cones {
            let ok = match *cone {
                Cone::Zero(k) => {
                    at += k;
                    true
                }
                Cone::SecondOrder(k) => {
                    let inside =
                        |v: &DVector<f64>| v[at] >= v.rows(at + 1, k - 1).norm() - CONE_TOLERANCE;
                    let ok = inside(&p.s) && inside(&p.z);
                    at += k;
                    ok
                }
            };
            if !ok {
                return false;
            }
        }
        true
    }
}
