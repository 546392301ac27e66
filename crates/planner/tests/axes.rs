//! Algorithm 1 on parts with known answers: a flat box, a box on its long side, a triangular
//! prism, a frame of separate bars. θ_max is checked against its closed form.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_geometry::shapes::{cuboid, prism, union};
use pregrasp_geometry::Mesh;
use pregrasp_io::scene::PlannerParams;
use pregrasp_planner::axes::{rotation_axis_candidates, Direction, RotationAxisCandidate};

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

fn params() -> PlannerParams {
    PlannerParams::default()
}

/// The one candidate on the edge `a`–`b` (either order) whose signed axis points along
/// `toward`.
fn find(
    cands: &[RotationAxisCandidate],
    a: Point3<f64>,
    b: Point3<f64>,
    toward: Vector3<f64>,
) -> &RotationAxisCandidate {
    let close = |x: &Point3<f64>, y: &Point3<f64>| (x - y).norm() < 1e-9;
    let found: Vec<_> = cands
        .iter()
        .filter(|c| {
            (close(&c.axis[0], &a) && close(&c.axis[1], &b))
                || (close(&c.axis[0], &b) && close(&c.axis[1], &a))
        })
        .filter(|c| c.signed_axis().dot(&toward.normalize()) > 0.999)
        .collect();
    assert_eq!(
        found.len(),
        1,
        "no single candidate on {a} – {b} about {toward:?}"
    );
    found[0]
}

fn assert_close(x: f64, y: f64, tol: f64, what: &str) {
    assert!(
        (x - y).abs() <= tol,
        "{what}: {x} vs {y} (diff {:e})",
        (x - y).abs()
    );
}

#[test]
fn flat_box_has_exactly_its_four_bottom_edges() {
    let (lx, ly, lz) = (0.6, 0.4, 0.03);
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(lx, ly, lz));
    let pr = params();
    let lift = pr.lift;
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &pr);
    assert_eq!(r.candidates.len(), 8, "{:#?}", r.candidates);
    assert_eq!(r.p_init.translation.vector, Vector3::new(0.0, 0.0, lift));
    for c in &r.candidates {
        // Bottom edges only: both ends at the lift height, axis-parallel, full length.
        assert_close(c.axis[0].z, lift, 1e-15, "axis[0].z");
        assert_close(c.axis[1].z, lift, 1e-15, "axis[1].z");
        let d = c.axis[1] - c.axis[0];
        assert!(d.x.abs() < 1e-15 || d.y.abs() < 1e-15, "diagonal {d:?}");
        assert!(c.axis[0] < c.axis[1] || (c.axis[0].x, c.axis[0].y) < (c.axis[1].x, c.axis[1].y));
    }
    // For an edge along x, the far side is ly away; along y, lx away.
    let z = lift;
    let edges = [
        (p(0.0, 0.0, z), p(lx, 0.0, z), Vector3::x(), ly),
        (p(0.0, ly, z), p(lx, ly, z), -Vector3::x(), ly),
        (p(0.0, 0.0, z), p(0.0, ly, z), -Vector3::y(), lx),
        (p(lx, 0.0, z), p(lx, ly, z), Vector3::y(), lx),
    ];
    for (a, b, lifting, far) in edges {
        // Rotating about `lifting` raises the body: capped at φ_obj.
        let up = find(&r.candidates, a, b, lifting);
        assert_eq!(up.theta_max, pr.max_angle);
        assert_close(up.theta_max_stepped, pr.max_angle, 1e-12, "stepped up");
        // The other way the far bottom edge sinks: lift − far · sin θ = 0.
        let down = find(&r.candidates, a, b, -lifting);
        assert_close(down.theta_max, (lift / far).asin(), 1e-6, "down θ_max");
        assert_close(
            down.theta_max,
            (lift / far).asin(),
            1e-14,
            "down θ_max (tight)",
        );
        assert_eq!(down.theta_max_stepped, 0.0);
        assert_close(up.length, (b - a).norm(), 1e-15, "length");
        assert_close(up.score, up.length + up.theta_max, 1e-15, "score");
    }
    // Sorted best first; ids are ranks.
    for (k, w) in r.candidates.windows(2).enumerate() {
        assert!(w[0].score >= w[1].score);
        assert_eq!(w[0].id, k);
    }
    // The best are the two long edges rotating up.
    assert_close(r.candidates[0].length, lx, 1e-15, "best length");
    assert_eq!(r.candidates[0].theta_max, pr.max_angle);
}

