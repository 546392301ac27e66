//! Graspable bars of a part lying on the support: where a parallel gripper can close across
//! the material from above.
//!
//! Frame: the object frame. `up` is the world `+z` seen from the object (the part rests on the
//! support with its lowest vertices); heights are measured from the lowest vertex along `up`.
//! The part's cross-section is probed in the mid-height plane on a grid: at a point inside the
//! material, rays along a direction `d` in the plane (12 directions, 15° apart) find the
//! interval of material through the point — the bar's width across `d`. A **site** is the
//! interval's centre with the narrowest `d` that qualifies:
//!
//! - width within the gripper's reach: [`MIN_BAR_WIDTH`] … [`MAX_BAR_WIDTH`] (the 2F-85 opens
//!   85 mm; 5 mm are left to close);
//! - straight for a pad: the width at ±[`HALF_PAD`] along the bar differs by at most
//!   [`STRAIGHT_TOLERANCE`] and the intervals stay centred;
//! - room for the open fingers: beyond both faces there is no material as far as the open
//!   fingers reach, [`finger_room`] (a hand hole next to the bar counts only if it is that
//!   wide): the gripper approaches open.
//!
//! Inside test: a point of the mid-plane is in the material when rays up and down both leave
//! the part within half its height (an extruded part has no material above a hole).

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use parry3d_f64::query::{Ray, RayCast};
use parry3d_f64::shape::TriMesh;
use pregrasp_geometry::Mesh;
use rayon::prelude::*;

/// Narrowest bar a site may have (m).
pub const MIN_BAR_WIDTH: f64 = 0.010;
/// Widest bar (m): the 2F-85's 85 mm stroke less 5 mm to close.
pub const MAX_BAR_WIDTH: f64 = 0.080;
/// Half the width of the fingers' links (m; the pads are 22 mm wide, the links a little more):
/// the bar must be straight, and the air beside it free, this far to each side of a site.
pub const HALF_PAD: f64 = 0.016;
/// Largest change of width (m) along a pad for a straight bar.
pub const STRAIGHT_TOLERANCE: f64 = 0.003;
/// The 2F-85's stroke (m): the gap between the open pads.
pub const STROKE: f64 = 0.085;
/// Thickness (m) of a finger beyond its pad, with a little clearance.
pub const FINGER_THICKNESS: f64 = 0.012;

/// Free space (m) needed beyond each face of a bar of `width` for the open fingers to come
/// down beside it: from the face to the open pad, plus the finger.
pub fn finger_room(width: f64) -> f64 {
    (STROKE - width) / 2.0 + FINGER_THICKNESS
}
/// Sites closer than this (m) with the same closing direction are one site.
pub const SITE_MERGE: f64 = 0.008;

/// A place to close a gripper across a bar, in the object frame.
#[derive(Clone, Debug, PartialEq)]
pub struct BarSite {
    /// Centre of the bar's cross-section interval, at mid-height (m).
    pub centre: Point3<f64>,
    /// Closing direction (unit, perpendicular to `up`), across the bar.
    pub across: Unit<Vector3<f64>>,
    /// Width of the bar along `across` (m).
    pub width: f64,
}

/// The part's vertical extent seen from `up`: heights of its lowest and highest vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    pub up: Unit<Vector3<f64>>,
    pub bottom: f64,
    pub top: f64,
}

impl Slab {
    pub fn of(mesh: &Mesh, up: Unit<Vector3<f64>>) -> Slab {
        let h = mesh.vertices.iter().map(|v| v.coords.dot(&up));
        let (bottom, top) = h.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
        Slab { up, bottom, top }
    }

    /// The part's height along `up` (m).
    pub fn height(&self) -> f64 {
        self.top - self.bottom
    }
}

