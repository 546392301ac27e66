//! The ranges of the physical values a scene, a plan file and the grip check share: the part's
//! mass and the `[physics]` values (friction, safety factor, torsion radius, density). One
//! table, read by the scene and plan-file readers (`pregrasp-io`) and by the grip check's own
//! settings (`pregrasp-physics`).

use std::fmt;

/// Heaviest part (kg) a scene or `pregrasp physics --mass` may name: far beyond what two
/// 2F-85s can turn (the physics check then says the pinch cannot hold), while every force
/// computed from it stays finite.
pub const MAX_MASS: f64 = 10_000.0;

/// A physical value with a range, by its key in the scene's `[physics]` table (`mass`:
/// `object.mass`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhysicsValue {
    MuPad,
    MuSupport,
    SafetyFactor,
    PadTorsionRadius,
    Density,
    MaxTwistArm,
    Mass,
}

impl PhysicsValue {
    /// Every value, in the `[physics]` table's order (the mass last).
    pub const ALL: [PhysicsValue; 7] = [
        PhysicsValue::MuPad,
        PhysicsValue::MuSupport,
        PhysicsValue::SafetyFactor,
        PhysicsValue::PadTorsionRadius,
        PhysicsValue::Density,
        PhysicsValue::MaxTwistArm,
        PhysicsValue::Mass,
    ];

    /// Its key: `mu_pad`, `mu_support`, `safety_factor`, `pad_torsion_radius`, `density`,
    /// `max_twist_arm`, `mass`.
    pub fn key(self) -> &'static str {
        match self {
            PhysicsValue::MuPad => "mu_pad",
            PhysicsValue::MuSupport => "mu_support",
            PhysicsValue::SafetyFactor => "safety_factor",
            PhysicsValue::PadTorsionRadius => "pad_torsion_radius",
            PhysicsValue::Density => "density",
            PhysicsValue::MaxTwistArm => "max_twist_arm",
            PhysicsValue::Mass => "mass",
        }
    }

    /// The value whose key is `key`.
    pub fn from_key(key: &str) -> Option<PhysicsValue> {
        PhysicsValue::ALL.into_iter().find(|v| v.key() == key)
    }

    /// The range it must lie in.
    pub fn range(self) -> ValueRange {
        let (lo, hi, lo_included, unit) = match self {
            PhysicsValue::MuPad => (0.0, 10.0, false, ""),
            PhysicsValue::MuSupport => (0.0, 10.0, true, ""),
            PhysicsValue::SafetyFactor => (1.0, 100.0, true, ""),
            PhysicsValue::PadTorsionRadius => (0.0, 0.1, true, " m"),
            PhysicsValue::Density => (0.0, 30_000.0, false, " kg/m³"),
            PhysicsValue::MaxTwistArm => (0.0, 1.0, true, " m"),
            PhysicsValue::Mass => (0.0, MAX_MASS, false, " kg"),
        };
        ValueRange {
            lo,
            hi,
            lo_included,
            unit,
        }
    }

    /// `x` if it lies in the value's range, else what is wrong with it.
    pub fn check(self, x: f64) -> Result<f64, OutOfRange> {
        let range = self.range();
        if range.contains(x) {
            Ok(x)
        } else {
            Err(OutOfRange { range, found: x })
        }
    }
}

impl fmt::Display for PhysicsValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.key())
    }
}

/// A finite range `(lo, hi]` or `[lo, hi]`, with the unit its bounds are written in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValueRange {
    pub lo: f64,
    pub hi: f64,
    /// `lo` itself is allowed.
    pub lo_included: bool,
    /// `""`, or the unit with its leading space (`" kg"`).
    pub unit: &'static str,
}

impl ValueRange {
    /// `x` is finite and in the range.
    pub fn contains(&self, x: f64) -> bool {
        let above_lo = if self.lo_included {
            x >= self.lo
        } else {
            x > self.lo
        };
        x.is_finite() && above_lo && x <= self.hi
    }
}

impl fmt::Display for ValueRange {
    /// `(0, 10]`, `[0, 0.1] m`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let open = if self.lo_included { '[' } else { '(' };
        write!(f, "{open}{}, {}]{}", self.lo, self.hi, self.unit)
    }
}

/// A value outside its range: `must be in (0, 10], found 0`.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("must be in {range}, found {found}")]
pub struct OutOfRange {
    pub range: ValueRange,
    pub found: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_say_what_they_allow() {
        assert_eq!(
            PhysicsValue::MuPad.check(0.0).unwrap_err().to_string(),
            "must be in (0, 10], found 0"
        );
        assert_eq!(PhysicsValue::MuSupport.check(0.0), Ok(0.0));
        assert_eq!(
            PhysicsValue::Mass
                .check(f64::INFINITY)
                .unwrap_err()
                .to_string(),
            "must be in (0, 10000] kg, found inf"
        );
        assert_eq!(
            PhysicsValue::PadTorsionRadius.range().to_string(),
            "[0, 0.1] m"
        );
        for v in PhysicsValue::ALL {
            assert_eq!(PhysicsValue::from_key(v.key()), Some(v));
        }
        assert_eq!(PhysicsValue::from_key("friction"), None);
    }
}