#[test]
fn box_on_its_long_narrow_side_tips_over_or_sinks() {
    // 0.6 long, 0.03 deep, 0.4 tall: standing on a 0.6 × 0.03 face.
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.03, 0.4));
    let pr = params();
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &pr);
    assert_eq!(r.candidates.len(), 4);
    let z = pr.lift;
    // Tipping over the y = 0 edge (rotation about +x raises the y > 0 side): the top edge
    // reaches the table at 90°.
    let over = find(&r.candidates, p(0.0, 0.0, z), p(0.6, 0.0, z), Vector3::x());
    assert_eq!(over.theta_max, FRAC_PI_2);
    let sink = find(&r.candidates, p(0.0, 0.0, z), p(0.6, 0.0, z), -Vector3::x());
    assert_close(sink.theta_max, (z / 0.03).asin(), 1e-14, "sink");
    // With a generous φ_obj the tip-over goes on until the top edge sinks by the lift.
    let wide = PlannerParams {
        max_angle: 2.5,
        ..params()
    };
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &wide);
    let over = find(&r.candidates, p(0.0, 0.0, z), p(0.6, 0.0, z), Vector3::x());
    assert_close(
        over.theta_max,
        FRAC_PI_2 + (z / 0.4).asin(),
        1e-14,
        "tip-over past 90°",
    );
}

#[test]
fn triangular_prism_angles_follow_its_cross_section() {
    // Cross-section (x, z): (0,0), (0.3,0), (0.1,0.2); extruded 0.7 along −y.
    let pose = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_euler_angles(FRAC_PI_2, 0.0, 0.0),
    );
    let mesh = prism(&[[0.0, 0.0], [0.3, 0.0], [0.1, 0.2]], 0.0, 0.7).transformed(&pose);
    let pr = PlannerParams {
        max_angle: 150f64.to_radians(),
        ..params()
    };
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &pr);
    assert_eq!(r.candidates.len(), 8);
    let z = pr.lift;
    let (a0, a1) = (p(0.0, -0.7, z), p(0.0, 0.0, z));
    let (b0, b1) = (p(0.3, -0.7, z), p(0.3, 0.0, z));
    let apex_a = 0.1f64.hypot(0.2);
    let apex_b = 0.2f64.hypot(0.2);
    // Over the x = 0 edge towards −x (about −y): the side face lands after π − atan2(0.2, 0.1).
    let c = find(&r.candidates, a0, a1, -Vector3::y());
    assert_close(
        c.theta_max,
        PI - 0.2f64.atan2(0.1) + (z / apex_a).asin(),
        1e-12,
        "over x=0",
    );
    let c = find(&r.candidates, a0, a1, Vector3::y());
    assert_close(c.theta_max, (z / 0.3).asin(), 1e-14, "into x=0");
    let c = find(&r.candidates, b0, b1, Vector3::y());
    assert_close(
        c.theta_max,
        PI - 0.2f64.atan2(0.2) + (z / apex_b).asin(),
        1e-12,
        "over x=0.3",
    );
    let c = find(&r.candidates, b0, b1, -Vector3::y());
    assert_close(c.theta_max, (z / 0.3).asin(), 1e-14, "into x=0.3");
    // Over the triangular ends: the end face turns flat at 90°, then the apex (0.2 up) sinks.
    let c = find(&r.candidates, p(0.0, 0.0, z), p(0.3, 0.0, z), -Vector3::x());
    assert_close(
        c.theta_max,
        FRAC_PI_2 + (z / 0.2).asin(),
        1e-12,
        "over end y=0",
    );
    let c = find(&r.candidates, p(0.0, 0.0, z), p(0.3, 0.0, z), Vector3::x());
    assert_close(c.theta_max, (z / 0.7).asin(), 1e-14, "into end y=0");
    // Stepped values are whole degrees not above the exact ones.
    for c in &r.candidates {
        let steps = c.theta_max_stepped / pr.step;
        assert_close(steps, steps.round(), 1e-9, "stepped multiple");
        assert!(c.theta_max_stepped <= c.theta_max && c.theta_max - c.theta_max_stepped < pr.step);
    }
}

/// A rectangular frame of four separate bars plus a middle cross bar, not touching.
fn frame() -> Mesh {
    let (w, h, t, b) = (0.8, 0.6, 0.03, 0.04);
    union(&[
        cuboid(p(0.0, 0.0, 0.0), p(w, b, t)),
        cuboid(p(0.0, h - b, 0.0), p(w, h, t)),
        cuboid(p(0.0, b + 0.001, 0.0), p(b, h - b - 0.001, t)),
        cuboid(p(w - b, b + 0.001, 0.0), p(w, h - b - 0.001, t)),
        cuboid(p(0.3, b + 0.001, 0.0), p(0.3 + b, h - b - 0.001, t)),
    ])
}