/// The bar sites of `mesh` resting on the support with world `+z` = `object_pose⁻¹ · ẑ`.
/// Deterministic: a fixed grid, fixed directions, sites in grid order.
pub fn bar_sites(mesh: &Mesh, object_pose: &Isometry3<f64>) -> (Slab, Vec<BarSite>) {
    let up = Unit::new_normalize(object_pose.rotation.inverse() * Vector3::z());
    let slab = Slab::of(mesh, up);
    let Ok(tri) = TriMesh::new(mesh.vertices.clone(), mesh.triangles.clone()) else {
        return (slab, Vec::new());
    };
    // An in-plane basis (e1, e2) ⟂ up.
    let helper = if up.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = up.cross(&helper).normalize();
    let e2 = up.cross(&e1);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for v in &mesh.vertices {
        for (k, e) in [e1, e2].iter().enumerate() {
            let x = v.coords.dot(e);
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    // 10 mm, coarser on large parts (at most ~150 points a side).
    let spacing = (extent / 150.0).max(0.010);
    let mid = (slab.bottom + slab.top) / 2.0;
    let half = slab.height() / 2.0;
    let directions: Vec<Unit<Vector3<f64>>> = (0..12)
        .map(|k| {
            let a = (k as f64 * 15.0).to_radians();
            Unit::new_normalize(e1 * a.cos() + e2 * a.sin())
        })
        .collect();
    let hit = |p: &Point3<f64>, d: &Vector3<f64>, max: f64| -> Option<f64> {
        tri.cast_local_ray(&Ray::new(*p, *d), max, false)
    };
    let inside = |p: &Point3<f64>| {
        hit(p, &up, half + 1e-3).is_some() && hit(p, &-up.into_inner(), half + 1e-3).is_some()
    };
    // The material interval through `p` along `d`: (back, forward) distances.
    let interval = |p: &Point3<f64>, d: &Vector3<f64>| -> Option<(f64, f64)> {
        let f = hit(p, d, MAX_BAR_WIDTH + 1e-3)?;
        let b = hit(p, &-d, MAX_BAR_WIDTH + 1e-3)?;
        Some((b, f))
    };
    let n1 = ((hi[0] - lo[0]) / spacing).floor() as usize + 1;
    let n2 = ((hi[1] - lo[1]) / spacing).floor() as usize + 1;
    // The narrowest qualifying direction at grid point (i, j): the intervals first, then the
    // straightness and room tests from the narrowest up, stopping at the first that passes.
    let site_at = |i: usize, j: usize| -> Option<BarSite> {
        let p = Point3::from(
            up.into_inner() * mid
                + e1 * (lo[0] + (i as f64 + 0.5) * spacing)
                + e2 * (lo[1] + (j as f64 + 0.5) * spacing),
        );
        if !inside(&p) {
            return None;
        }
        let mut widths: Vec<(f64, usize, f64, f64)> = directions
            .iter()
            .enumerate()
            .filter_map(|(k, d)| {
                let (b, f) = interval(&p, d)?;
                let width = b + f;
                (MIN_BAR_WIDTH..=MAX_BAR_WIDTH)
                    .contains(&width)
                    .then_some((width, k, b, f))
            })
            .collect();
        widths.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        widths.into_iter().find_map(|(width, k, b, f)| {
            let d = &directions[k];
            let centre = p + d.into_inner() * ((f - b) / 2.0);
            let along = up.cross(d);
            let straight = [-HALF_PAD, HALF_PAD].iter().all(|&s| {
                let q = centre + along * s;
                inside(&q)
                    && interval(&q, d).is_some_and(|(bq, fq)| {
                        ((bq + fq) - width).abs() <= STRAIGHT_TOLERANCE
                            && ((fq - bq) / 2.0).abs() <= STRAIGHT_TOLERANCE
                    })
            });
            // Air beyond both faces, for the fingers, across their whole width.
            let room = straight
                && [-HALF_PAD, 0.0, HALF_PAD].iter().all(|&s| {
                    [1.0, -1.0].iter().all(|&sgn| {
                        let face =
                            centre + along * s + d.into_inner() * (sgn * (width / 2.0 + 5e-4));
                        hit(&face, &(d.into_inner() * sgn), finger_room(width)).is_none()
                    })
                });
            room.then_some(BarSite {
                centre,
                across: *d,
                width,
            })
        })
    };
    // Rows in parallel, merged in grid order: the same sites on any number of threads.
    let rows: Vec<Vec<BarSite>> = (0..n1)
        .into_par_iter()
        .map(|i| (0..n2).filter_map(|j| site_at(i, j)).collect())
        .collect();
    let mut sites: Vec<BarSite> = Vec::new();
    for site in rows.into_iter().flatten() {
        let duplicate = sites.iter().any(|s| {
            (s.centre - site.centre).norm() < SITE_MERGE && s.across.dot(&site.across).abs() > 0.97
        });
        if !duplicate {
            sites.push(site);
        }
    }
    (slab, sites)
}
