//! The manipulated part: its real (non-convex) triangle mesh with parry's BVH.
//!
//! The mesh is kept as is, not replaced by its convex hull, so an arm may pass through an
//! opening of a frame-like part. Tests are surface tests: a primitive collides with the part
//! when it touches a triangle. A primitive wholly enclosed by a closed part without touching
//! its surface is not reported; edge validation at a resolution below the smallest primitive
//! radius cannot step into such a state without crossing the surface first.

use std::sync::{Arc, OnceLock};

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::partitioning::TraversalAction;
use parry3d_f64::query;
use parry3d_f64::shape::{Cuboid as PCuboid, TriMesh};
use pregrasp_geometry::Mesh;

use crate::distance::{aabb_aabb_sq, segment_triangle_sq, triangle_box_intersect};
use crate::error::CollisionError;
use crate::pose_memo::PoseMemo;
use crate::shape::{Bounded, Placed};
use crate::solid::PartSolid;

type P = Point3<f64>;

/// A triangle mesh in its own (object) frame, with a BVH and a bounding sphere.
#[derive(Clone)]
pub struct ObjectGeometry {
    mesh: TriMesh,
    /// Bounding sphere in the object frame: centre of the local AABB, half its diagonal.
    center: P,
    radius: f64,
    /// The mesh's bounding box in the object frame (its BVH's root box, kept at hand).
    aabb: (P, P),
    /// The part as a solid (the inside test), built when first asked for.
    solid: Arc<OnceLock<PartSolid>>,
    /// Answers at poses of the part, remembered (the 2F-85's closings: [`PoseMemo`]); shared
    /// by the clones, which are the same part.
    memo: Arc<PoseMemo>,
}

impl std::fmt::Debug for ObjectGeometry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ObjectGeometry")
            .field("triangles", &self.mesh.indices().len())
            .field("radius", &self.radius)
            .finish()
    }
}

impl ObjectGeometry {
    /// Builds the BVH of `mesh` (object frame, metres).
    pub fn new(mesh: &Mesh) -> Result<Self, CollisionError> {
        check_mesh(mesh)?;
        let trimesh = TriMesh::new(mesh.vertices.clone(), mesh.triangles.clone())
            .map_err(CollisionError::Mesh)?;
        let aabb = trimesh.local_aabb();
        let center = aabb.center();
        let radius = aabb.half_extents().norm();
        let aabb = (aabb.mins, aabb.maxs);
        Ok(ObjectGeometry {
            mesh: trimesh,
            center,
            radius,
            aabb,
            solid: Arc::default(),
            memo: Arc::default(),
        })
    }

    /// The mesh's bounding box in the object frame.
    pub fn aabb(&self) -> (P, P) {
        self.aabb
    }

    /// The part as a solid: its mesh oriented outward, for the inside test
    /// ([`crate::inside`]); built on first use.
    pub(crate) fn solid(&self) -> &PartSolid {
        crate::solid::solid_of(&self.solid, &self.mesh)
    }

    /// Answers at poses of the part computed so far ([`crate::pose_memo`]).
    pub(crate) fn memo(&self) -> &PoseMemo {
        &self.memo
    }

