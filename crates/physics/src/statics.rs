//! One quasi-static state: the part under gravity, pinched by two pads and resting on point
//! contacts with the support. [`min_grip_force`](crate::min_grip_force) finds the smallest grip force that keeps it in
//! equilibrium without slipping anywhere: a second-order cone program, solved in closed form or
//! by Newton's method from the previous state where the part rests on its edge
//! (module `pivot`), else by Clarabel.
//!
//! Variables (forces in units of the part's weight `W`, so the problem is well scaled):
//!
//! - `N ≥ 0`, the grip force: each pad presses with `N` along the closing axis `x`, the pad at
//!   `−x` towards `+x` and the pad at `+x` towards `−x`. The two normal forces cancel and, being
//!   collinear, exert no torque: `N` appears only in the friction cones.
//! - per pad `k`: a tangential force `t_k = t_k1·u + t_k2·v` (`u`, `v` orthonormal, ⟂ `x`) and,
//!   when the pad's torsion radius `e > 0`, a torsional moment `e·s_k` about `x`, with
//!   `‖(t_k1, t_k2, s_k)‖ ≤ μ_pad·N` (point contact when `e = 0`: no `s_k`);
//! - per support contact `j`: a normal force `n_j·ẑ`, `n_j ≥ 0`, and a tangential force
//!   `(a_j, b_j, 0)` with `‖(a_j, b_j)‖ ≤ μ_support·n_j` (omitted when `μ_support = 0`).
//!
//! Equations (6): the contact forces sum to `W·ẑ`, and their torques about the centre of mass
//! sum to zero. Objective: minimise `N`.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DVector, Point3, Vector3};

use crate::polish::{Cone, ConicProgram, PrimalDual};

/// The two pads of a parallel gripper closed on the part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pads {
    /// Midway between the pad contacts (the precision point), world.
    pub centre: Point3<f64>,
    /// The gripper's closing axis (tool `x`), world; normalised on use.
    pub closing_axis: Vector3<f64>,
    /// A second tool axis ⟂ `closing_axis` (tool `y`), world: with it the tangent plane's basis.
    pub width_axis: Vector3<f64>,
    /// Gap between the pad faces (m): the contacts are at `centre ∓ width/2 · x`.
    pub width: f64,
}

impl Pads {
    /// The contact points: the pad at `−x` (pushes towards `+x`), then the one at `+x`.
    pub fn contacts(&self) -> [Point3<f64>; 2] {
        let x = self.closing_axis.normalize();
        [
            self.centre - 0.5 * self.width * x,
            self.centre + 0.5 * self.width * x,
        ]
    }
}

/// One quasi-static problem, world frame (`z` up).
#[derive(Clone, Debug, PartialEq)]
pub struct StaticProblem {
    /// Centre of mass.
    pub com: Point3<f64>,
    /// Weight `m·g` (N), > 0.
    pub weight: f64,
    pub pads: Pads,
    /// Point contacts with the support (normal `+z`); may be empty.
    pub support: Vec<Point3<f64>>,
}

/// Friction and contact-model parameters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ContactModel {
    /// Coulomb coefficient pad–part, > 0.
    pub mu_pad: f64,
    /// Coulomb coefficient support–part, ≥ 0.
    pub mu_support: f64,
    /// Effective radius (m) of a pad's torsional friction (soft finger: moment about the
    /// normal ≤ `μ·N·e`, coupled with the tangential force in one cone). 0: point contact.
    pub pad_torsion_radius: f64,
}

/// Forces at the optimum (N, N·m), world frame.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Equilibrium {
    /// The minimum grip force N_min.
    pub grip_force: f64,
    /// Tangential force of each pad on the part (pad at `−x`, pad at `+x`).
    pub pad_tangential: [Vector3<f64>; 2],
    /// Torsional moment of each pad about the closing axis.
    pub pad_torsion: [f64; 2],
    /// Normal force of each support contact.
    pub support_normal: Vec<f64>,
    /// Tangential force of each support contact.
    pub support_tangential: Vec<Vector3<f64>>,
}

impl Equilibrium {
    /// Σ normal force at the support.
    pub fn support_normal_total(&self) -> f64 {
        self.support_normal.iter().sum()
    }

