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

use crate::lu::lu_solve;

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
            let (dx, ds, dz) = self.newton_step(&p, &r)?;
            p.x += dx;
            p.s += ds;
            p.z += dz;
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

    /// Newton's step `(dx, ds, dz)` for the residual `r` at `p`: the linearised equations
    ///
    /// `Aᵀ dz = −r_d`, `A dx + ds = −r_p`, `arrow(z) ds + arrow(s) dz = −r_c`
    ///
    /// (`arrow(v) = [[v₀, v̄ᵀ], [v̄, v₀ I]]`, the derivative of the Jordan product; `ds = −s` on
    /// a zero cone), solved with `ds = −r_p − A dx` eliminated: `n + m` unknowns instead of
    /// `n + 2m`. `None` if the system is singular.
    fn newton_step(
        &self,
        p: &PrimalDual,
        r: &DVector<f64>,
    ) -> Option<(DVector<f64>, DVector<f64>, DVector<f64>)> {
        let (m, n) = self.a.shape();
        let (r_d, r_p, r_c) = (r.rows(0, n), r.rows(n, m), r.rows(n + m, m));
        let mut k = DMatrix::zeros(n + m, n + m);
        let mut rhs = DVector::zeros(n + m);
        // Aᵀ dz = −r_d.
        k.view_mut((0, n), (n, m)).tr_copy_from(&self.a);
        rhs.rows_mut(0, n).copy_from(&(-r_d));
        let mut at = 0;
        for cone in &self.cones {
            match *cone {
                Cone::Zero(len) => {
                    // ds = −s, so A dx = s − r_p.
                    for i in at..at + len {
                        k.view_mut((n + i, 0), (1, n)).copy_from(&self.a.row(i));
                        rhs[n + i] = p.s[i] - r_p[i];
                    }
                    at += len;
                }
                Cone::SecondOrder(len) => {
                    // −arrow(z) A dx + arrow(s) dz = −r_c + arrow(z) r_p.
                    let arrow = |v: &DVector<f64>| {
                        let mut w = DMatrix::zeros(len, len);
                        for i in 0..len {
                            w[(0, i)] = v[at + i];
                            w[(i, 0)] = v[at + i];
                            w[(i, i)] = v[at];
                        }
                        w
                    };
                    let (az, as_) = (arrow(&p.z), arrow(&p.s));
                    let a_blk = self.a.rows(at, len);
                    k.view_mut((n + at, 0), (len, n)).copy_from(&(-&az * a_blk));
                    k.view_mut((n + at, n + at), (len, len)).copy_from(&as_);
                    let b = -r_c.rows(at, len) + &az * r_p.rows(at, len);
                    rhs.rows_mut(n + at, len).copy_from(&b);
                    at += len;
                }
            }
        }
        let step = lu_solve(k, rhs)?;
        if !step.iter().all(|v| v.is_finite()) {
            return None;
        }
        let dx = step.rows(0, n).into_owned();
        let dz = step.rows(n, m).into_owned();
        let ds = -r_p - &self.a * &dx;
        Some((dx, ds, dz))
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
