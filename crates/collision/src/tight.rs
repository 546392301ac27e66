//! The exact tier of the arm links: convex pieces inside each link cylinder.
//!
//! A link shape is tested in two steps. Its cylinder, grown by the pieces' `slack`
//! ([`pregrasp_robot::ConvexPieces`]), bounds its pieces: if the cylinder is clear of the other
//! solid by `margin + slack`, so are the pieces, and the test ends there (most pairs). Only
//! where the cylinder is that close are the pieces tested, each a convex polytope given by its
//! vertices in the link's DH frame, by parry's GJK on support maps with early exit at the margin
//! (`closest_points_support_map_support_map` with a prediction distance), against the other
//! solid's own pieces or primitive. A piece needs no faces at run time: GJK only asks for its
//! support point `argmax_v d·v`, so loading a model builds no hulls. The pieces hug the real
//! link surface (a few millimetres at most, see `crates/robot/data/PROVENANCE.md`), so this is
//! where near-contact outcomes are decided.

use std::ops::ControlFlow;

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query::details::{
    closest_points_support_map_support_map, distance_support_map_support_map,
};
use parry3d_f64::query::ClosestPoints;
use parry3d_f64::shape::{Cuboid as PCuboid, Segment, SupportMap, Triangle};
use pregrasp_robot::ConvexPieces;

use crate::shape::{parry_cylinder, Bounded, Placed};

type P = Point3<f64>;

/// A convex polytope as the convex hull of its vertices (link frame); its support point in a
/// direction is the vertex farthest along it.
#[derive(Clone, Debug)]
pub struct Polytope {
    points: Vec<P>,
}

impl SupportMap for Polytope {
    #[inline]
    fn local_support_point(&self, dir: &Vector3<f64>) -> P {
        parry3d_f64::utils::point_cloud_support_point(dir, &self.points)
    }
}

/// One convex piece, ready for GJK: the polytope in its link frame, its box and a bounding
/// sphere.
#[derive(Clone, Debug)]
pub struct Piece {
    poly: Polytope,
    center: P,
    radius: f64,
    lo: P,
    hi: P,
}

/// The pieces of one link shape and how far they reach outside it.
#[derive(Clone, Debug)]
pub struct Tight {
    pieces: Vec<Piece>,
    slack: f64,
}

impl Tight {
    /// The pieces of `src`; `None` if a piece has fewer than four vertices.
    pub fn new(src: &ConvexPieces) -> Option<Tight> {
        let pieces = src
            .pieces
            .iter()
            .map(|pts| {
                if pts.len() < 4 {
                    return None;
                }
                let (lo, hi) = pts.iter().fold(
                    (P::from([f64::INFINITY; 3]), P::from([f64::NEG_INFINITY; 3])),
                    |(lo, hi), p| (lo.inf(p), hi.sup(p)),
                );
                let center = nalgebra::center(&lo, &hi);
                let radius = pts.iter().map(|p| (p - center).norm()).fold(0.0, f64::max);
                Some(Piece {
                    poly: Polytope {
                        points: pts.clone(),
                    },
                    center,
                    radius,
                    lo,
                    hi,
                })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Tight {
            pieces,
            slack: src.slack,
        })
    }

    /// How far the pieces reach outside the link shape (m).
    pub fn slack(&self) -> f64 {
        self.slack
    }
}

/// A link's pieces placed by its DH frame (link → world).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Posed<'a> {
    pub tight: &'a Tight,
    pub frame: &'a Isometry3<f64>,
}

/// Where an arm shape's exact pieces are: the arm's table of pieces, its parts (for the DH
/// frame of shape `k`) and its posed frames.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lookup<'a> {
    pub tight: &'a [Option<Tight>],
    pub parts: &'a [(usize, pregrasp_robot::Primitive)],
    pub frames: &'a [Isometry3<f64>; 7],
    pub k: usize,
}

/// One solid taking part in a pair test: a placed primitive with its bounding sphere and slack,
/// and where to find its pieces if it has them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Part<'a> {
    pub bounded: &'a Bounded,
    pub lookup: Option<Lookup<'a>>,
}

impl<'a> Part<'a> {
    /// A solid that is its primitive.
    #[inline]
    pub fn plain(bounded: &'a Bounded) -> Self {
        Part {
            bounded,
            lookup: None,
        }
    }

