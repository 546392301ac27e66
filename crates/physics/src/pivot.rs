//! [`crate::statics`]' problem when the part rests on its edge: two support contacts, the
//! rotation axis' endpoints `A` and `B`. The six balance equations then reduce to one, and the
//! optimum is often in closed form.
//!
//! Forces in units of the part's weight `W`; `x`, `u`, `v` the pads' closing axis and tangent
//! basis (as in [`crate::statics`]); `q_k = (t_k·u, t_k·v, s_k)` pad `k`'s friction variables,
//! `‖q_k‖ ≤ μ_pad N` (`s_k`, the torsion, only with a radius `e > 0`).
//!
//! **Moments about the axis.** Let `a = (B − A)/L`, `L = ‖B − A‖`. The support forces act on the
//! axis and have no moment about it; the pads' normal forces `±N x` are collinear and have none
//! either. Gravity's moment about the axis is balanced by the pads' friction alone:
//!
//! `h₀·q₀ + h₁·q₁ = M`, `M = ((c − A) × ẑ)·a`, `h_k = (u·(a × (p_k − A)), v·(a × (p_k − A)), e x·a)`.
//!
//! **The support's share.** Given the pads' forces, the support supplies the force
//! `F = ẑ − t₀ − t₁` and, about `A`, the moment `R` that balances gravity and the pads; only `B`
//! has a lever about `A`: `L a × s_B = R`, solvable exactly when the equation above holds
//! (`R·a = 0`), with the general solution `s_B = (R × a)/L + δ a`, `s_A = F − s_B`. The free `δ`
//! squeezes the part along its edge and changes no balance. So the whole problem is
//!
//! `min N` over `(N, q₀, q₁, δ)`: `h₀·q₀ + h₁·q₁ = M`, `‖q_k‖ ≤ μ_pad N`, and each contact's
//! friction cone `‖s_j,xy‖ ≤ μ_support s_j,z`, with `s_j` affine in `(q, δ)`
//!
//! — one equation where the general program has six, and 2 + 2·dim q variables instead of
//! 1 + 2·dim q + 6 ([`EdgeProblem::conic`]).
//!
//! **Closed form.** Dropping the support's cones leaves `min N` subject to the one equation,
//! whose answer is `N* = |M| / (μ_pad (‖h₀‖ + ‖h₁‖))` with `q_k = sign(M) μ_pad N* h_k/‖h_k‖` —
//! a lower bound on the grip force. If these pad forces leave the support a load it can carry
//! for some `δ`, they are feasible, so `N*` is the exact minimum ([`EdgeProblem::closed_form`]).
//!
//! **The split reported.** Each contact's cone holds on an interval of `δ`; among the `δ` where
//! both hold, the equilibrium reported is the one that needs the least support friction
//! (smallest largest `‖s_j,xy‖/(μ_support s_j,z)`), whichever way the pad forces were found.

use nalgebra::{DMatrix, DVector, Point3, Vector2, Vector3};

use crate::polish::{Cone, ConicProgram, PrimalDual};
use crate::statics::{run_conic, ContactModel, Equilibrium, SolverError, StaticProblem};

/// Pad friction variables per pad: `(t·u, t·v, s)`; `s` is unused (0) without torsion.
type PadQ = Vector3<f64>;

/// The problem on the edge, in units of the weight.
pub(crate) struct EdgeProblem {
    a_pt: Point3<f64>,
    /// Unit axis `a`, and `L`.
    axis: Vector3<f64>,
    len: f64,
    com: Point3<f64>,
    pads: [Point3<f64>; 2],
    x: Vector3<f64>,
    u: Vector3<f64>,
    v: Vector3<f64>,
    /// Torsion radius `e` (0: point pads).
    e: f64,
    mu_pad: f64,
    /// The levers `h_k` and the moment `M`.
    h: [PadQ; 2],
    moment: f64,
}

