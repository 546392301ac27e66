use super::pair::segment_meets_box;
use super::*;
use nalgebra::UnitQuaternion;
use parry3d_f64::query;
use parry3d_f64::shape::Capsule as PCapsule;

/// Numbers uniform in `[−1, 1)`, the same for the same `seed` (a 64-bit LCG).
fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

fn cap(a: [f64; 3], b: [f64; 3], r: f64) -> Placed {
    Placed::Capsule {
        a: P::from(a),
        b: P::from(b),
        radius: r,
    }
}

#[test]
fn capsule_plane_is_lowest_point() {
    let c = cap([0., 0., 0.5], [0., 0., 0.2], 0.05);
    assert!((plane_distance(&c, 0.1) - 0.05).abs() < 1e-15);
}

#[test]
fn rotated_cuboid_plane_uses_support_extent() {
    // A unit cube rotated 45° about x: its lowest edge is √2/2·... below the centre.
    let pose = Isometry3::from_parts(
        nalgebra::Translation3::new(0., 0., 1.),
        UnitQuaternion::from_euler_angles(std::f64::consts::FRAC_PI_4, 0., 0.),
    );
    let c = Placed::Cuboid {
        pose,
        half: V::new(0.5, 0.5, 0.5),
    };
    let expect = 1.0 - 0.5 * std::f64::consts::SQRT_2;
    assert!((plane_distance(&c, 0.0) - expect).abs() < 1e-12);
}

#[test]
fn capsule_pair_distance_and_margin() {
    let c1 = cap([0., 0., 0.], [1., 0., 0.], 0.1);
    let c2 = cap([0.5, 0.5, -1.], [0.5, 0.5, 1.], 0.1);
    assert!((pair_distance(&c1, &c2) - 0.3).abs() < 1e-12);
    assert!(!pair_intersects(&c1, &c2, 0.0));
    assert!(!pair_intersects(&c1, &c2, 0.29));
    assert!(pair_intersects(&c1, &c2, 0.31));
}

#[test]
fn capsule_cuboid_agrees_with_distance() {
    let pose = Isometry3::from_parts(
        nalgebra::Translation3::new(0.3, -0.2, 0.1),
        UnitQuaternion::from_euler_angles(0.3, -0.5, 1.1),
    );
    let cub = Placed::Cuboid {
        pose,
        half: V::new(0.2, 0.1, 0.05),
    };
    for (i, z) in [0.0, 0.1, 0.2, 0.3, 0.4, 0.6].iter().enumerate() {
        let c = cap([-0.5, -0.2, *z], [0.8, 0.1, *z + 0.05], 0.03);
        let d = pair_distance(&c, &cub);
        assert_eq!(
            pair_intersects(&c, &cub, 0.0),
            d <= 1e-9,
            "case {i}: d = {d}"
        );
        assert_eq!(
            pair_intersects(&c, &cub, 0.02),
            d < 0.02 + 1e-9,
            "case {i}: d = {d}"
        );
    }
}

#[test]
fn capsule_cuboid_agrees_with_gjk_distance_on_random_pairs() {
    // Segments through faces, past edges and corners, parallel to faces, points.
    let mut next = uniform(11);
    let (mut hits, mut misses) = (0, 0);
    for case in 0..20_000 {
        let pose = Isometry3::from_parts(
            nalgebra::Translation3::new(next() * 0.1, next() * 0.1, next() * 0.1),
            UnitQuaternion::from_euler_angles(next() * 3.0, next() * 1.5, next() * 3.0),
        );
        let half = V::new(0.02 + 0.2 * next().abs(), 0.02 + 0.1 * next().abs(), 0.01);
        let a = P::new(next() * 0.3, next() * 0.3, next() * 0.3);
        let b = match case % 4 {
            0 => a,
            1 => a + V::new(next() * 0.5, 0.0, 0.0),
            _ => P::new(next() * 0.3, next() * 0.3, next() * 0.3),
        };
        let r = 0.005 + 0.08 * next().abs();
        let cub = Placed::Cuboid { pose, half };
        let capsule = Placed::Capsule { a, b, radius: r };
        // The truth: the segment's distance from the box (parry's GJK) against the radius.
        let segment = PCapsule::new(a, b, 0.0);
        let id = Isometry3::identity();
        let d = query::distance(&id, &segment, &pose, &PCuboid::new(half)).unwrap() - r;
        if d.abs() < 1e-9 {
            continue;
        }
        let got = pair_intersects(&capsule, &cub, 0.0);
        assert_eq!(got, d <= 0.0, "case {case}: distance {d}");
        if got {
            hits += 1;
        } else {
            misses += 1;
        }
    }
    assert!(hits > 3000 && misses > 3000, "{hits} hits, {misses} misses");
}

