//! The edge's reduced program and its closed form ([`pregrasp_physics::min_grip_force`]) against
//! the general conic program ([`pregrasp_physics::min_grip_force_conic`]), on random parts
//! resting on two support contacts, and along a rotation where each state starts from the last.

mod common;

use common::{turned, G};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use pregrasp_physics::{
    min_grip_force, min_grip_force_conic, min_grip_force_from, ContactModel, Equilibrium, Pads,
    StaticOutcome, StaticProblem, WarmStart, PAD_PATCH_TORSION_RADIUS,
};
use proptest::prelude::*;

/// A part resting on the axis `A → B` (yawed by `yaw`, `B` lifted by `lift` ≤ 1 mm), its centre
/// of mass `reach` from the axis at `height`, pinched at a random pose.
#[allow(clippy::too_many_arguments)]
fn problem(
    yaw: f64,
    length: f64,
    lift: f64,
    along: f64,
    reach: f64,
    height: f64,
    pad_at: [f64; 3],
    closing: [f64; 3],
    width: f64,
) -> StaticProblem {
    let r = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw);
    let a = Point3::new(0.3, -0.2, 0.0);
    let b = a + r * Vector3::new(length, 0.0, lift);
    let com = a + r * Vector3::new(along * length, reach, height);
    let x = Vector3::from(closing).normalize();
    let helper = if x.z.abs() < 0.9 {
        Vector3::z()
    } else {
        Vector3::x()
    };
    StaticProblem {
        com,
        weight: 3.0 * G,
        pads: Pads {
            centre: a + r * Vector3::from(pad_at),
            closing_axis: x,
            width_axis: x.cross(&helper),
            width,
        },
        support: vec![a, b],
    }
}

/// The balance residual (force and torque about the centre of mass) and the largest violation
/// of a cone, both relative to the largest force (the weight or the grip).
fn residuals(p: &StaticProblem, model: &ContactModel, eq: &Equilibrium) -> (f64, f64) {
    let x = p.pads.closing_axis.normalize();
    let pads = p.pads.contacts();
    let mut force = Vector3::new(0.0, 0.0, -p.weight);
    let mut torque = Vector3::zeros();
    let normals = [eq.grip_force * x, -eq.grip_force * x];
    let mut cone: f64 = 0.0;
    for k in 0..2 {
        let f = eq.pad_tangential[k] + normals[k];
        force += f;
        torque += (pads[k] - p.com).cross(&f) + eq.pad_torsion[k] * x;
        let s = if model.pad_torsion_radius > 0.0 {
            eq.pad_torsion[k] / model.pad_torsion_radius
        } else {
            0.0
        };
        let need = (eq.pad_tangential[k].norm_squared() + s * s).sqrt();
        cone = cone.max(need - model.mu_pad * eq.grip_force);
        cone = cone.max(eq.pad_tangential[k].dot(&x).abs());
    }
    for (j, a) in p.support.iter().enumerate() {
        let f = Vector3::z() * eq.support_normal[j] + eq.support_tangential[j];
        force += f;
        torque += (a - p.com).cross(&f);
        cone = cone.max(-eq.support_normal[j]);
        cone = cone.max(eq.support_tangential[j].norm() - model.mu_support * eq.support_normal[j]);
    }
    // Both relative to the largest force in play: the pads' normal forces enter the sums as
    // ±grip_force, so rounding leaves about ε·grip_force there (a 0.3 mm pad gap needs 44 kN
    // against a 29 N part: 6e-7 N left, 2e-8 of the weight, 1e-11 of the grip).
    let scale = p.weight.max(eq.grip_force);
    ((force.norm() + torque.norm()) / scale, cone / scale)
}

fn kind(o: &StaticOutcome) -> &'static str {
    match o {
        StaticOutcome::Held(_) => "held",
        StaticOutcome::Slides => "slides",
        StaticOutcome::CannotHold => "cannot hold",
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Same verdict, same minimum grip force, and an equilibrium that balances and respects
    /// every cone.
    #[test]
    fn the_edge_program_agrees_with_the_general_one(
        yaw in -3.1..3.1f64,
        length in 0.05..0.8f64,
        lift in 0.0..0.001f64,
        along in -0.2..1.2f64,
        reach in -0.6..0.6f64,
        height in 0.0..0.3f64,
        pad_at in [-0.2..1.0f64, -0.6..0.6f64, 0.0..0.4f64],
        closing in [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64],
        width in 0.0..0.08f64,
        mu_pad in 0.3..1.2f64,
        mu_support in 0.05..1.0f64,
        torsion in prop::bool::ANY,
    ) {
        prop_assume!(Vector3::from(closing).norm() > 0.2);
        let p = problem(yaw, length, lift, along, reach, height, pad_at, closing, width);
        let model = ContactModel {
            mu_pad,
            mu_support,
            pad_torsion_radius: if torsion { PAD_PATCH_TORSION_RADIUS } else { 0.0 },
        };
        let fast = min_grip_force(&p, &model).unwrap();
        let general = min_grip_force_conic(&p, &model).unwrap();
        prop_assert_eq!(kind(&fast), kind(&general));
        if let (StaticOutcome::Held(f), StaticOutcome::Held(g)) = (&fast, &general) {
            // The interior-point program is accurate to about 1e-7 of the force it finds
            // (seen: 1.5e-7 at 49 kN, a 30 µm pad gap); the edge program is exact.
            let tol = 1e-6 * (f.grip_force.max(g.grip_force) + p.weight);
            prop_assert!((f.grip_force - g.grip_force).abs() <= tol,
                "grip {} vs {}", f.grip_force, g.grip_force);
            let (balance, cone) = residuals(&p, &model, f);
            prop_assert!(balance < 1e-8, "balance residual {balance:e}");
            prop_assert!(cone < 1e-8, "cone violation {cone:e}");
        }
    }
}

/// A 0.6 m bar pinched across its thickness near its far end and turned 0–85°: the pads lever
/// the part off its edge and the support's friction binds, so the general program's answer
/// is what each state started from the last must reproduce.
#[test]
fn a_rotation_started_state_from_state_matches_each_state_solved_alone() {
    let model = ContactModel {
        mu_pad: 0.8,
        mu_support: 0.3,
        pad_torsion_radius: 0.0,
    };
    let mut warm = WarmStart::default();
    let mut held = 0;
    for step in 0..=85 {
        let pose = turned(f64::from(step).to_radians());
        let p = StaticProblem {
            com: pose * Point3::new(0.3, 0.02, 0.01),
            weight: 2.0 * G,
            pads: Pads {
                centre: pose * Point3::new(0.55, 0.02, 0.01),
                closing_axis: pose * Vector3::z(),
                width_axis: pose * Vector3::y(),
                width: 0.02,
            },
            support: vec![Point3::origin(), Point3::new(0.0, 0.04, 0.0)],
        };
        let chained = min_grip_force_from(&p, &model, &mut warm).unwrap();
        let alone = min_grip_force_conic(&p, &model).unwrap();
        assert_eq!(kind(&chained), kind(&alone), "{step}°");
        if let (StaticOutcome::Held(c), StaticOutcome::Held(a)) = (&chained, &alone) {
            held += 1;
            assert!(
                (c.grip_force - a.grip_force).abs() <= 1e-8 * a.grip_force.max(1.0),
                "{step}°: {} vs {}",
                c.grip_force,
                a.grip_force
            );
            let (balance, cone) = residuals(&p, &model, c);
            assert!(
                balance < 1e-9 && cone < 1e-9,
                "{step}°: {balance:e} {cone:e}"
            );
        }
    }
    assert!(held > 60, "only {held} states held");
}
