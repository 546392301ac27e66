//! Will the pinch hold? The quasi-static check of `μ_rot` (crate `pregrasp-physics`, paper
//! condition c5: the table carries the part's weight while the fingertip pinch turns it) applied
//! to the μ_rot of every candidate whose straight lines hold, before its transits are planned
//! ([`crate::paths::integrated_path`]'s `accept`).
//!
//! Each plan gets the plan file's `physics` object (required and recommended grip force,
//! friction use at the pads and the support; [`physics_json`]). With `[physics] reject = true`
//! (the default) a candidate whose rotation the 2F-85 cannot hold — more than 235 N with the
//! safety factor, or no force at all — or that slides at the support is rejected with that
//! reason. A part whose mesh is not a closed solid has no known centre of mass: its plans are
//! not checked, and the report says so ([`Unchecked`]), rather than being judged on made-up
//! numbers.
//!
//! This is where physics meets the scene and the plan file: [`physics_settings`] applies a
//! scene's `[physics]` table, [`physics_json`] writes a report as the file's `physics` object.

use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PhysicsJson;
use pregrasp_io::scene::{PhysicsParams, Scene};
use pregrasp_model::{Plan, PlanSet};
use pregrasp_physics::{
    analyse_one, screen_one, PartMass, PhysicsError, PhysicsSettings, PlanPhysics, StateReport,
    Unheld,
};

/// The settings and the part's mass properties, computed once per scene.
pub struct HoldCheck {
    part: Result<PartMass, PhysicsError>,
    settings: PhysicsSettings,
    /// Each arm's gripper's grip force range (N), in the scene's order.
    grip_force: [(f64, f64); 2],
    reject: bool,
}

/// The check of one plan.
pub struct HoldResult {
    /// The plan file's `physics` object.
    pub json: PhysicsJson,
    /// Why the candidate is rejected, when it does not hold and `[physics] reject` is on.
    pub rejection: Option<Unheld>,
}

/// Why a run's plans carry no `physics` object: the part has no mass properties (its mesh is
/// not a closed solid, or its mass is out of range).
#[derive(Debug, thiserror::Error)]
#[error("physics: the rotation is not checked: {0}")]
pub struct Unchecked(#[from] pub PhysicsError);

impl HoldCheck {
    /// The check of `scene`'s part (its `object.mass`, else its density × the volume of
    /// `mesh`); `hull`: the vertices of the mesh's convex hull, when the caller has them.
    pub fn new(scene: &Scene, mesh: &Mesh, hull: Option<&[nalgebra::Point3<f64>]>) -> HoldCheck {
        let settings = physics_settings(&scene.physics);
        let part =
            PartMass::resolve_with_hull(scene.object.mass, mesh, hull, None, settings.density);
        HoldCheck {
            part,
            settings,
            grip_force: scene
                .robots
                .each_ref()
                .map(|r| r.gripper_model().grip_force_range()),
            reject: scene.physics.reject,
        }
    }

    /// Why no plan gets a `physics` object, if none does (the mesh has no mass properties).
    pub fn unavailable(&self) -> Option<&PhysicsError> {
        self.part.as_ref().err()
    }

    /// [`HoldCheck::unavailable`], kept for the report once the checks are done.
    pub fn into_unchecked(self) -> Option<Unchecked> {
        self.part.err().map(Unchecked)
    }

    /// The carry check of `ctx`'s scene with these mass properties and settings.
    pub fn carry_check(&self, ctx: &crate::context::PlanningContext) -> crate::carry::CarryCheck {
        crate::carry::CarryCheck::new(ctx, self.part.as_ref().ok(), &self.settings)
    }

    /// Checks `plan` as a plan of `set` (its candidates, P_init, G_s, support height and lift;
    /// its own `plans` are not read). The poses are judged as given: a caller holding poses
    /// that are about to be written passes them through [`pregrasp_model::as_written`], so
    /// that a reader of the file finds the same numbers. `None` when the part's mass is
    /// unknown, or when the analysis cannot run on the plan (which the plan checker would have
    /// refused).
    pub fn check(&self, set: &PlanSet, plan: &Plan) -> Option<HoldResult> {
        let part = self.part.as_ref().ok()?;
        // A rotation that will be refused needs no more than its first failing state.
        let analyse = if self.reject { screen_one } else { analyse_one };
        // The supportive arm's gripper pinches: its force range.
        let mut settings = self.settings;
        if let Some(range) = self.grip_force.get(plan.roles.supportive) {
            settings.grip_force = *range;
        }
        let report = analyse(set, plan, 0, part, &settings).ok()?;
        Some(HoldResult {
            json: physics_json(&report),
            rejection: if self.reject {
                report.rejection()
            } else {
                None
            },
        })
    }
}

/// The grip check's settings for a scene: the defaults with its `[physics]` values on top (the
/// scene loader has checked their ranges).
pub fn physics_settings(params: &PhysicsParams) -> PhysicsSettings {
    let mut settings = PhysicsSettings::default();
    let set = |field: &mut f64, value: Option<f64>| {
        if let Some(v) = value {
            *field = v;
        }
    };
    set(&mut settings.mu_pad, params.mu_pad);
    set(&mut settings.mu_support, params.mu_support);
    set(&mut settings.safety_factor, params.safety_factor);
    set(&mut settings.pad_torsion_radius, params.pad_torsion_radius);
    set(&mut settings.density, params.density);
    set(&mut settings.max_twist_arm, params.max_twist_arm);
    settings
}

/// The plan file's `physics` object of a plan's check: the worst state's numbers and the
/// largest friction use over all states, the warnings and the mass's source in words.
pub fn physics_json(r: &PlanPhysics) -> PhysicsJson {
    let max = |f: fn(&StateReport) -> Option<f64>| r.states.iter().filter_map(f).reduce(f64::max);
    let worst = r.states.get(r.worst);
    PhysicsJson {
        verdict: r.verdict,
        mass: r.part.mass,
        mass_source: r.part.source.to_string(),
        mu_pad: r.settings.mu_pad,
        mu_support: r.settings.mu_support,
        safety_factor: r.settings.safety_factor,
        grip_force_min: r.n_max,
        grip_force_required: r.required,
        grip_force_recommended: r.recommended,
        pad_friction_use: max(|s| s.pad_friction_use),
        support_friction_use: max(|s| s.support_friction_use),
        support_normal_max: max(|s| s.support_normal),
        worst_t: worst.map_or(0.0, |s| s.t),
        worst_theta_deg: worst.map_or(0.0, |s| s.theta_deg),
        states: r.states.len(),
        warnings: r.warnings.iter().map(ToString::to_string).collect(),
    }
}
