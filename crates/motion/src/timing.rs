//! Time parameterisation of joint paths under per-joint speed and acceleration limits.
//!
//! Each edge `q_a → q_b` of the path is executed as a rest-to-rest trapezoidal
//! velocity profile of the path parameter `u ∈ [0, 1]`, `q(u) = q_a + u Δ`. With
//! `Δ_i = q_b,i − q_a,i`, the joint limits become limits on `u`:
//! `u̇ ≤ v_u = min_i v_max,i / |Δ_i|`, `ü ≤ a_u = min_i a_max,i / |Δ_i|`, so every joint
//! respects its own speed and acceleration limit (the slowest joint sets the pace and
//! all joints arrive together). If `v_u² / a_u ≥ 1` the profile is triangular (the
//! peak speed `√a_u` is never reached), otherwise it accelerates for `t_a = v_u / a_u`,
//! cruises, and decelerates for `t_a`.
//!
//! The profile is sampled into points: [`RAMP_SAMPLES`] during each ramp and the
//! cruise end. Between neighbouring samples the arm is then taken to move linearly
//! in joint space (the plan-file convention); the chord speed is the *average* of the
//! profile speed over the interval, hence `|q_{k+1,i} − q_{k,i}| / (t_{k+1} − t_k) ≤
//! v_max,i`. That rule is also enforced numerically on the final floating-point
//! times. Finite-difference accelerations of the chord speeds stay within `a_max,i`
//! too (averages of an `a_max`-Lipschitz speed).
//!
//! Why stop at each waypoint rather than blend through it: a joint-space corner
//! traversed at non-zero speed needs infinite acceleration, and a blend that keeps
//! the acceleration finite leaves the polyline, i.e. leaves the edges the
//! [`MotionValidator`](crate::MotionValidator) checked. Rest-to-rest keeps every
//! sampled point on a validated edge; simplified paths have few waypoints, so the
//! cost in duration is small.

use thiserror::Error;

use crate::space::State;

/// Samples per acceleration (and per deceleration) ramp of one edge.
pub const RAMP_SAMPLES: usize = 6;

/// Invalid limits passed to [`try_time_parameterize`].
#[derive(Clone, Debug, PartialEq, Error)]
pub enum TimingError {
    /// `vmax[joint]` is not finite and positive.
    #[error("joint {joint}: speed limit {value} must be finite and > 0")]
    InvalidSpeedLimit { joint: usize, value: f64 },
    /// `amax[joint]` is not finite and positive.
    #[error("joint {joint}: acceleration limit {value} must be finite and > 0")]
    InvalidAccelerationLimit { joint: usize, value: f64 },
    /// A path state has a non-finite coordinate.
    #[error("path state {index} is not finite")]
    NonFiniteState { index: usize },
}

/// Time-stamped joint states: `t[k]` (seconds, `t[0] = 0`, strictly increasing) is
/// the time of `q[k]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimedPath<const D: usize> {
    /// Time stamps (seconds).
    pub t: Vec<f64>,
    /// Joint states.
    pub q: Vec<State<D>>,
}

