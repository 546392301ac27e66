//! Will it hold? A quasi-static check of pregrasp's rotation (`μ_rot`).
//!
//! While the supportive arm turns the part about its edge, the part is pinched by the two pads
//! of a parallel gripper at `G_s` and rests on the support along the rotation axis. At every
//! state of the plan's `rot` segment this crate finds the **smallest grip force** that keeps the
//! part in static equilibrium — gravity, Coulomb friction at the pads and at the support, six
//! equations — as a small second-order cone program ([`statics`]), and from the worst state the
//! grip force to set ([`plan`]).
//!
//! Assumptions: rigid bodies, Coulomb friction, quasi-static motion (no inertia: the rotation
//! is slow), the line contact with the support modelled by its two endpoints, both pads
//! squeezing with the same normal force. See `docs/physics.md`.

pub mod carry;
mod error;
mod grip_force;
mod lu;
pub mod mass;
pub mod part_mass;
mod pivot;
pub mod plan;
pub mod plan_report;
mod polish;
pub mod settings;
pub mod statics;
pub mod twist;
mod words;

pub use carry::{min_carry_force, Carry, CarryOutcome, CarryProblem, HoldKind, PowerHold};
pub use error::PhysicsError;
pub use grip_force::{min_grip_force, min_grip_force_from, WarmStart};
pub use mass::{MassError, MassProperties};
pub use part_mass::{MassSource, PartMass};
pub use plan::{analyse_one, analyse_plan, screen_one, screen_plan, SUPPORT_CONTACT_TOLERANCE};
pub use plan_report::{
    At, ClosingForce, GripWarning, PlanPhysics, StateReport, StateStatus, Unheld, Verdict,
};
pub use settings::{
    PhysicsSettings, SettingsError, DEFAULT_DENSITY, DEFAULT_MU_PAD, DEFAULT_MU_SUPPORT,
    DEFAULT_SAFETY_FACTOR, GRAVITY, GRIP_FORCE_RANGE, PAD_PATCH_TORSION_RADIUS,
};
pub use statics::{
    min_grip_force_conic, ContactModel, Equilibrium, Pads, SolverError, StaticOutcome,
    StaticProblem,
};