    /// The parry mesh (object frame).
    pub fn trimesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.mesh.indices().len()
    }

    /// Bounding sphere of the part at `pose` (object → world).
    #[inline]
    pub(crate) fn world_sphere(&self, pose: &Isometry3<f64>) -> (P, f64) {
        (pose * self.center, self.radius)
    }

    /// Whether the bounding sphere of `s` comes within `margin` of the part's box (its mesh's
    /// bounding box in the object frame) at `pose`: a cheap test before the BVH, much tighter
    /// than the part's sphere for a flat part.
    #[inline]
    pub(crate) fn sphere_near_box(&self, pose: &Isometry3<f64>, s: &Bounded, margin: f64) -> bool {
        let local = pose.inverse_transform_point(&s.center);
        let (mins, maxs) = &self.aabb;
        let outside = (mins - local).sup(&(local - maxs)).sup(&Vector3::zeros());
        let reach = s.radius + margin;
        outside.norm_squared() <= reach * reach
    }

    /// Whether the primitive `s` comes within `margin` of the part at `pose`.
    pub(crate) fn intersects(&self, pose: &Isometry3<f64>, s: &Bounded, margin: f64) -> bool {
        let (c, r) = self.world_sphere(pose);
        let reach = r + s.radius + margin;
        if (c - s.center).norm_squared() > reach * reach {
            return false;
        }
        if !self.sphere_near_box(pose, s, margin) {
            return false;
        }
        match s.shape {
            Placed::Capsule { a, b, radius } => {
                let la = pose.inverse_transform_point(&a);
                let lb = pose.inverse_transform_point(&b);
                self.capsule_hits(&la, &lb, radius + margin)
            }
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } => {
                let la = pose.inverse_transform_point(&a);
                let lb = pose.inverse_transform_point(&b);
                self.cylinder_hits(&la, &lb, radius, margin + border)
            }
            Placed::Cuboid { pose: bp, half } => {
                self.cuboid_hits(&pose.inv_mul(&bp), &(half + Vector3::repeat(margin)))
            }
        }
    }

    /// Whether the exact pieces `t` of a link come within `margin` of the part at `pose`: per
    /// piece, BVH descent with its box grown by the margin, GJK with early exit at the leaves
    /// (a remembered separating axis tried first against the piece's box).
    pub(crate) fn pieces_intersect(
        &self,
        pose: &Isometry3<f64>,
        t: &crate::tight::Posed,
        margin: f64,
    ) -> bool {
        let grow = Vector3::repeat(margin);
        crate::tight::any_piece_in(t, pose, |p| {
            let (lo, hi) = p.aabb;
            self.any_triangle(&(lo - grow), &(hi + grow), |ta, tb, tc| {
                let tri = parry3d_f64::shape::Triangle::new(*ta, *tb, *tc);
                let pair = (p.key, ta as *const P as usize);
                let bounds = &p.local_box;
                crate::tight::piece_near_triangle_bounded(
                    pair, p.rel, &p.poly, bounds, &tri, margin,
                )
            })
        })
    }

    /// Distance from the exact pieces `t` of a link to the part at `pose` (`0` in contact):
    /// BVH descent pruning every node whose box is farther from the piece's box than the best
    /// distance so far, GJK distance at the leaves.
    pub(crate) fn pieces_distance(&self, pose: &Isometry3<f64>, t: &crate::tight::Posed) -> f64 {
        let verts = self.mesh.vertices();
        let idx = self.mesh.indices();
        let mut best = f64::INFINITY;
        crate::tight::any_piece_in(t, pose, |p| {
            let (lo, hi) = p.aabb;
            self.mesh.bvh().traverse(|node| {
                if aabb_aabb_sq(&lo, &hi, &node.mins(), &node.maxs()) >= best * best {
                    return TraversalAction::Prune;
                }
                if let Some(leaf) = node.leaf_data() {
                    let [i, j, k] = idx[leaf as usize];
                    let tri = parry3d_f64::shape::Triangle::new(
                        verts[i as usize],
                        verts[j as usize],
                        verts[k as usize],
                    );
                    best = best.min(crate::tight::piece_triangle_distance(p.rel, &p.poly, &tri));
                }
                TraversalAction::Continue
            });
            false
        });
        best
    }

    /// Whether the box `half` at `box_pose` (box → object frame) touches the part's surface.
    pub fn box_touches(&self, box_pose: &Isometry3<f64>, half: &Vector3<f64>) -> bool {
        self.cuboid_hits(box_pose, half)
    }

    /// Whether the cylinder (end-face centres `a`, `b`, radius `r`, object frame) comes within
    /// `margin` of a triangle: BVH descent with its AABB; at a leaf, the enclosing capsule
    /// rejects and the inscribed capsule accepts by closed-form segment–triangle distances,
    /// and only what falls between goes to GJK ([`crate::gjk::within`]).
    fn cylinder_hits(&self, a: &P, b: &P, r: f64, margin: f64) -> bool {
        let ext = crate::shape::cylinder_rim_extent(a, b, r) + Vector3::repeat(margin);
        let outer2 = (r + margin) * (r + margin);
        let (_, _, inner) = crate::shape::cylinder_capsules(a, b, r);
        // Built only if a triangle falls between the two capsule bounds.
        let mut parry = None;
        self.any_triangle(&(a.inf(b) - ext), &(a.sup(b) + ext), |ta, tb, tc| {
            if segment_triangle_sq(a, b, ta, tb, tc) > outer2 {
                return false;
            }
            if inner.is_some_and(|(ia, ib)| segment_triangle_sq(&ia, &ib, ta, tb, tc) <= outer2) {
                return true;
            }
            let (cyl_pose, cyl) =
                parry.get_or_insert_with(|| crate::shape::parry_cylinder(a, b, r));
            let tri = parry3d_f64::shape::Triangle::new(*ta, *tb, *tc);
            crate::gjk::within(&cyl_pose.inverse(), cyl, &tri, margin, None).is_ok()
        })
    }

    /// Whether `touches` holds for any triangle whose BVH leaf box meets the box `[lo, hi]`
    /// (object frame); stops at the first.
    fn any_triangle(&self, lo: &P, hi: &P, mut touches: impl FnMut(&P, &P, &P) -> bool) -> bool {
        let verts = self.mesh.vertices();
        let idx = self.mesh.indices();
        let mut hit = false;
        self.mesh.bvh().traverse(|node| {
            if aabb_aabb_sq(lo, hi, &node.mins(), &node.maxs()) > 0.0 {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                let [i, j, k] = idx[leaf as usize];
                if touches(&verts[i as usize], &verts[j as usize], &verts[k as usize]) {
                    hit = true;
                    return TraversalAction::EarlyExit;
                }
            }
            TraversalAction::Continue
        });
        hit
    }

    /// Whether the box `half` at `box_pose` (box → object frame) touches a triangle: BVH
    /// descent with the box's AABB, the separating-axis box–triangle test at the leaves, in the
    /// box's frame ([`triangle_box_intersect`]). A margin is applied by growing the half
    /// extents (conservative at edges and corners).
    fn cuboid_hits(&self, box_pose: &Isometry3<f64>, half: &Vector3<f64>) -> bool {
        self.any_triangle_in_box(box_pose, half, |_, _, _| true)
    }

    /// Whether `touches` holds for any triangle that meets the box `half` at `box_pose` (box →
    /// object frame): [`cuboid_hits`](Self::cuboid_hits)'s descent, `touches` asked of each
    /// triangle the box meets (object frame), first hit wins.
    pub(crate) fn any_triangle_in_box(
        &self,
        box_pose: &Isometry3<f64>,
        half: &Vector3<f64>,
        mut touches: impl FnMut(&P, &P, &P) -> bool,
    ) -> bool {
        let rot = box_pose.rotation.to_rotation_matrix();
        let ext = rot.matrix().abs() * half;
        let c = P::from(box_pose.translation.vector);
        // Object frame → box frame (the rows of the box's rotation).
        let to_box = rot.matrix().transpose();
        let local = |p: &P| P::from(to_box * (p - c));
        self.any_triangle(&(c - ext), &(c + ext), |ta, tb, tc| {
            triangle_box_intersect(&local(ta), &local(tb), &local(tc), half) && touches(ta, tb, tc)
        })
    }

    /// Distance from the primitive to the part at `pose` (signed for capsules).
    pub(crate) fn distance(&self, pose: &Isometry3<f64>, s: &Bounded) -> f64 {
        match s.shape {
            Placed::Capsule { a, b, radius } => {
                let la = pose.inverse_transform_point(&a);
                let lb = pose.inverse_transform_point(&b);
                self.segment_distance(&la, &lb) - radius
            }
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } => {
                let (cp, cyl) = crate::shape::parry_cylinder(&a, &b, radius);
                query::distance(pose, &self.mesh, &cp, &cyl).unwrap_or(0.0) - border
            }
            Placed::Cuboid { pose: bp, half } => {
                query::distance(pose, &self.mesh, &bp, &PCuboid::new(half)).unwrap_or(0.0)
            }
        }
    }

    /// Whether the capsule `([a, b], r)` (object frame) touches a triangle: BVH descent with
    /// the capsule's AABB, exact segment–triangle distance at the leaves, first hit wins.
    fn capsule_hits(&self, a: &P, b: &P, r: f64) -> bool {
        let rv = Vector3::repeat(r);
        let r2 = r * r;
        self.any_triangle(&(a.inf(b) - rv), &(a.sup(b) + rv), |ta, tb, tc| {
            segment_triangle_sq(a, b, ta, tb, tc) <= r2
        })
    }

    /// Distance from segment `[a, b]` (object frame) to the mesh surface: BVH descent pruning
    /// every node whose box is farther from the segment's box than the best distance so far.
    fn segment_distance(&self, a: &P, b: &P) -> f64 {
        let (lo, hi) = (a.inf(b), a.sup(b));
        let verts = self.mesh.vertices();
        let idx = self.mesh.indices();
        let mut best = f64::INFINITY;
        self.mesh.bvh().traverse(|node| {
            if aabb_aabb_sq(&lo, &hi, &node.mins(), &node.maxs()) >= best {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                let [i, j, k] = idx[leaf as usize];
                let d = segment_triangle_sq(
                    a,
                    b,
                    &verts[i as usize],
                    &verts[j as usize],
                    &verts[k as usize],
                );
                best = best.min(d);
            }
            TraversalAction::Continue
        });
        best.sqrt()
    }
}

/// Whether `mesh` can be a part: it has triangles, every index names a vertex and every
/// vertex is finite (what [`ObjectGeometry::new`] checks before it builds the BVH).
pub fn check_mesh(mesh: &Mesh) -> Result<(), CollisionError> {
    if mesh.triangles.is_empty() {
        return Err(CollisionError::EmptyMesh);
    }
    let n = mesh.vertices.len();
    if let Some((t, tri)) = mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, tri)| tri.iter().any(|&i| i as usize >= n))
    {
        return Err(CollisionError::BadTriangle {
            triangle: t,
            indices: *tri,
            vertices: n,
        });
    }
    if mesh
        .vertices
        .iter()
        .any(|v| !v.coords.iter().all(|c| c.is_finite()))
    {
        return Err(CollisionError::NonFiniteVertex);
    }
    Ok(())
}