#[test]
fn frame_of_separate_bars_rotates_about_its_outline() {
    let mesh = frame();
    let pr = params();
    let r = rotation_axis_candidates(
        &mesh,
        &Isometry3::from_parts(
            Translation3::new(0.2, -0.1, 0.75),
            UnitQuaternion::identity(),
        ),
        0.75,
        &pr,
    );
    assert_eq!(r.hull.faces.len(), 6);
    assert_eq!(r.candidates.len(), 8);
    let z = 0.75 + pr.lift;
    let c = find(
        &r.candidates,
        p(0.2, -0.1, z),
        p(1.0, -0.1, z),
        Vector3::x(),
    );
    assert_eq!(c.theta_max, pr.max_angle);
    let c = find(
        &r.candidates,
        p(0.2, -0.1, z),
        p(1.0, -0.1, z),
        -Vector3::x(),
    );
    assert_close(c.theta_max, (pr.lift / 0.6).asin(), 1e-14, "frame sink");
    let c = find(&r.candidates, p(0.2, -0.1, z), p(0.2, 0.5, z), Vector3::y());
    assert_close(c.theta_max, (pr.lift / 0.8).asin(), 1e-14, "frame sink y");
}

#[test]
fn thresholds_select_edges() {
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.04, 0.2));
    // Δl between the 0.04 and 0.6 sides: only the two long bottom edges.
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &params());
    assert_eq!(r.candidates.len(), 4);
    let r = rotation_axis_candidates(
        &mesh,
        &Isometry3::identity(),
        0.0,
        &PlannerParams {
            min_axis_length: 0.01,
            ..params()
        },
    );
    assert_eq!(r.candidates.len(), 8);
    // Raised above Δd_s: nothing rests on the support.
    let raised = Isometry3::translation(0.0, 0.0, 0.02);
    let r = rotation_axis_candidates(&mesh, &raised, 0.0, &params());
    assert!(r.candidates.is_empty());
    // A tilted box touches the support with one edge only.
    let tilt = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_euler_angles(0.3, 0.0, 0.0),
    );
    let r = rotation_axis_candidates(&mesh, &tilt, 0.0, &params());
    assert_eq!(r.candidates.len(), 2);
}

#[test]
fn rotated_pose_turns_about_the_signed_axis() {
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.4, 0.03));
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &params());
    for c in &r.candidates {
        // Axis endpoints stay put; the lowest hull vertex touches the support at θ_max
        // (unless capped) and nothing is below it at any angle up to θ_max.
        let at = c.rotated_pose(&r.p_init, c.theta_max);
        for e in &c.axis {
            let obj = r.p_init.inverse() * e;
            assert!((at * obj - e).norm() < 1e-12);
        }
        let lowest = |pose: &Isometry3<f64>| {
            r.hull
                .vertices
                .iter()
                .map(|v| (pose * v).z)
                .fold(f64::INFINITY, f64::min)
        };
        if c.theta_max < params().max_angle {
            assert_close(lowest(&at), 0.0, 1e-12, "touch at θ_max");
        }
        for k in 0..=20 {
            let pose = c.rotated_pose(&r.p_init, c.theta_max * k as f64 / 20.0);
            assert!(lowest(&pose) >= -1e-12);
        }
        let ccw = Isometry3::rotation_wrt_point(
            UnitQuaternion::from_axis_angle(&c.signed_axis(), 0.1),
            c.axis[0],
        );
        assert!(
            (c.rotated_pose(&r.p_init, 0.1).to_homogeneous() - (ccw * r.p_init).to_homogeneous())
                .norm()
                < 1e-12
        );
        match c.direction {
            Direction::Ccw => assert!(
                (c.signed_axis().into_inner() - (c.axis[1] - c.axis[0]).normalize()).norm() < 1e-15
            ),
            Direction::Cw => assert!(
                (c.signed_axis().into_inner() + (c.axis[1] - c.axis[0]).normalize()).norm() < 1e-15
            ),
        }
    }
}

#[test]
fn json_entries_follow_the_plan_format() {
    let mesh = cuboid(p(0.0, 0.0, 0.0), p(0.6, 0.4, 0.03));
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &params());
    let j = r.candidates[3].to_json();
    assert_eq!(j.id, 3);
    assert_eq!(j.direction, r.candidates[3].direction);
    assert_eq!(j.theta_goal, None);
    assert_eq!(j.outcome.to_string(), "not evaluated (axes only)");
    assert_eq!(
        j.axis[1],
        [
            r.candidates[3].axis[1].x,
            r.candidates[3].axis[1].y,
            r.candidates[3].axis[1].z
        ]
    );
    assert_eq!(j.theta_max, r.candidates[3].theta_max);
}

#[test]
fn degenerate_mesh_gives_no_candidates_and_a_warning() {
    let mesh = Mesh::new(
        vec![p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(2.0, 0.0, 0.0)],
        vec![[0, 1, 2]],
    );
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, &params());
    assert!(r.candidates.is_empty());
    assert_eq!(r.warnings.len(), 1);
}
