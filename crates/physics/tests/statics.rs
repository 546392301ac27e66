//! The quasi-static problem against closed forms: a uniform bar on the table turned about its
//! bottom edge and pinched at its far end.
//!
//! Bar `[0, L] × [0, W] × [0, H]`, mass `m`, turned by `θ` about its bottom edge (world `y`
//! through the origin). Support contacts: the edge's endpoints `(0, 0, 0)` and `(0, W, 0)`.
//! Centre of mass at horizontal distance `X_c = (L/2) cos θ − (H/2) sin θ` from the axis.

mod common;

use common::{turned, G};
use nalgebra::{Point3, Vector3};
use pregrasp_physics::{
    min_grip_force, ContactModel, Equilibrium, Pads, StaticOutcome, StaticProblem,
    PAD_PATCH_TORSION_RADIUS,
};

const L: f64 = 0.6;
const W: f64 = 0.04;
const H: f64 = 0.02;
const M: f64 = 2.0;
/// The grasp's distance from the far end.
const DELTA: f64 = 0.02;

fn model(mu_pad: f64, mu_support: f64, e: f64) -> ContactModel {
    ContactModel {
        mu_pad,
        mu_support,
        pad_torsion_radius: e,
    }
}

/// Pinched across its width `W` at `(L − δ, W/2, H/2)`: the closing axis is the object's `y`
/// (the axis direction), the pads are on the side faces `y = 0` and `y = W`.
fn across_width(theta: f64) -> StaticProblem {
    let pose = turned(theta);
    StaticProblem {
        com: pose * Point3::new(L / 2.0, W / 2.0, H / 2.0),
        weight: M * G,
        pads: Pads {
            centre: pose * Point3::new(L - DELTA, W / 2.0, H / 2.0),
            closing_axis: pose * Vector3::y(),
            width_axis: pose * Vector3::x(),
            width: W,
        },
        support: vec![Point3::origin(), Point3::new(0.0, W, 0.0)],
    }
}

/// Pinched across its thickness `H` at `(L − δ, W/2, H/2)`: the closing axis is the object's
/// `z`, which tilts with the bar; the pads are on the top and bottom faces, `width` apart.
fn across_thickness(theta: f64, width: f64) -> StaticProblem {
    let pose = turned(theta);
    StaticProblem {
        pads: Pads {
            centre: pose * Point3::new(L - DELTA, W / 2.0, H / 2.0),
            closing_axis: pose * Vector3::z(),
            width_axis: pose * Vector3::x(),
            width,
        },
        ..across_width(theta)
    }
}

fn held(problem: &StaticProblem, model: &ContactModel) -> Equilibrium {
    match min_grip_force(problem, model).expect("solver converges") {
        StaticOutcome::Held(eq) => eq,
        other => panic!("expected equilibrium, got {other:?}"),
    }
}

fn assert_rel(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        ((got - want) / want).abs() <= tol,
        "{what}: got {got}, want {want} (rel. error {:.2e})",
        ((got - want) / want).abs()
    );
}

