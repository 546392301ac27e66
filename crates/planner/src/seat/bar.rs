//! Where a power grasp's bar lies: lines through the grasp (object frame) and the part's
//! surface they cross. Across the bar (the grasp's `x`, the closing direction): its mid-plane
//! ([`bar_mid_plane`]) and how far an off-centre grasp moves onto it ([`off_centre`]); along
//! the approach (`z`): the bar's thickness ([`thickness_at`]) and the depth of its middle
//! ([`bar_depth`]).

use nalgebra::{Isometry3, Translation3, Vector3};
use parry3d_f64::query::{Ray, RayCast};
use pregrasp_collision::ObjectGeometry;

use super::CENTRE_REACH;
use crate::hold_kind::PAD_HALF_WIDTH;

/// Half the open 2F-85's stroke (m): how far from the grasp's origin each open pad starts.
fn half_stroke() -> f64 {
    pregrasp_robot::FingerKinematics::robotiq_2f85().stroke() / 2.0
}

/// How much material (m) the line through `grasp`'s origin along its approach (`z`) crosses
/// from where it enters the part to where it leaves it again: the bar's thickness there. The
/// first stretch of material on that line (as [`material_along`] reads them across) entered
/// from 0.25 m behind the grasp; `None` if it does not begin and end within 0.5 m of there.
pub fn thickness_at(object: &ObjectGeometry, grasp: &Isometry3<f64>) -> Option<f64> {
    let (entry, exit) = material_on_line(object, grasp, &Vector3::z())
        .into_iter()
        .find(|&(entry, _)| entry >= -0.25)?;
    (entry <= 0.25 && exit - entry <= 0.5).then_some(exit - entry)
}

/// How far (m) along `grasp`'s `x` (the closing direction) the mid-plane of the bar at its
/// origin lies: halfway between the faces each pad meets first. Rays run from the open 2F-85's
/// stroke ends (± half the stroke along `x`) towards the bar through the origin and through
/// the pad's two edges along the bar (± [`PAD_HALF_WIDTH`] along `y`): on a bar whose faces
/// are not parallel to the fingers (a tapered leg) a pad meets the face at its edge first.
/// `None` if a ray through the origin misses.
pub fn bar_mid_plane(object: &ObjectGeometry, grasp: &Isometry3<f64>) -> Option<f64> {
    let half = half_stroke();
    let hit = |side: f64, along: f64| {
        let start = grasp * nalgebra::Point3::new(side * half, along, 0.0);
        let towards = grasp.rotation * Vector3::new(-side, 0.0, 0.0);
        let hit = object
            .trimesh()
            .cast_local_ray(&Ray::new(start, towards), half, false)?;
        Some(half - hit)
    };
    // The face a pad meets first: the least distance it closes, over its width.
    let face = |side: f64| {
        let centre = hit(side, 0.0)?;
        let edges = [-PAD_HALF_WIDTH, PAD_HALF_WIDTH].map(|y| hit(side, y));
        let nearest = edges.into_iter().flatten().fold(centre, f64::max);
        Some(side * nearest)
    };
    Some(0.5 * (face(1.0)? + face(-1.0)?))
}

/// How far (m, along `grasp`'s `x`, to the micrometre) a 2F-85 power grasp moves across onto the
/// mid-plane of its bar, where that is more than [`CENTRE_REACH`] from its origin: the drivers
/// turn together, so the pad that meets an off-centre bar first shoves it until the other pad
/// meets it (the whole-plan replay of scenes whose grasps a user moved up to 2 cm across: the
/// master's closing pushed the pinched part 3.7–20 mm or closed on one side,
/// `docs/physics.md`, "Scenes a user might write").
///
/// The bar is the stretch of material the line through the grasp's origin along `x` crosses
/// ([`material_along`]): the one holding the origin, else the nearest whose near face lies
/// within half the stroke. It must be narrower than the stroke, with no other material within
/// the open pads' reach once centred (the open fingers would lie in it). The grasp moves to
/// that stretch's middle, then onto [`bar_mid_plane`] there (the faces each pad meets first
/// over its width). `None` where the grasp is centred already or there is no such bar.
pub fn off_centre(object: &ObjectGeometry, grasp: &Isometry3<f64>) -> Option<f64> {
    let half = half_stroke();
    let stretches = material_along(object, grasp);
    let (k, _) = nearest_stretch(&stretches).filter(|&(_, distance)| distance <= half)?;
    let (low, high) = stretches[k];
    let middle = 0.5 * (low + high);
    let alone = |j: usize| {
        j == k || {
            let (l, h) = stretches[j];
            h < middle - half || l > middle + half
        }
    };
    if high - low >= 2.0 * half || !(0..stretches.len()).all(alone) {
        return None;
    }
    let across = middle + bar_mid_plane(object, &(grasp * Translation3::new(middle, 0.0, 0.0)))?;
    (across.abs() > CENTRE_REACH).then_some((across * 1e6).round() / 1e6)
}

/// The stretches of material (m along `grasp`'s `x`, from its origin: entry, exit) the line
/// through the grasp's origin along `x` crosses, in order: the line is cast from beyond the
/// part's bounding box and each crossing of the surface alternately enters and leaves the
/// (closed) part.
pub fn material_along(object: &ObjectGeometry, grasp: &Isometry3<f64>) -> Vec<(f64, f64)> {
    material_on_line(object, grasp, &Vector3::x())
}

/// [`material_along`] the line through `grasp`'s origin along `axis` (grasp frame, unit).
fn material_on_line(
    object: &ObjectGeometry,
    grasp: &Isometry3<f64>,
    axis: &Vector3<f64>,
) -> Vec<(f64, f64)> {
    let (lo, hi) = object.aabb();
    let far = (hi - lo).norm() + (grasp.translation.vector - 0.5 * (lo.coords + hi.coords)).norm();
    let direction = grasp.rotation * axis;
    let start = grasp * nalgebra::Point3::from(-far * axis);
    let mesh = object.trimesh();
    let mut crossings = Vec::new();
    let mut t = 0.0;
    // A part has few bars along one line; the bound stops a degenerate mesh's loop.
    while crossings.len() < 64 {
        let ray = Ray::new(start + direction * t, direction);
        let Some(hit) = mesh.cast_local_ray(&ray, 2.0 * far - t, false) else {
            break;
        };
        t += hit + 1e-7;
        crossings.push(t - far);
    }
    crossings.chunks_exact(2).map(|c| (c[0], c[1])).collect()
}

/// The stretch of `stretches` (m along a line, from a grasp's origin) that holds the origin,
/// else the one nearest to it, and how far its nearer end lies (0: it holds the origin).
fn nearest_stretch(stretches: &[(f64, f64)]) -> Option<(usize, f64)> {
    let distance = |&(low, high): &(f64, f64)| {
        if low <= 0.0 && high >= 0.0 {
            0.0
        } else {
            low.abs().min(high.abs())
        }
    };
    (0..stretches.len())
        .map(|k| (k, distance(&stretches[k])))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// How far (m) the middle of the bar on `grasp`'s approach line (its `z`, the material the line
/// crosses nearest the origin) lies beyond the origin, towards the fingertips.
pub fn bar_depth(object: &ObjectGeometry, grasp: &Isometry3<f64>) -> Option<f64> {
    let stretches = material_on_line(object, grasp, &Vector3::z());
    let (k, _) = nearest_stretch(&stretches)?;
    Some(0.5 * (stretches[k].0 + stretches[k].1))
}
