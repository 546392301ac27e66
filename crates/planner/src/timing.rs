//! Timing of the plan's segments.
//!
//! Transit motions (RRT-Connect paths, few waypoints with corners) are timed rest-to-rest per
//! edge by [`pregrasp_motion::time_parameterize`]. Motions that follow a smooth curve — μ_rot and
//! the straight approaches and retreats — are timed by one trapezoidal profile of the curve's
//! own parameter `u` (rotation angle, or distance along the line) by [`time_along`], so the arm
//! does not stop at every intermediate point.

use pregrasp_robot::Joints;

/// Fraction of the arms' speed and acceleration limits used for transit motions.
pub const TRANSIT_SCALE: f64 = 0.5;
/// Fraction used for the slow phases: straight approaches/retreats and turning the part.
pub const CONTACT_SCALE: f64 = 0.2;

/// Times for points `q[k]` at curve parameters `u[k]` (strictly increasing), under per-joint
/// limits `vmax`, `amax`, with `q` taken to move linearly between points.
///
/// With `g_i = max_k |Δq_i| / Δu` over the path (the steepest joint slope), the profile
/// `u(t)` is a rest-to-rest trapezoid with `u̇ ≤ min_i vmax_i / g_i`, `ü ≤ min_i amax_i / g_i`.
/// Between neighbouring points the chord speed is `|Δq_i| / Δt ≤ g_i · Δu / Δt ≤ g_i · u̇_max
/// ≤ vmax_i`: the plan-format speed rule holds on every pair of points.
pub fn time_along(q: &[Joints], u: &[f64], vmax: &Joints, amax: &Joints) -> Vec<f64> {
    assert_eq!(q.len(), u.len());
    if q.len() < 2 {
        return vec![0.0; q.len()];
    }
    let mut slope = [0.0f64; 6];
    for k in 1..q.len() {
        let du = u[k] - u[k - 1];
        assert!(du > 0.0, "curve parameter must increase strictly");
        for i in 0..6 {
            slope[i] = slope[i].max((q[k][i] - q[k - 1][i]).abs() / du);
        }
    }
    let mut v = f64::INFINITY;
    let mut a = f64::INFINITY;
    for i in 0..6 {
        if slope[i] > 0.0 {
            v = v.min(vmax[i] / slope[i]);
            a = a.min(amax[i] / slope[i]);
        }
    }
    if !v.is_finite() {
        // No joint moves (degenerate); keep time increasing.
        return (0..q.len()).map(|k| k as f64 * 1e-3).collect();
    }
    let length = u[u.len() - 1] - u[0];
    let profile = Trapezoid::new(length, v, a);
    let mut t: Vec<f64> = u.iter().map(|&x| profile.time_at(x - u[0])).collect();
    // Guard the strict increase against rounding.
    for k in 1..t.len() {
        if t[k] <= t[k - 1] {
            t[k] = t[k - 1] + 1e-6;
        }
    }
    t
}

/// Rest-to-rest trapezoidal (or triangular) profile over a distance.
struct Trapezoid {
    length: f64,
    v: f64,
    a: f64,
    /// Distance covered while accelerating.
    ramp: f64,
    /// Peak speed.
    peak: f64,
}

impl Trapezoid {
    fn new(length: f64, v: f64, a: f64) -> Self {
        let ramp_full = v * v / (2.0 * a);
        if 2.0 * ramp_full >= length {
            let ramp = length / 2.0;
            Trapezoid {
                length,
                v,
                a,
                ramp,
                peak: (2.0 * a * ramp).sqrt(),
            }
        } else {
            Trapezoid {
                length,
                v,
                a,
                ramp: ramp_full,
                peak: v,
            }
        }
    }

    /// Time at which distance `x` is reached.
    fn time_at(&self, x: f64) -> f64 {
        let x = x.clamp(0.0, self.length);
        let t_ramp = self.peak / self.a;
        if x <= self.ramp {
            (2.0 * x / self.a).sqrt()
        } else if x <= self.length - self.ramp {
            t_ramp + (x - self.ramp) / self.peak
        } else {
            let cruise = (self.length - 2.0 * self.ramp) / self.peak.min(self.v);
            let rest = self.length - x;
            2.0 * t_ramp + cruise - (2.0 * rest / self.a).sqrt()
        }
    }
}

/// Limits scaled by a fraction.
pub fn scaled(limits: &Joints, scale: f64) -> Joints {
    limits.map(|x| x * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_rule_holds_on_every_pair() {
        let n = 40;
        let u: Vec<f64> = (0..=n).map(|k| k as f64 * 0.01).collect();
        let q: Vec<Joints> = u
            .iter()
            .map(|&x| [x.sin(), 2.0 * x, -x * x, 0.0, 0.3 * x, (3.0 * x).cos()])
            .collect();
        let vmax = [0.5; 6];
        let amax = [1.0; 6];
        let t = time_along(&q, &u, &vmax, &amax);
        assert_eq!(t[0], 0.0);
        for k in 1..t.len() {
            assert!(t[k] > t[k - 1]);
            for i in 0..6 {
                let speed = (q[k][i] - q[k - 1][i]).abs() / (t[k] - t[k - 1]);
                assert!(speed <= vmax[i] * (1.0 + 1e-9), "joint {i} speed {speed}");
            }
        }
    }

    #[test]
    fn trapezoid_times_are_monotone_and_end_at_the_full_duration() {
        let p = Trapezoid::new(1.0, 0.5, 1.0);
        // Ramp 0.125 each side, cruise 0.75 at 0.5 → 0.5 + 1.5 + 0.5 = 2.5 s.
        assert!((p.time_at(1.0) - 2.5).abs() < 1e-12);
        let tri = Trapezoid::new(0.1, 10.0, 1.0);
        // Triangular: 2·sqrt(0.05 / 0.5) ... = 2·sqrt(2·0.05/1).
        assert!((tri.time_at(0.1) - 2.0 * (0.1f64).sqrt()).abs() < 1e-12);
    }
}