impl EdgeProblem {
    /// `None` unless the part rests on exactly two distinct support contacts.
    pub(crate) fn new(problem: &StaticProblem, model: &ContactModel) -> Option<EdgeProblem> {
        let [a_pt, b_pt] = problem.support[..] else {
            return None;
        };
        let ab = b_pt - a_pt;
        let len = ab.norm();
        if len < 1e-6 {
            return None;
        }
        let axis = ab / len;
        let x = problem.pads.closing_axis.normalize();
        let u = (problem.pads.width_axis - problem.pads.width_axis.dot(&x) * x).normalize();
        let v = x.cross(&u);
        let e = model.pad_torsion_radius.max(0.0);
        let pads = problem.pads.contacts();
        let lever = |p: &Point3<f64>| {
            let m = axis.cross(&(p - a_pt));
            Vector3::new(u.dot(&m), v.dot(&m), e * x.dot(&axis))
        };
        Some(EdgeProblem {
            a_pt,
            axis,
            len,
            com: problem.com,
            pads,
            x,
            u,
            v,
            e,
            mu_pad: model.mu_pad,
            h: [lever(&pads[0]), lever(&pads[1])],
            moment: (problem.com - a_pt).cross(&Vector3::z()).dot(&axis),
        })
    }

    /// The pads' tangential forces and torsional moments for `q`.
    fn pad_forces(&self, q: &[PadQ; 2]) -> ([Vector3<f64>; 2], [f64; 2]) {
        (
            q.map(|qk| qk.x * self.u + qk.y * self.v),
            q.map(|qk| self.e * qk.z),
        )
    }

    /// The support forces `(s_A, s_B)` at `δ = 0` for pad variables `q` (which must meet the
    /// moment equation for the pair to balance; linear in `q` plus a constant).
    fn support_at(&self, q: &[PadQ; 2]) -> (Vector3<f64>, Vector3<f64>) {
        let (tangential, torsion) = self.pad_forces(q);
        let force = Vector3::z() - tangential[0] - tangential[1];
        // About A: gravity and the pads (their normal forces cancel, whatever N), then R.
        let mut about_a = (self.com - self.a_pt).cross(&(-Vector3::z()));
        for k in 0..2 {
            about_a += (self.pads[k] - self.a_pt).cross(&tangential[k]) + torsion[k] * self.x;
        }
        let s_b = (-about_a).cross(&self.axis) / self.len;
        (force - s_b, s_b)
    }

    /// The equilibrium (in newtons, for weight `w`) for grip `n` and pad variables `q`, with the
    /// support split that needs the least friction, if the contacts can carry the load at all;
    /// `None` if they cannot.
    fn equilibrium(&self, w: f64, n: f64, q: &[PadQ; 2], mu_s: f64) -> Option<Equilibrium> {
        let (s_a0, s_b0) = self.support_at(q);
        let delta = least_friction_delta(&s_a0, &s_b0, &self.axis, mu_s)?;
        Some(self.equilibrium_at(w, n, q, &s_a0, &s_b0, delta))
    }

    fn equilibrium_at(
        &self,
        w: f64,
        n: f64,
        q: &[PadQ; 2],
        s_a0: &Vector3<f64>,
        s_b0: &Vector3<f64>,
        delta: f64,
    ) -> Equilibrium {
        let (tangential, torsion) = self.pad_forces(q);
        let support = [s_a0 - delta * self.axis, s_b0 + delta * self.axis];
        // The pads' cones hold by construction: a solver's N may fall short of its own pad
        // forces by its tolerance.
        let n = q.iter().fold(n, |n, qk| n.max(qk.norm() / self.mu_pad));
        Equilibrium {
            grip_force: w * n,
            pad_tangential: tangential.map(|t| w * t),
            pad_torsion: torsion.map(|s| w * s),
            support_normal: support.iter().map(|s| w * s.z.max(0.0)).collect(),
            support_tangential: support
                .iter()
                .map(|s| w * Vector3::new(s.x, s.y, 0.0))
                .collect(),
        }
    }

    /// The exact optimum when the moment-optimal pad forces leave the support a load it can
    /// carry (module doc), else `None`. `w`: the weight (N).
    pub(crate) fn closed_form(&self, w: f64, mu_s: f64) -> Option<Equilibrium> {
        let reach = self.h[0].norm() + self.h[1].norm();
        if reach < 1e-12 {
            return None;
        }
        let n = self.moment.abs() / (self.mu_pad * reach);
        // q_k = (M / (‖h₀‖ + ‖h₁‖)) ĥ_k, and 0 where h_k = 0 (that pad has no lever: any force
        // within its cone is as good, and none is the one tried).
        let q = self.h.map(|hk| {
            let norm = hk.norm();
            if norm > 0.0 {
                hk * (self.moment / (reach * norm))
            } else {
                Vector3::zeros()
            }
        });
        self.equilibrium(w, n, &q, mu_s)
    }

