//! What an arm model is built from once per model: the exact pieces of its links and gripper
//! (shared by every world of that model) and the bounding spheres of its shape groups.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

use nalgebra::{Isometry3, Point3};
use pregrasp_robot::{Gripper, LinkShape, LINKS_PER_FINGER, SIDES};

use crate::shape::Bounded;
use crate::tight::{Polytope, Tight};

use super::posed::place;

/// The exact pieces of the gripper's shapes (shared by every arm with that gripper).
pub(super) fn gripper_tight(gripper: &Gripper) -> Arc<Vec<Option<Tight>>> {
    type ByGripper = BTreeMap<String, Arc<Vec<Option<Tight>>>>;
    static TIGHT: OnceLock<Mutex<ByGripper>> = OnceLock::new();
    let cache = TIGHT.get_or_init(Default::default);
    let key = gripper.shape_key();
    if let Some(t) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(key) {
        return t.clone();
    }
    let tight: Arc<Vec<Option<Tight>>> = Arc::new(
        gripper
            .shape_pieces()
            .into_iter()
            .map(|p| p.and_then(Tight::new))
            .collect(),
    );
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .entry(key.to_string())
        .or_insert(tight)
        .clone()
}

/// The hull of the 2F-85's finger shape `j` (`0..FINGER_SHAPES`, in shape order: the `−x`
/// finger's links, then the `+x` finger's), in its link frame, from the link hulls the closing
/// computes too ([`crate::closing::robotiq_link_hull`]; the `−x` links mirrored `x → −x`, as
/// `FingerSolids` mirrors their pieces): the hull `Tight::lowest` would build of the same
/// points, with the same extreme vertices, so the same least heights.
pub(super) fn robotiq_finger_hull(j: usize) -> Polytope {
    let (verts, faces) = crate::closing::robotiq_link_hull(j % LINKS_PER_FINGER);
    let side = SIDES[j / LINKS_PER_FINGER];
    let verts: Vec<Point3<f64>> = verts
        .iter()
        .map(|p| Point3::new(side * p.x, p.y, p.z))
        .collect();
    if faces.is_empty() {
        Polytope::new(verts)
    } else {
        Polytope::with_faces(verts, faces)
    }
}

/// A sphere around the gripper at every opening: centre on the flange axis, radius covering
/// every shape's bounding sphere at 65 openings from closed to open, plus 1 mm for the motion
/// between them (the fingers move less than that between neighbouring samples' spheres).
pub(super) fn gripper_sphere(gripper: &Gripper) -> (nalgebra::Point3<f64>, f64) {
    // The shapes (not the precision and power points) decide it.
    type Sphere = (nalgebra::Point3<f64>, f64);
    static SPHERE: OnceLock<Mutex<BTreeMap<String, Sphere>>> = OnceLock::new();
    let cache = SPHERE.get_or_init(Default::default);
    let key = gripper.shape_key();
    if let Some(s) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(key) {
        return *s;
    }
    let sphere = gripper_sphere_of(gripper);
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key.to_string(), sphere);
    sphere
}

pub(super) fn gripper_sphere_of(gripper: &Gripper) -> (nalgebra::Point3<f64>, f64) {
    let center = nalgebra::Point3::new(0.0, 0.0, 0.09);
    let mut radius: f64 = 0.0;
    let states = gripper.sample_states();
    for state in states {
        gripper.for_each_shape(state, |_, _, prim| {
            let b = Bounded::new(place(&Isometry3::identity(), &prim));
            radius = radius.max((b.center - center).norm() + b.radius);
        });
    }
    (center, radius + 0.001)
}

