//! `pregrasp batch DIR -o OUT`: every scene under DIR planned in parallel (`pregrasp-batch`),
//! its plan file and viewer page under OUT, and `summary.csv`, `summary.json`, `report.html`.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use indicatif::{ProgressBar, ProgressStyle};
use pregrasp_batch::report::{self, Counts};
use pregrasp_io::output::Outputs;
use pregrasp_planner::pipeline::PlanOptions;

use super::EXIT_OK;

#[derive(clap::Args)]
#[command(
    after_help = "Every *.toml under DIR (recursively, OUT left out) is a scene. Under OUT, per scene <path>.plan.json, <path>.html and <path>.stamp (a fingerprint of the scene text, the mesh bytes and the pregrasp version: a scene whose stamp matches is not planned again), and summary.csv, summary.json, report.html.\n\nExit status: 0 the batch ran (whatever each scene's outcome: see the summary; a scene that cannot be loaded, or a folder that cannot be read, is a row with its error), 1 DIR is not a folder or holds no scene, OUT is DIR, or OUT cannot be written (then nothing is written)."
)]
pub struct Args {
    /// The folder of scene files.
    pub dir: PathBuf,
    /// Where the plans, viewer pages and summaries go.
    #[arg(short, long, default_value = "batch-out")]
    pub output: PathBuf,
    /// Keep at most this many plans per scene.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub max_plans: u32,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let scenes = pregrasp_batch::discover(&args.dir, Some(&args.output))?;
    // The summary files are declared before any planning: a folder in their way stops the
    // batch now, and nothing at all is written unless everything can be.
    let mut outputs = Outputs::new();
    let summary = report::declare(&mut outputs, &args.output)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()?;
    let bar = if std::io::stderr().is_terminal() {
        ProgressBar::new(scenes.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(ProgressStyle::with_template(
        "{msg} [{bar:30}] {pos}/{len} scenes ({eta})",
    )?);
    bar.set_message("planning");
    let options = PlanOptions {
        max_plans: args.max_plans as usize,
        ..PlanOptions::default()
    };
    let records = pool.install(|| {
        pregrasp_batch::run_staged(
            &args.dir,
            &args.output,
            &scenes,
            &options,
            &mut outputs,
            &|r| {
                bar.set_message(r.scene.clone());
                bar.inc(1);
            },
        )
    });
    bar.finish_and_clear();
    let title = format!("pregrasp batch: {}", args.dir.display());
    report::stage(&mut outputs, summary, &records, &title).map_err(anyhow::Error::msg)?;
    outputs.commit()?;
    for r in &records {
        println!(
            "{:<40} {:<8} {}",
            r.scene,
            r.status,
            r.reason.as_deref().unwrap_or("")
        );
    }
    let c = Counts::of(&records);
    println!(
        "{} scenes: {} planned, {} no plan, {} errors ({} up to date, reused)",
        c.scenes, c.planned, c.no_plan, c.error, c.reused
    );
    println!("wrote {}", args.output.join("report.html").display());
    Ok(ExitCode::from(EXIT_OK))
}