#[test]
fn the_loose_filter_passes_every_pair_that_meets() {
    let mut next = uniform(5);
    let (mut meet, mut filtered) = (0, 0);
    for case in 0..6000 {
        let mut shape = |kind: usize| {
            let a = P::new(next() * 0.1, next() * 0.1, next() * 0.1);
            let b = a + V::new(next(), next(), next()) * 0.15;
            let r = 0.01 + 0.05 * next().abs();
            match kind {
                0 => Placed::Capsule { a, b, radius: r },
                1 => Placed::Cylinder {
                    a,
                    b,
                    radius: r,
                    border: 0.01 * next().abs(),
                },
                _ => Placed::Cuboid {
                    pose: Isometry3::from_parts(
                        nalgebra::Translation3::from(a.coords),
                        UnitQuaternion::from_euler_angles(next() * 3.0, next(), next() * 3.0),
                    ),
                    half: V::new(r, 2.0 * r, 0.5 * r),
                },
            }
        };
        let (s1, s2) = (shape(case % 3), shape(case / 3 % 3));
        let margin = 0.02 * next().abs();
        let exact = pair_intersects(&s1, &s2, margin);
        let may = pair_may_intersect(&s1, &s2, margin);
        assert!(may || !exact, "case {case}: {s1:?} {s2:?} at {margin}");
        meet += usize::from(exact);
        filtered += usize::from(!may);
    }
    assert!(
        meet > 1000 && filtered > 1000,
        "{meet} meet, {filtered} filtered out"
    );
}

#[test]
fn boxes_meet_within_a_margin_exactly_when_their_distance_says() {
    let mut next = uniform(3);
    let (mut corners, mut cases) = (0, 0);
    for case in 0..5000 {
        let mut cuboid = |spread: f64| Placed::Cuboid {
            pose: Isometry3::from_parts(
                nalgebra::Translation3::new(next() * spread, next() * spread, next() * spread),
                UnitQuaternion::from_euler_angles(next() * 3.0, next() * 1.5, next() * 3.0),
            ),
            half: V::new(0.02 + 0.05 * next().abs(), 0.01 + 0.03 * next().abs(), 0.02),
        };
        let (b1, b2) = (cuboid(0.12), cuboid(0.0));
        let margin = 0.03 * next().abs();
        let d = pair_distance(&b1, &b2);
        if (d - margin).abs() < 1e-9 {
            continue;
        }
        cases += 1;
        assert_eq!(
            pair_intersects(&b1, &b2, margin),
            d <= margin,
            "case {case}: {d}"
        );
        // Past a face's slab of the grown box, where growing it along its axes would hit.
        let grown = match b1 {
            Placed::Cuboid { pose, half } => Placed::Cuboid {
                pose,
                half: half + V::repeat(margin),
            },
            _ => unreachable!(),
        };
        corners += usize::from(d > margin && pair_distance(&grown, &b2) <= 0.0);
    }
    assert!(
        cases > 4000 && corners > 20,
        "{cases} cases, {corners} at corners"
    );
}