/// Per DH frame, a sphere holding the bounding spheres of that frame's link shapes: centre at
/// the middle of their box, radius to the farthest one.
pub(super) fn frame_spheres(links: &[LinkShape]) -> [(nalgebra::Point3<f64>, f64); 7] {
    std::array::from_fn(|f| {
        let spheres: Vec<Bounded> = links
            .iter()
            .filter(|l| l.frame == f)
            .map(|l| {
                let mut b = Bounded::new(place(&Isometry3::identity(), &l.primitive));
                b.radius += l.pieces.map_or(0.0, |p| p.slack);
                b
            })
            .collect();
        if spheres.is_empty() {
            return (nalgebra::Point3::origin(), 0.0);
        }
        let mut lo = nalgebra::Point3::from([f64::INFINITY; 3]);
        let mut hi = nalgebra::Point3::from([f64::NEG_INFINITY; 3]);
        for b in &spheres {
            let r = nalgebra::Vector3::repeat(b.radius);
            lo = lo.inf(&(b.center - r));
            hi = hi.sup(&(b.center + r));
        }
        let c = nalgebra::center(&lo, &hi);
        let radius = spheres
            .iter()
            .map(|b| (b.center - c).norm() + b.radius)
            .fold(0.0, f64::max);
        (c, radius)
    })
}

/// Per link shape of an arm, its exact pieces where it has them.
pub(super) type TightSet = Arc<Vec<Option<Tight>>>;

/// The exact pieces of the link shapes of the arm named `key` ([`ArmDescription::key`]),
/// built once per process and arm, then shared by every arm of that kind.
///
/// [`ArmDescription::key`]: pregrasp_robot::ArmDescription::key
pub(super) fn tight_pieces(key: &str, links: &[LinkShape]) -> TightSet {
    static CACHE: OnceLock<Mutex<BTreeMap<String, TightSet>>> = OnceLock::new();
    let mut cache = CACHE
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    cache
        .entry(key.to_string())
        .or_insert_with(|| {
            Arc::new(
                links
                    .iter()
                    .map(|l| l.pieces.and_then(Tight::new))
                    .collect(),
            )
        })
        .clone()
}

#[cfg(test)]
mod tests {
    use nalgebra::{Translation3, UnitQuaternion};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// The lowest point of a 2F-85 finger shape climbed on the shared link hull
    /// ([`robotiq_finger_hull`]) is the same number, to the bit, as the least world `z` over
    /// every vertex of its pieces — and so as `Tight::lowest` on the hull of its own pieces —
    /// for both fingers' links, in random frames and in axis-aligned ones (where vertices tie).
    #[test]
    fn the_shared_finger_hulls_give_the_least_height_of_every_vertex() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let solids = pregrasp_robot::FingerSolids::robotiq_2f85();
        for (j, link) in solids.links.iter().enumerate() {
            let shared = Tight::new(&link.pieces).expect("finger pieces are solids");
            let own = Tight::new(&link.pieces).expect("finger pieces are solids");
            let aligned = [
                UnitQuaternion::identity(),
                UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0),
                UnitQuaternion::from_euler_angles(0.0, std::f64::consts::FRAC_PI_2, 0.0),
            ];
            let random: Vec<_> = (0..200)
                .map(|_| {
                    UnitQuaternion::from_euler_angles(
                        rng.random_range(-3.2..3.2),
                        rng.random_range(-1.6..1.6),
                        rng.random_range(-3.2..3.2),
                    )
                })
                .collect();
            for rotation in aligned.into_iter().chain(random) {
                let frame = Isometry3::from_parts(Translation3::new(0.1, -0.2, 0.3), rotation);
                let row = crate::distance::world_up_in(&frame);
                let least = link
                    .pieces
                    .pieces
                    .iter()
                    .flatten()
                    .map(|v| row.dot(&v.coords))
                    .fold(f64::INFINITY, f64::min)
                    + frame.translation.vector.z;
                let climbed = shared.lowest_on(&frame, || robotiq_finger_hull(j));
                assert_eq!(climbed, least, "shape {j} ({}) at {rotation:?}", link.name);
                assert_eq!(own.lowest(&frame), climbed, "shape {j}");
            }
        }
    }
}
