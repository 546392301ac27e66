//! The joint space: box bounds and the weighted L1 metric used for edge resolution.

use rand::Rng;
use thiserror::Error;

/// A configuration: one value per joint (radians for revolute joints, metres for
/// prismatic ones).
pub type State<const D: usize> = [f64; D];

/// Reasons a [`JointSpace`] cannot be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum JointSpaceError {
    /// Joint `joint` has `lower > upper` or a non-finite bound.
    #[error("joint {joint}: invalid bounds [{lower}, {upper}]")]
    InvalidBounds {
        joint: usize,
        lower: f64,
        upper: f64,
    },
    /// Joint `joint` has a negative or non-finite weight.
    #[error("joint {joint}: weight {weight} must be finite and >= 0")]
    InvalidWeight { joint: usize, weight: f64 },
}

/// Bounds and metric of a `D`-dimensional joint space.
///
/// The metric is the weighted L1 distance `d(a, b) = Σ_i w_i |a_i − b_i|`. With
/// `w_i` an upper bound (metres) on the distance of any point of the arm from joint
/// axis `i` (for a revolute joint; `w_i = 1` for a prismatic one), `d(a, b)` bounds
/// how far (metres) any point of the arm can travel along the straight joint-space
/// segment from `a` to `b`: a rotation by `Δq_i` moves a point at radius `r ≤ w_i`
/// along an arc of length `r |Δq_i|`, and displacements add up along the chain.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpace<const D: usize> {
    /// Lower joint limits.
    pub lower: [f64; D],
    /// Upper joint limits.
    pub upper: [f64; D],
    /// Metric weights `w_i ≥ 0` (metres per radian for revolute joints).
    pub weights: [f64; D],
}

impl<const D: usize> JointSpace<D> {
    /// A space with validated bounds (`lower ≤ upper`, finite) and weights (finite, `≥ 0`).
    pub fn new(
        lower: [f64; D],
        upper: [f64; D],
        weights: [f64; D],
    ) -> Result<Self, JointSpaceError> {
        for j in 0..D {
            let (lo, hi) = (lower[j], upper[j]);
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(JointSpaceError::InvalidBounds {
                    joint: j,
                    lower: lo,
                    upper: hi,
                });
            }
            let w = weights[j];
            if !(w.is_finite() && w >= 0.0) {
                return Err(JointSpaceError::InvalidWeight {
                    joint: j,
                    weight: w,
                });
            }
        }
        Ok(Self {
            lower,
            upper,
            weights,
        })
    }

    /// Whether every coordinate of `q` lies within its closed bounds (NaN never does).
    pub fn contains(&self, q: &State<D>) -> bool {
        (0..D).all(|i| q[i] >= self.lower[i] && q[i] <= self.upper[i])
    }

    /// Upper bound (metres) on the displacement of any arm point between `a` and `b`
    /// when moving linearly in joint space: `Σ_i w_i |a_i − b_i|`. This is also the
    /// distance of the space (a norm, so the triangle inequality holds).
    #[inline]
    pub fn motion_bound(&self, a: &State<D>, b: &State<D>) -> f64 {
        let mut d = 0.0;
        for i in 0..D {
            d += self.weights[i] * (a[i] - b[i]).abs();
        }
        d
    }

    /// The point `a + s (b − a)`; `s = 0` gives `a`, `s = 1` gives exactly `b`.
    #[inline]
    pub fn interpolate(&self, a: &State<D>, b: &State<D>, s: f64) -> State<D> {
        if s >= 1.0 {
            return *b;
        }
        let mut q = *a;
        for i in 0..D {
            q[i] += s * (b[i] - a[i]);
        }
        q
    }

    /// A state drawn uniformly from the bounds box.
    pub fn sample(&self, rng: &mut impl Rng) -> State<D> {
        std::array::from_fn(|i| {
            let u: f64 = rng.random();
            self.lower[i] + u * (self.upper[i] - self.lower[i])
        })
    }

    /// `q` with every coordinate clamped into its bounds.
    pub fn clamp(&self, q: &State<D>) -> State<D> {
        std::array::from_fn(|i| q[i].clamp(self.lower[i], self.upper[i]))
    }

    /// Length of a polyline in the space's metric (sum of [`Self::motion_bound`] over edges).
    pub fn path_length(&self, path: &[State<D>]) -> f64 {
        path.windows(2)
            .map(|w| self.motion_bound(&w[0], &w[1]))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn space() -> JointSpace<3> {
        JointSpace::new([-1.0, 0.0, -2.0], [1.0, 2.0, 2.0], [1.0, 0.5, 0.25]).unwrap()
    }

    #[test]
    fn motion_bound_is_weighted_l1() {
        let s = space();
        let d = s.motion_bound(&[0.0, 0.0, 0.0], &[1.0, -2.0, 4.0]);
        assert!((d - (1.0 + 1.0 + 1.0)).abs() < 1e-15);
    }

    #[test]
    fn interpolate_hits_endpoints_and_midpoint() {
        let s = space();
        let (a, b) = ([0.1, 0.2, 0.3], [0.5, 1.0, -1.3]);
        assert_eq!(s.interpolate(&a, &b, 0.0), a);
        assert_eq!(s.interpolate(&a, &b, 1.0), b);
        let m = s.interpolate(&a, &b, 0.5);
        assert!((s.motion_bound(&a, &m) - s.motion_bound(&m, &b)).abs() < 1e-12);
    }

    #[test]
    fn samples_lie_in_bounds() {
        let s = space();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        assert!((0..1000).all(|_| s.contains(&s.sample(&mut rng))));
        assert!(!s.contains(&[0.0, 3.0, 0.0]));
        assert!(!s.contains(&[f64::NAN, 1.0, 0.0]));
    }

    #[test]
    fn clamp_projects_into_bounds_and_path_length_sums_edges() {
        let s = space();
        assert_eq!(s.clamp(&[-3.0, 1.0, 9.0]), [-1.0, 1.0, 2.0]);
        let path = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0, 0.0]];
        assert!((s.path_length(&path) - 2.0).abs() < 1e-15);
        assert_eq!(s.path_length(&path[..1]), 0.0);
    }

    #[test]
    fn new_rejects_bad_bounds_and_weights() {
        assert_eq!(
            JointSpace::new([1.0], [0.0], [1.0]),
            Err(JointSpaceError::InvalidBounds {
                joint: 0,
                lower: 1.0,
                upper: 0.0
            })
        );
        assert!(matches!(
            JointSpace::new([0.0], [1.0], [-1.0]),
            Err(JointSpaceError::InvalidWeight { joint: 0, .. })
        ));
    }
}