#[test]
fn segments_meet_boxes_as_clipping_says() {
    let half = V::new(1.0, 0.5, 0.25);
    let meets = |p: [f64; 3], q: [f64; 3]| segment_meets_box(&P::from(p), &P::from(q), &half);
    assert!(meets([0.0; 3], [0.0; 3]), "a point inside");
    assert!(meets([-2.0, 0.0, 0.0], [2.0, 0.0, 0.0]), "through");
    assert!(
        meets([1.0, 0.5, 0.25], [3.0, 3.0, 3.0]),
        "touching a corner"
    );
    assert!(!meets([1.1, 0.0, 0.0], [3.0, 0.0, 0.0]), "beyond a face");
    assert!(
        !meets([0.0, 0.6, -1.0], [0.0, 0.6, 1.0]),
        "parallel, outside"
    );
    assert!(
        !meets([2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
        "past the corner region"
    );
    assert!(meets([1.4, 0.0, 0.0], [0.0, 1.4, 0.0]), "across the corner");
}

fn cyl(a: [f64; 3], b: [f64; 3], r: f64) -> Placed {
    Placed::Cylinder {
        a: P::from(a),
        b: P::from(b),
        radius: r,
        border: 0.0,
    }
}

#[test]
fn cylinder_plane_distance_is_the_lowest_rim_point() {
    // Upright: the end face. Lying: the side. Tilted 45°: rim r·√½ below the low face centre.
    assert!((plane_distance(&cyl([0., 0., 0.1], [0., 0., 0.3], 0.05), 0.0) - 0.1).abs() < 1e-15);
    assert!((plane_distance(&cyl([0., 0., 0.1], [0.2, 0., 0.1], 0.05), 0.0) - 0.05).abs() < 1e-15);
    let h = 0.1 / 2f64.sqrt();
    let tilted = cyl([0., 0., 0.2], [h, 0., 0.2 + h], 0.05);
    assert!((plane_distance(&tilted, 0.0) - (0.2 - 0.05 * 0.5f64.sqrt())).abs() < 1e-12);
}

#[test]
fn flat_ends_do_not_reach_as_far_as_round_caps() {
    // A point 1 cm beyond the flat end, on the axis: clear of the cylinder, inside the
    // capsule of the same segment and radius.
    let c = cyl([0., 0., 0.], [0., 0., 0.1], 0.06);
    let probe = cap([0., 0., 0.11], [0., 0., 0.11], 0.0);
    assert!(!pair_intersects(&c, &probe, 0.0));
    assert!((pair_distance(&c, &probe) - 0.01).abs() < 1e-9);
    assert!(pair_intersects(&c, &probe, 0.0101));
    let capsule = cap([0., 0., 0.], [0., 0., 0.1], 0.06);
    assert!(pair_intersects(&capsule, &probe, 0.0));
}

/// The yes/no segment–cylinder search answers as the full search does at every distance
/// asked, the segments placed through, near and far from the cylinders.
#[test]
fn segment_cylinder_within_answers_as_the_distance() {
    let mut u = uniform(17);
    let mut pt = |s: f64| P::new(s * u(), s * u(), s * u());
    let (mut near, mut far) = (0, 0);
    for i in 0..3000 {
        let (a, b) = (pt(0.1), pt(0.1));
        let (p, q) = (pt(0.3), pt(0.3));
        let r = 0.01 + 0.03 * (i % 7) as f64 / 7.0;
        let d = segment_cylinder_distance(&p, &q, &a, &b, r);
        for dist in [0.0, 0.005, 0.02, 0.1] {
            let within = segment_cylinder_within(&p, &q, &a, &b, r, dist);
            assert_eq!(within, d <= dist, "case {i}, dist {dist}: d = {d}");
            if within {
                near += 1;
            } else {
                far += 1;
            }
        }
    }
    assert!(near > 1000 && far > 1000, "{near} near, {far} far");
}

#[test]
fn cylinder_pairs_agree_with_parry() {
    // Random cylinder–capsule, cylinder–cylinder and cylinder–box pairs: the exact
    // segment–cylinder distance and the cascades agree with parry's GJK distance.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let pt = |rng: &mut rand_chacha::ChaCha8Rng| {
        P::new(
            rng.random_range(-0.2..0.2),
            rng.random_range(-0.2..0.2),
            rng.random_range(-0.2..0.2),
        )
    };
    // The reference: parry's GJK on its own shapes, rounded cylinders as `RoundCylinder`.
    let parry = |s: &Placed| -> (Isometry3<f64>, Box<dyn parry3d_f64::shape::Shape>) {
        match *s {
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } => {
                let (pose, c) = parry_cylinder(&a, &b, radius);
                let round = parry3d_f64::shape::RoundCylinder {
                    inner_shape: c,
                    border_radius: border,
                };
                (pose, Box::new(round))
            }
            Placed::Capsule { a, b, radius } => {
                (Isometry3::identity(), Box::new(PCapsule::new(a, b, radius)))
            }
            Placed::Cuboid { pose, half } => (pose, Box::new(PCuboid::new(half))),
        }
    };
    for i in 0..600 {
        let c = Placed::Cylinder {
            a: pt(&mut rng),
            b: pt(&mut rng),
            radius: rng.random_range(0.01..0.08),
            border: if i % 2 == 0 {
                0.0
            } else {
                rng.random_range(0.0..0.02)
            },
        };
        let other = match i % 3 {
            0 => Placed::Capsule {
                a: pt(&mut rng),
                b: pt(&mut rng),
                radius: rng.random_range(0.0..0.05),
            },
            1 => Placed::Cylinder {
                a: pt(&mut rng),
                b: pt(&mut rng),
                radius: rng.random_range(0.01..0.05),
                border: if i % 4 == 1 {
                    0.0
                } else {
                    rng.random_range(0.0..0.01)
                },
            },
            _ => Placed::Cuboid {
                pose: Isometry3::from_parts(
                    pt(&mut rng).coords.into(),
                    UnitQuaternion::from_euler_angles(0.3 * i as f64, 0.2, -0.1),
                ),
                half: V::new(0.03, 0.05, 0.02),
            },
        };
        let ((p1, g1), (p2, g2)) = (parry(&c), parry(&other));
        let reference = query::distance(&p1, &*g1, &p2, &*g2).unwrap().max(0.0);
        let d = pair_distance(&c, &other).max(0.0);
        assert!((d - reference).abs() < 1e-5, "case {i}: {d} vs {reference}");
        for margin in [0.0, 0.01] {
            if (reference - margin).abs() > 1e-5 {
                assert_eq!(
                    pair_intersects(&c, &other, margin),
                    reference <= margin,
                    "case {i}, margin {margin}: d = {reference}"
                );
            }
        }
    }
}

#[test]
fn aabb_of_rotated_cuboid_contains_corners() {
    let pose = Isometry3::from_parts(
        nalgebra::Translation3::new(1., 2., 3.),
        UnitQuaternion::from_euler_angles(0.4, 0.2, -0.7),
    );
    let half = V::new(0.3, 0.2, 0.1);
    let (lo, hi) = Bounded::new(Placed::Cuboid { pose, half }).aabb();
    for s in 0..8 {
        let l = P::new(
            if s & 1 == 0 { -half.x } else { half.x },
            if s & 2 == 0 { -half.y } else { half.y },
            if s & 4 == 0 { -half.z } else { half.z },
        );
        let w = pose * l;
        for i in 0..3 {
            assert!(w[i] >= lo[i] - 1e-12 && w[i] <= hi[i] + 1e-12);
        }
    }
}
