//! Physical parameters of the check, and the optional `[physics]` table of a scene file.
//!
//! ```toml
//! [physics]                  # every key optional
//! mu_pad = 0.8               # Coulomb friction pad–part
//! mu_support = 0.4           # Coulomb friction part–support
//! safety_factor = 2.0        # recommended grip force = safety_factor × worst N_min
//! pad_torsion_radius = 0.0   # m; > 0 lets each pad resist a twist about its normal
//! density = 700.0            # kg/m³, used when the scene gives no object.mass
//! ```
//!
//! The table is read here, with `toml` directly, so the scene loader stays as it is (it reports
//! `[physics]` as an unknown key and ignores it).

use std::path::Path;

use toml::{Table, Value};

use crate::statics::ContactModel;

/// Coulomb coefficient pad–part: the 2F-85's silicone pads on wood or painted metal [C].
pub const DEFAULT_MU_PAD: f64 = 0.8;
/// Coulomb coefficient part–support: wood on a laminated or steel table top [C].
pub const DEFAULT_MU_SUPPORT: f64 = 0.4;
/// Recommended grip force = this × the largest N_min along the rotation.
pub const DEFAULT_SAFETY_FACTOR: f64 = 2.0;
/// Density (kg/m³) assumed when neither the plan nor the user gives a mass: light hardwood.
pub const DEFAULT_DENSITY: f64 = 700.0;
/// Standard gravity (m/s²).
pub const GRAVITY: f64 = 9.81;
/// The Robotiq 2F-85's rated grip force range (N), `docs/hardware-facts.md`.
pub const GRIP_FORCE_RANGE: (f64, f64) = (20.0, 235.0);
/// Effective torsion radius (m) of one 2F-85 pad in full contact (22 mm × 37.5 mm, uniform
/// pressure): the mean distance of the patch from its centre. The default model does not use
/// it (point contacts, `pad_torsion_radius = 0`): a bar narrower than the pad fills only part of
/// it, and ignoring torsion only makes the required force larger.
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
        }
    }
}

/// A bad `[physics]` table or setting.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SettingsError {
    #[error("{file}: cannot read: {error}")]
    Read { file: String, error: String },
    #[error("{file}: not TOML: {error}")]
    Parse { file: String, error: String },
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

    /// Checks every value's range.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let bad = |key: &str, problem: String| {
            Err(SettingsError::Value {
                key: key.into(),
                problem,
            })
        };
        let finite = |v: f64| v.is_finite();
        if !(finite(self.mu_pad) && self.mu_pad > 0.0 && self.mu_pad <= 10.0) {
            return bad(
                "mu_pad",
                format!("must be in (0, 10], found {}", self.mu_pad),
            );
        }
        if !(finite(self.mu_support) && (0.0..=10.0).contains(&self.mu_support)) {
            return bad(
                "mu_support",
                format!("must be in [0, 10], found {}", self.mu_support),
            );
        }
        if !(finite(self.safety_factor) && self.safety_factor >= 1.0 && self.safety_factor <= 100.0)
        {
            return bad(
                "safety_factor",
                format!("must be in [1, 100], found {}", self.safety_factor),
            );
        }
        if !(finite(self.pad_torsion_radius) && (0.0..=0.1).contains(&self.pad_torsion_radius)) {
            return bad(
                "pad_torsion_radius",
                format!("must be in [0, 0.1] m, found {}", self.pad_torsion_radius),
            );
        }
        if !(finite(self.density) && self.density > 0.0 && self.density <= 30_000.0) {
            return bad(
                "density",
                format!("must be in (0, 30000] kg/m³, found {}", self.density),
            );
        }
        Ok(())
    }

    /// These settings with the scene's `[physics]` table (TOML text) applied on top. A scene
    /// without the table changes nothing; an unknown key in it is an error.
    pub fn with_scene_toml(mut self, text: &str, file: &str) -> Result<Self, SettingsError> {
        let table: Table = text
            .parse()
            .map_err(|e: toml::de::Error| SettingsError::Parse {
                file: file.into(),
                error: e.message().to_string(),
            })?;
        let Some(physics) = table.get("physics") else {
            return Ok(self);
        };
        let Value::Table(physics) = physics else {
            return Err(SettingsError::Value {
                key: "physics".into(),
                problem: "must be a table".into(),
            });
        };
        for (key, value) in physics {
            let number = match value {
                Value::Float(f) => *f,
                Value::Integer(i) => *i as f64,
                _ => {
                    return Err(SettingsError::Value {
                        key: format!("physics.{key}"),
                        problem: "must be a number".into(),
                    })
                }
            };
            match key.as_str() {
                "mu_pad" => self.mu_pad = number,
                "mu_support" => self.mu_support = number,
                "safety_factor" => self.safety_factor = number,
                "pad_torsion_radius" => self.pad_torsion_radius = number,
                "density" => self.density = number,
                _ => {
                    return Err(SettingsError::Value {
                        key: format!("physics.{key}"),
                        problem: "unknown key (mu_pad, mu_support, safety_factor, pad_torsion_radius, density)".into(),
                    })
                }
            }
        }
        self.validate().map_err(|e| match e {
            SettingsError::Value { key, problem } => SettingsError::Value {
                key: format!("physics.{key}"),
                problem,
            },
            other => other,
        })?;
        Ok(self)
    }

    /// [`Self::with_scene_toml`] on a scene file.
    pub fn with_scene_file(self, path: &Path) -> Result<Self, SettingsError> {
        let text = std::fs::read_to_string(path).map_err(|e| SettingsError::Read {
            file: path.display().to_string(),
            error: e.to_string(),
        })?;
        self.with_scene_toml(&text, &path.display().to_string())
    }
}
