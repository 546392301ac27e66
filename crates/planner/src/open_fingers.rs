//! The fully open gripper at a grasp, against the part's mesh: the real finger geometry (each
//! link's convex pieces placed by the open state, [`Gripper::shape_frames`]; the 2F-85's
//! finger links, [`pregrasp_robot::FingerSolids`], placed by the open linkage; a jaw
//! gripper's jaw parts), and its palm (the 2F-85's housing boxes, a jaw gripper's static
//! parts), not a width rule.
//!
//! - [`OpenFingers::touch`]: the first finger link of the open hand inside the part with the
//!   flange at a grasp: the gripper cannot come down around the bar there (a power grasp's
//!   inner knuckles reach only ±31 mm just below the palm, so a bar wider than that under them
//!   is refused whatever the stroke says). The palm may touch the part it grasps: how deep it
//!   may be is the open-hand rule's ([`pregrasp_collision::open_approach_inside`]).
//! - [`OpenFingers::clear_by`]: every piece of the hand, palm included, at least `d` from the
//!   part: the straight approach outside its contact zone must keep the cell's link clearance.
//!
//! Each link's box (grown by `d`) is tested first; the pieces only where it meets the part
//! (and they are built the first time it does).

use std::sync::{Arc, OnceLock};

use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use parry3d_f64::query::{closest_points, intersection_test, ClosestPoints};
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, TriMesh};
use pregrasp_collision::baked_hulls::convex_polyhedron;
use pregrasp_robot::{Gripper, GripperState, PerShape, Primitive};

/// One open link: its box and pieces, placed in the flange frame G.
struct Link {
    name: &'static str,
    /// Rigid with the flange (the palm): it may touch the part at a grasp.
    palm: bool,
    box_pose: Isometry3<f64>,
    half: Vector3<f64>,
    pose: Isometry3<f64>,
    /// The pieces' points; their solids are built the first time the link's box is near the
    /// part (most links' boxes settle every query).
    points: Vec<Vec<Point3<f64>>>,
    pieces: OnceLock<Vec<ConvexPolyhedron>>,
}

impl Link {
    fn pieces(&self) -> &[ConvexPolyhedron] {
        self.pieces.get_or_init(|| {
            self.points
                .iter()
                .filter_map(|v| convex_polyhedron(v))
                .collect()
        })
    }
}

/// The open hand's links in G (built once per gripper shape).
pub struct OpenFingers {
    links: Vec<Link>,
}

impl OpenFingers {
    /// The open hand of `gripper`, built once per gripper shape ([`Gripper::shape_key`]).
    pub fn of(gripper: &Gripper) -> Arc<OpenFingers> {
        static HANDS: PerShape<Arc<OpenFingers>> = PerShape::new();
        HANDS.get_or_build(gripper, |g| Arc::new(Self::build(g)))
    }

    fn build(gripper: &Gripper) -> OpenFingers {
        let frames = gripper.shape_frames(GripperState::Open);
        let pieces = gripper.shape_pieces();
        let statics = gripper.static_count();
        let mut links = Vec::with_capacity(frames.len());
        gripper.for_each_shape(GripperState::Open, |k, name, primitive| {
            let Primitive::Cuboid { pose, half_extents } = primitive else {
                return;
            };
            let (frame, points) = match (pieces.get(k).copied().flatten(), frames.get(k)) {
                (Some(p), Some(frame)) => (*frame, p.pieces.to_vec()),
                // An exact box (the 2F-85's housing), in the flange frame.
                _ => {
                    let h = half_extents;
                    let corners: Vec<_> = (0..8)
                        .map(|c| {
                            let s = |b: usize| if c & b == 0 { -1.0 } else { 1.0 };
                            Point3::new(s(1) * h.x, s(2) * h.y, s(4) * h.z)
                        })
                        .collect();
                    (pose, vec![corners])
                }
            };
            links.push(Link {
                name,
                palm: k < statics,
                box_pose: pose,
                half: half_extents,
                pose: frame,
                points,
                pieces: OnceLock::new(),
            });
        });
        OpenFingers { links }
    }

    /// Builds every link's pieces now rather than when a query first needs them (the baked
    /// hull table's test records them all).
    pub fn prepare(&self) {
        for link in &self.links {
            link.pieces();
        }
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

    /// The first open link (by name; the palm's only if `palm`) within `d` of the part with
    /// the flange at `flange_in_object` (flange → object frame).
    pub fn within(
        &self,
        part: &TriMesh,
        flange_in_object: &Isometry3<f64>,
        d: f64,
        palm: bool,
    ) -> Option<&'static str> {
        for link in self.links.iter().filter(|l| palm || !l.palm) {
            let cuboid = Cuboid::new(link.half);
            if !Self::near(part, &(flange_in_object * link.box_pose), &cuboid, d) {
                continue;
            }
            let at = flange_in_object * link.pose;
            if link.pieces().iter().any(|p| Self::near(part, &at, p, d)) {
                return Some(link.name);
            }
        }
        None
    }

    /// The first open finger link (not the palm) inside the part (see
    /// [`OpenFingers::within`]).
    pub fn touch(&self, part: &TriMesh, flange_in_object: &Isometry3<f64>) -> Option<&'static str> {
        self.within(part, flange_in_object, 0.0, false)
    }

    /// No open link, palm included, within `d` of the part.
    pub fn clear_by(&self, part: &TriMesh, flange_in_object: &Isometry3<f64>, d: f64) -> bool {
        self.within(part, flange_in_object, d, true).is_none()
    }

    /// Whether the straight approach to the grasp with the flange at `flange_in_object` keeps
    /// `clearance` (m) from the part outside its contact zone: the open hand [`clear_by`]
    /// that much where the zone ends (`zone` back along the flange's `z`), at the stand-off
    /// (`stand_off` back) and half way — the line the pipeline will build and check.
    ///
    /// [`clear_by`]: OpenFingers::clear_by
    pub fn approach_clear(
        &self,
        part: &TriMesh,
        flange_in_object: &Isometry3<f64>,
        [zone, stand_off]: [f64; 2],
        clearance: f64,
    ) -> bool {
        let zone = zone.min(stand_off);
        [zone, 0.5 * (zone + stand_off), stand_off]
            .iter()
            .all(|&h| {
                let back = flange_in_object * Translation3::new(0.0, 0.0, -h);
                self.clear_by(part, &back, clearance)
            })
    }
}
