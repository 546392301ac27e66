//! Will the power grasps carry the part? The final state of a plan: the part at P_obj, off the
//! table, held by both arms' power grasps while the cell lifts it. [`min_carry_force`] finds
//! the smallest grip force, the same setting on both grippers, that holds the part against
//! gravity and the lift's acceleration without slipping in either hand: a second-order cone
//! program (Clarabel), like the pinch's ([`crate::statics`]).
//!
//! What each hand gives the part ([`PowerHold`]), from where the real closing put the fingers:
//!
//! - **The squeeze.** The two fingers press on the bar from both sides along the line between
//!   their contacts with a normal force `N_g` each, `N_g ≤ N` (the setting) and, for a closing
//!   whose finger tips met each other before the drivers were blocked (caged), `N_g ≤`
//!   [`CAGED_SQUEEZE`]: the actuator's force then goes into the tips, only the spring links
//!   press on the bar. Each contact is a soft finger: tangential force `t` and a moment `e·s`
//!   about the squeeze line with `‖(t, s)‖ ≤ μ·N_g`.
//! - **The enclosure**, where the fingers wrapped the bar: the bar cannot leave the closed hand,
//!   so the hand pushes on it with any force across the bar (grasp `x`, `z`). Where the drivers
//!   were blocked by the bar (encompassing) the wrap is tight and also resists a moment about
//!   those two axes, each at most `w·N_g`: the fingers bear on the bar across their width `w`
//!   along it ([`PowerHold::wrap_moment_arm`]) and press with the squeeze, so the pressure
//!   shifting to one edge of each finger holds no more; where the tips met around it first
//!   (caged) the bar has room to turn in the hand, and only the forces remain. Along the bar
//!   (`y`) and about it only the squeeze's friction holds it. The friction the enclosure's own
//!   push would add is left out, on purpose: the two hands could push on the part against each
//!   other without limit in the program (the arms hold positions; their internal force is not
//!   known), and that would make friction from nothing.
//!
//! A caged hand squeezes with its spring links only ([`CAGED_SQUEEZE`]); a one-sided closing
//! gives nothing. Held to the whole-plan replay (`crates/planner/tests/carry_truth.rs`): of the
//! variants "caged: no enclosure", "forces only" and "forces and moments", forces only departs
//! from the replay least (3 of 46 rows when chosen; 2 of 46 since the closing model of b6ce5a2).
//! An encompassing wrap held any moment until 2026-11-30, and panel_18, carried so, tilted in
//! the replay; with the bound `w·N_g` it is slid towards its centre of mass and lifts, and the
//! test's 327 rows keep one departure, on the cautious side (`docs/physics.md`).
//!
//! A pinch (the pads alone bear on the bar) has the squeeze only. Equations: the hands' forces
//! sum to `W·(g + a)/g · ẑ`, their moments about the centre of mass to zero. Forces are solved
//! in units of that load, so the program is well scaled. Objective: minimise `N`.

use clarabel::solver::SupportedConeT;
use nalgebra::{Isometry3, Point3, Vector3};

use crate::statics::{run_clarabel_unrefined, SolverError};

/// Squeeze (N) a caged closing puts on the bar whatever the setting: its finger tips bear on
/// each other, and only the spring links press on the bar. The whole-plan replay measured
/// 2.9–5.9 N per side in such closings at 20 and 235 N settings
/// (`crates/physics/data/replay_truth/plan_replay_2f85.csv`, chair plan 0, `mas1_close.N_*`);
/// the smaller side, rounded down.
pub const CAGED_SQUEEZE: f64 = 2.5;

/// Upward acceleration (m/s²) the cell lifts the part with: the carry check holds the part
/// under `g + LIFT_ACCELERATION`.
pub const LIFT_ACCELERATION: f64 = 1.0;