    /// |Σ tangential force| at the support.
    pub fn support_tangential_total(&self) -> f64 {
        self.support_tangential
            .iter()
            .fold(Vector3::zeros(), |a, t| a + t)
            .norm()
    }

    /// Largest `|t|/(μ n)` over the support contacts that carry load (0 when the support
    /// carries nothing). A contact whose normal force is below 1e-6 of the support's total is
    /// unloaded: there both forces are solver round-off and their ratio means nothing.
    pub fn support_friction_use(&self, mu_support: f64) -> f64 {
        let total = self.support_normal_total();
        self.support_normal
            .iter()
            .zip(&self.support_tangential)
            .filter(|(&n, _)| n > 1e-6 * total)
            .map(|(&n, t)| use_ratio(t.norm(), mu_support * n))
            .fold(0.0, f64::max)
    }

    /// Largest friction use of the two pads if they squeeze with `grip_force` instead of
    /// N_min: `‖(t, τ/e)‖ / (μ·grip_force)`.
    pub fn pad_friction_use(&self, model: &ContactModel, grip_force: f64) -> f64 {
        (0..2)
            .map(|k| {
                let s = if model.pad_torsion_radius > 0.0 {
                    self.pad_torsion[k] / model.pad_torsion_radius
                } else {
                    0.0
                };
                use_ratio(
                    (self.pad_tangential[k].norm_squared() + s * s).sqrt(),
                    model.mu_pad * grip_force,
                )
            })
            .fold(0.0, f64::max)
    }
}

fn use_ratio(need: f64, capacity: f64) -> f64 {
    if need <= 1e-9 {
        0.0
    } else if capacity <= 1e-12 {
        f64::INFINITY
    } else {
        need / capacity
    }
}

/// What a state needs.
#[derive(Clone, Debug, PartialEq)]
pub enum StaticOutcome {
    /// Equilibrium is possible; the forces at the smallest grip force.
    Held(Equilibrium),
    /// No grip force works with the support's friction, but one would with unlimited support
    /// friction: the part slides on the support.
    Slides,
    /// No grip force works even with unlimited support friction (e.g. no support contact and a
    /// load the pads cannot push against).
    CannotHold,
}

/// The solver failed to decide: numerical trouble (its status), or it refused the problem it
/// was given (what it found wrong with it).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SolverError {
    #[error("the conic solver did not converge: {0:?}")]
    Status(SolverStatus),
    #[error("the conic solver did not converge: BadInputData({0:?})")]
    BadInput(&'static str),
    #[error("the conic solver refused its settings")]
    Settings,
}

/// The support friction that stands for "unlimited" when telling sliding from not holding.
pub(crate) const STICKY: f64 = 1e3;

/// [`min_grip_force`](crate::min_grip_force) by the second-order cone program alone (Clarabel), whatever the contacts.
pub fn min_grip_force_conic(
    problem: &StaticProblem,
    model: &ContactModel,
) -> Result<StaticOutcome, SolverError> {
    match solve(problem, model)? {
        Some(eq) => Ok(StaticOutcome::Held(eq)),
        None if !problem.support.is_empty() => {
            // Diagnose: would the support hold with (practically) unlimited friction?
            let sticky = ContactModel {
                mu_support: STICKY,
                ..*model
            };
            Ok(match solve(problem, &sticky)? {
                Some(_) => StaticOutcome::Slides,
                None => StaticOutcome::CannotHold,
            })
        }
        None => Ok(StaticOutcome::CannotHold),
    }
}

pub(crate) fn check_model(problem: &StaticProblem, model: &ContactModel) {
    assert!(model.mu_pad > 0.0, "mu_pad must be > 0");
    assert!(model.mu_support >= 0.0, "mu_support must be >= 0");
    assert!(problem.weight > 0.0, "weight must be > 0");
}

