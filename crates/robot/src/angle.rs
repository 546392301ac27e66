//! Angle helpers: wrapping into (−π, π], a fast, accurate `atan2` for the IK hot path, and
//! `sin_cos` (with the plane rotation built on it) for the FK and linkage hot paths.
//!
//! `atan2` dominates the analytic IK (about 22 calls per pose). [`atan2`] reduces
//! `t = min(|x|,|y|)/max(|x|,|y|) ∈ [0, 1]` to `u = (t − c)/(1 + t·c)` with `c = k/8` the
//! nearest table point, so `|u| ≤ 1/16` and `atan t = atan c + atan u`, and evaluates
//! `atan u = u − u³/3 + u⁵/5 − …` to `u¹⁷` (truncation error < `u¹⁹/19` ≈ 7·10⁻²⁵). The
//! result is within a few ulp of the correctly rounded value (tested against `f64::atan2`).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::{Matrix2, Rotation2};

/// `(sin x, cos x)` by the `libm` crate (musl's kernels, in Rust). The platform's
/// `f64::sin_cos` (glibc's) saves and restores the floating-point rounding mode on every call:
/// 9.7 ns here against libm's 5.6 ns. libm also gives the same bits on every platform, so the
/// kinematics that use it (the arms' FK, the finger linkage) do not depend on the C library.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// The rotation of the plane by `angle`: nalgebra's `Rotation2::new` on [`sin_cos`].
#[inline]
pub(crate) fn rotation2(angle: f64) -> Rotation2<f64> {
    let (s, c) = sin_cos(angle);
    Rotation2::from_matrix_unchecked(Matrix2::new(c, -s, s, c))
}

/// `atan(k/8)` for k = 0..=8.
const ATAN_TABLE: [f64; 9] = [
    0.0,
    0.124_354_994_546_761_44,
    0.244_978_663_126_864_14,
    0.358_770_670_270_572_25,
    0.463_647_609_000_806_1,
    0.558_599_315_343_562_4,
    0.643_501_108_793_284_4,
    0.718_829_999_621_624_5,
    std::f64::consts::FRAC_PI_4,
];

/// Taylor coefficients of atan: (−1)^n / (2n + 1), n = 0..=8.
const ATAN_SERIES: [f64; 9] = [
    1.0,
    -1.0 / 3.0,
    1.0 / 5.0,
    -1.0 / 7.0,
    1.0 / 9.0,
    -1.0 / 11.0,
    1.0 / 13.0,
    -1.0 / 15.0,
    1.0 / 17.0,
];

/// The angle of the vector `(x, y)` in [−π, π], like `f64::atan2` (same quadrant and zero
/// rules; non-finite or all-zero inputs fall back to `f64::atan2`).
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    if !(ax.is_finite() && ay.is_finite()) || (ax == 0.0 && ay == 0.0) {
        return y.atan2(x);
    }
    let swap = ay > ax;
    let (num, den) = if swap { (ax, ay) } else { (ay, ax) };
    let t = num / den; // ∈ [0, 1]
    let k = (t * 8.0 + 0.5) as usize; // ∈ 0..=8
    let c = k as f64 * 0.125;
    // u = (t − c)/(1 + t·c), with the division by `den` folded in.
    let u = (num - c * den) / (den + c * num);
    let u2 = u * u;
    // Horner form of Σ (−1)^n u^(2n+1)/(2n+1), n = 0..=8.
    let mut p = ATAN_SERIES[8];
    for &coef in ATAN_SERIES[..8].iter().rev() {
        p = coef + u2 * p;
    }
    let mut a = ATAN_TABLE[k] + u * p;
    if swap {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// The angle in (−π, π] with the given (not necessarily unit) sine and cosine.
#[inline]
pub(crate) fn angle_of(s: f64, c: f64) -> f64 {
    let a = atan2(s, c);
    if a == -PI {
        PI
    } else {
        a
    }
}

/// Wraps an angle into (−π, π].
#[inline]
pub fn wrap_angle(x: f64) -> f64 {
    // Fast paths for the common cases (no libm call).
    if x > -PI && x <= PI {
        return x;
    }
    if x > PI && x <= 3.0 * PI {
        return x - TAU;
    }
    if x > -3.0 * PI && x <= -PI {
        return x + TAU;
    }
    let y = x - TAU * (x / TAU).round();
    if y <= -PI {
        y + TAU
    } else if y > PI {
        y - TAU
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn atan2_matches_std_to_a_few_ulp() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut worst: f64 = 0.0;
        for _ in 0..1_000_000 {
            let scale = 10f64.powi(rng.random_range(-12..=3));
            let y = rng.random_range(-1.0..1.0) * scale;
            let x = rng.random_range(-1.0..1.0) * 10f64.powi(rng.random_range(-12..=3));
            let err = (atan2(y, x) - y.atan2(x)).abs();
            worst = worst.max(err);
        }
        assert!(worst < 2e-15, "worst error {worst}");
    }

    /// libm's sine and cosine are the platform's to the last bit or one ulp from it, over the
    /// joint range and beyond (several turns, where the argument reduction matters); the plane
    /// rotation is nalgebra's on them.
    #[test]
    fn sin_cos_within_an_ulp_of_std() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let ulp = |a: f64, b: f64| (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
        let (mut worst, mut differ) = (0, 0);
        for _ in 0..1_000_000 {
            let x = rng.random_range(-20.0..20.0);
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max(ulp(s, s0)).max(ulp(c, c0));
            differ += usize::from(s != s0 || c != c0);
        }
        assert!(worst <= 1, "{worst} ulp");
        assert!(differ < 100_000, "{differ} of 10⁶ differ");
        let r = rotation2(0.7);
        let (s, c) = sin_cos(0.7);
        assert_eq!(r.matrix(), &Matrix2::new(c, -s, s, c));
        assert!((r.angle() - 0.7).abs() < 1e-15);
    }

    #[test]
    fn atan2_special_values() {
        for (y, x) in [
            (0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (1.0, 1.0),
            (-1.0, -1.0),
            (0.0, 0.0),
            (1e-300, 1.0),
            (1.0, 1e-300),
            (f64::INFINITY, 1.0),
        ] {
            assert!((atan2(y, x) - f64::atan2(y, x)).abs() < 1e-15, "({y}, {x})");
        }
        assert!(atan2(f64::NAN, 1.0).is_nan());
    }

    #[test]
    fn wrap_angle_lands_in_half_open_interval() {
        for x in [-10.0, -3.0 * PI, -PI, -1.0, 0.0, PI, 3.0 * PI, 7.5, 1e6] {
            let w = wrap_angle(x);
            assert!(w > -PI && w <= PI, "{x} -> {w}");
            let k = (x - w) / TAU;
            assert!((k - k.round()).abs() < 1e-9, "{x} -> {w}");
        }
        assert_eq!(wrap_angle(-PI), PI);
        assert_eq!(wrap_angle(0.5), 0.5);
    }
}
