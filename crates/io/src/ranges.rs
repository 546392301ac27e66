//! Ranges of values that both the scene file and the plan file hold (the part's mass and the
//! `[physics]` values the plan echoes), checked alike wherever they are read.

/// Checks the range of one numeric `[physics]` value (also used for the command-line overrides
/// of `pregrasp physics`): `Err` says what the range is and what was found.
pub fn check_physics_value(key: &str, x: f64) -> Result<(), String> {
    // (lowest, highest, lowest allowed itself, unit)
    let (lo, hi, lo_in, unit) = match key {
        "mu_pad" => (0.0, 10.0, false, ""),
        "mu_support" => (0.0, 10.0, true, ""),
        "safety_factor" => (1.0, 100.0, true, ""),
        "pad_torsion_radius" => (0.0, 0.1, true, " m"),
        "density" => (0.0, 30_000.0, false, " kg/m³"),
        "mass" => (0.0, MAX_MASS, false, " kg"),
        _ => return Err("unknown key".into()),
    };
    let above_lo = if lo_in { x >= lo } else { x > lo };
    if x.is_finite() && above_lo && x <= hi {
        Ok(())
    } else {
        let open = if lo_in { '[' } else { '(' };
        Err(format!("must be in {open}{lo}, {hi}]{unit}, found {x}"))
    }
}

/// Heaviest part (kg) a scene or `pregrasp physics --mass` may name: far beyond what two
/// 2F-85s can turn (the physics check then says the pinch cannot hold), while every force
/// computed from it stays finite.
pub const MAX_MASS: f64 = 10_000.0;
