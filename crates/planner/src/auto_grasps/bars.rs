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
//! - width within the gripper's reach: [`MIN_BAR_WIDTH`] … [`BarHand::max_bar_width`] (the
//!   2F-85 opens 85 mm; 5 mm are left to close);
//! - straight for a pad: the width at ±[`BarHand::half_pad`] along the bar differs by at most
//!   [`STRAIGHT_TOLERANCE`] and the intervals stay centred;
//! - room for the open fingers: beyond both faces there is no material as far as the open
//!   fingers reach, [`BarHand::finger_room`] (a hand hole next to the bar counts only if it is
//!   that wide): the gripper approaches open.
//!
//! Each site also says how far along the bar, beyond the fingers' sides, the bar stays the
//! same and the air beside it free ([`BarSite::clear_along`], up to [`JUNCTION_REACH`]): a
//! site near a junction (a rail at a rung's end, a corner, a hole's edge) has other material
//! there, which the closing fingers and the palm may meet.
//!
//! Inside test: a point of the mid-plane is in the material when rays up and down both leave
//! the part within half its height (an extruded part has no material above a hole).

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use parry3d_f64::query::{Ray, RayCast};
use parry3d_f64::shape::TriMesh;
use pregrasp_geometry::Mesh;
use rayon::prelude::*;

use super::hand::BarHand;

/// Narrowest bar a site may have (m).
pub const MIN_BAR_WIDTH: f64 = 0.010;
/// How far (m) beyond a finger's side the bar is followed to find where other material meets
/// it ([`BarSite::clear_along`]).
pub const JUNCTION_REACH: f64 = 0.040;
/// Step (m) along the bar when following it.
const ALONG_STEP: f64 = 0.004;
/// Largest change of width (m) along a pad for a straight bar.
pub const STRAIGHT_TOLERANCE: f64 = 0.003;
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
    /// How far (m, at most [`JUNCTION_REACH`]) beyond each finger's side the bar stays
    /// straight with free air beside it, the smaller of the two sides: 0 next to a junction.
    pub clear_along: f64,
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

/// The bar sites of `mesh` resting on the support with world `+z` = `object_pose⁻¹ · ẑ`, for
/// a gripper of the dimensions `hand`. Deterministic: a fixed grid, fixed directions, sites in
/// grid order.
pub fn bar_sites(
    mesh: &Mesh,
    object_pose: &Isometry3<f64>,
    hand: &BarHand,
) -> (Slab, Vec<BarSite>) {
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
    let max_width = hand.max_bar_width();
    let half_pad = hand.half_pad();
    // The material interval through `p` along `d`: (back, forward) distances.
    let interval = |p: &Point3<f64>, d: &Vector3<f64>| -> Option<(f64, f64)> {
        let f = hit(p, d, max_width + 1e-3)?;
        let b = hit(p, &-d, max_width + 1e-3)?;
        Some((b, f))
    };
    // At `s` along the bar from `centre`: the bar as wide as `width` and centred, with air
    // beyond both faces for the fingers.
    let same_bar = |centre: &Point3<f64>, d: &Unit<Vector3<f64>>, width: f64, s: f64| {
        let along = up.cross(d);
        let q = centre + along * s;
        inside(&q)
            && interval(&q, d).is_some_and(|(bq, fq)| {
                ((bq + fq) - width).abs() <= STRAIGHT_TOLERANCE
                    && ((fq - bq) / 2.0).abs() <= STRAIGHT_TOLERANCE
            })
    };
    let air = |centre: &Point3<f64>, d: &Unit<Vector3<f64>>, width: f64, s: f64| {
        let along = up.cross(d);
        [1.0, -1.0].iter().all(|&sgn| {
            let face = centre + along * s + d.into_inner() * (sgn * (width / 2.0 + 5e-4));
            hit(&face, &(d.into_inner() * sgn), hand.finger_room(width)).is_none()
        })
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
                (MIN_BAR_WIDTH..=max_width)
                    .contains(&width)
                    .then_some((width, k, b, f))
            })
            .collect();
        widths.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        widths.into_iter().find_map(|(width, k, b, f)| {
            let d = &directions[k];
            let centre = p + d.into_inner() * ((f - b) / 2.0);
            let straight = [-half_pad, half_pad]
                .iter()
                .all(|&s| same_bar(&centre, d, width, s));
            // Air beyond both faces, for the fingers, across their whole width.
            let room = straight
                && [-half_pad, 0.0, half_pad]
                    .iter()
                    .all(|&s| air(&centre, d, width, s));
            room.then_some(BarSite {
                centre,
                across: *d,
                width,
                clear_along: 0.0,
            })
        })
    };
    // How far beyond the fingers' sides the bar goes on unchanged, the nearer side.
    let clear_along = |site: &BarSite| {
        let steps = (JUNCTION_REACH / ALONG_STEP).round() as usize;
        let clear = |sign: f64| {
            (1..=steps)
                .map(|k| k as f64 * ALONG_STEP)
                .take_while(|&e| {
                    let s = sign * (half_pad + e);
                    same_bar(&site.centre, &site.across, site.width, s)
                        && air(&site.centre, &site.across, site.width, s)
                })
                .last()
                .unwrap_or(0.0)
        };
        clear(1.0).min(clear(-1.0))
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
    let clear: Vec<f64> = sites.par_iter().map(clear_along).collect();
    for (site, c) in sites.iter_mut().zip(clear) {
        site.clear_along = c;
    }
    (slab, sites)
}

#[cfg(test)]
mod tests {
    use super::super::hand::HALF_PAD_2F85;
    use super::*;
    use pregrasp_geometry::shapes::cuboid;

    /// Two boxes side by side as one mesh.
    fn two_boxes(a: [Point3<f64>; 2], b: [Point3<f64>; 2]) -> Mesh {
        let mut mesh = cuboid(a[0], a[1]);
        let other = cuboid(b[0], b[1]);
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(other.vertices);
        mesh.triangles
            .extend(other.triangles.iter().map(|t| t.map(|k| k + base)));
        mesh
    }

    #[test]
    fn a_site_next_to_a_rail_knows_the_rail_is_there() {
        // A 40 mm rung along y from 0 to 0.3 m meets a 50 mm rail across its end (a T).
        let mesh = two_boxes(
            [Point3::new(-0.02, 0.0, 0.0), Point3::new(0.02, 0.3, 0.03)],
            [Point3::new(-0.3, 0.3, 0.0), Point3::new(0.3, 0.35, 0.03)],
        );
        let (_, sites) = bar_sites(&mesh, &Isometry3::identity(), &BarHand::Robotiq2F85);
        let rung: Vec<&BarSite> = sites
            .iter()
            .filter(|s| s.centre.y < 0.3 && (s.width - 0.04).abs() < 1e-3)
            .collect();
        assert!(!rung.is_empty());
        let nearest = |y: f64| {
            *rung
                .iter()
                .min_by(|a, b| (a.centre.y - y).abs().total_cmp(&(b.centre.y - y).abs()))
                .unwrap()
        };
        // Mid-rung: the bar goes on unchanged as far as it is followed.
        let mid = nearest(0.15);
        assert!((mid.clear_along - JUNCTION_REACH).abs() < 1e-9, "{mid:?}");
        // 25 mm from the rail: at most 25 − 16 mm (half the fingers' width) of rung beyond.
        let near = nearest(0.275);
        assert!(
            near.clear_along <= 0.3 - near.centre.y - HALF_PAD_2F85 + 1e-9,
            "{near:?}"
        );
        assert!(near.clear_along < 0.015, "{near:?}");
    }
}
