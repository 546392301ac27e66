//! The pre-grasp manipulation pipeline of the paper (§IV–VI), from a scene to a plan file:
//!
//! - [`axes`]: Algorithm 1, rotation-axis candidates λ with θ_max and S_rot;
//! - [`poses`] (with [`dummies`]): Algorithm 2, P_obj and θ_goal per candidate, roles, IK sets;
//! - [`rotate`], [`reach`], [`paths`]: Algorithm 3, μ_rot, μ_sup1, μ_mas1, μ_sup2;
//! - [`timing`], [`output`]: timed segments and the plan file;
//! - [`plan_format`]: is a file a plan file (shape and ranges, before any motion is judged);
//! - [`check`]: the plan-file validity rules, re-verified with our own models;
//! - [`hold`]: will the pinch hold the part during `μ_rot` (quasi-static grip force check);
//! - [`carry`]: will the power grasps carry the part once it is lifted off the table;
//! - [`closings`]: how the grippers close on the part at G_s and at the power grasps;
//! - [`seat`]: power grasps moved onto the palm, so the closing does not pull the part;
//! - [`slide`]: power grasps slid along their bars towards the centre of mass, where the
//!   scene's cannot carry the part;
//! - [`pipeline`]: all of it, candidates in parallel, deterministic for any thread count,
//!   ranked by score (`ranking`);
//! - [`replan`]: the same plan for a part measured at another pose (issue 16);
//! - [`settle`]: a measured pose brought onto the support (the part lies on the table);
//! - [`robustness`]: Monte-Carlo over placement errors, re-planning each sample;
//! - [`auto_grasps`]: `[grasps] mode = "auto"`, grasps found from the mesh.
//!
//! [`context`] holds the read-only models every stage shares; `pregrasp_model::timeline` the semantics of a
//! plan's instants (who moves, which gripper is closed, where contact is allowed); [`clock`]
//! where Algorithm 3's time goes.

pub mod carry;
pub mod check;
pub mod clock;
pub mod closings;
pub mod context;
pub mod dummies;
pub mod error;
mod halves;
pub mod hold;
pub mod hold_kind;
mod no_plan;
pub mod open_fingers;
mod outcome;
pub mod output;
pub mod pass_memo;
pub mod paths;
pub mod pipeline;
/// Moved to the I/O crate, so every reader of a plan file validates it; kept here by name.
pub use pregrasp_io::plan_format;
pub mod poses;
mod ranking;
pub mod reach;
pub mod rejection;
pub mod replan;
pub mod resume;
pub mod robustness;
pub mod rotate;
pub mod seat;
pub mod settle;
pub mod slide;
pub mod timing;

pub mod auto_grasps;
pub mod axes;
pub use axes::{rotation_axis_candidates, AxesResult, Direction, RotationAxisCandidate};
pub use error::PlanError;

/// A scene planned as `pregrasp plan` plans it: with its grasps found from the mesh when it
/// asks for `[grasps] mode = "auto"` ([`auto_grasps::plan_auto`]), otherwise with its own grasps
/// and plans ranked by robustness when `[planner] robustness_samples` > 0
/// ([`robustness::plan_ranked_by_robustness`], which is the plain [`pipeline::plan`] when it is 0).
///
/// A scene without a plan is a report (`status = "no_plan"`, with its reason); an error is a
/// scene or mesh the planner cannot work on ([`PlanError`]), which a scene loaded from a file
/// never is but one built in code may be.
pub fn plan_scene(
    scene: &pregrasp_io::scene::Scene,
    mesh: &pregrasp_geometry::Mesh,
    options: &pipeline::PlanOptions,
    on_candidates: &(dyn Fn(usize) + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<pipeline::PlanReport, PlanError> {
    if scene.grasps.auto.is_some() {
        auto_grasps::plan_auto(scene, mesh, options, on_candidates, progress)
    } else {
        robustness::plan_ranked_by_robustness(scene, mesh, options, on_candidates, progress)
    }
}
