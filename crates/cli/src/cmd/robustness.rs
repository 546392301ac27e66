//! `pregrasp robustness SCENE.toml`: how far may the part lie from where the scene says? A
//! Monte-Carlo over placement errors, each sample re-planned (`pregrasp_planner::robustness`).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::output::Outputs;
use pregrasp_io::scene::Scene;
use pregrasp_planner::auto_grasps::plan_auto;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::robustness::{default_levels, per_plan, robustness, svg, PlacementError};

use super::{EXIT_NO_PLAN, EXIT_OK};

#[derive(clap::Args)]
#[command(
    after_help = "Without --pos-mm / --yaw-deg: fourteen levels, ±2 / ±5 / ±10 / ±20 / ±50 mm, ±1 / ±2 / ±5 / ±10 / ±20°, and the pairs (2 mm, 1°), (5 mm, 2°), (10 mm, 5°), (20 mm, 10°). Offsets are uniform in [-e, e] along world x, along world y, and in yaw about the vertical through the part's bounding-box centre.\n\nExit status: 0 the report was made, 2 the nominal scene has no plan (nothing to follow), 1 bad input."
)]
pub struct Args {
    /// The scene file.
    pub scene: PathBuf,
    /// Samples per error level.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub samples: u32,
    /// One level: the largest position error (mm) along x and along y.
    #[arg(long)]
    pub pos_mm: Option<f64>,
    /// One level: the largest yaw error (degrees).
    #[arg(long)]
    pub yaw_deg: Option<f64>,
    /// Seed of the placement samples.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (default: all cores). The report is the same for any number.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Write the whole report (every sample) as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write an SVG bar chart of the share planned per level.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Write the nominal plan file with each plan's `robustness` object (the share of samples
    /// in which its rotation axis planned again, per level, and the largest level it always did).
    #[arg(long, value_name = "FILE")]
    pub write_plan: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let levels = match (args.pos_mm, args.yaw_deg) {
        (None, None) => default_levels(),
        (p, y) => {
            let p = p.unwrap_or(0.0);
            let y = y.unwrap_or(0.0);
            anyhow::ensure!(
                p.is_finite() && (0.0..=500.0).contains(&p),
                "--pos-mm {p}: must be in [0, 500]"
            );
            anyhow::ensure!(
                y.is_finite() && (0.0..=180.0).contains(&y),
                "--yaw-deg {y}: must be in [0, 180]"
            );
            vec![PlacementError {
                pos: p * 1e-3,
                yaw: y.to_radians(),
            }]
        }
    };
    let scene = Scene::load(&args.scene)?;
    // All three outputs are declared before any planning and written together at the end.
    let mut outputs = Outputs::new();
    outputs
        .reading(&args.scene, "the scene")
        .reading(&scene.object.mesh_path, "the mesh");
    let mut declare =
        |path: &Option<PathBuf>| path.as_deref().map(|p| outputs.declare(p)).transpose();
    let (svg_out, plan_out, json_out) = (
        declare(&args.svg)?,
        declare(&args.write_plan)?,
        declare(&args.json)?,
    );
    let mesh = load_mesh(&scene.object.mesh_path, scene.object.scale)
        .with_context(|| format!("{}: object.mesh", args.scene.display()))?
        .mesh;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()?;
    let nominal =
        pool.install(|| plan_auto(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {}))?;
    // An auto scene's placements keep the grasps its search chose at the nominal pose.
    let scene = scene.with_grasps_of(&nominal.file.grasps);
    if nominal.file.plans.is_empty() {
        println!(
            "no plan at the nominal pose: {}",
            nominal.file.reason.as_deref().unwrap_or("-")
        );
        return Ok(ExitCode::from(EXIT_NO_PLAN));
    }
    let samples = args.samples as usize;
    let bar = if std::io::stderr().is_terminal() {
        ProgressBar::new((samples * levels.len()) as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(ProgressStyle::with_template(
        "placements [{bar:30}] {pos}/{len} ({eta})",
    )?);
    let report = pool.install(|| {
        robustness(
            &scene,
            &mesh,
            &nominal.file,
            &levels,
            samples,
            args.seed,
            &|| bar.inc(1),
        )
    })?;
    bar.finish_and_clear();

    let best = &nominal.file.plans[0];
    println!(
        "{}: nominal plan candidate {}, {} samples per level, seed {}",
        args.scene.display(),
        best.candidate,
        samples,
        args.seed
    );
    println!(
        "{:<16} {:>9} {:>10}  {:<34} grasp–table clearance min / median",
        "error (±)", "any plan", "same axis", "no plan because (count)"
    );
    for l in &report.levels {
        let pct = |n: usize| format!("{:.0} %", 100.0 * n as f64 / l.samples.max(1) as f64);
        let stages = if l.stages.is_empty() {
            "-".to_string()
        } else {
            l.stages
                .iter()
                .map(|(s, n)| format!("{s} ({n})"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mm = |v: Option<f64>| v.map_or("-".into(), |x| format!("{:.1}", x * 1e3));
        println!(
            "{:<16} {:>9} {:>10}  {:<34} {} / {} mm",
            l.error.label(),
            pct(l.planned),
            pct(l.same_axis),
            stages,
            mm(l.clearance_min),
            mm(l.clearance_median)
        );
    }
    match &report.axis_tolerance {
        Some(e) => println!(
            "the plan's axis planned again in every sample up to {}",
            e.label()
        ),
        None => println!("the plan's axis failed in some sample at every level"),
    }
    if let Some(id) = svg_out {
        let chart = svg(
            &report,
            &format!("{}: placement error vs planning", args.scene.display()),
        );
        outputs.write(id, chart.as_bytes())?;
    }
    if let Some(id) = plan_out {
        let mut file = nominal.file.clone();
        for (p, r) in file
            .plans
            .iter_mut()
            .zip(per_plan(&report, nominal.file.plans.len()))
        {
            p.robustness = Some(r);
        }
        if let Some(path) = &args.write_plan {
            file.locate_inputs(path);
        }
        outputs.write(id, file.to_json().as_bytes())?;
    }
    if let Some(id) = json_out {
        let text = serde_json::to_string_pretty(&report)?;
        outputs.write(id, text.as_bytes())?;
    }
    for path in outputs.commit()? {
        println!("wrote {path}");
    }
    Ok(ExitCode::from(EXIT_OK))
}