    /// The placed primitive (the bound of the pieces, grown by [`slack`](Self::slack)).
    #[inline]
    pub fn shape(&self) -> &'a Placed {
        &self.bounded.shape
    }

    /// How far the exact solid may reach outside [`shape`](Self::shape).
    #[inline]
    pub fn slack(&self) -> f64 {
        self.bounded.slack
    }

    /// The exact pieces placed by their link frame, if the solid has them.
    #[inline]
    pub fn tight(&self) -> Option<Posed<'a>> {
        let l = self.lookup?;
        let tight = l.tight.get(l.k)?.as_ref()?;
        Some(Posed {
            tight,
            frame: &l.frames[l.parts[l.k].0],
        })
    }

    /// Calls `f(pose, convex, inflation)` for each convex part of the exact solid, stopping
    /// when it breaks: the pieces (inflation 0) whose bounding sphere comes within `reach` of
    /// the sphere `(c, r)`, or the primitive itself (capsule: its segment inflated by the
    /// radius; rounded cylinder: its core inflated by the border).
    fn each_convex(
        &self,
        near: Option<(&P, f64)>,
        mut f: impl FnMut(&Isometry3<f64>, &dyn SupportMap, f64) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        match self.tight() {
            Some(Posed { tight, frame }) => {
                for piece in &tight.pieces {
                    if let Some((c, reach)) = near {
                        let d = reach + piece.radius;
                        if (frame * piece.center - c).norm_squared() > d * d {
                            continue;
                        }
                    }
                    f(frame, &piece.poly, 0.0)?;
                }
                ControlFlow::Continue(())
            }
            None => with_primitive(self.shape(), |pose, shape, inflation| {
                f(pose, shape, inflation)
            }),
        }
    }

    /// Height of the exact solid's lowest point above the plane `z = height`.
    pub fn plane_distance(&self, height: f64) -> Option<f64> {
        let Posed { tight, frame } = self.tight()?;
        let row = frame
            .rotation
            .to_rotation_matrix()
            .matrix()
            .row(2)
            .transpose();
        let tz = frame.translation.vector.z;
        let low = tight
            .pieces
            .iter()
            .flat_map(|p| p.poly.points.iter())
            .map(|v| row.dot(&v.coords))
            .fold(f64::INFINITY, f64::min);
        Some(low + tz - height)
    }
}

/// Calls `f` with a primitive as a parry support map: its pose, the shape, and the radius by
/// which that shape must be inflated to be the primitive.
fn with_primitive(
    s: &Placed,
    f: impl FnOnce(&Isometry3<f64>, &dyn SupportMap, f64) -> ControlFlow<()>,
) -> ControlFlow<()> {
    let id = Isometry3::identity();
    match *s {
        Placed::Capsule { a, b, radius } => f(&id, &Segment::new(a, b), radius),
        Placed::Cylinder {
            a,
            b,
            radius,
            border,
        } => {
            let (pose, cyl) = parry_cylinder(&a, &b, radius);
            f(&pose, &cyl, border)
        }
        Placed::Cuboid { pose, half } => f(&pose, &PCuboid::new(half), 0.0),
    }
}

/// Whether two convex shapes at `p1`, `p2` come within `dist` of each other (GJK, stopping as
/// soon as it proves they are farther).
#[inline]
fn near(
    p1: &Isometry3<f64>,
    g1: &dyn SupportMap,
    p2: &Isometry3<f64>,
    g2: &dyn SupportMap,
    dist: f64,
) -> bool {
    !matches!(
        closest_points_support_map_support_map(&p1.inv_mul(p2), g1, g2, dist),
        ClosestPoints::Disjoint
    )
}