/// (a) Closed form, pinched across the width. Moments about the axis line (`y`): gravity
/// gives `m g X_c`; the support contacts lie on the axis and give none; the pad normals are
/// along `y` and give none. What is left is each pad's tangential force `(f_x, f_z)` in the
/// world `x`–`z` plane at `(X_p, Z_p)`, whose moment is `Z_p f_x − X_p f_z`, and (soft finger)
/// its torsion `e·s` about `y`, with `‖(f_x, f_z, s)‖ ≤ μ N`. By symmetry both pads carry half:
/// `Z_p f_x − X_p f_z + e s = −m g X_c / 2`. The smallest `‖(f_x, f_z, s)‖` meeting it is
/// `(m g X_c / 2) / √(X_p² + Z_p² + e²)`, so
///
/// `N_min = m g X_c / (2 μ_pad √(R_p² + e²))`, `R_p = √((L − δ)² + (H/2)²)`
///
/// — the pad's full distance from the axis is the lever, not its horizontal distance: the
/// optimal pad force is tangent to the pad's circle about the axis, and the support takes the
/// horizontal part `2 f_x` by friction. That holds while `2|f_x| ≤ μ_s (m g − 2 f_z)`, which
/// the test asserts too.
#[test]
fn pinched_bar_needs_the_closed_form_grip_force() {
    let (mu_p, mu_s) = (0.8, 0.4);
    let r_p = ((L - DELTA).powi(2) + (H / 2.0).powi(2)).sqrt();
    for e in [0.0, PAD_PATCH_TORSION_RADIUS] {
        for deg in [0.0_f64, 5.0, 20.0, 45.0, 70.0] {
            let theta = deg.to_radians();
            let x_c = L / 2.0 * theta.cos() - H / 2.0 * theta.sin();
            let k = M * G * x_c / (2.0 * (r_p * r_p + e * e));
            let (x_p, z_p) = (
                (L - DELTA) * theta.cos() - H / 2.0 * theta.sin(),
                (L - DELTA) * theta.sin() + H / 2.0 * theta.cos(),
            );
            let (f_x, f_z) = (-k * z_p, k * x_p);
            assert!(
                2.0 * f_x.abs() <= mu_s * (M * G - 2.0 * f_z),
                "support sticks"
            );
            let want = M * G * x_c / (2.0 * mu_p * (r_p * r_p + e * e).sqrt());
            let eq = held(&across_width(theta), &model(mu_p, mu_s, e));
            assert_rel(eq.grip_force, want, 1e-6, &format!("θ {deg}°, e {e}"));
            // The support carries the rest of the weight and the horizontal force.
            assert_rel(
                eq.support_normal_total(),
                M * G - 2.0 * f_z,
                1e-5,
                "support normal",
            );
        }
    }
}

/// (a') With a frictionless support the pads must not push sideways at all (`f_x = 0`), so
/// only the vertical part counts and the lever is the pads' *horizontal* distance `X_p`:
/// `N_min = m g X_c / (2 μ X_p)` (point pads).
#[test]
fn frictionless_support_leaves_the_horizontal_lever() {
    for deg in [10.0_f64, 30.0, 60.0] {
        let theta = deg.to_radians();
        let x_c = L / 2.0 * theta.cos() - H / 2.0 * theta.sin();
        let x_p = (L - DELTA) * theta.cos() - H / 2.0 * theta.sin();
        let eq = held(&across_width(theta), &model(0.8, 0.0, 0.0));
        assert_rel(
            eq.grip_force,
            M * G * x_c / (2.0 * 0.8 * x_p),
            1e-6,
            "N_min",
        );
        assert!(eq.support_tangential_total() == 0.0);
    }
}

/// (b) Turned until the centre of mass is straight above the axis (`X_c = 0`): the support
/// carries the whole weight and the pads need (almost) no force.
#[test]
fn centre_of_mass_over_the_axis_needs_no_grip() {
    let theta = (L / H).atan(); // tan θ = (L/2)/(H/2)
    for e in [0.0, PAD_PATCH_TORSION_RADIUS] {
        let eq = held(&across_width(theta), &model(0.8, 0.4, e));
        assert!(
            eq.grip_force < 1e-6 * M * G,
            "N_min {} N over the axis",
            eq.grip_force
        );
        assert_rel(eq.support_normal_total(), M * G, 1e-6, "support normal");
        assert!(eq.support_tangential_total() < 1e-6 * M * G);
    }
    // Nearby, on either side, some force is needed again.
    for d in [-0.05, 0.05] {
        let eq = held(&across_width(theta + d), &model(0.8, 0.4, 0.0));
        assert!(eq.grip_force > 1e-3 * M * G);
    }
}

/// (c) Pinched across its thickness at one point (a sheet: pad gap 0), the closing axis tilts
/// with the bar, so every force the pads can exert is in the tilted face plane and has a
/// horizontal part: the support must push sideways. Frictionless, it cannot — the part slides
/// (no grip force is enough).
#[test]
fn frictionless_support_with_a_tilted_reaction_slides() {
    let theta = 20f64.to_radians();
    let problem = across_thickness(theta, 0.0);
    assert_eq!(
        min_grip_force(&problem, &model(0.8, 0.0, 0.0)).unwrap(),
        StaticOutcome::Slides
    );
    assert_eq!(
        min_grip_force(&problem, &model(0.8, 0.0, PAD_PATCH_TORSION_RADIUS)).unwrap(),
        StaticOutcome::Slides
    );
    // The lever of a face-plane force about the axis is only H/2: the horizontal force the
    // support must take is ~50 m g, more than μ_s = 0.4 gives too; a very sticky support holds.
    assert_eq!(
        min_grip_force(&problem, &model(0.8, 0.4, 0.0)).unwrap(),
        StaticOutcome::Slides
    );
    let eq = held(&problem, &model(0.8, 1e3, 0.0));
    assert!(eq.support_tangential_total() > 10.0 * M * G);
}

