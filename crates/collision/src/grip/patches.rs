//! Where the pads of a [`Grip`] bear on the part ([`pad_patches`]).

use nalgebra::{Isometry3, Point3};
use pregrasp_robot::{linkage, FingerConfig, Gripper, PAD};

use super::Grip;
use crate::distance::triangle_box_intersect;
use crate::object::ObjectGeometry;

/// Where a pad presses on the part: the part of its contact face that lies on the part's
/// surface (within [`PATCH_DEPTH`]), sampled every [`PATCH_STEP`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PadPatch {
    /// Centroid of the patch, in G.
    pub center: Point3<f64>,
    /// Area (m²).
    pub area: f64,
    /// Mean distance of the patch from its centroid (m): under uniform pressure the pad's
    /// torsional friction is `μ·N·e` with this `e` (the soft-finger model).
    pub torsion_radius: f64,
}

/// How close (m) the part's surface must come to a point of a pad's contact face for the point
/// to bear on it: the silicone pad yields about this much under the squeeze.
pub const PATCH_DEPTH: f64 = 5e-4;
/// Sampling step (m) of a pad's contact face.
pub const PATCH_STEP: f64 = 0.002;
/// The pad's contact face in the pad frame of the `+x` finger: `x`, and its extent in `y`
/// (22 mm wide) and `z` (37.5 mm long).
const PAD_FACE_X: f64 = -0.0066;
const PAD_FACE_Y: (f64, f64) = (-0.011, 0.011);
const PAD_FACE_Z: (f64, f64) = (0.0, 0.0375);

/// One pad's contact face: the frame it is given in (flange frame), its `x` in that frame and
/// its extent in `y` and `z`.
struct Face {
    frame: Isometry3<f64>,
    x: f64,
    y: (f64, f64),
    z: (f64, f64),
}

/// The patches where the pads of `grip` bear on the part, `[+x, −x]` (`None`: the pad does not
/// touch it), `gripper` at `flange_in_object` (flange → object frame).
pub fn pad_patches(
    object: &ObjectGeometry,
    gripper: &Gripper,
    flange_in_object: &Isometry3<f64>,
    grip: &Grip,
) -> [Option<PadPatch>; 2] {
    match gripper {
        Gripper::Robotiq2F85(_) => {
            let configs = grip.fingers().configs();
            let patches = || {
                let l = linkage();
                [0, 1].map(|k| {
                    let side = if k == 0 { 1.0 } else { -1.0 };
                    let face = Face {
                        frame: configs[k].link_frames(l)[PAD].to_isometry(side),
                        x: side * PAD_FACE_X,
                        y: PAD_FACE_Y,
                        z: PAD_FACE_Z,
                    };
                    face_patch(object, flange_in_object, &face)
                })
            };
            // The 2F-85's pads are built in: the patches depend on the part, the pose and the
            // fingers. Remembered by the pose with the fingers they were found for (a plan's
            // passes ask again at G_s), computed as asked for other fingers.
            let known = object.memo().get_or(flange_in_object, || PatchesAt {
                configs,
                patches: patches(),
            });
            if known.configs == configs {
                known.patches
            } else {
                patches()
            }
        }
        Gripper::Jaws(jaws) => jaws.faces_at(grip.state()).map(|f| {
            let face = Face {
                frame: jaws.closing_frame(),
                x: f.x,
                y: f.y,
                z: f.z,
            };
            face_patch(object, flange_in_object, &face)
        }),
    }
}

/// The 2F-85's pad patches at a pose, with the fingers they were found for.
#[derive(Clone, Copy)]
struct PatchesAt {
    configs: [FingerConfig; 2],
    patches: [Option<PadPatch>; 2],
}

/// Where `face` bears on the part (see [`pad_patches`]).
fn face_patch(
    object: &ObjectGeometry,
    flange_in_object: &Isometry3<f64>,
    face: &Face,
) -> Option<PadPatch> {
    let (fy, fz) = (face.y, face.z);
    let ny = (((fy.1 - fy.0) / PATCH_STEP).round() as usize).max(1);
    let nz = (((fz.1 - fz.0) / PATCH_STEP).round() as usize).max(1);
    let (dy, dz) = ((fy.1 - fy.0) / ny as f64, (fz.1 - fz.0) / nz as f64);
    let half = nalgebra::Vector3::repeat(PATCH_DEPTH);
    let to_object = flange_in_object.rotation.to_rotation_matrix();
    let pad = face.frame;
    // The triangles near the face (its slab, grown by a sample cube's half diagonal, √3 × the
    // depth: the cubes have G's axes, the slab the pad's), once; then each sample's cube of
    // half size PATCH_DEPTH against them.
    let grow = PATCH_DEPTH * 3f64.sqrt();
    let slab_center = Point3::new(face.x, 0.5 * (fy.0 + fy.1), 0.5 * (fz.0 + fz.1));
    let slab_half =
        nalgebra::Vector3::new(grow, 0.5 * (fy.1 - fy.0) + grow, 0.5 * (fz.1 - fz.0) + grow);
    let slab = flange_in_object * pad * nalgebra::Translation3::from(slab_center.coords);
    let mut near: Vec<[Point3<f64>; 3]> = Vec::new();
    object.any_triangle_in_box(&slab, &slab_half, |a, b, c| {
        near.push([*a, *b, *c]);
        false
    });
    if near.is_empty() {
        return None;
    }
    let mut touching = Vec::new();
    for i in 0..ny {
        for j in 0..nz {
            let local = Point3::new(
                face.x,
                fy.0 + (i as f64 + 0.5) * dy,
                fz.0 + (j as f64 + 0.5) * dz,
            );
            let p = pad * local;
            // The sample's cube has G's axes: the triangles in its frame.
            let c = flange_in_object * p;
            let cube = |v: &Point3<f64>| Point3::from(to_object.transpose() * (v - c));
            let hit = near
                .iter()
                .any(|[a, b, t]| triangle_box_intersect(&cube(a), &cube(b), &cube(t), &half));
            if hit {
                touching.push(p);
            }
        }
    }
    if touching.is_empty() {
        return None;
    }
    let n = touching.len() as f64;
    let center = Point3::from(
        touching
            .iter()
            .map(|p| p.coords)
            .sum::<nalgebra::Vector3<f64>>()
            / n,
    );
    let torsion_radius = touching.iter().map(|p| (p - center).norm()).sum::<f64>() / n;
    Some(PadPatch {
        center,
        area: n * dy * dz,
        torsion_radius,
    })
}
