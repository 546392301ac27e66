//! Will the pinch hold? The quasi-static check of `μ_rot` (crate `pregrasp-physics`, paper
//! condition c5: the table carries the part's weight while the fingertip pinch turns it) applied
//! to the μ_rot of every candidate whose straight lines hold, before its transits are planned
//! ([`crate::paths::integrated_path`]'s `accept`).
//!
//! Each plan gets the plan file's `physics` object (required and recommended grip force,
//! friction use at the pads and the support). With `[physics] reject = true` (the default) a
//! candidate whose rotation the 2F-85 cannot hold — more than 235 N with the safety factor, or
//! no force at all — or that slides at the support is rejected with that reason. A part whose
//! mesh is not a closed solid has no known centre of mass: its plans are not checked, and the
//! report says so, rather than being judged on made-up numbers.

use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{PhysicsJson, PlanFile, PlanJson};
use pregrasp_io::scene::Scene;
use pregrasp_physics::{analyse_one, screen_one, PartMass, PhysicsSettings};

/// The settings and the part's mass properties, computed once per scene.
pub struct HoldCheck {
    part: Result<PartMass, String>,
    settings: PhysicsSettings,
    /// Each robot's name and its gripper's grip force range (N).
    grip_force: [(String, (f64, f64)); 2],
    reject: bool,
}

/// The check of one plan.
pub struct HoldResult {
    /// The plan file's `physics` object.
    pub json: PhysicsJson,
    /// Why the candidate is rejected, when it does not hold and `[physics] reject` is on.
    pub rejection: Option<String>,
}

impl HoldCheck {
    /// `header`: the plan file being written (its `object.mass` and `object.mesh`); `hull`:
    /// the vertices of the mesh's convex hull, when the caller has them.
    pub fn new(
        scene: &Scene,
        header: &PlanFile,
        mesh: &Mesh,
        hull: Option<&[nalgebra::Point3<f64>]>,
    ) -> HoldCheck {
        let settings = PhysicsSettings::default().with_scene(&scene.physics);
        let part = PartMass::resolve_with_hull(header, mesh, hull, None, settings.density)
            .map_err(|e| format!("physics: the rotation is not checked: {e}"));
        HoldCheck {
            part,
            settings,
            grip_force: scene
                .robots
                .each_ref()
                .map(|r| (r.name.clone(), r.gripper_model().grip_force_range())),
            reject: scene.physics.reject,
        }
    }

    /// Why no plan gets a `physics` object, if none does (the mesh has no mass properties).
    pub fn unavailable(&self) -> Option<&str> {
        self.part.as_ref().err().map(String::as_str)
    }

    /// Checks `plan` as a plan of a file with header `header`. `None` when the part's mass is
    /// unknown, or when the analysis cannot run on the plan (which the plan checker would have
    /// refused).
    pub fn check(&self, header: &PlanFile, plan: &PlanJson) -> Option<HoldResult> {
        let part = self.part.as_ref().ok()?;
        // A rotation that will be refused needs no more than its first failing state.
        let analyse = if self.reject { screen_one } else { analyse_one };
        // The supportive arm's gripper pinches: its force range.
        let mut settings = self.settings;
        if let Some((_, range)) = self.grip_force.iter().find(|(n, _)| *n == plan.supportive) {
            settings.grip_force = *range;
        }
        let report = analyse(header, plan, 0, part, &settings).ok()?;
        Some(HoldResult {
            json: report.to_json(),
            rejection: if self.reject {
                report.rejection()
            } else {
                None
            },
        })
    }
}
