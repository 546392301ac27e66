//! Every hard family over 20 seeds: closed meshes of the drawn stock, the axis the longest
//! hull edge, grasps a 2F-85 can take, each power grasp next to material the open hand fits
//! beside.

use nalgebra::{Point2, Vector2};

use super::*;
use crate::design::GraspSite;
use crate::mesh_check::{check_closed_oriented, signed_volume};

const SEEDS: u64 = 20;

/// Inside the ring (even-odd crossings of a ray towards `+x`).
fn in_ring(ring: &[Point2<f64>], q: Point2<f64>) -> bool {
    let mut inside = false;
    for (i, a) in ring.iter().enumerate() {
        let b = ring[(i + 1) % ring.len()];
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// In the part's face: inside the outline, outside every hole.
fn in_part(design: &PartDesign, q: Point2<f64>) -> bool {
    in_ring(&design.outline, q) && !design.holes.iter().any(|h| in_ring(h, q))
}

/// Length of the longest edge of the outline's convex hull, and whether it is the axis.
fn longest_hull_edge_is_axis(design: &PartDesign) -> bool {
    let mut pts: Vec<Point2<f64>> = design.outline.clone();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: Point2<f64>, a: Point2<f64>, b: Point2<f64>| (a - o).perp(&(b - o));
    let mut hull: Vec<Point2<f64>> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2<f64>>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    let edges: Vec<(f64, [Point2<f64>; 2])> = (0..hull.len())
        .map(|i| {
            let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
            ((b - a).norm(), [a, b])
        })
        .collect();
    let best = edges.iter().map(|e| e.0).fold(0.0, f64::max);
    let axis_len = (design.axis[1] - design.axis[0]).norm();
    let second = edges
        .iter()
        .map(|e| e.0)
        .filter(|&len| len < best - 1e-9)
        .fold(0.0, f64::max);
    let ties = edges.iter().filter(|e| e.0 > best - 1e-9).count();
    (axis_len - best).abs() < 1e-9 && ties == 1 && second < best - 0.01
}

/// Points of the open hand's footprint beside the grasped bar (the part plane, grasp frame:
/// `u` across the bar, `v` along it): `|u|` from the bar's edge + 1 mm to `reach`, `|v|` up
/// to `half`.
fn beside(site: &GraspSite, reach: f64, half: f64) -> Vec<Point2<f64>> {
    let u = Vector2::new(site.closing_angle.cos(), site.closing_angle.sin());
    let v = Vector2::new(-u.y, u.x);
    let mut out = Vec::new();
    let (nu, nv) = (40, 16);
    let u0 = site.bar_width / 2.0 + 0.001;
    for i in 0..=nu {
        let du = u0 + (reach - u0) * i as f64 / nu as f64;
        for j in 0..=nv {
            let dv = -half + 2.0 * half * j as f64 / nv as f64;
            for s in [-1.0, 1.0] {
                out.push(site.point + s * du * u + dv * v);
            }
        }
    }
    out
}

#[test]
fn every_hard_family_makes_closed_deterministic_plausible_parts() {
    for part in hard_sweep(1, SEEDS as usize) {
        let label = part.label();
        let d = &part.design;
        let mesh = d.mesh();
        check_closed_oriented(&mesh).unwrap_or_else(|e| panic!("{label}: {e}"));
        let volume = signed_volume(&mesh);
        assert!(
            (volume - d.face_area() * d.thickness).abs() < 1e-9,
            "{label}"
        );
        assert!((STOCK.0..=STOCK.1).contains(&part.thickness), "{label}");
        let [l, depth] = part.size;
        assert!(
            (0.40..=1.0).contains(&l) && (0.30..=0.60).contains(&depth),
            "{label}"
        );
        assert!(
            longest_hull_edge_is_axis(d),
            "{label}: axis not the longest hull edge"
        );
        assert_eq!(generate_hard(part.family, part.seed), part, "deterministic");
    }
}

#[test]
fn hard_grasps_are_takeable_and_next_to_material() {
    for part in hard_sweep(1, SEEDS as usize) {
        let label = part.label();
        let d = &part.design;
        let near = d.distance_to_axis(&d.power_near.point);
        let far = d.distance_to_axis(&d.power_far.point);
        assert!(near < far, "{label}: near {near} far {far}");
        for site in [&d.support, &d.power_near, &d.power_far] {
            assert!(in_part(d, site.point), "{label}: {} off the part", site.bar);
            assert!(
                (0.010..0.062).contains(&site.bar_width),
                "{label}: {} is {} wide",
                site.bar,
                site.bar_width
            );
        }
        for site in [&d.power_near, &d.power_far] {
            // The open fingers' footprint is free of material; a little farther along the bar
            // or across it, there is material: the hard feature (the thin rungs' left grasp
            // has only its thin rung).
            if part.family == Family::ThinRungs && std::ptr::eq(site, &d.power_near) {
                continue;
            }
            let free = beside(site, FINGER_REACH, FINGER_HALF_WIDTH);
            assert!(
                free.iter().all(|&q| !in_part(d, q)),
                "{label}: the open hand at the {} lies in the part",
                site.bar
            );
            let wider = beside(site, FINGER_REACH + 0.015, NEXT_TO.1 + 0.010);
            assert!(
                wider.iter().any(|&q| in_part(d, q)),
                "{label}: nothing next to the {}",
                site.bar
            );
        }
    }
}
