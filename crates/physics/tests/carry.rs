//! The carry check ([`min_carry_force`]) on cases solved by hand: two hands on horizontal bars
//! side by side, the centre of mass between them or off their line, pinched, enclosed or
//! caged, the bars horizontal or upright.

use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use pregrasp_physics::carry::{CAGED_SQUEEZE, LIFT_ACCELERATION};
use pregrasp_physics::{min_carry_force, CarryOutcome, CarryProblem, HoldKind, PowerHold, GRAVITY};

const MU: f64 = 0.8;
const E: f64 = 0.005;
/// The fingers' width along the bar: a wrap's moments per newton of squeeze.
const W: f64 = 0.022;
const WEIGHT: f64 = 30.0;

/// The load the hands carry: the weight under the lift's acceleration.
fn load(weight: f64) -> f64 {
    weight * (GRAVITY + LIFT_ACCELERATION) / GRAVITY
}

/// A hand at `at` closing along world `x`, its bar along `bar` (world `y` or `z`), squeezing a
/// 20 mm bar.
fn hold(at: [f64; 3], bar: Vector3<f64>, closing: HoldKind) -> PowerHold {
    let x = Vector3::x();
    let z = x.cross(&bar);
    let r = Rotation3::from_basis_unchecked(&[x, bar, z]);
    let o = Point3::from(at);
    PowerHold {
        frame: Isometry3::from_parts(
            Translation3::from(o.coords),
            UnitQuaternion::from_rotation_matrix(&r),
        ),
        squeeze: [o - 0.01 * x, o + 0.01 * x],
        torsion_radius: E,
        patch_half_extent: [0.0; 2],
        wrap_moment_arm: W,
        closing,
    }
}

fn problem(com: [f64; 3], bar: Vector3<f64>, closing: HoldKind, weight: f64) -> CarryProblem {
    CarryProblem {
        com: Point3::from(com),
        weight,
        lift_acceleration: LIFT_ACCELERATION,
        holds: [
            hold([-0.2, 0.0, 0.0], bar, closing),
            hold([0.2, 0.0, 0.0], bar, closing),
        ],
        mu: MU,
    }
}

