//! Prisms: a planar outline with holes extruded along `z`.

use nalgebra::{Point2, Point3};
use pregrasp_geometry::Mesh;

use crate::triangulate::{signed_area, triangulate, TriangulationError};

/// Extrudes the region inside `outline` and outside every ring of `holes` (x-y plane, metres)
/// from `z = 0` to `z = thickness`.
///
/// The result is closed and consistently oriented: every edge is shared by exactly two
/// triangles that traverse it in opposite directions, and triangles are counter-clockwise
/// seen from outside (outward normals). Its volume is `area × thickness`, where `area` is
/// the outline's area minus the holes'. Vertex `k` of the concatenated rings
/// (`outline ++ holes[0] ++ …`) is mesh vertex `k` at `z = 0` and `k + n` at `z = thickness`.
///
/// ```
/// use nalgebra::Point2;
/// use pregrasp_examples::{extrude, mesh_check::signed_volume};
/// let square = |c: f64, h: f64| vec![
///     Point2::new(c - h, c - h), Point2::new(c + h, c - h),
///     Point2::new(c + h, c + h), Point2::new(c - h, c + h),
/// ];
/// // A 1 m square frame with a 0.5 m square window, 0.1 m thick: 0.075 m³.
/// let frame = extrude(&square(0.5, 0.5), &[square(0.5, 0.25)], 0.1);
/// assert!((signed_volume(&frame) - 0.075).abs() < 1e-15);
/// ```
///
/// # Panics
/// When the rings are not a valid polygon with holes or `thickness` is not positive and
/// finite; [`try_extrude`] reports these as errors instead.
pub fn extrude(outline: &[Point2<f64>], holes: &[Vec<Point2<f64>>], thickness: f64) -> Mesh {
    try_extrude(outline, holes, thickness).unwrap_or_else(|err| panic!("extrude: {err}"))
}

/// Errors of [`try_extrude`].
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ExtrudeError {
    #[error("thickness must be positive and finite, got {0}")]
    Thickness(f64),
    #[error(transparent)]
    Triangulation(#[from] TriangulationError),
}

/// [`extrude`], reporting invalid input as an error.
pub fn try_extrude(
    outline: &[Point2<f64>],
    holes: &[Vec<Point2<f64>>],
    thickness: f64,
) -> Result<Mesh, ExtrudeError> {
    if !(thickness > 0.0 && thickness.is_finite()) {
        return Err(ExtrudeError::Thickness(thickness));
    }
    let cap = triangulate(outline, holes)?;
    let rings: Vec<&[Point2<f64>]> = std::iter::once(outline)
        .chain(holes.iter().map(Vec::as_slice))
        .collect();
    let n = rings.iter().map(|r| r.len()).sum::<usize>() as u32;
    let mut vertices = Vec::with_capacity(2 * n as usize);
    for z in [0.0, thickness] {
        vertices.extend(
            rings
                .iter()
                .flat_map(|r| r.iter())
                .map(|p| Point3::new(p.x, p.y, z)),
        );
    }
    let mut triangles = Vec::with_capacity(2 * cap.len() + 2 * n as usize);
    // Top cap as triangulated (counter-clockwise seen from +z), bottom cap reversed.
    triangles.extend(cap.iter().map(|t| [t[0] + n, t[1] + n, t[2] + n]));
    triangles.extend(cap.iter().map(|t| [t[0], t[2], t[1]]));
    // Side walls: walk each ring with the solid on the left (outline counter-clockwise,
    // holes clockwise); the outward normal of the wall is then on the right of each edge.
    let mut first = 0u32;
    for (r, ring) in rings.iter().enumerate() {
        let len = ring.len() as u32;
        let solid_on_left = (r == 0) == (signed_area(ring) > 0.0);
        for k in 0..len {
            let (mut a, mut b) = (first + k, first + (k + 1) % len);
            if !solid_on_left {
                std::mem::swap(&mut a, &mut b);
            }
            triangles.push([a, b, b + n]);
            triangles.push([a, b + n, a + n]);
        }
        first += len;
    }
    Ok(Mesh::new(vertices, triangles))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_check::{check_closed_oriented, signed_volume};

    fn rect(x0: f64, y0: f64, w: f64, h: f64) -> Vec<Point2<f64>> {
        vec![
            Point2::new(x0, y0),
            Point2::new(x0 + w, y0),
            Point2::new(x0 + w, y0 + h),
            Point2::new(x0, y0 + h),
        ]
    }

    #[test]
    fn square_with_square_hole_has_exact_volume_and_is_closed() {
        let mesh = extrude(&rect(0.0, 0.0, 0.5, 0.5), &[rect(0.1, 0.2, 0.2, 0.2)], 0.02);
        check_closed_oriented(&mesh).unwrap();
        let expected = (0.25 - 0.04) * 0.02;
        assert!(
            (signed_volume(&mesh) - expected).abs() < 1e-15,
            "{}",
            signed_volume(&mesh)
        );
        assert_eq!(mesh.vertices.len(), 16);
    }

    #[test]
    fn orientation_of_the_input_rings_does_not_matter() {
        let mut outer = rect(0.0, 0.0, 1.0, 0.3);
        outer.reverse();
        let hole = rect(0.2, 0.1, 0.1, 0.1); // counter-clockwise hole
        let mesh = extrude(&outer, &[hole], 0.01);
        check_closed_oriented(&mesh).unwrap();
        assert!((signed_volume(&mesh) - (0.3 - 0.01) * 0.01).abs() < 1e-15);
    }

    #[test]
    fn bad_thickness_is_an_error() {
        assert_eq!(
            try_extrude(&rect(0.0, 0.0, 1.0, 1.0), &[], 0.0),
            Err(ExtrudeError::Thickness(0.0))
        );
        assert!(try_extrude(&rect(0.0, 0.0, 1.0, 1.0), &[], f64::NAN).is_err());
    }
}