    /// The reduced program (module doc) with the support friction `mu_s` > 0: its optimum, and
    /// the primal-dual point to start the next state's from; `Ok(None)` when it is infeasible.
    /// Newton's method from `warm` (a neighbouring state's optimum) where it reaches a certified
    /// optimum ([`crate::polish`]), else Clarabel.
    pub(crate) fn conic(
        &self,
        w: f64,
        mu_s: f64,
        warm: Option<&PrimalDual>,
    ) -> Result<Option<(Equilibrium, PrimalDual)>, SolverError> {
        let d = if self.e > 0.0 { 3 } else { 2 };
        let program = self.program(mu_s, d);
        let solution = match warm.and_then(|start| program.polish(start)) {
            Some(p) => p,
            None => match run_conic(&program)? {
                // Newton's steps from the interior-point answer sharpen it to round-off.
                Some(p) => program.polish(&p).unwrap_or(p),
                None => return Ok(None),
            },
        };
        let mut q = [PadQ::zeros(); 2];
        for (k, qk) in q.iter_mut().enumerate() {
            for i in 0..d {
                qk[i] = solution.x[1 + k * d + i];
            }
        }
        let n = solution.x[0];
        // The least-friction split for these pad forces; the solver's own δ if round-off at
        // the cones' boundary leaves no interval.
        let (s_a0, s_b0) = self.support_at(&q);
        let delta = least_friction_delta(&s_a0, &s_b0, &self.axis, mu_s)
            .unwrap_or(solution.x[2 + 2 * d - 1]);
        let eq = self.equilibrium_at(w, n, &q, &s_a0, &s_b0, delta);
        Ok(Some((eq, solution)))
    }

    /// The reduced program in Clarabel's form: columns `N, q₀ (d), q₁ (d), δ`; rows the moment
    /// equation, the pad cones `(μ_pad N, q_k)`, the support cones `(μ_s s_z, s_x, s_y)`.
    fn program(&self, mu_s: f64, d: usize) -> ConicProgram {
        let nvar = 2 + 2 * d;
        let col_q = |k: usize, i: usize| 1 + k * d + i;
        let col_delta = nvar - 1;
        // The support forces' affine map: constant and one column per q variable.
        let zero = [PadQ::zeros(); 2];
        let (c_a, c_b) = self.support_at(&zero);
        let mut g_a = vec![Vector3::zeros(); nvar];
        let mut g_b = vec![Vector3::zeros(); nvar];
        for k in 0..2 {
            for i in 0..d {
                let mut q = zero;
                q[k][i] = 1.0;
                let (s_a, s_b) = self.support_at(&q);
                g_a[col_q(k, i)] = s_a - c_a;
                g_b[col_q(k, i)] = s_b - c_b;
            }
        }
        g_a[col_delta] = -self.axis;
        g_b[col_delta] = self.axis;

        let rows = 1 + 2 * (1 + d) + 6;
        let mut a = DMatrix::zeros(rows, nvar);
        let mut b = DVector::zeros(rows);
        // Row 0: h₀·q₀ + h₁·q₁ = M.
        for k in 0..2 {
            for i in 0..d {
                a[(0, col_q(k, i))] = self.h[k][i];
            }
        }
        b[0] = self.moment;
        let mut cones = vec![Cone::Zero(1)];
        let mut row = 1;
        // Pad cones (μ_pad N, q_k): rows −(μ_pad, I), b = 0.
        for k in 0..2 {
            a[(row, 0)] = -self.mu_pad;
            for i in 0..d {
                a[(row + 1 + i, col_q(k, i))] = -1.0;
            }
            row += 1 + d;
            cones.push(Cone::SecondOrder(1 + d));
        }
        // Support cones (μ_s s_z, s_x, s_y), s = c + G x: rows −G, b = c.
        for (c, g) in [(c_a, &g_a), (c_b, &g_b)] {
            for (col, gc) in g.iter().enumerate() {
                a[(row, col)] = -mu_s * gc.z;
                a[(row + 1, col)] = -gc.x;
                a[(row + 2, col)] = -gc.y;
            }
            b[row] = mu_s * c.z;
            b[row + 1] = c.x;
            b[row + 2] = c.y;
            row += 3;
            cones.push(Cone::SecondOrder(3));
        }
        let mut c = DVector::zeros(nvar);
        c[0] = 1.0;
        ConicProgram { a, b, c, cones }
    }
}

