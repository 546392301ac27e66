//! The fully open 2F-85 fingers at a grasp, against the part's mesh: the real finger geometry
//! (each link's convex pieces, [`pregrasp_robot::FingerSolids`], placed by the open linkage,
//! [`pregrasp_robot::FingerPair::open`]), not a width rule.
//!
//! - [`OpenFingers::touch`]: the first link of the open fingers inside the part with the
//!   flange at a grasp: the gripper cannot come down around the bar there (a power grasp's
//!   inner knuckles reach only ±31 mm just below the palm, so a bar wider than that under them
//!   is refused whatever the stroke says).
//! - [`OpenFingers::clear_by`]: every piece at least `d` from the part: the straight approach
//!   outside its contact zone must keep the cell's link clearance.
//!
//! Each link's box (grown by `d`) is tested first; the pieces only where it meets the part.

use std::sync::OnceLock;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::query::{closest_points, intersection_test, ClosestPoints};
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, TriMesh};
use pregrasp_robot::{FingerPair, FingerSolids};

/// One open finger link: its box and pieces, placed in the flange frame G.
struct Link {
    name: &'static str,
    box_pose: Isometry3<f64>,
    half: Vector3<f64>,
    pose: Isometry3<f64>,
    pieces: Vec<ConvexPolyhedron>,
}

/// The open fingers' links in G (built once).
pub struct OpenFingers {
    links: Vec<Link>,
}

impl OpenFingers {
    /// The built-in 2F-85's open fingers.
    pub fn robotiq_2f85() -> &'static OpenFingers {
        static OPEN: OnceLock<OpenFingers> = OnceLock::new();
        OPEN.get_or_init(|| {
            let frames = FingerPair::open().link_frames();
            let links = frames
                .iter()
                .zip(&FingerSolids::robotiq_2f85().links)
                .map(|(frame, solid)| {
                    let b = &solid.bounds;
                    let in_link = Isometry3::from_parts(
                        Translation3::from(Vector3::from(b.center)),
                        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), b.angle),
                    );
                    Link {
                        name: solid.name,
                        box_pose: frame * in_link,
                        half: Vector3::from(b.half),
                        pose: *frame,
                        pieces: solid
                            .pieces
                            .pieces
                            .iter()
                            .filter_map(|p| ConvexPolyhedron::from_convex_hull(p))
                            .collect(),
                    }
                })
                .collect();
            OpenFingers { links }
        })
    }

    /// Whether `shape` at `pose` comes within `d` of the part (`d = 0`: touches it).
    fn near(
        part: &TriMesh,
        pose: &Isometry3<f64>,
        shape: &dyn parry3d_f64::shape::Shape,
        d: f64,
    ) -> bool {
        let id = Isometry3::identity();
        if d <= 0.0 {
            return intersection_test(pose, shape, &id, part).unwrap_or(true);
        }
        !matches!(
            closest_points(pose, shape, &id, part, d),
            Ok(ClosestPoints::Disjoint)
        )
    }

    /// The first open finger link (by name) within `d` of the part with the flange at
    /// `flange_in_object` (flange → object frame).
    pub fn within(
        &self,
        part: &TriMesh,
        flange_in_object: &Isometry3<f64>,
        d: f64,
    ) -> Option<&'static str> {
        for link in &self.links {
            let cuboid = Cuboid::new(link.half);
            if !Self::near(part, &(flange_in_object * link.box_pose), &cuboid, d) {
                continue;
            }
            let at = flange_in_object * link.pose;
            if link.pieces.iter().any(|p| Self::near(part, &at, p, d)) {
                return Some(link.name);
            }
        }
        None
    }

    /// The first open finger link inside the part (see [`OpenFingers::within`]).
    pub fn touch(&self, part: &TriMesh, flange_in_object: &Isometry3<f64>) -> Option<&'static str> {
        self.within(part, flange_in_object, 0.0)
    }

    /// No open finger link within `d` of the part.
    pub fn clear_by(&self, part: &TriMesh, flange_in_object: &Isometry3<f64>, d: f64) -> bool {
        self.within(part, flange_in_object, d).is_none()
    }
}
