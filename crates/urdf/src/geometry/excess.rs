//! How far the pieces reach outside the geometry they stand for (the price of convexity).
//!
//! For each piece, points are sampled on its surface: every hull triangle gets the
//! barycentric grid `a + (i/n)(b − a) + (j/n)(c − a)`, `i + j ≤ n`, with
//! `n = ⌈longest edge / spacing⌉` (at most 64). Each sample's distance to the element's
//! solid is measured: to the mesh surface (parry `TriMesh`, unsigned: a hull surface point is
//! never inside the mesh's solid, since the hull contains it), or to the primitive solid
//! (parry's cuboid, cylinder — parry's axis y turned onto URDF's z —, ball, capsule). The
//! **excess** of a piece is the largest such distance (m); the **mean** is the
//! area-weighted mean over the triangles of each triangle's sample mean. A piece equal to its
//! geometry (a box) has excess 0.

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, TriMesh};

use super::load::{collision_elements, element_mesh, GeometryOptions};
use super::pieces::max_outside;
use super::types::UrdfGeometry;
use crate::error::UrdfError;
use crate::model::UrdfModel;

/// Distance from a point (link frame) to an element's geometry.
type Distance = Box<dyn Fn(&Point3<f64>) -> f64>;

/// Surface sampling step (m).
pub const EXCESS_SPACING: f64 = 0.002;

/// The excess of one piece.
#[derive(Clone, Debug, PartialEq)]
pub struct PieceExcess {
    /// The link.
    pub link: String,
    /// The `<collision>` element index within the link.
    pub element: usize,
    /// `"mesh"`, `"box"`, `"cylinder"`, `"sphere"` or `"capsule"`.
    pub kind: &'static str,
    /// Vertices of the element's mesh (0 for a primitive).
    pub mesh_vertices: usize,
    /// Vertices of the piece.
    pub piece_vertices: usize,
    /// Largest distance from the piece's surface to the element (m).
    pub max: f64,
    /// Area-weighted mean of that distance (m).
    pub mean: f64,
    /// Largest distance of a mesh vertex outside the piece (m; ≤ 0: all inside).
    pub vertex_outside: f64,
}

/// The excess of every piece of `geometry`, derived from `model` with `opts` (the meshes are
/// read again).
pub fn measure_excess(
    model: &UrdfModel,
    geometry: &UrdfGeometry,
    opts: &GeometryOptions,
) -> Result<Vec<PieceExcess>, UrdfError> {
    use urdf_rs::Geometry as G;
    let elements = collision_elements(model, opts)?;
    let mut out = Vec::new();
    for lp in &geometry.links {
        for (piece, &index) in lp.pieces.iter().zip(&lp.elements) {
            let Some(e) = elements
                .iter()
                .find(|e| e.link == lp.link && e.index == index)
            else {
                continue;
            };
            let mesh = element_mesh(model, e)?;
            let along_z =
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
            let turned = e.origin * Isometry3::from_parts(Default::default(), along_z);
            let (kind, dist): (&'static str, Distance) = match (&e.geometry, &mesh) {
                (_, Some(m)) => {
                    let tri =
                        TriMesh::new(m.vertices.clone(), m.triangles.clone()).map_err(|err| {
                            UrdfError::Mesh {
                                file: model.source().to_string(),
                                link: lp.link.clone(),
                                path: e
                                    .mesh
                                    .as_ref()
                                    .map(|m| m.0.display().to_string())
                                    .unwrap_or_default(),
                                message: err.to_string(),
                            }
                        })?;
                    (
                        "mesh",
                        Box::new(move |p| tri.distance_to_local_point(p, false)),
                    )
                }
                (G::Box { size }, None) => {
                    let s = Cuboid::new(Vector3::from(size.0) / 2.0);
                    let o = e.origin;
                    ("box", Box::new(move |p| s.distance_to_point(&o, p, true)))
                }
                (G::Cylinder { radius, length }, None) => {
                    let s = Cylinder::new(length / 2.0, *radius);
                    (
                        "cylinder",
                        Box::new(move |p| s.distance_to_point(&turned, p, true)),
                    )
                }
                (G::Sphere { radius }, None) => {
                    let s = Ball::new(*radius);
                    let o = e.origin;
                    (
                        "sphere",
                        Box::new(move |p| s.distance_to_point(&o, p, true)),
                    )
                }
                (G::Capsule { radius, length }, None) => {
                    let s = Capsule::new_z(length / 2.0, *radius);
                    let o = e.origin;
                    (
                        "capsule",
                        Box::new(move |p| s.distance_to_point(&o, p, true)),
                    )
                }
                (G::Mesh { .. }, None) => unreachable!("a mesh element has its mesh"),
            };
            let (max, mean) = surface_distance(piece, &*dist);
            out.push(PieceExcess {
                link: lp.link.clone(),
                element: index,
                kind,
                mesh_vertices: mesh.as_ref().map_or(0, |m| m.vertices.len()),
                piece_vertices: piece.len(),
                max,
                mean,
                vertex_outside: mesh
                    .as_ref()
                    .map_or(f64::NEG_INFINITY, |m| max_outside(piece, &m.vertices)),
            });
        }
    }
    Ok(out)
}

/// Max and area-weighted mean of `dist` over the surface samples of the hull of `piece`.
fn surface_distance(piece: &[Point3<f64>], dist: &dyn Fn(&Point3<f64>) -> f64) -> (f64, f64) {
    let Ok((v, tris)) = parry3d_f64::transformation::try_convex_hull(piece) else {
        return (f64::NAN, f64::NAN);
    };
    let (mut max, mut weighted, mut area_sum) = (0.0f64, 0.0, 0.0);
    for t in &tris {
        let [a, b, c] = t.map(|i| v[i as usize]);
        let area = (b - a).cross(&(c - a)).norm() / 2.0;
        let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
        let n = ((longest / EXCESS_SPACING).ceil() as usize).clamp(1, 64);
        let (mut sum, mut count) = (0.0, 0usize);
        for i in 0..=n {
            for j in 0..=n - i {
                let p = a + (b - a) * (i as f64 / n as f64) + (c - a) * (j as f64 / n as f64);
                let d = dist(&p);
                max = max.max(d);
                sum += d;
                count += 1;
            }
        }
        weighted += area * sum / count as f64;
        area_sum += area;
    }
    (
        max,
        if area_sum > 0.0 {
            weighted / area_sum
        } else {
            0.0
        },
    )
}
