//! Checks of mesh validity used by the generators' tests: closedness, orientation, volume.

use std::collections::BTreeMap;

use pregrasp_geometry::Mesh;

/// Why a mesh is not a closed, consistently oriented surface.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
pub enum TopologyError {
    #[error("triangle {0} repeats a vertex")]
    Degenerate(usize),
    #[error("triangle {0} refers to a missing vertex")]
    BadIndex(usize),
    #[error("directed edge {0}->{1} is used {2} times (expected once)")]
    DirectedEdgeCount(u32, u32, usize),
    #[error("edge {0}->{1} has no opposite edge {1}->{0} (hole or flipped triangle)")]
    Unpaired(u32, u32),
}

/// Checks that every directed edge of the mesh occurs exactly once and its reverse exactly
/// once: the surface is closed (each edge shared by exactly two triangles), edge-manifold,
/// and its triangles are consistently oriented.
pub fn check_closed_oriented(mesh: &Mesh) -> Result<(), TopologyError> {
    let mut edges: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for (i, t) in mesh.triangles.iter().enumerate() {
        if t.iter().any(|&v| v as usize >= mesh.vertices.len()) {
            return Err(TopologyError::BadIndex(i));
        }
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return Err(TopologyError::Degenerate(i));
        }
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &edges {
        if count != 1 {
            return Err(TopologyError::DirectedEdgeCount(a, b, count));
        }
        if !edges.contains_key(&(b, a)) {
            return Err(TopologyError::Unpaired(a, b));
        }
    }
    Ok(())
}

/// Signed volume enclosed by the mesh (m³) by the divergence theorem:
/// `V = Σ (a · (b × c)) / 6` over triangles `a b c`. Positive for a closed mesh with outward
/// (counter-clockwise seen from outside) triangles.
pub fn signed_volume(mesh: &Mesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize].coords);
            a.dot(&b.cross(&c))
        })
        .sum::<f64>()
        / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    fn tetra() -> Mesh {
        let v = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        Mesh::new(v, vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    }

    #[test]
    fn unit_tetrahedron_is_closed_with_volume_one_sixth() {
        let m = tetra();
        check_closed_oriented(&m).unwrap();
        assert!((signed_volume(&m) - 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn flipped_or_missing_triangle_is_detected() {
        let mut m = tetra();
        m.triangles[0] = [0, 1, 2];
        assert!(matches!(
            check_closed_oriented(&m),
            Err(TopologyError::DirectedEdgeCount(..))
        ));
        let mut m = tetra();
        m.triangles.pop();
        assert!(matches!(
            check_closed_oriented(&m),
            Err(TopologyError::Unpaired(..))
        ));
    }
}
