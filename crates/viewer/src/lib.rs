//! A self-contained HTML 3D viewer for pregrasp plan files.
//!
//! [`render_html`] turns a [`PlanFile`](pregrasp_io::plan_file::PlanFile) and the part's
//! mesh into one HTML page: the data (plan, mesh, hull feature edges, robot models) is
//! embedded as JSON in a `<script type="application/json">`, and a small WebGL program of the
//! page's own (no library, no network request: the page works offline) draws the support,
//! the part at P_init, the hull's feature edges, every rotation-axis candidate and both arms
//! with their grippers, and animates the selected plan (μ_sup1, μ_rot, μ_mas1, μ_sup2).
//!
//! The arms are posed in the browser by forward kinematics from the embedded standard DH
//! table; the page cross-checks that FK against Rust's [`pregrasp_robot::UrKinematics`]
//! for a few embedded configurations (`window.pregraspViewer.fkError()`).

pub mod data;
pub mod fixture;
pub mod html;
pub mod options;

pub use data::THREE_VERSION;
pub use html::{
    escape_json_for_script, render_html, render_html_with_hull, CONTENT_SECURITY_POLICY,
};
pub use options::ViewOptions;
