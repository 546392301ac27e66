//! `pregrasp view PLAN.json -o plan.html`: one self-contained HTML page with an interactive
//! 3D view of the plan (drawn by its own WebGL code, no network needed; open it in any browser).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
pub use pregrasp_batch::page::page_html;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::output::Outputs;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_viewer::ViewOptions;

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
