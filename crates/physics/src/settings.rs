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
//! max_twist_arm = 0.005      # m; the most weight moment the pads' twist may hold (crate::twist)
//! ```
//!
//! The scene loader (`pregrasp_io::scene`) reads and range-checks the table (with `reject`, which
//! tells the planner whether to drop a rotation that does not hold); the planner
//! (`pregrasp_planner::hold::physics_settings`) applies its values on top of these defaults.
//! The ranges are the model's ([`pregrasp_model::ranges`]), shared with the scene and plan files.

use pregrasp_model::{OutOfRange, PhysicsValue};

use crate::statics::ContactModel;
use crate::twist::MAX_TWIST_ARM;

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
    /// Largest twist arm (m) of a rotation that holds ([`crate::twist`]; default
    /// [`MAX_TWIST_ARM`]).
    pub max_twist_arm: f64,
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
            max_twist_arm: MAX_TWIST_ARM,
        }
    }
}

/// A bad setting: `mu_pad: must be in (0, 10], found 0`.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SettingsError {
    #[error("{key}: {problem}")]
    Value {
        key: PhysicsValue,
        problem: OutOfRange,
    },
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
    /// [`PhysicsValue::range`]).
    pub fn validate(&self) -> Result<(), SettingsError> {
        for (key, value) in [
            (PhysicsValue::MuPad, self.mu_pad),
            (PhysicsValue::MuSupport, self.mu_support),
            (PhysicsValue::SafetyFactor, self.safety_factor),
            (PhysicsValue::PadTorsionRadius, self.pad_torsion_radius),
            (PhysicsValue::Density, self.density),
            (PhysicsValue::MaxTwistArm, self.max_twist_arm),
        ] {
            key.check(value)
                .map_err(|problem| SettingsError::Value { key, problem })?;
        }
        Ok(())
    }
}