fn force(p: &CarryProblem) -> f64 {
    match min_carry_force(p).unwrap() {
        CarryOutcome::Carried(c) => c.grip_force,
        CarryOutcome::CannotCarry => f64::INFINITY,
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-5 * b.abs().max(1.0)
}

#[test]
fn two_pinches_share_the_load_in_four_friction_cones() {
    // Each of four pads carries a quarter of the load by friction: N μ = load / 4.
    let n = force(&problem([0.0; 3], Vector3::y(), HoldKind::Pinch, WEIGHT));
    assert!(close(n, load(WEIGHT) / (4.0 * MU)), "{n}");
}

#[test]
fn a_centre_of_mass_off_the_line_needs_the_pads_torsion() {
    // Off the line through both hands by d: the moment load·d about that line (the squeeze
    // axis) only the pads' torsion resists, in the same cone as their share of the load.
    for d in [0.01, 0.05, 0.1] {
        let n = force(&problem(
            [0.0, d, 0.0],
            Vector3::y(),
            HoldKind::Pinch,
            WEIGHT,
        ));
        let want = load(WEIGHT) / (4.0 * MU) * (1.0 + (d / E).powi(2)).sqrt();
        assert!(close(n, want), "d {d}: {n} vs {want}");
    }
}

#[test]
fn an_enclosed_horizontal_bar_hangs_in_the_hand() {
    // Across the bar the closed hand carries any force: with the centre of mass on the line
    // through both hands, no squeeze is needed.
    for com in [[0.0; 3], [0.1, 0.0, 0.0], [0.1, 0.0, -0.05]] {
        let n = force(&problem(com, Vector3::y(), HoldKind::Encompassing, WEIGHT));
        assert!(n < 1e-6, "{com:?}: {n}");
    }
    // Off that line by d, the moment load·d about it (the grasps' x) rests on the wraps, w N
    // each, and on the four pads' torsion, μ e N each.
    for d in [0.01, 0.05, 0.1] {
        let n = force(&problem(
            [0.0, d, 0.0],
            Vector3::y(),
            HoldKind::Encompassing,
            WEIGHT,
        ));
        let want = load(WEIGHT) * d / (2.0 * W + 4.0 * MU * E);
        assert!(close(n, want), "d {d}: {n} vs {want}");
    }
}

#[test]
fn a_caged_bar_hangs_but_may_turn() {
    // Caged, the hand holds the bar from leaving it (the load across it: no squeeze needed)...
    let n = force(&problem([0.0; 3], Vector3::y(), HoldKind::Caged, WEIGHT));
    assert!(n < 1e-6, "{n}");
    // ...but not from turning: off the line through both hands, the moment about it rests on
    // the pads' torsion, and the spring links squeeze with CAGED_SQUEEZE only.
    let d = 0.05;
    let most = 4.0 * MU * CAGED_SQUEEZE / (1.0 + (d / E).powi(2)).sqrt();
    let light = most / load(1.0) * 0.99;
    let heavy = most / load(1.0) * 1.01;
    let off = |w| force(&problem([0.0, d, 0.0], Vector3::y(), HoldKind::Caged, w));
    assert!(off(light).is_finite() && off(heavy).is_infinite());
    // Wrapped tightly (encompassing), the wraps' moments hold the heavy one too.
    let wrapped = force(&problem(
        [0.0, d, 0.0],
        Vector3::y(),
        HoldKind::Encompassing,
        heavy,
    ));
    assert!(wrapped.is_finite(), "{wrapped}");
    // One-sided: nothing holds.
    assert!(force(&problem([0.0; 3], Vector3::y(), HoldKind::OneSided, 0.1)).is_infinite());
}

#[test]
fn along_an_upright_bar_only_the_squeeze_holds() {
    // The bars upright: the load runs along them, and the enclosure adds no friction.
    let n = force(&problem(
        [0.0; 3],
        Vector3::z(),
        HoldKind::Encompassing,
        WEIGHT,
    ));
    assert!(close(n, load(WEIGHT) / (4.0 * MU)), "{n}");
    // Caged, the spring links' squeeze carries at most 4 μ CAGED_SQUEEZE.
    let most = 4.0 * MU * CAGED_SQUEEZE;
    let light = most / load(1.0) * 0.99;
    let heavy = most / load(1.0) * 1.01;
    assert!(force(&problem([0.0; 3], Vector3::z(), HoldKind::Caged, light)).is_finite());
    assert!(force(&problem([0.0; 3], Vector3::z(), HoldKind::Caged, heavy)).is_infinite());
}

#[test]
fn the_force_scales_with_the_weight() {
    let one = force(&problem(
        [0.0, 0.03, 0.0],
        Vector3::y(),
        HoldKind::Pinch,
        10.0,
    ));
    let three = force(&problem(
        [0.0, 0.03, 0.0],
        Vector3::y(),
        HoldKind::Pinch,
        30.0,
    ));
    assert!(close(three, 3.0 * one), "{one} {three}");
}

/// `p` with both hands and the centre of mass turned by `angle` (rad) about `axis` through the
/// origin: the part tilted in the hands' frame, the weight still along world −z.
fn turned(p: &CarryProblem, axis: Vector3<f64>, angle: f64) -> CarryProblem {
    let r = Isometry3::rotation(axis.normalize() * angle);
    CarryProblem {
        com: r * p.com,
        holds: p.holds.map(|h| PowerHold {
            frame: r * h.frame,
            squeeze: h.squeeze.map(|s| r * s),
            ..h
        }),
        ..*p
    }
}

#[test]
fn parallel_pinches_hold_no_weight_along_their_closing_axis() {
    // Both hands pinch along world x. Their pads press with one squeeze each, equal and
    // opposite, so no hand pushes along x: tilt the part about the bars (y) and the weight's
    // part along x, load·sin α, has nothing to rest on, whatever the grip force.
    let level = problem([0.0; 3], Vector3::y(), HoldKind::Pinch, WEIGHT);
    assert!(close(force(&level), load(WEIGHT) / (4.0 * MU)));
    for deg in [0.5_f64, 5.0, 30.0] {
        let tilted = turned(&level, Vector3::y(), deg.to_radians());
        assert_eq!(
            min_carry_force(&tilted).unwrap(),
            CarryOutcome::CannotCarry,
            "{deg}°"
        );
        // The same tilt about the line through the hands (x) keeps the weight across the
        // closing axis: the pads carry it as before.
        let about_x = turned(&level, Vector3::x(), deg.to_radians());
        assert!(close(force(&about_x), force(&level)), "{deg}°");
    }
    // A hand closing across the other's axis pushes along it: tilted, the pair carries.
    let mut crossed = level;
    let quarter = Isometry3::rotation(Vector3::z() * std::f64::consts::FRAC_PI_2);
    let at = Isometry3::translation(0.2, 0.0, 0.0);
    crossed.holds[1] = PowerHold {
        frame: at * quarter * at.inverse() * crossed.holds[1].frame,
        squeeze: crossed.holds[1]
            .squeeze
            .map(|s| at * quarter * at.inverse() * s),
        ..crossed.holds[1]
    };
    let tilted = turned(&crossed, Vector3::y(), 5.0_f64.to_radians());
    assert!(force(&tilted).is_finite());
}
