//! `pregrasp view PLAN.json -o plan.html`: one self-contained HTML page with an interactive
//! 3D view of the plan (drawn by its own WebGL code, no network needed; open it in any browser).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::output::Outputs;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_viewer::{render_html_with_hull, Page, ViewOptions};

#[derive(clap::Args)]
pub struct Args {
    /// Plan file written by `pregrasp plan` or `pregrasp demo`.
    pub plan: PathBuf,
    /// Output HTML file (written atomically).
    #[arg(short, long, default_value = "plan.html")]
    pub output: PathBuf,
    /// Part mesh to show instead of the plan's `object.mesh` (the plan's `object.scale` is
    /// still applied). A relative `object.mesh` is looked up from the current directory,
    /// then beside the plan file.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Page title (default: the scene name).
    #[arg(long)]
    pub title: Option<String>,
    /// Which plan to show first (1 = best).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub plan_number: u64,
    /// Playback speed factor: 0.25, 0.5, 1, 2, 4 or 8 (the page's menu).
    #[arg(long, default_value_t = 1.0, value_parser = parse_speed)]
    pub speed: f64,
    /// Do not start playing when the page opens.
    #[arg(long)]
    pub no_autoplay: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let plan = PlanFile::read(&args.plan)?;
    let mesh_path = match &args.mesh {
        Some(p) => p.clone(),
        None => plan.mesh_path(&args.plan),
    };
    let mut outputs = Outputs::new();
    outputs
        .reading(&args.plan, "the plan")
        .reading(&mesh_path, "the mesh");
    let out = outputs.declare(&args.output)?;
    let loaded = load_mesh(&mesh_path, plan.object.scale)
        .with_context(|| format!("{}: object.mesh", args.plan.display()))?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let options = ViewOptions {
        title: args.title,
        initial_plan: (args.plan_number - 1) as usize,
        speed: args.speed,
        autoplay: !args.no_autoplay,
    };
    let html = page_html(&plan, Some(&args.plan), &loaded.mesh, None, &options)
        .with_context(|| args.plan.display().to_string())?;
    outputs.write(out, html.as_bytes())?;
    outputs.commit()?;
    eprintln!(
        "wrote {} ({} plan(s), {} candidate(s), {} KiB)",
        args.output.display(),
        plan.plans.len(),
        plan.candidates.len(),
        html.len() / 1024
    );
    Ok(ExitCode::SUCCESS)
}

/// The page of the plan file `plan` (read from `plan_path`, which finds the robot descriptions
/// of arms given by one, as `check` does; `None`: from the current directory) with the part
/// `mesh`: the file as a plan set, its JSON embedded as it is, its arms and grippers loaded
/// (an arm whose description cannot be loaded is not drawn, a gripper that cannot be is drawn
/// as the 2F-85), titled by the scene's name (else its file) unless `options` give a title.
/// Fails only when the file is not a plan set.
pub fn page_html(
    plan: &PlanFile,
    plan_path: Option<&Path>,
    mesh: &Mesh,
    hull: Option<&ConvexHull>,
    options: &ViewOptions,
) -> anyhow::Result<String> {
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

/// The playback speeds the page's menu offers.
const SPEEDS: [f64; 6] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0];

/// A playback speed the page offers (one of [`SPEEDS`]): any other value would silently play
/// at 1×.
fn parse_speed(text: &str) -> Result<f64, String> {
    let speed: f64 = text
        .parse()
        .map_err(|_| format!("{text:?} is not a number"))?;
    if SPEEDS.contains(&speed) {
        Ok(speed)
    } else {
        Err(format!(
            "{text} is not one of the page's speeds: choose 0.25, 0.5, 1, 2, 4 or 8"
        ))
    }
}
