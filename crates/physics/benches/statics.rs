//! One state of the grip check by each of its three ways (`pregrasp_physics::statics`): the
//! closed form, Newton's method from the previous state's optimum, and Clarabel alone — on a
//! 0.6 m bar turned about its bottom edge and pinched near its far end.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_physics::{
    min_grip_force, min_grip_force_conic, min_grip_force_from, ContactModel, Pads, StaticOutcome,
    StaticProblem, WarmStart,
};

/// The bar turned by `deg`, pinched across its thickness (`thickness: true`; the support's
/// friction binds) or across its width (the closed form holds).
fn bar(deg: f64, thickness: bool) -> StaticProblem {
    let pose = Isometry3::rotation(Vector3::y() * -deg.to_radians());
    let (closing, width_axis, width) = if thickness {
        (Vector3::z(), Vector3::y(), 0.02)
    } else {
        (Vector3::y(), Vector3::x(), 0.04)
    };
    StaticProblem {
        com: pose * Point3::new(0.3, 0.02, 0.01),
        weight: 20.0,
        pads: Pads {
            centre: pose * Point3::new(0.55, 0.02, 0.01),
            closing_axis: pose * closing,
            width_axis: pose * width_axis,
            width,
        },
        support: vec![Point3::origin(), Point3::new(0.0, 0.04, 0.0)],
    }
}

const MODEL: ContactModel = ContactModel {
    mu_pad: 0.8,
    mu_support: 0.3,
    pad_torsion_radius: 0.0,
};

fn bench_statics(c: &mut Criterion) {
    let mut group = c.benchmark_group("grip_state");
    // Across its width on a grippier support (μ 0.4), the support carries what the
    // moment-optimal pad forces leave it: the closed form.
    let open = bar(30.0, false);
    let grippy = ContactModel {
        mu_support: 0.4,
        ..MODEL
    };
    group.bench_function("closed_form", |b| {
        b.iter(|| min_grip_force(black_box(&open), &grippy).expect("solves"))
    });
    // Newton from the optimum one degree before (the support binds at both).
    let (before, state) = (bar(40.0, true), bar(41.0, true));
    let mut warm = WarmStart::default();
    let first = min_grip_force_from(&before, &MODEL, &mut warm).expect("solves");
    assert!(matches!(first, StaticOutcome::Held(_)));
    group.bench_function("newton_from_last_state", |b| {
        b.iter(|| {
            let mut w = warm.clone();
            min_grip_force_from(black_box(&state), &MODEL, &mut w).expect("solves")
        })
    });
    group.bench_function("clarabel_reduced", |b| {
        b.iter(|| min_grip_force(black_box(&state), &MODEL).expect("solves"))
    });
    group.bench_function("clarabel_general", |b| {
        b.iter(|| min_grip_force_conic(black_box(&state), &MODEL).expect("solves"))
    });
    group.finish();
}

criterion_group!(benches, bench_statics);
criterion_main!(benches);
