//! Physical parameters of the check, and the optional `[physics]` table of a scene file.
//!
//! ```toml
//! [physics]                  # every key optional
//! mu_pad = 0.8               # Coulomb friction pad–part
//! mu_support = 0.4           # Coulomb friction part–support
//! safety_factor = 2.0        # recommended grip force = safety_factor × worst N_min
//! pad_torsion_radius = 0.0   # m; > 0: each pad resists a twist about its normal up to μ·N·e
//!                            # with this e; 0: the e of the plan's pad contact patches
//! density = 700.0            # kg/m³, used when the scene gives no object.mass
//! ```
//!
//! The scene loader (`pregrasp_io::scene`) reads and range-checks the table (with `reject`, which
//! tells the planner whether to drop a rotation that does not hold); here its values are applied
//! on top of the defaults.

use std::path::Path;

use pregrasp_io::scene::{check_physics_value, PhysicsParams, Scene};

use crate::statics::ContactModel;

/// Coulomb coefficient pad–part: the 2F-85's silicone pads on wood or painted metal \[C\].
pub const DEFAULT_MU_PAD: f64 = 0.8;
/// Coulomb coefficient part–support: wood on a laminated or steel table top \[C\].
pub const DEFAULT_MU_SUPPORT: f64 = 0.4;
/// Recommended grip force = this × the largest N_min along the rotation.
pub const DEFAULT_SAFETY_FACTOR: f64 = 2.0;
/// Density (kg/m³) assumed when neither the plan nor the user gives a mass: light hardwood.
pub const DEFAULT_DENSITY: f64 = 700.0;
/// Standard gravity (m/s²).
pub const GRAVITY: f64 = 9.81;
/// The Robotiq 2F-85's rated grip force range (N), `docs/hardware-facts.md`: the default of
/// [`PhysicsSettings::grip_force`].
pub const GRIP_FORCE_RANGE: (f64, f64) = pregrasp_robot::ROBOTIQ_2F85_GRIP_FORCE;
/// Effective torsion radius (m) of one 2F-85 pad in full contact (22 mm × 37.5 mm, uniform
/// pressure): the mean distance of the patch from its centre. The default model does not use
/// it as such: with `pad_torsion_radius = 0` the patches the pads really make on the part (the
/// plan's `rot.pad_contact`) give `e`, and a plan without them gets point contacts.
pub const PAD_PATCH_TORSION_RADIUS: f64 = 0.011_62;

/// Every parameter of the check.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PhysicsSettings {
    pub mu_pad: f64,
    pub mu_support: f64,
    pub safety_factor: f64,
    pub pad_torsion_radius: f64,
    /// kg/m³, for a part without a given mass.
    pub density: f64,
    /// States checked between two neighbouring points of `rot` (pose interpolated: translation
    /// linearly, rotation by slerp). 0: the plan's points only.
    pub substeps: usize,
    /// Interpolate in every interval; by default only in those where the worst state can hide
    /// (next to a local maximum of the grip force, or where the status or the support contacts
    /// change).
    pub refine_all: bool,
    /// The supportive gripper's grip force range (N): a pinch needing more cannot be held,
    /// the recommended force is clamped into it (default: the 2F-85's, [`GRIP_FORCE_RANGE`]).
    pub grip_force: (f64, f64),
}

impl Default for PhysicsSettings {
    fn default() -> Self {
        PhysicsSettings {
            mu_pad: DEFAULT_MU_PAD,
            mu_support: DEFAULT_MU_SUPPORT,
            safety_factor: DEFAULT_SAFETY_FACTOR,
            pad_torsion_radius: 0.0,
            density: DEFAULT_DENSITY,
            substeps: 4,
            refine_all: false,
            grip_force: GRIP_FORCE_RANGE,
        }
    }
}

/// A bad `[physics]` table or setting.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SettingsError {
    /// The scene file could not be used (its message names the file and key).
    #[error("{0}")]
    Scene(String),
    #[error("{key}: {problem}")]
    Value { key: String, problem: String },
}

impl PhysicsSettings {
    /// The contact model these settings describe.
    pub fn contact_model(&self) -> ContactModel {
        ContactModel {
            mu_pad: self.mu_pad,
            mu_support: self.mu_support,
            pad_torsion_radius: self.pad_torsion_radius,
        }
    }

    /// Checks every value's range (the ranges of the scene's `[physics]` table,
    /// [`pregrasp_io::scene::check_physics_value`]).
    pub fn validate(&self) -> Result<(), SettingsError> {
        for (key, value) in [
            ("mu_pad", self.mu_pad),
            ("mu_support", self.mu_support),
            ("safety_factor", self.safety_factor),
            ("pad_torsion_radius", self.pad_torsion_radius),
            ("density", self.density),
        ] {
            check_physics_value(key, value).map_err(|problem| SettingsError::Value {
                key: key.into(),
                problem,
            })?;
        }
        Ok(())
    }

    /// These settings with a scene's `[physics]` values applied on top (the scene loader has
    /// checked their ranges).
    pub fn with_scene(mut self, params: &PhysicsParams) -> Self {
        let set = |field: &mut f64, value: Option<f64>| {
            if let Some(v) = value {
                *field = v;
            }
        };
        set(&mut self.mu_pad, params.mu_pad);
        set(&mut self.mu_support, params.mu_support);
        set(&mut self.safety_factor, params.safety_factor);
        set(&mut self.pad_torsion_radius, params.pad_torsion_radius);
        set(&mut self.density, params.density);
        self
    }

    /// These settings with the `[physics]` table of the scene file at `path` applied on top.
    pub fn with_scene_file(self, path: &Path) -> Result<Self, SettingsError> {
        let scene = Scene::load(path).map_err(|e| SettingsError::Scene(e.to_string()))?;
        Ok(self.with_scene(&scene.physics))
    }
}
