//! Mass properties of a closed triangle mesh: volume and centre of mass from signed-tetrahedron
//! integrals (each triangle with the origin spans a tetrahedron; their signed volumes add up to
//! the enclosed volume whatever the origin, and so do their first moments).

use pregrasp_geometry::{Mesh, Point, Vector};

/// Volume and centre of mass of a solid of uniform density bounded by a mesh.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MassProperties {
    /// Enclosed volume (m³), > 0 (the absolute value: inward-wound meshes are accepted).
    pub volume: f64,
    /// Centre of mass in the mesh's frame (m).
    pub centroid: Point,
}

/// Why a mesh has no usable mass properties.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MassError {
    #[error("the mesh encloses no volume ({volume:.3e} m³): it is not a closed solid")]
    NoVolume { volume: f64 },
    #[error(
        "the mesh is not a closed surface ({open} of its edges do not join exactly two \
         triangles): its volume and centre of mass are unknown — close it, or give object.mass \
         and check the result"
    )]
    NotClosed { open: usize },
}

impl MassProperties {
    /// Volume and centroid of the solid `mesh` bounds. The mesh must be closed and consistently
    /// oriented (either way round); otherwise the integrals mean nothing, and a mesh enclosing
    /// less than 1 mm³ is refused.
    pub fn from_mesh(mesh: &Mesh) -> Result<MassProperties, MassError> {
        let open = open_edges(mesh);
        if open > 0 {
            return Err(MassError::NotClosed { open });
        }
        // Work relative to a vertex of the mesh, so large coordinates lose no precision.
        let origin = mesh.vertices.first().copied().unwrap_or_else(Point::origin);
        let mut six_volume = 0.0;
        let mut moment = Vector::zeros(); // Σ 6·V_i · (a + b + c) (relative to `origin`)
        for t in &mesh.triangles {
            let a = mesh.vertices[t[0] as usize] - origin;
            let b = mesh.vertices[t[1] as usize] - origin;
            let c = mesh.vertices[t[2] as usize] - origin;
            let v6 = a.dot(&b.cross(&c));
            six_volume += v6;
            moment += v6 * (a + b + c);
        }
        let volume = six_volume / 6.0;
        if !volume.is_finite() || volume.abs() < 1e-9 {
            return Err(MassError::NoVolume { volume });
        }
        // Centroid of a tetrahedron (0, a, b, c) is (a + b + c) / 4.
        let centroid = origin + moment / (4.0 * six_volume);
        Ok(MassProperties {
            volume: volume.abs(),
            centroid,
        })
    }
}

/// The undirected edges of `mesh` not shared by exactly two triangles (0 for a closed surface).
pub fn open_edges(mesh: &Mesh) -> usize {
    pregrasp_geometry::mesh::open_edges(&mesh.triangles)
}

#[cfg(test)]
mod tests {
    use super::open_edges;
    use pregrasp_geometry::shapes::cuboid;
    use pregrasp_geometry::Point;

    /// A closed box has no open edge; one triangle taken out opens its three edges, two
    /// neighbours taken out open the four edges around them.
    #[test]
    fn open_edges_counts_the_edges_not_joining_two_triangles() {
        let closed = cuboid(Point::new(0.0, 0.0, 0.0), Point::new(0.3, 0.2, 0.1));
        assert_eq!(open_edges(&closed), 0);
        let mut holed = closed.clone();
        holed.triangles.remove(0);
        assert_eq!(open_edges(&holed), 3);
        // A triangle sharing an edge with the first: both out, the four edges around them open.
        let shared = |a: &[u32; 3], b: &[u32; 3]| a.iter().filter(|v| b.contains(v)).count() == 2;
        let next = (1..closed.triangles.len())
            .find(|&k| shared(&closed.triangles[0], &closed.triangles[k]))
            .expect("a closed surface's triangle has neighbours");
        let mut holed = closed.clone();
        holed.triangles.remove(next);
        holed.triangles.remove(0);
        assert_eq!(open_edges(&holed), 4);
    }
}
