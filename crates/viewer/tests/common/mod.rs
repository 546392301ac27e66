//! The viewer's fixture plan file and its page, made as the CLI makes a page from a plan file.

#![allow(dead_code)]

pub mod fixture;

use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_viewer::{render_html, Page, ViewOptions};

/// The page of `plan` with the part `mesh`, as `pregrasp view` renders it: the file as a plan
/// set, its JSON embedded, its arms and grippers loaded (from the current directory), the
/// scene's name as the title.
pub fn render(plan: &PlanFile, mesh: &Mesh, options: &ViewOptions) -> String {
    let set = plan.to_model().expect("the fixture is a plan set");
    let json = serde_json::value::to_raw_value(plan).expect("the plan serialises");
    let arms = plan.arm_descriptions(None).ok();
    let grippers = plan.grippers(None).ok();
    let title = plan
        .scene
        .name
        .clone()
        .unwrap_or_else(|| format!("pregrasp plan: {}", plan.scene.file));
    let page = Page {
        set: &set,
        plan_json: &json,
        title: &title,
        mesh,
        arms: arms.as_ref().map(|a| &a[..]),
        grippers: grippers.as_ref().map(|g| &g[..]),
    };
    render_html(&page, options)
}
