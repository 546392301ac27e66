//! `pregrasp demo`: the whole method on the built-in chair side, with nothing but the binary.
//!
//! It is exactly `pregrasp example write DIR` followed by `pregrasp plan DIR/chair_side.toml
//! -o demo-plan.json --html demo-plan.html`.

use std::path::PathBuf;
use std::process::ExitCode;

use pregrasp_planner::pipeline::PlanOptions;

#[derive(clap::Args)]
pub struct Args {
    /// Directory for the example's scene and mesh files.
    #[arg(long, default_value = "pregrasp-demo")]
    pub dir: PathBuf,
    /// Where to write the plan file.
    #[arg(short, long, default_value = "demo-plan.json")]
    pub output: PathBuf,
    /// Where to write the interactive 3D view.
    #[arg(long, default_value = "demo-plan.html")]
    pub html: PathBuf,
    /// Which built-in example to run (chair_side, shelf_side, stool_side).
    #[arg(long, default_value = "chair_side")]
    pub example: String,
    /// No progress bar and no tables.
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let example = pregrasp_examples::by_name(&args.example).ok_or_else(|| {
        anyhow::anyhow!(
            "unknown example {:?} (try `pregrasp example list`)",
            args.example
        )
    })?;
    let [scene, _mesh] = pregrasp_examples::write_example(&args.dir, &example)?;
    if !args.quiet {
        println!(
            "{}: {} (scene {})",
            example.name,
            example.title,
            scene.display()
        );
    }
    super::plan::plan_scene_file(
        &scene,
        &args.output,
        Some(&args.html),
        None,
        args.quiet,
        &PlanOptions::default(),
    )
}