/// How one power grasp holds the part, in the world frame of the final state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerHold {
    /// The grasp frame: origin at the power point on the bar, `x` the closing axis, `y` along
    /// the bar, `z` the approach (towards the palm's far side).
    pub frame: Isometry3<f64>,
    /// Where the two fingers press on the bar (world), each pushing towards the other.
    pub squeeze: [Point3<f64>; 2],
    /// The squeeze contacts' torsion radius `e` (m); 0 for point contacts.
    pub torsion_radius: f64,
    /// Half the extent (m) of each squeeze contact's patch along the bar (`u`) and across it
    /// (`v`): a pad pressing with `N_g` over its patch tilts the bar by at most `N_g` times
    /// these about `v` and `u` (its pressure shifting to the patch's edge). 0: point contacts.
    pub patch_half_extent: [f64; 2],
    /// The moment (m, per newton of squeeze) an encompassing wrap resists about each of the
    /// grasp's `x` and `z` axes: the width of the fingers along the bar. 0: forces only.
    pub wrap_moment_arm: f64,
    /// How the closing ended.
    pub closing: HoldKind,
}

/// How a power grasp's closing ended, as it matters to carrying.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HoldKind {
    /// The pads alone bear on the bar: the squeeze, nothing else.
    Pinch,
    /// The fingers wrapped the bar and the drivers were blocked by it: squeeze and enclosure.
    Encompassing,
    /// The fingers wrapped the bar and their tips met: the enclosure's forces (no moments) and
    /// the spring links' squeeze ([`CAGED_SQUEEZE`]).
    Caged,
    /// One finger closed on nothing: no squeeze, no enclosure.
    OneSided,
}

/// One carry problem: the part under its load, held by both power grasps.
#[derive(Clone, Debug, PartialEq)]
pub struct CarryProblem {
    /// Centre of mass (world).
    pub com: Point3<f64>,
    /// Weight `m·g` (N), > 0.
    pub weight: f64,
    /// Upward acceleration of the lift (m/s², ≥ 0).
    pub lift_acceleration: f64,
    pub holds: [PowerHold; 2],
    /// Coulomb coefficient finger–part, > 0.
    pub mu: f64,
}

/// The forces at the optimum (N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Carry {
    /// The smallest setting `N` both grippers need.
    pub grip_force: f64,
}

/// What the carry needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CarryOutcome {
    /// Some setting holds the part; the forces at the smallest.
    Carried(Carry),
    /// No setting holds it: the hands' contacts cannot balance the load (for example both
    /// caged, with the part hanging off the line between them).
    CannotCarry,
}

/// Columns of one hand's variables.
struct Columns {
    /// `N_g`.
    squeeze: usize,
    /// `t1, t2, s` of each squeeze contact.
    pads: [usize; 2],
    /// `r_x, r_z, m_x, m_z`, when enclosed (`m_x`, `m_z` unused, caged).
    enclosure: Option<usize>,
}

const PER_PAD: usize = 5;
const PER_ENCLOSURE: usize = 4;

