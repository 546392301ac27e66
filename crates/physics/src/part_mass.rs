//! The part's mass and centre of mass, as the grip check of a plan needs them.

use nalgebra::Point3;
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;

use crate::error::PhysicsError;
use crate::mass::MassProperties;

/// The part's mass and centre of mass.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PartMass {
    /// kg.
    pub mass: f64,
    /// Where the mass comes from, for reports: `"--mass"`, `"plan object.mass"` or
    /// `"700 kg/m³ × mesh volume 0.00459 m³"`.
    pub source: String,
    /// Volume enclosed by the mesh (m³).
    pub volume: f64,
    /// Centre of mass in the object frame (uniform density), m.
    pub centroid: Point3<f64>,
    /// The points of the part that can touch a plane (its convex hull's vertices), object frame.
    #[serde(skip)]
    pub hull: Vec<Point3<f64>>,
}

impl PartMass {
    /// Mass from `given` (e.g. `--mass`, labelled `given_label`), else the plan's `object.mass`,
    /// else `settings.density` × the mesh's volume; centre of mass from the mesh.
    pub fn resolve(
        file: &PlanFile,
        mesh: &Mesh,
        given: Option<(f64, &str)>,
        density: f64,
    ) -> Result<PartMass, PhysicsError> {
        PartMass::resolve_with_hull(file, mesh, None, given, density)
    }

    /// [`PartMass::resolve`] with the vertices of the mesh's convex hull given by a caller
    /// that has them (the planner computed the hull for Algorithm 1); computed when `None`.
    pub fn resolve_with_hull(
        file: &PlanFile,
        mesh: &Mesh,
        hull: Option<&[Point3<f64>]>,
        given: Option<(f64, &str)>,
        density: f64,
    ) -> Result<PartMass, PhysicsError> {
        let props = MassProperties::from_mesh(mesh)?;
        let (mass, source) = match (given, file.object.mass) {
            (Some((m, label)), _) => (m, label.to_string()),
            (None, Some(m)) => (m, "plan object.mass".to_string()),
            (None, None) => (
                density * props.volume,
                format!(
                    "{density} kg/m³ × mesh volume {:.6} m³ (no mass given)",
                    props.volume
                ),
            ),
        };
        if !(mass.is_finite() && mass > 0.0 && mass <= pregrasp_io::scene::MAX_MASS) {
            return Err(PhysicsError::BadMass(mass));
        }
        let hull = match hull {
            Some(vertices) => vertices.to_vec(),
            None => pregrasp_geometry::ConvexHull::of_mesh(mesh)
                .map(|h| h.vertices)
                .unwrap_or_else(|_| mesh.vertices.clone()),
        };
        Ok(PartMass {
            mass,
            source,
            volume: props.volume,
            centroid: props.centroid,
            hull,
        })
    }
}
