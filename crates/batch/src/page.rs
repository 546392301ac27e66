//! The viewer page of a plan file, as `pregrasp plan --html`, `pregrasp view` and a batch's
//! per-scene pages make it: the file as a plan set ([`PlanFile::to_model`]), its JSON text
//! embedded as it is, its arms and grippers loaded by io (an arm whose description cannot be
//! loaded is not drawn, a gripper that cannot be is drawn as the 2F-85), titled by the scene's
//! name, else its file, unless the options give a title.

use std::path::Path;

use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::plan_model::ModelError;
use pregrasp_viewer::{render_html_with_hull, Page, ViewOptions};

/// Why a plan file has no page: it is not a plan set.
#[derive(Debug, thiserror::Error)]
pub enum PageError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("the plan does not serialise: {0}")]
    Json(#[from] serde_json::Error),
}

/// The page of `plan` (read from `plan_path`, which finds its robot descriptions; `None`: from
/// the current directory) with the part `mesh` and its hull when the caller has it.
pub fn page_html(
    plan: &PlanFile,
    plan_path: Option<&Path>,
    mesh: &Mesh,
    hull: Option<&ConvexHull>,
    options: &ViewOptions,
) -> Result<String, PageError> {
    let set = plan.to_model()?;
    let json = serde_json::value::to_raw_value(plan)?;
    let arms = plan.arm_descriptions(plan_path).ok();
    let grippers = plan.grippers(plan_path).ok();
    let title = match &plan.scene.name {
        Some(name) => name.clone(),
        None => format!("pregrasp plan: {}", plan.scene.file),
    };
    let page = Page {
        set: &set,
        plan_json: &json,
        title: &title,
        mesh,
        arms: arms.as_ref().map(|a| &a[..]),
        grippers: grippers.as_ref().map(|g| &g[..]),
    };
    Ok(render_html_with_hull(&page, hull, options))
}
