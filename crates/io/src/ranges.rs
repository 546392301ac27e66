//! Ranges of values that both the scene file and the plan file hold (the part's mass and the
//! `[physics]` values the plan echoes), checked alike wherever they are read. The table is
//! [`pregrasp_model::ranges`], shared with the grip check's settings.

use pregrasp_model::PhysicsValue;

pub use pregrasp_model::MAX_MASS;

/// Checks the range of one numeric `[physics]` value (also used for the command-line overrides
/// of `pregrasp physics`): `Err` says what the range is and what was found.
pub fn check_physics_value(key: &str, x: f64) -> Result<(), String> {
    let value = PhysicsValue::from_key(key).ok_or("unknown key")?;
    value.check(x).map(|_| ()).map_err(|e| e.to_string())
}
