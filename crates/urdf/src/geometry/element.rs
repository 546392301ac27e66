//! One `<collision>` element of a description and the points it stands for in its link frame:
//! a mesh's vertices (scale and origin applied) or a primitive's polytope. The pieces of the
//! collision model are made from them ([`element_piece`]), and a cache entry is checked
//! against them (`entry_check.rs`).

use std::path::PathBuf;

use nalgebra::{Isometry3, Point3};

use super::mesh::{self, LinkMesh};
use super::pieces::hull_piece;
use super::primitives::{box_corners, capsule_vertices, cylinder_vertices, sphere_vertices};
use super::values::check_extent;
use crate::error::UrdfError;
use crate::model::UrdfModel;

/// One `<collision>` element with its mesh file read.
#[derive(Clone, Debug)]
pub struct Element {
    /// The link.
    pub link: String,
    /// Index of the element among the link's `<collision>` elements.
    pub index: usize,
    /// `<origin>`: the element frame in the link frame.
    pub origin: Isometry3<f64>,
    /// The geometry as parsed.
    pub geometry: urdf_rs::Geometry,
    /// For a mesh: the resolved file and its bytes.
    pub mesh: Option<(PathBuf, Vec<u8>)>,
}

/// The mesh of a mesh element in the link frame (`None` for a primitive).
pub fn element_mesh(model: &UrdfModel, e: &Element) -> Result<Option<LinkMesh>, UrdfError> {
    let (Some((path, bytes)), urdf_rs::Geometry::Mesh { scale, .. }) = (&e.mesh, &e.geometry)
    else {
        return Ok(None);
    };
    let scale = scale.map_or([1.0; 3], |s| s.0);
    let bad = |message: String| UrdfError::Mesh {
        file: model.source().to_string(),
        link: e.link.clone(),
        path: path.display().to_string(),
        message,
    };
    let m = mesh::parse(bytes, path, scale, &e.origin).map_err(|err| bad(err.to_string()))?;
    if m.vertices.is_empty() {
        return Err(bad("no vertices".to_string()));
    }
    let what = format!("mesh {}", path.display());
    check_extent(model.source(), &e.link, &what, &m.vertices)?;
    Ok(Some(m))
}

/// The piece of one element in the link frame: the hull of its mesh, or the polytope of its
/// primitive ([`super::primitives`]) placed by its origin.
pub fn element_piece(model: &UrdfModel, e: &Element) -> Result<Vec<Point3<f64>>, UrdfError> {
    let (points, is_mesh) = element_points(model, e)?;
    Ok(if is_mesh { hull_piece(&points) } else { points })
}

/// The points of one element in the link frame, and whether they are a mesh's vertices (of
/// which the piece is the hull) or already a primitive's polytope.
pub fn element_points(
    model: &UrdfModel,
    e: &Element,
) -> Result<(Vec<Point3<f64>>, bool), UrdfError> {
    use urdf_rs::Geometry as G;
    if let Some(m) = element_mesh(model, e)? {
        return Ok((m.vertices, true));
    }
    let local = match &e.geometry {
        G::Box { size } => box_corners(size.0),
        G::Cylinder { radius, length } => cylinder_vertices(*radius, *length),
        G::Capsule { radius, length } => capsule_vertices(*radius, *length),
        G::Sphere { radius } => sphere_vertices(*radius),
        G::Mesh { .. } => unreachable!("meshes handled above"),
    };
    let piece: Vec<Point3<f64>> = local.iter().map(|p| e.origin * p).collect();
    check_extent(model.source(), &e.link, "the element", &piece)?;
    Ok((piece, false))
}