/// The squeeze `δ` (support forces `s_A0 − δ a`, `s_B0 + δ a`) at which both contacts are
/// within their friction cones with the least friction use, or `None` if there is none — or
/// if the axis is too steep for the cones to bound `δ` (`μ |a_z| ≥ ‖a_xy‖/2`; supports are
/// horizontal, so not for any axis within 60° of them).
fn least_friction_delta(
    s_a0: &Vector3<f64>,
    s_b0: &Vector3<f64>,
    axis: &Vector3<f64>,
    mu_s: f64,
) -> Option<f64> {
    if mu_s <= 0.0 || (mu_s * axis.z).powi(2) > 0.25 * (axis.x * axis.x + axis.y * axis.y) {
        return None;
    }
    let cone_a = DeltaCone::new(s_a0, &(-axis), mu_s);
    let cone_b = DeltaCone::new(s_b0, axis, mu_s);
    let (lo_a, hi_a) = cone_a.interval()?;
    let (lo_b, hi_b) = cone_b.interval()?;
    let (lo, hi) = (lo_a.max(lo_b), hi_a.min(hi_b));
    if lo > hi {
        return None;
    }
    Some(golden_min(
        |d| cone_a.friction_use(d).max(cone_b.friction_use(d)),
        lo,
        hi,
    ))
}

/// One support contact's force `s0 + δ d` as a function of the squeeze `δ`, and its friction
/// cone `‖s_xy‖ ≤ μ s_z`.
struct DeltaCone {
    /// Normal force at δ = 0, and its rate.
    n0: f64,
    n1: f64,
    /// Tangential force at δ = 0, and its rate.
    t0: Vector2<f64>,
    t1: Vector2<f64>,
    mu: f64,
}

impl DeltaCone {
    fn new(s0: &Vector3<f64>, d: &Vector3<f64>, mu: f64) -> DeltaCone {
        DeltaCone {
            n0: s0.z,
            n1: d.z,
            t0: Vector2::new(s0.x, s0.y),
            t1: Vector2::new(d.x, d.y),
            mu,
        }
    }

    /// `{δ : ‖t0 + δ t1‖ ≤ μ (n0 + δ n1)}`: `α δ² + 2 β δ + γ ≤ 0` with `α = ‖t1‖² − μ² n1² > 0`
    /// (the caller's steepness bound), so a closed interval, or `None` when empty. On it the
    /// normal force is ≥ 0 (it bounds a norm).
    fn interval(&self) -> Option<(f64, f64)> {
        let mu2 = self.mu * self.mu;
        let alpha = self.t1.norm_squared() - mu2 * self.n1 * self.n1;
        let beta = self.t0.dot(&self.t1) - mu2 * self.n0 * self.n1;
        let gamma = self.t0.norm_squared() - mu2 * self.n0 * self.n0;
        let disc = beta * beta - alpha * gamma;
        if disc < 0.0 {
            return None;
        }
        // Roots (−β ∓ √disc)/α, the pair computed without cancellation.
        let q = -(beta + beta.signum() * disc.sqrt());
        let (r1, r2) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            (q / alpha, gamma / q)
        };
        let (lo, hi) = (r1.min(r2), r1.max(r2));
        // The squared inequality also holds on the mirror cone (μ (n0 + δ n1) < 0); the normal
        // force keeps one sign on the interval, so its middle tells which cone this is.
        let mid = 0.5 * (lo + hi);
        (self.n0 + mid * self.n1 >= 0.0).then_some((lo, hi))
    }

    /// `‖t‖ / (μ n)` at `δ` (0 without tangential force, ∞ with no normal force).
    fn friction_use(&self, delta: f64) -> f64 {
        let t = (self.t0 + delta * self.t1).norm();
        let n = self.n0 + delta * self.n1;
        if t <= 1e-12 {
            0.0
        } else if n <= 0.0 {
            f64::INFINITY
        } else {
            t / (self.mu * n)
        }
    }
}

