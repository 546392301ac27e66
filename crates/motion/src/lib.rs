//! Generic motion planning for pregrasp, in the style of OMPL/VAMP: the planner never
//! knows what a robot is. It sees a [`JointSpace`] (box bounds and a weighted L1
//! metric that bounds arm-point travel in metres) and a [`StateValidator`]
//! (a predicate on joint states); everything else is built on those two.
//!
//! - [`space`]: [`State`], [`JointSpace`] (`contains`, `motion_bound`, `interpolate`, `sample`).
//! - [`validity`]: [`StateValidator`], [`MotionValidator`] — edges checked every
//!   `resolution` metres of arm-point travel, coarse-to-fine, first failure stops; whole boxes
//!   of states at once where the validator can, a failed box handing its [`Doubts`] down.
//! - [`rrt_connect`](mod@rrt_connect): [`rrt_connect()`] with [`RrtConnectSettings`], and
//!   [`rrt_connect_until`] that a caller may stop (its answer no longer wanted); the outcome
//!   is a [`PlanResult`] with a [`PlanStatus`] and [`PlanStats`], never an error.
//! - [`simplify`](mod@simplify): [`simplify()`] / [`simplify_by`] — greedy, seeded random
//!   and single-joint (partial) shortcutting, then waypoint removal; never invalidates a
//!   path nor raises its [`PathCost`] (length, or [`RestToRest`] duration).
//! - [`cartesian`]: [`straight_line`] — straight tool moves by seeded IK with branch
//!   continuity; typed [`CartesianError`].
//! - [`timing`]: [`time_parameterize`] — trapezoidal timing under speed and acceleration
//!   limits into a [`TimedPath`].
//!
//! ```
//! use pregrasp_motion::*;
//!
//! // A 2-D space with a wall at x ∈ (−0.1, 0.1) open for y > 0.5.
//! let space = JointSpace::new([-1.0; 2], [1.0; 2], [1.0; 2]).unwrap();
//! let free = |q: &State<2>| q[0].abs() >= 0.1 || q[1] > 0.5;
//! let motion = MotionValidator::new(&space, &free, 0.01);
//! let settings = RrtConnectSettings { seed: 7, ..Default::default() };
//! let result = rrt_connect(&space, &motion, &[-0.8, -0.8], &[0.8, -0.8], &settings);
//! assert_eq!(result.status, PlanStatus::Solved);
//! assert!(motion.check_path(&result.path));
//!
//! let timed = time_parameterize(&result.path, &[1.0; 2], &[2.0; 2]);
//! assert_eq!(timed.t[0], 0.0);
//! assert!(timed.t.windows(2).all(|w| w[0] < w[1]));
//! ```
//!
//! Determinism: all randomness comes from ChaCha8 seeded by the caller; only the
//! optional wall-clock limit ([`PlanStatus::Timeout`]) and a caller's stop
//! ([`PlanStatus::Stopped`]) can make results differ.

pub mod cartesian;
pub mod rrt_connect;
pub mod simplify;
pub mod space;
pub mod timing;
pub mod validity;

pub use cartesian::{interpolate_pose, straight_line, CartesianError, CartesianSettings};
pub use rrt_connect::{
    rrt_connect, rrt_connect_until, PlanResult, PlanStats, PlanStatus, RrtConnectSettings,
    SIMPLIFY_ROUNDS,
};
pub use simplify::{simplify, simplify_by, PathCost, RestToRest};
pub use space::{JointSpace, JointSpaceError, State};
pub use timing::{
    rest_to_rest_duration, time_parameterize, try_time_parameterize, TimedPath, TimingError,
};
pub use validity::{Doubts, MotionValidator, StateValidator};
