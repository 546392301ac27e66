//! How a parallel-jaw gripper ([`JawGripper`]) closes on the part: both jaws slide toward
//! each other, driven together (one joint, the other jaw its mimic), until a jaw's piece meets
//! the part's surface; the first touch stops both.
//!
//! The touch is found by shape casting (parry's `cast_shapes`, each convex piece along its
//! jaw's closing direction against the part's triangles): exact, no stepping. The jaws only
//! translate, so every pose of the closing lies in the convex hull of the open and the final
//! pose: those two are the swept points the support must clear ([`Grip::lowest`]).

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query::{self, ShapeCastOptions};
use pregrasp_robot::{ClosingKind, GripperState, JawGripper};

use super::sweep::{Frame, LinkPoints, Swept};
use super::{Grip, GripFailure};
use crate::baked_hulls::convex_polyhedron;
use crate::object::ObjectGeometry;

/// Closing travel (m of gap) below which a touch counts as touching already open.
const AT_OPEN: f64 = 1e-9;
/// How much later (m of gap) than the first a jaw's own touch may come and still count as
/// bearing on the part (both jaws of a centred grasp touch at once, to round-off).
const BOTH_TOUCH: f64 = 1e-6;

/// Closes `jaws` on the part with the flange at `flange_in_object` (flange → object frame).
pub(super) fn close_jaws(
    object: &ObjectGeometry,
    jaws: &JawGripper,
    flange_in_object: &Isometry3<f64>,
) -> Result<Grip, GripFailure> {
    let open = GripperState::Open;
    let open_gap = jaws.open_gap();
    let stroke = open_gap - jaws.closed_gap();
    let open_frames = jaws.jaw_frames(open);
    let closed_frames = jaws.jaw_frames(jaws.at_gap(jaws.closed_gap()));
    let mesh = object.trimesh();
    // Per jaw, the gap closed when it first touches (at most the stroke).
    let mut touch = [f64::INFINITY; 2];
    for k in 0..2 {
        // The jaw's motion per metre of gap closed (each jaw covers its share of the gap).
        let path = closed_frames[k].translation.vector - open_frames[k].translation.vector;
        let velocity = flange_in_object.rotation * (path / stroke);
        let at = flange_in_object * open_frames[k];
        for part in jaws.jaw_parts(k) {
            for piece in &part.pieces.pieces {
                let Some(poly) = convex_polyhedron(piece) else {
                    continue;
                };
                let options = ShapeCastOptions {
                    max_time_of_impact: stroke,
                    target_distance: 0.0,
                    stop_at_penetration: true,
                    compute_impact_geometry_on_penetration: false,
                };
                let hit = query::cast_shapes(
                    &at,
                    &velocity,
                    &poly,
                    &Isometry3::identity(),
                    &Vector3::zeros(),
                    mesh,
                    options,
                )
                .ok()
                .flatten();
                if let Some(hit) = hit {
                    touch[k] = touch[k].min(hit.time_of_impact);
                }
            }
        }
    }
    let first = touch[0].min(touch[1]);
    if first <= AT_OPEN {
        return Err(GripFailure::OpenTouches);
    }
    if !first.is_finite() {
        return Err(GripFailure::ClosesOnNothing);
    }
    let state = jaws.at_gap(open_gap - first);
    let kinds = touch.map(|t| {
        if t <= first + BOTH_TOUCH {
            ClosingKind::Pinch
        } else {
            ClosingKind::Closed
        }
    });
    // Each jaw part open and closed, in the flange frame.
    let closed = jaws.jaw_frames(state);
    let links: Vec<Vec<Point3<f64>>> = (0..2)
        .flat_map(|k| {
            jaws.jaw_parts(k).iter().map(move |part| {
                part.pieces
                    .pieces
                    .iter()
                    .flatten()
                    .flat_map(|v| [open_frames[k] * v, closed[k] * v])
                    .collect()
            })
        })
        .collect();
    Ok(Grip {
        state,
        width: jaws.gap(state),
        kinds,
        swept: Arc::new(sweep_of(&links)),
    })
}

/// The sweep of points (flange frame) grouped per link: one pose, each link's points in the
/// flange frame (its frame the identity), grouped by `y`.
fn sweep_of(links: &[Vec<Point3<f64>>]) -> Swept {
    let links: Vec<LinkPoints> = links
        .iter()
        .map(|pts| {
            let mut levels: Vec<(f64, Vec<[f64; 2]>)> = Vec::new();
            for p in pts {
                match levels.iter_mut().find(|(y, _)| *y == p.y) {
                    Some((_, level)) => level.push([p.x, p.z]),
                    None => levels.push((p.y, vec![[p.x, p.z]])),
                }
            }
            LinkPoints::new(1.0, &levels)
        })
        .collect();
    let n = links.len();
    let mut sweep = Swept::new(Arc::new(links), 1);
    sweep.push(std::iter::repeat_n(Frame::IDENTITY, n));
    sweep.finish()
}