/// [`run_clarabel`] on a dense program of [`crate::polish`]'s form (its objective is `x₀`).
pub(crate) fn run_conic(program: &ConicProgram) -> Result<Option<PrimalDual>, SolverError> {
    let (m, n) = program.a.shape();
    let (mut ri, mut ci, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    for c in 0..n {
        for r in 0..m {
            let v = program.a[(r, c)];
            if v != 0.0 {
                ri.push(r);
                ci.push(c);
                vals.push(v);
            }
        }
    }
    let a = CscMatrix::new_from_triplets(m, n, ri, ci, vals);
    let cones: Vec<SupportedConeT<f64>> = program
        .cones
        .iter()
        .map(|c| match *c {
            Cone::Zero(k) => SupportedConeT::ZeroConeT(k),
            Cone::SecondOrder(k) => SupportedConeT::SecondOrderConeT(k),
        })
        .collect();
    run_clarabel(&a, program.b.as_slice(), &cones)
}

/// Solves `min x₀ subject to A x + s = b, s ∈ cones` with Clarabel at this crate's tolerances;
/// `None` when it is infeasible, else the optimal primal-dual point.
pub(crate) fn run_clarabel(
    a: &CscMatrix<f64>,
    b: &[f64],
    cones: &[SupportedConeT<f64>],
) -> Result<Option<PrimalDual>, SolverError> {
    run_clarabel_with(a, b, cones, true)
}

/// [`run_clarabel`] without the iterative refinement of each step's linear solve, and to a
/// tolerance of 1e-8 instead of 1e-11: for an answer read to the newton (the carry check's),
/// not to the last digit (the pinch's, which the plan file writes). Without the refinement a
/// solve takes about 30 % fewer instructions; the looser tolerance saves about a tenth of the
/// rest (the chair side's cone programs: 23.4 → 21.4 M).
pub(crate) fn run_clarabel_unrefined(
    a: &CscMatrix<f64>,
    b: &[f64],
    cones: &[SupportedConeT<f64>],
) -> Result<Option<PrimalDual>, SolverError> {
    run_clarabel_with(a, b, cones, false)
}

/// [`run_clarabel`], its linear solves refined or not.
fn run_clarabel_with(
    a: &CscMatrix<f64>,
    b: &[f64],
    cones: &[SupportedConeT<f64>],
    refine: bool,
) -> Result<Option<PrimalDual>, SolverError> {
    let nvar = a.n;
    let p = CscMatrix::zeros((nvar, nvar));
    let mut q = vec![0.0; nvar];
    q[0] = 1.0;
    // Unrefined answers are read to the newton: 1e-8 of the load is far below that.
    let tol = if refine { 1e-11 } else { 1e-8 };
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(tol)
        .tol_gap_rel(tol)
        .tol_feas(tol)
        .iterative_refinement_enable(refine)
        .max_iter(200)
        .build()
        .expect("valid solver settings");
    let mut solver = DefaultSolver::new(&p, &q, a, b, cones, settings).map_err(|e| match e {
        clarabel::solver::SolverError::BadInputData(what) => SolverError::BadInput(what),
        _ => SolverError::Settings,
    })?;
    solver.solve();
    let sol = solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(Some(PrimalDual {
            x: DVector::from_vec(sol.x),
            s: DVector::from_vec(sol.s),
            z: DVector::from_vec(sol.z),
        })),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Ok(None),
        other => Err(SolverError::Status(other)),
    }
}

