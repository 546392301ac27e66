//! The part's mass and centre of mass, as the grip check of a plan needs them.

use std::fmt;

use nalgebra::Point3;
use pregrasp_geometry::Mesh;

use crate::error::PhysicsError;
use crate::mass::MassProperties;

/// The part's mass and centre of mass.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PartMass {
    /// kg.
    pub mass: f64,
    /// Where the mass comes from, for reports (written by its `Display`).
    #[serde(serialize_with = "crate::words::as_text")]
    pub source: MassSource,
    /// Volume enclosed by the mesh (m³).
    pub volume: f64,
    /// Centre of mass in the object frame (uniform density), m.
    pub centroid: Point3<f64>,
    /// The points of the part that can touch a plane (its convex hull's vertices), object frame.
    #[serde(skip)]
    pub hull: Vec<Point3<f64>>,
}

/// Where [`PartMass::mass`] comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MassSource {
    /// Given by the caller, who names it (`"--mass"`).
    Given(&'static str),
    /// The plan's `object.mass` (the scene's).
    Plan,
    /// `density` (kg/m³) × the mesh's `volume` (m³): no mass was given.
    Density { density: f64, volume: f64 },
}

impl fmt::Display for MassSource {
    /// `--mass`, `plan object.mass`, `700 kg/m³ × mesh volume 0.004590 m³ (no mass given)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MassSource::Given(label) => f.write_str(label),
            MassSource::Plan => f.write_str("plan object.mass"),
            MassSource::Density { density, volume } => write!(
                f,
                "{density} kg/m³ × mesh volume {volume:.6} m³ (no mass given)"
            ),
        }
    }
}

impl PartMass {
    /// Mass from `given` (a mass and the label that names it, e.g. `--mass`), else the plan's
    /// `plan_mass` (its `object.mass`), else `density` × the mesh's volume; centre of mass from
    /// the mesh.
    pub fn resolve(
        plan_mass: Option<f64>,
        mesh: &Mesh,
        given: Option<(f64, &'static str)>,
        density: f64,
    ) -> Result<PartMass, PhysicsError> {
        PartMass::resolve_with_hull(plan_mass, mesh, None, given, density)
    }

    /// [`PartMass::resolve`] with the vertices of the mesh's convex hull given by a caller
    /// that has them (the planner computed the hull for Algorithm 1); computed when `None`.
    pub fn resolve_with_hull(
        plan_mass: Option<f64>,
        mesh: &Mesh,
        hull: Option<&[Point3<f64>]>,
        given: Option<(f64, &'static str)>,
        density: f64,
    ) -> Result<PartMass, PhysicsError> {
        let props = MassProperties::from_mesh(mesh)?;
        let (mass, source) = match (given, plan_mass) {
            (Some((m, label)), _) => (m, MassSource::Given(label)),
            (None, Some(m)) => (m, MassSource::Plan),
            (None, None) => (
                density * props.volume,
                MassSource::Density {
                    density,
                    volume: props.volume,
                },
            ),
        };
        if !(mass.is_finite() && mass > 0.0 && mass <= pregrasp_model::MAX_MASS) {
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
