//! The values of a `<collision>` element, checked before any geometry is made from them.
//!
//! A description is input like any other: a box `size="1e308 1 1"` would make a piece that
//! every later step (hulls, bounding spheres, the sampling of self-collision pairs) handles
//! for minutes, a `scale="nan 1 1"` a mesh of NaNs. Each number must be finite and within
//! what a robot link can measure ([`MAX_LINK_EXTENT`]); sizes and radii must not be negative
//! (zero is allowed: a flat or empty element simply gives no piece with volume); a mesh scale
//! may be negative (a mirrored mesh) but not zero. The whole element, placed by its
//! `<origin>`, must lie within [`MAX_LINK_EXTENT`] of the link frame ([`check_extent`]).

use nalgebra::Point3;

use crate::chain::number;
use crate::error::UrdfError;

/// How far (m) from its link frame any collision geometry may reach: 100 m, a hundred times
/// the largest industrial arm's reach.
pub const MAX_LINK_EXTENT: f64 = 100.0;

/// Checks the numbers of one element of `link` (see the module documentation).
pub fn check_element(
    file: &str,
    link: &str,
    geometry: &urdf_rs::Geometry,
) -> Result<(), UrdfError> {
    use urdf_rs::Geometry as G;
    let bad = |problem: String| UrdfError::BadCollision {
        file: file.to_string(),
        link: link.to_string(),
        problem,
    };
    let size = |what: &str, v: f64| -> Result<(), UrdfError> {
        if v.is_finite() && (0.0..=MAX_LINK_EXTENT).contains(&v) {
            Ok(())
        } else {
            Err(bad(format!(
                "{what} {}: must be finite, at least 0 and at most {MAX_LINK_EXTENT} m",
                number(v)
            )))
        }
    };
    match geometry {
        G::Box { size: s } => s.0.iter().try_for_each(|&v| size("box size", v)),
        G::Cylinder { radius, length } | G::Capsule { radius, length } => {
            let kind = if matches!(geometry, G::Cylinder { .. }) {
                "cylinder"
            } else {
                "capsule"
            };
            size(&format!("{kind} radius"), *radius)?;
            size(&format!("{kind} length"), *length)
        }
        G::Sphere { radius } => size("sphere radius", *radius),
        G::Mesh { filename, scale } => {
            if filename.trim().is_empty() {
                return Err(bad("<mesh> has an empty filename".to_string()));
            }
            let s = scale.map_or([1.0; 3], |s| s.0);
            if s.iter()
                .any(|v| !v.is_finite() || *v == 0.0 || v.abs() > 1e4)
            {
                return Err(bad(format!(
                    "<mesh filename=\"{filename}\" scale=\"{} {} {}\">: each factor must be \
                     finite, not zero and at most 10 000 in size",
                    number(s[0]),
                    number(s[1]),
                    number(s[2])
                )));
            }
            Ok(())
        }
    }
}

/// Checks that every point of an element's geometry in the link frame is finite and within
/// [`MAX_LINK_EXTENT`] of the link's origin.
pub fn check_extent(
    file: &str,
    link: &str,
    what: &str,
    points: &[Point3<f64>],
) -> Result<(), UrdfError> {
    let far = points
        .iter()
        .map(|p| p.coords.amax())
        .fold(
            0.0,
            |m: f64, v| if v.is_nan() { f64::INFINITY } else { m.max(v) },
        );
    if far <= MAX_LINK_EXTENT {
        return Ok(());
    }
    Err(UrdfError::BadCollision {
        file: file.to_string(),
        link: link.to_string(),
        problem: format!(
            "{what} reaches {} m from the link frame (at most {MAX_LINK_EXTENT} m)",
            number(far)
        ),
    })
}
