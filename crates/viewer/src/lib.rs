//! A self-contained HTML 3D viewer for pregrasp plans.
//!
//! [`render_html`] turns a [`Page`] — the plan set ([`pregrasp_model::PlanSet`]), the plan
//! file's JSON text, the part's mesh and the arms as the caller loaded them — into one HTML
//! page: the data (plan, mesh, hull feature edges, robot models) is embedded as JSON in a
//! `<script type="application/json">`, and a small WebGL program of the page's own (no
//! library, no network request: the page works offline) draws the support, the part at
//! P_init, the hull's feature edges, every rotation-axis candidate and both arms with their
//! grippers, and animates the selected plan (μ_sup1, μ_rot, μ_mas1, μ_sup2).
//!
//! The viewer reads no file: the caller (the CLI, the batch runner) reads the plan file, turns
//! it into the model and loads the arms' robot descriptions and grippers.
//!
//! The arms are posed in the browser by forward kinematics from the embedded standard DH
//! table; the page cross-checks that FK against Rust's [`pregrasp_robot::UrKinematics`]
//! for a few embedded configurations (`window.pregraspViewer.fkError()`).

pub mod data;
pub mod html;
pub mod options;

use pregrasp_geometry::Mesh;
use pregrasp_model::PlanSet;
use pregrasp_robot::{ArmDescription, Gripper};
use serde_json::value::RawValue;

pub use data::THREE_VERSION;
pub use html::{
    escape_json_for_script, render_html, render_html_with_hull, CONTENT_SECURITY_POLICY,
};
pub use options::ViewOptions;

/// What one page shows, as the caller resolved it.
#[derive(Clone, Copy, Debug)]
pub struct Page<'a> {
    /// The plans and their cell: what the Rust side computes from (robot models, FK checks,
    /// the fingers each gripper holds the part with).
    pub set: &'a PlanSet,
    /// The plan file as JSON, embedded verbatim as the page's `plan` (its script reads it).
    pub plan_json: &'a RawValue,
    /// The title when the options give none: the scene's name, else the scene file.
    pub title: &'a str,
    /// The part in its object frame (metres).
    pub mesh: &'a Mesh,
    /// The arms, one per arm of `set` (built-in or from their robot descriptions); `None`:
    /// they could not be loaded, and an arm known only by its description is not drawn.
    pub arms: Option<&'a [ArmDescription]>,
    /// The arms' grippers, one per arm of `set`; `None`: they could not be loaded, and each
    /// arm is drawn with the 2F-85 at its tool points.
    pub grippers: Option<&'a [Gripper]>,
}