/// The minimiser of a quasi-convex `f` on `[lo, hi]` by golden-section search: a fixed number
/// of steps (the interval shrinks to its round-off), so the same answer every time.
fn golden_min(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    let (mut a, mut b) = (lo, hi);
    let mut c = b - INV_PHI * (b - a);
    let mut d = a + INV_PHI * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..80 {
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - INV_PHI * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + INV_PHI * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::Pads;
    use nalgebra::{Isometry3, Vector3};

    /// A 0.6 m × 0.04 m × 0.02 m bar of weight 1 turned by `deg` about its bottom edge (world
    /// `y`), pinched across its thickness near its far end.
    fn bar(deg: f64) -> StaticProblem {
        let pose = Isometry3::rotation(Vector3::y() * -deg.to_radians());
        StaticProblem {
            com: pose * Point3::new(0.3, 0.02, 0.01),
            weight: 1.0,
            pads: Pads {
                centre: pose * Point3::new(0.55, 0.02, 0.01),
                closing_axis: pose * Vector3::z(),
                width_axis: pose * Vector3::y(),
                width: 0.02,
            },
            support: vec![Point3::origin(), Point3::new(0.0, 0.04, 0.0)],
        }
    }

    const MODEL: ContactModel = ContactModel {
        mu_pad: 0.8,
        mu_support: 0.3,
        pad_torsion_radius: 0.0,
    };

    /// Where the support's friction binds, the closed form does not apply; Newton's method from
    /// the last such state's optimum (as in a plan's check, a few degrees back where the
    /// closed form held in between) reaches the grip force Clarabel finds for each state.
    #[test]
    fn newton_from_the_last_state_reaches_each_optimum() {
        let (mut bound, mut polished) = (0, 0);
        let mut last: Option<PrimalDual> = None;
        for deg in 0..=60 {
            let p = bar(f64::from(deg));
            let edge = EdgeProblem::new(&p, &MODEL).unwrap();
            if edge.closed_form(1.0, MODEL.mu_support).is_some() {
                continue;
            }
            bound += 1;
            let program = edge.program(MODEL.mu_support, 2);
            let alone = run_conic(&program).unwrap().expect("held");
            if let Some(start) = &last {
                if let Some(p) = program.polish(start) {
                    polished += 1;
                    // The grip force; the forces may differ where the optimum is not unique
                    // (a pad whose cone is slack).
                    assert!(
                        (p.x[0] - alone.x[0]).abs() < 1e-10,
                        "{deg}°: {} vs {}",
                        p.x,
                        alone.x
                    );
                }
            }
            last = Some(alone);
        }
        assert!(bound > 30, "the support binds at only {bound} states");
        assert!(
            polished + 1 >= bound,
            "Newton reached {polished} of {bound}"
        );
    }

    /// The closed form where the support holds what the moment-optimal pad forces leave it:
    /// `N = m g X_c / (2 μ R_p)` for the bar pinched across its width (the test of
    /// `tests/statics.rs`), and not where a slippery support cannot.
    #[test]
    fn the_closed_form_applies_only_where_the_support_holds() {
        let across_width = |deg: f64| StaticProblem {
            pads: Pads {
                closing_axis: Isometry3::rotation(Vector3::y() * -deg.to_radians()) * Vector3::y(),
                width_axis: Isometry3::rotation(Vector3::y() * -deg.to_radians()) * Vector3::x(),
                width: 0.04,
                ..bar(deg).pads
            },
            ..bar(deg)
        };
        let p = across_width(30.0);
        let theta = 30f64.to_radians();
        let x_c = 0.3 * theta.cos() - 0.01 * theta.sin();
        let r_p = (0.55f64.powi(2) + 0.01f64.powi(2)).sqrt();
        let eq = EdgeProblem::new(&p, &MODEL)
            .unwrap()
            .closed_form(1.0, 0.4)
            .expect("the support holds");
        assert!((eq.grip_force - x_c / (2.0 * 0.8 * r_p)).abs() < 1e-12);
        assert!(EdgeProblem::new(&p, &MODEL)
            .unwrap()
            .closed_form(1.0, 0.01)
            .is_none());
    }
}