/// Whether the exact solids of `s1` and `s2` come within `margin` of each other.
pub(crate) fn within(s1: &Part, s2: &Part, margin: f64) -> bool {
    let (b1, b2) = (s1.bounded, s2.bounded);
    s1.each_convex(Some((&b2.center, b2.radius + margin)), |p1, g1, e1| {
        s2.each_convex(Some((&b1.center, b1.radius + margin)), |p2, g2, e2| {
            if near(p1, g1, p2, g2, margin + e1 + e2) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
    })
    .is_break()
}

/// Distance between the exact solids of `s1` and `s2` (`0` in contact).
pub(crate) fn distance(s1: &Part, s2: &Part) -> f64 {
    let mut best = f64::INFINITY;
    let _ = s1.each_convex(None, |p1, g1, e1| {
        s2.each_convex(None, |p2, g2, e2| {
            let d = distance_support_map_support_map(&p1.inv_mul(p2), g1, g2) - e1 - e2;
            best = best.min(d.max(0.0));
            ControlFlow::Continue(())
        })
    });
    best
}

/// Calls `f(piece pose in the mesh frame, polytope, piece's box in the mesh frame)` for each
/// piece of `t`, a mesh being at `mesh_pose`, until it returns `true`.
pub(crate) fn any_piece_in(
    t: &Posed,
    mesh_pose: &Isometry3<f64>,
    mut f: impl FnMut(&Isometry3<f64>, &Polytope, (P, P)) -> bool,
) -> bool {
    let rel = mesh_pose.inv_mul(t.frame);
    let m = rel.rotation.to_rotation_matrix().matrix().abs();
    t.tight.pieces.iter().any(|piece| {
        let c = rel * nalgebra::center(&piece.lo, &piece.hi);
        let ext: Vector3<f64> = m * (0.5 * (piece.hi - piece.lo));
        f(&rel, &piece.poly, (c - ext, c + ext))
    })
}

/// Whether the polytope at `pose` comes within `margin` of the triangle (both in one frame).
#[inline]
pub(crate) fn piece_near_triangle(
    pose: &Isometry3<f64>,
    poly: &Polytope,
    tri: &Triangle,
    margin: f64,
) -> bool {
    near(pose, poly, &Isometry3::identity(), tri, margin)
}

/// Distance from the polytope at `pose` to the triangle (both in one frame; `0` in contact).
#[inline]
pub(crate) fn piece_triangle_distance(
    pose: &Isometry3<f64>,
    poly: &Polytope,
    tri: &Triangle,
) -> f64 {
    distance_support_map_support_map(&pose.inverse(), poly, tri).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Capsule as PCapsule, ConvexPolyhedron};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The support-map GJK on raw vertices agrees with parry's own polyhedron (built as the
    /// hull of the same vertices) against capsules, rounded cylinders, boxes and other pieces:
    /// distances within 1e-5 (GJK's tolerance), and `within` is `distance ≤ margin` away from the boundary.
    #[test]
    fn pieces_agree_with_parry_polyhedra() {
        let mut rng = ChaCha8Rng::seed_from_u64(20);
        let cloud = |rng: &mut ChaCha8Rng, c: Vector3<f64>| -> Vec<P> {
            (0..30)
                .map(|_| P::from(c + Vector3::from_fn(|_, _| rng.random_range(-0.05..0.05))))
                .collect()
        };
        let frame = Isometry3::new(Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.3, -0.5, 0.2));
        let mut checked = 0;
        for k in 0..300 {
            let pts = cloud(&mut rng, Vector3::zeros());
            let tight = Tight::new(&ConvexPieces {
                pieces: vec![pts.clone()],
                slack: 0.0,
            })
            .unwrap();
            let hull = ConvexPolyhedron::from_convex_hull(&pts).unwrap();
            let c = frame * P::from(Vector3::from_fn(|_, _| rng.random_range(-0.15..0.15)));
            let other_pts = cloud(&mut rng, c.coords);
            let (shape, reference) = match k % 4 {
                0 => {
                    let (a, b) = (c, c + Vector3::new(0.05, 0.02, -0.03));
                    let r = 0.02;
                    let d = query::distance(
                        &frame,
                        &hull,
                        &Isometry3::identity(),
                        &PCapsule::new(a, b, r),
                    );
                    (Placed::Capsule { a, b, radius: r }, d.unwrap())
                }
                1 => {
                    let (a, b, r, e) = (c, c + Vector3::new(0.0, 0.06, 0.01), 0.03, 0.005);
                    let (pose, cyl) = parry_cylinder(&a, &b, r);
                    let d = query::distance(&frame, &hull, &pose, &cyl).unwrap() - e;
                    (
                        Placed::Cylinder {
                            a,
                            b,
                            radius: r,
                            border: e,
                        },
                        d.max(0.0),
                    )
                }
                2 => {
                    let pose = Isometry3::new(c.coords, Vector3::new(0.1, 0.7, -0.3));
                    let half = Vector3::new(0.03, 0.01, 0.05);
                    let d = query::distance(&frame, &hull, &pose, &PCuboid::new(half));
                    (Placed::Cuboid { pose, half }, d.unwrap())
                }
                _ => {
                    let other = ConvexPolyhedron::from_convex_hull(&other_pts).unwrap();
                    let d = query::distance(&frame, &hull, &Isometry3::identity(), &other);
                    // The bounding sphere holds the other piece (its points lie within 0.087 of c).
                    (
                        Placed::Capsule {
                            a: c,
                            b: c,
                            radius: 0.09,
                        },
                        d.unwrap(),
                    )
                }
            };
            // Shape 0 of a one-shape arm posed with every DH frame at `frame`.
            let dummy = pregrasp_robot::Primitive::Capsule(pregrasp_robot::Capsule {
                a: P::origin(),
                b: P::origin(),
                radius: 0.0,
            });
            let parts = [(0usize, dummy)];
            let own_table = [Some(tight)];
            let frames = [frame; 7];
            let b1 = Bounded::new(Placed::Capsule {
                a: P::from(frame.translation.vector),
                b: P::from(frame.translation.vector),
                radius: 0.1,
            });
            let s1 = Part {
                bounded: &b1,
                lookup: Some(Lookup {
                    tight: &own_table,
                    parts: &parts,
                    frames: &frames,
                    k: 0,
                }),
            };
            let other_table = [Some(
                Tight::new(&ConvexPieces {
                    pieces: vec![other_pts],
                    slack: 0.0,
                })
                .unwrap(),
            )];
            let ids = [Isometry3::identity(); 7];
            let b2 = Bounded::new(shape);
            let s2 = if k % 4 == 3 {
                Part {
                    bounded: &b2,
                    lookup: Some(Lookup {
                        tight: &other_table,
                        parts: &parts,
                        frames: &ids,
                        k: 0,
                    }),
                }
            } else {
                Part::plain(&b2)
            };
            let d = distance(&s1, &s2);
            assert!(
                (d - reference).abs() < 1e-5,
                "case {k}: {d} vs parry {reference}"
            );
            for margin in [0.0, 0.005, 0.02] {
                if (reference - margin).abs() > 1e-5 {
                    assert_eq!(
                        within(&s1, &s2, margin),
                        reference <= margin,
                        "case {k}, margin {margin}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 800);
    }
}
