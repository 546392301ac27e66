//! The part as a solid: its closed mesh oriented outward, with the pseudo-normals that tell
//! inside from outside ([`PartSolid`]), for [`crate::inside`]'s signed distance.

use std::sync::OnceLock;

use nalgebra::Point3;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

type P = Point3<f64>;

/// The part as a solid: its mesh oriented outward with pseudo-normals (the inside test), or
/// `None` when it bounds no solid (not closed, no volume, or parry refuses the orientation).
#[derive(Clone, Debug, Default)]
pub(crate) struct PartSolid {
    mesh: Option<TriMesh>,
}

impl PartSolid {
    /// From the part's mesh (object frame).
    pub(crate) fn of(mesh: &TriMesh) -> PartSolid {
        let mut indices: Vec<[u32; 3]> = mesh.indices().to_vec();
        let vertices = mesh.vertices().to_vec();
        if open_edges(&indices) > 0 {
            return PartSolid { mesh: None };
        }
        let o = vertices.first().copied().unwrap_or_else(P::origin);
        let six_volume: f64 = indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| vertices[k as usize] - o);
                a.dot(&b.cross(&c))
            })
            .sum();
        if six_volume.is_nan() || six_volume.abs() <= 1e-12 {
            return PartSolid { mesh: None };
        }
        if six_volume < 0.0 {
            indices.iter_mut().for_each(|t| t.swap(1, 2));
        }
        PartSolid {
            mesh: TriMesh::with_flags(vertices, indices, TriMeshFlags::ORIENTED).ok(),
        }
    }

    /// `f(x)` of the module documentation (object frame): signed distance to the surface,
    /// positive inside. `None` without an inside test.
    pub(crate) fn signed_distance(&self, x: &P) -> Option<f64> {
        let mesh = self.mesh.as_ref()?;
        let (proj, _) = mesh.project_local_point_and_get_location(x, false);
        let d = (x - proj.point).norm();
        Some(if proj.is_inside { d } else { -d })
    }
}

/// The undirected edges of the triangles `indices` not shared by exactly two of them.
fn open_edges(indices: &[[u32; 3]]) -> usize {
    let mut edges: Vec<(u32, u32)> = indices
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges
        .chunk_by(|a, b| a == b)
        .filter(|run| run.len() != 2)
        .count()
}

/// The part's [`PartSolid`], built on first use and kept with its geometry.
pub(crate) fn solid_of<'a>(cell: &'a OnceLock<PartSolid>, mesh: &TriMesh) -> &'a PartSolid {
    cell.get_or_init(|| PartSolid::of(mesh))
}
