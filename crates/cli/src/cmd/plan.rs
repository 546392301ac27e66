//! `pregrasp plan SCENE.toml`: Algorithms 1–3 end to end, a checked plan file written atomically.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::output::Outputs;
use pregrasp_io::plan_file::{PlanFile, PlanStatus};
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::{CandidateOutcome, PlanOptions, PlanReport};
use pregrasp_planner::plan_scene;

use super::{EXIT_NO_PLAN, EXIT_OK};

#[derive(clap::Args)]
#[command(
    after_help = "Exit status: 0 planned, 2 no plan (the file says why), 1 bad input (nothing written).\n\
Every plan is re-verified with `pregrasp check`'s rules before it is written."
)]
pub struct Args {
    /// The scene file (TOML, see docs/scene-format.md).
    pub scene: PathBuf,
    /// Where to write the plan file (JSON). Written atomically; nothing is written on bad input.
    #[arg(short, long, default_value = "plan.json")]
    pub output: PathBuf,
    /// Keep at most this many plans, best first (by S_rot).
    #[arg(long, default_value_t = 3)]
    pub max_plans: usize,
    /// Worker threads for evaluating candidates in parallel (default: all cores). The plan is the
    /// same for any number.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Also write the interactive 3D view of the plan to this HTML file.
    #[arg(long)]
    pub html: Option<PathBuf>,
    /// No progress bar and no tables; errors are still printed.
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let options = PlanOptions {
        max_plans: args.max_plans.max(1),
        ..PlanOptions::default()
    };
    plan_scene_file(
        &args.scene,
        &args.output,
        args.html.as_deref(),
        args.threads,
        args.quiet,
        &options,
    )
}

/// Loads, plans, prints and writes; shared with `pregrasp demo`.
pub fn plan_scene_file(
    scene_path: &Path,
    output: &Path,
    html: Option<&Path>,
    threads: Option<usize>,
    quiet: bool,
    options: &PlanOptions,
) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    let scene = Scene::load(scene_path)?;
    // Every output is declared before planning: a path that cannot be written is refused now,
    // and nothing is written unless all of them can be.
    let mut outputs = Outputs::new();
    outputs
        .reading(scene_path, "the scene")
        .reading(&scene.object.mesh_path, "the mesh");
    let plan_out = outputs.declare(output)?;
    let html_out = html.map(|p| outputs.declare(p)).transpose()?;
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }
    let loaded = load_mesh(&scene.object.mesh_path, scene.object.scale)
        .with_context(|| format!("{}: object.mesh", scene_path.display()))?;
    for warning in &loaded.warnings {
        eprintln!("warning: {warning}");
    }
    let pool = match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()?,
        None => rayon::ThreadPoolBuilder::new().build()?,
    };
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(0);
        bar.set_style(ProgressStyle::with_template(
            "{msg} [{bar:30}] {pos}/{len} candidates",
        )?);
        bar.set_message("planning");
        bar
    };
    let report = pool.install(|| {
        plan_scene(
            &scene,
            &loaded.mesh,
            options,
            &|total| bar.set_length(total as u64),
            &|| bar.inc(1),
        )
    });
    bar.finish_and_clear();
    let report = report.with_context(|| format!("{}: cannot plan", scene_path.display()))?;
    let mut file = report.file.clone();
    file.timing_ms
        .insert("process".into(), started.elapsed().as_secs_f64() * 1e3);

    file.locate_inputs(output);
    outputs.write(plan_out, file.to_json().as_bytes())?;
    if let Some(id) = html_out {
        let page = super::view::page_html(
            &file,
            None,
            &loaded.mesh,
            report.hull.as_ref(),
            &Default::default(),
        )?;
        outputs.write(id, page.as_bytes())?;
    }
    outputs.commit()?;
    if !quiet {
        print_summary(&report, &file);
        println!("wrote {}", output.display());
        if let Some(html_path) = html {
            println!("wrote {}", html_path.display());
        }
    }
    Ok(ExitCode::from(if file.status == PlanStatus::Planned {
        EXIT_OK
    } else {
        EXIT_NO_PLAN
    }))
}