/// Solves the SOCP; `None` when it is infeasible.
fn solve(
    problem: &StaticProblem,
    model: &ContactModel,
) -> Result<Option<Equilibrium>, SolverError> {
    check_model(problem, model);
    let w = problem.weight;
    let x = problem.pads.closing_axis.normalize();
    // Tangent basis of the pads: u ⟂ x from the width axis, v = x × u.
    let u = (problem.pads.width_axis - problem.pads.width_axis.dot(&x) * x).normalize();
    let v = x.cross(&u);
    let torsion = model.pad_torsion_radius > 0.0;
    let friction_support = model.mu_support > 0.0;
    let per_pad = if torsion { 3 } else { 2 };
    let per_support = if friction_support { 3 } else { 1 };
    let pad_at = |k: usize| 1 + k * per_pad;
    let sup_at = |j: usize| 1 + 2 * per_pad + j * per_support;
    let nvar = 1 + 2 * per_pad + problem.support.len() * per_support;

    // Triplets of A (rows: 6 equalities, then the cones), and b.
    let (mut ri, mut ci, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    let mut push = |r: usize, c: usize, val: f64| {
        if val != 0.0 {
            ri.push(r);
            ci.push(c);
            vals.push(val);
        }
    };
    // A force `f` (column vector per unit variable) at point p: rows 0..3 force, 3..6 torque.
    let wrench_column =
        |push: &mut dyn FnMut(usize, usize, f64), col: usize, p: &Point3<f64>, f: &Vector3<f64>| {
            let tau = (p - problem.com).cross(f);
            for i in 0..3 {
                push(i, col, f[i]);
                push(3 + i, col, tau[i]);
            }
        };
    let pads = problem.pads.contacts();
    for (k, p) in pads.iter().enumerate() {
        wrench_column(&mut push, pad_at(k), p, &u);
        wrench_column(&mut push, pad_at(k) + 1, p, &v);
        if torsion {
            // A pure moment e·s about x.
            let m = model.pad_torsion_radius * x;
            for i in 0..3 {
                push(3 + i, pad_at(k) + 2, m[i]);
            }
        }
    }
    let z = Vector3::z();
    for (j, p) in problem.support.iter().enumerate() {
        wrench_column(&mut push, sup_at(j), p, &z);
        if friction_support {
            wrench_column(&mut push, sup_at(j) + 1, p, &Vector3::x());
            wrench_column(&mut push, sup_at(j) + 2, p, &Vector3::y());
        }
    }
    // Σ contact forces = W ẑ (unit: W), Σ torques about the centre of mass = 0.
    let mut b = vec![0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let mut cones = vec![SupportedConeT::ZeroConeT(6)];
    let mut row = 6;
    // Nonnegative: N, and every n_j. (A x + s = b, s ≥ 0: row −1 at the variable, b 0.)
    push(row, 0, -1.0);
    row += 1;
    for j in 0..problem.support.len() {
        push(row, sup_at(j), -1.0);
        row += 1;
    }
    b.extend(std::iter::repeat_n(0.0, 1 + problem.support.len()));
    cones.push(SupportedConeT::NonnegativeConeT(1 + problem.support.len()));
    // Pad cones: (μ_pad N, t1, t2[, s]).
    for k in 0..2 {
        push(row, 0, -model.mu_pad);
        for i in 0..per_pad {
            push(row + 1 + i, pad_at(k) + i, -1.0);
        }
        row += 1 + per_pad;
        b.extend(std::iter::repeat_n(0.0, 1 + per_pad));
        cones.push(SupportedConeT::SecondOrderConeT(1 + per_pad));
    }
    // Support cones: (μ_s n, a, b).
    if friction_support {
        for j in 0..problem.support.len() {
            push(row, sup_at(j), -model.mu_support);
            push(row + 1, sup_at(j) + 1, -1.0);
            push(row + 2, sup_at(j) + 2, -1.0);
            row += 3;
            b.extend([0.0; 3]);
            cones.push(SupportedConeT::SecondOrderConeT(3));
        }
    }
    let a = CscMatrix::new_from_triplets(row, nvar, ri, ci, vals);
    let Some(solution) = run_clarabel(&a, &b, &cones)? else {
        return Ok(None);
    };
    let xs = &solution.x;
    let pad_tangential = [0, 1].map(|k| w * (xs[pad_at(k)] * u + xs[pad_at(k) + 1] * v));
    let pad_torsion = [0, 1].map(|k| {
        if torsion {
            w * model.pad_torsion_radius * xs[pad_at(k) + 2]
        } else {
            0.0
        }
    });
    let support_normal = (0..problem.support.len())
        .map(|j| w * xs[sup_at(j)].max(0.0))
        .collect();
    let support_tangential = (0..problem.support.len())
        .map(|j| {
            if friction_support {
                w * Vector3::new(xs[sup_at(j) + 1], xs[sup_at(j) + 2], 0.0)
            } else {
                Vector3::zeros()
            }
        })
        .collect();
    Ok(Some(Equilibrium {
        grip_force: w * xs[0].max(0.0),
        pad_tangential,
        pad_torsion,
        support_normal,
        support_tangential,
    }))
}