/// (c') Across the thickness with the real pad gap `w`, frictionless: the pads' forces must
/// cancel (any net force would be tilted), so they can only form a couple `w·|f|` about the
/// axis direction, `|f| ≤ μ N`: `N_min = m g X_c / (μ w)` — hundreds of newtons.
#[test]
fn frictionless_support_leaves_only_the_pad_couple() {
    let theta = 20f64.to_radians();
    let x_c = L / 2.0 * theta.cos() - H / 2.0 * theta.sin();
    let eq = held(&across_thickness(theta, H), &model(0.8, 0.0, 0.0));
    let want = M * G * x_c / (0.8 * H);
    assert_rel(eq.grip_force, want, 1e-6, "N_min");
    assert!(eq.grip_force > 235.0);
}

/// No support contact: the pads alone hold the part. Across the width (closing axis
/// horizontal) they can, but at a price: vertical force `m g` and the moment about the pads.
#[test]
fn without_support_the_pads_carry_everything() {
    let theta = 20f64.to_radians();
    let mut p = across_width(theta);
    p.support.clear();
    let with = held(&across_width(theta), &model(0.8, 0.4, 0.0)).grip_force;
    match min_grip_force(&p, &model(0.8, 0.4, 0.0)).unwrap() {
        StaticOutcome::Held(eq) => assert!(eq.grip_force > 2.0 * with),
        StaticOutcome::CannotHold => {}
        StaticOutcome::Slides => panic!("no support: cannot slide on it"),
    }
    // Across the (tilted) thickness, with no support the weight has a component along the
    // closing axis that no pad friction can take.
    let mut q = across_thickness(theta, H);
    q.support.clear();
    assert_eq!(
        min_grip_force(&q, &model(0.8, 0.4, 0.0)).unwrap(),
        StaticOutcome::CannotHold
    );
}

/// Equilibrium of the returned forces, checked independently of the solver's equations.
#[test]
fn returned_forces_balance_gravity() {
    let theta = 35f64.to_radians();
    let p = across_width(theta);
    let eq = held(&p, &model(0.8, 0.4, PAD_PATCH_TORSION_RADIUS));
    let x = p.pads.closing_axis.normalize();
    let pads = p.pads.contacts();
    let mut force = Vector3::new(0.0, 0.0, -M * G);
    let mut torque = Vector3::zeros();
    let normals = [eq.grip_force * x, -eq.grip_force * x];
    for k in 0..2 {
        let f = eq.pad_tangential[k] + normals[k];
        force += f;
        torque += (pads[k] - p.com).cross(&f) + eq.pad_torsion[k] * x;
        assert!(eq.pad_tangential[k].dot(&x).abs() < 1e-9);
        let s = eq.pad_torsion[k] / PAD_PATCH_TORSION_RADIUS;
        assert!(
            (eq.pad_tangential[k].norm_squared() + s * s).sqrt()
                <= 0.8 * eq.grip_force * (1.0 + 1e-6)
        );
    }
    for (j, a) in p.support.iter().enumerate() {
        let f = Vector3::z() * eq.support_normal[j] + eq.support_tangential[j];
        force += f;
        torque += (a - p.com).cross(&f);
        assert!(eq.support_normal[j] >= 0.0);
        assert!(
            eq.support_tangential[j].norm() <= 0.4 * eq.support_normal[j] * (1.0 + 1e-6) + 1e-9
        );
    }
    assert!(force.norm() < 1e-6 * M * G, "force residual {force}");
    assert!(torque.norm() < 1e-6 * M * G, "torque residual {torque}");
}