/// The smallest common grip force that carries the part (see the module documentation).
pub fn min_carry_force(problem: &CarryProblem) -> Result<CarryOutcome, SolverError> {
    assert!(problem.weight > 0.0, "weight must be > 0");
    assert!(problem.mu > 0.0, "mu must be > 0");
    let load = problem.weight * (1.0 + problem.lift_acceleration.max(0.0) / crate::GRAVITY);
    // Columns: N, then per hand N_g, its pads, its enclosure.
    let mut n = 1;
    let columns = problem.holds.map(|h| {
        let squeeze = n;
        let pads = [squeeze + 1, squeeze + 1 + PER_PAD];
        n = squeeze + 1 + 2 * PER_PAD;
        let enclosure = matches!(h.closing, HoldKind::Encompassing | HoldKind::Caged).then(|| {
            n += PER_ENCLOSURE;
            n - PER_ENCLOSURE
        });
        Columns {
            squeeze,
            pads,
            enclosure,
        }
    });
    let (mut ri, mut ci, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    let mut push = |r: usize, c: usize, v: f64| {
        if v != 0.0 {
            ri.push(r);
            ci.push(c);
            vals.push(v);
        }
    };
    let com = problem.com;
    // A unit force `f` at `p` (rows 0..3) and its moment about the centre of mass (3..6).
    let force =
        |push: &mut dyn FnMut(usize, usize, f64), c: usize, p: &Point3<f64>, f: Vector3<f64>| {
            let m = (p - com).cross(&f);
            for i in 0..3 {
                push(i, c, f[i]);
                push(3 + i, c, m[i]);
            }
        };
    let moment = |push: &mut dyn FnMut(usize, usize, f64), c: usize, m: Vector3<f64>| {
        for i in 0..3 {
            push(3 + i, c, m[i]);
        }
    };
    for (h, col) in problem.holds.iter().zip(&columns) {
        let [x, u, v] = squeeze_basis(h);
        for (k, p) in h.squeeze.iter().enumerate() {
            let c = col.pads[k];
            force(&mut push, c, p, u);
            force(&mut push, c + 1, p, v);
            moment(&mut push, c + 2, h.torsion_radius * x);
            // The pressure's moments about the patch's two tangent axes.
            moment(&mut push, c + 3, u);
            moment(&mut push, c + 4, v);
        }
        if let Some(c) = col.enclosure {
            let o = Point3::from(h.frame.translation.vector);
            let axis = |i: usize| h.frame.rotation * Vector3::ith(i, 1.0);
            force(&mut push, c, &o, axis(0));
            force(&mut push, c + 1, &o, axis(2));
            // A caged bar has room to turn in the closed hand: no moments.
            if h.closing == HoldKind::Encompassing {
                moment(&mut push, c + 2, axis(0));
                moment(&mut push, c + 3, axis(2));
            }
        }
    }
    let mut b = vec![0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let mut cones = vec![SupportedConeT::ZeroConeT(6)];
    let mut row = 6;
    // Nonnegative rows `A x + s = b`, `s ≥ 0`: N ≥ 0; per hand N − N_g ≥ 0, N_g ≥ 0 and, caged,
    // CAGED_SQUEEZE − N_g ≥ 0 (in units of the load).
    let mut nonneg = 0;
    let mut ge = |push: &mut dyn FnMut(usize, usize, f64),
                  b: &mut Vec<f64>,
                  terms: &[(usize, f64)],
                  rhs: f64| {
        for &(c, v) in terms {
            push(row, c, -v);
        }
        b.push(-rhs);
        row += 1;
        nonneg += 1;
    };
    ge(&mut push, &mut b, &[(0, 1.0)], 0.0);
    for (h, col) in problem.holds.iter().zip(&columns) {
        ge(&mut push, &mut b, &[(0, 1.0), (col.squeeze, -1.0)], 0.0);
        ge(&mut push, &mut b, &[(col.squeeze, 1.0)], 0.0);
        let most = match h.closing {
            HoldKind::Caged => Some(CAGED_SQUEEZE),
            HoldKind::OneSided => Some(0.0),
            HoldKind::Pinch | HoldKind::Encompassing => None,
        };
        if let Some(most) = most {
            ge(&mut push, &mut b, &[(col.squeeze, -1.0)], -most / load);
        }
        // |m_x|, |m_z| ≤ w N_g: the wrap's moments, at most the squeeze across the fingers.
        if let (Some(c), HoldKind::Encompassing) = (col.enclosure, h.closing) {
            let w = h.wrap_moment_arm.max(0.0);
            for m in [c + 2, c + 3] {
                ge(&mut push, &mut b, &[(col.squeeze, w), (m, -1.0)], 0.0);
                ge(&mut push, &mut b, &[(col.squeeze, w), (m, 1.0)], 0.0);
            }
        }
        // |m_u| ≤ a_v N_g (the pressure shifts across the bar), |m_v| ≤ a_u N_g (along it).
        for c in col.pads {
            for (m, a) in [
                (c + 3, h.patch_half_extent[1]),
                (c + 4, h.patch_half_extent[0]),
            ] {
                ge(&mut push, &mut b, &[(col.squeeze, a), (m, -1.0)], 0.0);
                ge(&mut push, &mut b, &[(col.squeeze, a), (m, 1.0)], 0.0);
            }
        }
    }
    cones.push(SupportedConeT::NonnegativeConeT(nonneg));
    let mut cone = |push: &mut dyn FnMut(usize, usize, f64),
                    b: &mut Vec<f64>,
                    head: (usize, f64),
                    tail: &[usize]| {
        push(row, head.0, -head.1);
        for (i, &c) in tail.iter().enumerate() {
            push(row + 1 + i, c, -1.0);
        }
        row += 1 + tail.len();
        b.extend(std::iter::repeat_n(0.0, 1 + tail.len()));
        cones.push(SupportedConeT::SecondOrderConeT(1 + tail.len()));
    };
    for col in &columns {
        for c in col.pads {
            // With `e = 0` the torsion's column is empty and `s` changes nothing.
            cone(
                &mut push,
                &mut b,
                (col.squeeze, problem.mu),
                &[c, c + 1, c + 2],
            );
        }
    }
    // No force of any size balances a load outside the span of the hands' wrenches: the
    // cone program would only find that out after its iterations.
    if !load_in_span(&ri, &ci, &vals, n) {
        return Ok(CarryOutcome::CannotCarry);
    }
    let a = clarabel::algebra::CscMatrix::new_from_triplets(row, n, ri, ci, vals);
    let Some(solution) = run_clarabel_unrefined(&a, &b, &cones)? else {
        return Ok(CarryOutcome::CannotCarry);
    };
    let x = &solution.x;
    Ok(CarryOutcome::Carried(Carry {
        grip_force: load * x[0].max(0.0),
    }))
}

/// Smallest eigenvalue of `A·Aᵀ`, relative to its largest, that still counts as a direction the
/// hands' wrenches span.
const SPAN_EIGEN: f64 = 1e-10;

/// Least distance of the load from that span, in units of the load, past which the load is
/// surely outside it; nearer, the cone program decides.
const SPAN_RESIDUAL: f64 = 1e-6;

/// Whether the load `(ẑ, 0)` (equality rows `0..6` of the program's matrix, given as
/// triplets, `n` columns) may lie in the span of the hands' wrenches, every column taken with
/// any sign and size.
///
/// Every variable's bound is a multiple of a hand's squeeze `N_g ≤ N` (or none), except a caged
/// hand's (at most [`CAGED_SQUEEZE`]) and a one-sided hand's (none): so the wrenches the hands
/// can give lie in that span, and a load outside it cannot be carried by any grip force. With
/// `A` the 6 × `n` equality block, the load's part outside the span is its projection on the
/// eigenvectors of the symmetric 6 × 6 `A·Aᵀ` whose eigenvalues vanish. Two pinches whose
/// closing axes are parallel give no force along that axis, for instance: a part tilted so its
/// weight has a part along it is not carried.
fn load_in_span(ri: &[usize], ci: &[usize], vals: &[f64], n: usize) -> bool {
    let mut a = nalgebra::DMatrix::<f64>::zeros(6, n);
    for ((&r, &c), &v) in ri.iter().zip(ci).zip(vals) {
        if r < 6 {
            a[(r, c)] = v;
        }
    }
    let gram = nalgebra::Matrix6::from_fn(|i, j| a.row(i).dot(&a.row(j)));
    let eigen = gram.symmetric_eigen();
    let largest = eigen.eigenvalues.amax();
    if largest <= 0.0 {
        return false;
    }
    let load = nalgebra::Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
    let outside: f64 = (0..6)
        .filter(|&i| eigen.eigenvalues[i] < SPAN_EIGEN * largest)
        .map(|i| eigen.eigenvectors.column(i).dot(&load).powi(2))
        .sum();
    outside.sqrt() <= SPAN_RESIDUAL
}

/// The squeeze line `x` (from the first contact to the second; the grasp's `x` if they meet)
/// and the contacts' tangent basis: `u` along the bar as far as it is ⟂ `x`, `v = x × u`.
fn squeeze_basis(h: &PowerHold) -> [Vector3<f64>; 3] {
    let x = (h.squeeze[1] - h.squeeze[0])
        .try_normalize(1e-9)
        .unwrap_or_else(|| h.frame.rotation * Vector3::x());
    let bar = h.frame.rotation * Vector3::y();
    let u = (bar - bar.dot(&x) * x).normalize();
    [x, u, x.cross(&u)]
}
