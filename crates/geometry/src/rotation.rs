//! Rotation about a line in space, and the exact height of a rotating point.
//!
//! Rotating a point `x` by `θ` about the line through `p` with unit direction `u`
//! (right-hand rule) gives, with `r = x − p` (Rodrigues):
//!
//! `x(θ) = p + (r·u) u + cos θ (r − (r·u) u) + sin θ (u × r)`.
//!
//! Its world height is therefore a sinusoid `h(θ) = c + A cos θ + B sin θ` with
//! `c = p_z + (r·u) u_z`, `A = r_z − (r·u) u_z`, `B = (u × r)_z`. Where a sinusoid first goes below
//! a level is found in closed form, through `t = tan(θ/2)`, which turns `h(θ) = L` into the
//! quadratic `(c − L − A) t² + 2B t + (c − L + A) = 0` and keeps small roots accurate.

use std::f64::consts::{PI, TAU};

use nalgebra::{Translation3, Unit, UnitQuaternion};

use crate::{Point, Pose, Vector};

/// The rigid motion rotating by `angle` (rad, right-hand rule about `axis`) about the line
/// through `point` with direction `axis`: `x ↦ point + R (x − point)`.
pub fn rotation_about_line(point: &Point, axis: &Unit<Vector>, angle: f64) -> Pose {
    let r = UnitQuaternion::from_axis_angle(axis, angle);
    let t = point.coords - r * point.coords;
    Pose::from_parts(Translation3::from(t), r)
}

/// `h(θ) = c + a cos θ + b sin θ`: the world `z` of a point rotated by `θ` about a line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightSinusoid {
    pub c: f64,
    pub a: f64,
    pub b: f64,
}

impl HeightSinusoid {
    /// Height of `x` rotating about the line through `point` along unit `axis`.
    pub fn of_point(x: &Point, point: &Point, axis: &Unit<Vector>) -> HeightSinusoid {
        let r = x - point;
        let along = r.dot(axis);
        HeightSinusoid {
            c: point.z + along * axis.z,
            a: r.z - along * axis.z,
            b: axis.cross(&r).z,
        }
    }

    pub fn eval(&self, theta: f64) -> f64 {
        self.c + self.a * theta.cos() + self.b * theta.sin()
    }

    /// `dh/dθ`.
    pub fn derivative(&self, theta: f64) -> f64 {
        -self.a * theta.sin() + self.b * theta.cos()
    }

    /// Half the peak-to-peak swing of the height, `√(A² + B²)`: 0 for a point on the axis
    /// (or on a circle in a horizontal plane, i.e. a vertical axis).
    pub fn amplitude(&self) -> f64 {
        self.a.hypot(self.b)
    }

    /// The smallest `θ ∈ [0, 2π)` at which the height goes below `level`: `Some(0)` when it
    /// starts below (by more than `tol`) or starts at the level (within `tol`) heading down;
    /// `None` when it never goes below. Touching the level tangentially is not going below.
    pub fn first_descent_below(&self, level: f64, tol: f64) -> Option<f64> {
        let h0 = self.c + self.a - level;
        if h0 < -tol {
            return Some(0.0);
        }
        if h0 <= tol && self.b < 0.0 {
            return Some(0.0);
        }
        let d = self.c - level;
        // (d − A) t² + 2B t + (d + A) = 0, t = tan(θ/2); θ = π ⇔ t = ∞.
        let (qa, qb, qc) = (d - self.a, 2.0 * self.b, d + self.a);
        let mut thetas: Vec<f64> = Vec::with_capacity(3);
        let from_t = |t: f64| {
            let theta = 2.0 * t.atan();
            if theta < 0.0 {
                theta + TAU
            } else {
                theta
            }
        };
        if qa == 0.0 {
            thetas.push(PI);
            if qb != 0.0 {
                thetas.push(from_t(-qc / qb));
            }
        } else {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc < 0.0 {
                return None;
            }
            let q = -0.5 * (qb + qb.signum() * disc.sqrt());
            if q != 0.0 {
                thetas.push(from_t(q / qa));
                thetas.push(from_t(qc / q));
            }
        }
        let mut best: Option<f64> = None;
        for theta in thetas {
            // Skip the start itself (handled above) and tangential touches.
            if theta <= 0.0 || self.derivative(theta) >= 0.0 {
                continue;
            }
            best = Some(best.map_or(theta, |b: f64| b.min(theta)));
        }
        best
    }
}

/// The largest `θ ∈ [0, cap]` such that rotating all `points` by any angle in `[0, θ]` about the
/// line (`point`, `axis`) keeps every one at or above `level` (within `tol` at the start).
/// Points within `tol` of the axis never move and are skipped.
pub fn max_rotation_above(
    points: &[Point],
    point: &Point,
    axis: &Unit<Vector>,
    level: f64,
    cap: f64,
    tol: f64,
) -> f64 {
    let mut theta = cap;
    for x in points {
        let s = HeightSinusoid::of_point(x, point, axis);
        if s.amplitude() <= tol {
            continue;
        }
        if let Some(t) = s.first_descent_below(level, tol) {
            theta = theta.min(t);
        }
    }
    theta.max(0.0)
}