impl<const D: usize> TimedPath<D> {
    /// Duration (seconds): the last time stamp, or 0 for an empty path.
    pub fn duration(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

/// [`try_time_parameterize`] for limits known to be valid.
///
/// # Panics
/// If a limit is not finite and positive or a state is not finite.
pub fn time_parameterize<const D: usize>(
    path: &[State<D>],
    vmax: &[f64; D],
    amax: &[f64; D],
) -> TimedPath<D> {
    try_time_parameterize(path, vmax, amax).unwrap_or_else(|e| panic!("time_parameterize: {e}"))
}

/// Rest-to-rest trapezoidal timing of every edge of `path` (see the module docs).
/// Consecutive duplicate states are merged (time must strictly increase). An empty
/// path gives an empty result; a single state gives one point at `t = 0`.
pub fn try_time_parameterize<const D: usize>(
    path: &[State<D>],
    vmax: &[f64; D],
    amax: &[f64; D],
) -> Result<TimedPath<D>, TimingError> {
    for j in 0..D {
        if !(vmax[j].is_finite() && vmax[j] > 0.0) {
            return Err(TimingError::InvalidSpeedLimit {
                joint: j,
                value: vmax[j],
            });
        }
        if !(amax[j].is_finite() && amax[j] > 0.0) {
            return Err(TimingError::InvalidAccelerationLimit {
                joint: j,
                value: amax[j],
            });
        }
    }
    if let Some(index) = path.iter().position(|q| q.iter().any(|x| !x.is_finite())) {
        return Err(TimingError::NonFiniteState { index });
    }
    let mut out = TimedPath {
        t: Vec::new(),
        q: Vec::new(),
    };
    let Some(&first) = path.first() else {
        return Ok(out);
    };
    out.t.push(0.0);
    out.q.push(first);
    for w in path.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if a == b {
            continue;
        }
        let Some(profile) = Trapezoid::new(a, b, vmax, amax) else {
            continue;
        };
        let t0 = *out.t.last().expect("non-empty");
        for (tau, u) in profile.samples() {
            let q = if u >= 1.0 { *b } else { lerp(a, b, u) };
            push_point(&mut out, t0 + tau, q, vmax);
        }
    }
    Ok(out)
}

/// Duration (s) of the rest-to-rest profile of the edge `a → b` that
/// [`time_parameterize`] samples (before its floating-point delays, which are a few ulps):
/// `2 t_ramp + t_cruise`, 0 when `a = b`. Limits must be finite and positive.
pub fn rest_to_rest_duration<const D: usize>(
    a: &State<D>,
    b: &State<D>,
    vmax: &[f64; D],
    amax: &[f64; D],
) -> f64 {
    Trapezoid::new(a, b, vmax, amax).map_or(0.0, |p| p.duration())
}

fn lerp<const D: usize>(a: &State<D>, b: &State<D>, u: f64) -> State<D> {
    let mut q = *a;
    for i in 0..D {
        q[i] += u * (b[i] - a[i]);
    }
    q
}

/// Appends `(t, q)`, delaying `t` if needed so the chord speed from the previous point
/// satisfies `|Δq_i| / Δt ≤ vmax_i` exactly in floating point, and `Δt > 0`.
fn push_point<const D: usize>(out: &mut TimedPath<D>, t: f64, q: State<D>, vmax: &[f64; D]) {
    let (tp, qp) = (
        *out.t.last().expect("non-empty"),
        *out.q.last().expect("non-empty"),
    );
    let dt_min = (0..D)
        .map(|i| (q[i] - qp[i]).abs() / vmax[i])
        .fold(0.0, f64::max);
    let mut t = t.max(tp + dt_min);
    let ok = |t: f64| t > tp && (0..D).all(|i| (q[i] - qp[i]).abs() / (t - tp) <= vmax[i]);
    while !ok(t) {
        t += (t.abs() * f64::EPSILON).max(f64::MIN_POSITIVE);
    }
    out.t.push(t);
    out.q.push(q);
}

/// A rest-to-rest trapezoidal profile of `u ∈ [0, 1]`.
struct Trapezoid {
    /// Acceleration of `u` (1/s²).
    acc: f64,
    /// Duration of each ramp (s).
    t_ramp: f64,
    /// Duration of the cruise phase (s), 0 for a triangular profile.
    t_cruise: f64,
    /// Cruise (peak) speed of `u` (1/s).
    v_peak: f64,
}

impl Trapezoid {
    fn new<const D: usize>(
        a: &State<D>,
        b: &State<D>,
        vmax: &[f64; D],
        amax: &[f64; D],
    ) -> Option<Self> {
        let (mut v_u, mut a_u) = (f64::INFINITY, f64::INFINITY);
        for i in 0..D {
            let d = (b[i] - a[i]).abs();
            if d > 0.0 {
                v_u = v_u.min(vmax[i] / d);
                a_u = a_u.min(amax[i] / d);
            }
        }
        if !v_u.is_finite() {
            return None;
        }
        Some(if v_u * v_u / a_u >= 1.0 {
            let t_ramp = (1.0 / a_u).sqrt();
            Self {
                acc: a_u,
                t_ramp,
                t_cruise: 0.0,
                v_peak: a_u * t_ramp,
            }
        } else {
            Self {
                acc: a_u,
                t_ramp: v_u / a_u,
                t_cruise: (1.0 - v_u * v_u / a_u) / v_u,
                v_peak: v_u,
            }
        })
    }

    fn duration(&self) -> f64 {
        2.0 * self.t_ramp + self.t_cruise
    }

    /// `u(t)` for `t ∈ [0, duration]`.
    fn position(&self, t: f64) -> f64 {
        let ramp = 0.5 * self.acc * self.t_ramp * self.t_ramp;
        if t <= self.t_ramp {
            0.5 * self.acc * t * t
        } else if t <= self.t_ramp + self.t_cruise {
            ramp + self.v_peak * (t - self.t_ramp)
        } else {
            let r = (self.duration() - t).max(0.0);
            1.0 - 0.5 * self.acc * r * r
        }
    }

    /// `(t, u(t))` at the ramp samples and the cruise end; the last is `(T, 1)`.
    fn samples(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let n = RAMP_SAMPLES;
        let up = (1..=n).map(move |k| self.t_ramp * k as f64 / n as f64);
        let cruise_end = (self.t_cruise > 0.0).then_some(self.t_ramp + self.t_cruise);
        let down =
            (1..=n).map(move |k| self.t_ramp + self.t_cruise + self.t_ramp * k as f64 / n as f64);
        up.chain(cruise_end).chain(down).map(move |t| {
            if t >= self.duration() {
                (self.duration(), 1.0)
            } else {
                (t, self.position(t))
            }
        })
    }
}