/// The candidate table, the chosen plan and the time per stage.
pub fn print_summary(report: &PlanReport, file: &PlanFile) {
    println!(
        "{:>3}  {:<4} {:>8} {:>9} {:>7} {:>8}  outcome",
        "id", "dir", "length", "θ_max°", "score", "θ_goal°"
    );
    for (c, json) in report.candidates.iter().zip(&file.candidates) {
        let goal = json
            .theta_goal
            .map_or("-".to_string(), |g| format!("{:.1}", g.to_degrees()));
        println!(
            "{:>3}  {:<4} {:>8.3} {:>9.2} {:>7.3} {:>8}  {}",
            c.id,
            json.direction,
            c.length,
            c.theta_max.to_degrees(),
            c.score,
            goal,
            json.outcome
        );
    }
    if file.candidates.is_empty() {
        println!("(no rotation-axis candidates)");
    }
    match file.plans.first() {
        Some(best) => {
            let c = &file.candidates[best.candidate];
            println!();
            println!(
                "plan: candidate {} ({} about {:.3},{:.3},{:.3} → {:.3},{:.3},{:.3}), θ_goal {:.1}°, score {:.3}",
                best.candidate,
                c.direction,
                c.axis[0][0], c.axis[0][1], c.axis[0][2],
                c.axis[1][0], c.axis[1][1], c.axis[1][2],
                c.theta_goal.unwrap_or(0.0).to_degrees(),
                best.score
            );
            println!(
                "      master {}, supportive {}",
                best.master, best.supportive
            );
            if let Some(p) = &best.physics {
                println!(
                    "      grip: {} — needs {} N (× {} safety), set {} N; friction use pads {}, support {} (mass {:.2} kg, μ pad {}, support {})",
                    p.verdict.describe(),
                    opt(p.grip_force_min, 1),
                    p.safety_factor,
                    opt(p.grip_force_recommended, 0),
                    opt(p.pad_friction_use, 2),
                    opt(p.support_friction_use, 2),
                    p.mass,
                    p.mu_pad,
                    p.mu_support
                );
            }
            for seg in &best.segments {
                println!(
                    "      {:<5} {:<6} {:>4} points {:>6.2} s",
                    seg.name,
                    seg.robot,
                    seg.points.len(),
                    seg.points.last().map_or(0.0, |p| p.t)
                );
            }
            let planned = report
                .outcomes
                .iter()
                .filter(|o| matches!(o, CandidateOutcome::Planned { .. }))
                .count();
            println!(
                "      {} plan(s) written, {} candidate(s) planned",
                file.plans.len(),
                planned
            );
        }
        None => {
            println!();
            println!("no plan: {}", file.reason.as_deref().unwrap_or("-"));
        }
    }
    if let Some(note) = &report.physics_note {
        println!("{note}");
    }
    if let Some(a) = &file.grasps.auto {
        println!(
            "grasps: auto — {} bar sites, {} grasp sets, {} tried, {} planned{}; bar widths support {:.0} mm, power {:.0} / {:.0} mm",
            a.sites,
            a.sets,
            a.tried,
            a.planned,
            a.chosen.map_or(String::new(), |k| format!(", set {k} chosen")),
            a.widths[0] * 1e3,
            a.widths[1] * 1e3,
            a.widths[2] * 1e3
        );
    }
    if let Some(s) = file.grasps.slid {
        println!(
            "grasps: the scene's power grasps cannot carry the part; slid along their bars by \
             {:.1} and {:.1} mm towards its centre of mass (grasps.slid)",
            s[0] * 1e3,
            s[1] * 1e3
        );
    }
    let t = &file.timing_ms;
    let get = |k: &str| t.get(k).copied().unwrap_or(0.0);
    println!(
        "time: axes {:.2} ms, grips {:.2} ms, poses {:.2} ms, paths (incl. re-check) {:.2} ms, \
         total {:.2} ms",
        get("axes"),
        get("grips"),
        get("poses"),
        get("paths"),
        get("total")
    );
    if t.contains_key("rot") {
        println!(
            "      in paths, summed over candidates: μ_rot {:.2} ms, lines {:.2} ms, transits \
             {:.2} ms, re-check {:.2} ms, grip check {:.2} ms",
            get("rot"),
            get("lines"),
            get("transit"),
            get("recheck"),
            get("hold")
        );
    }
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.digits$}"))
}
