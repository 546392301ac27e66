//! `pregrasp bench`: benchmarks anyone can rerun.
//!
//! `pregrasp bench reach PROBLEMS.json [--json]` plans every start/goal query of a reach
//! problem set (one arm among cuboids, see `pregrasp_reach::problem`) with
//! RRT-Connect and simplification, and prints the success rate and the median / p95
//! in-process planning time.
//!
//! `pregrasp bench plan SCENE.toml… [--runs N]` runs the whole pipeline (Algorithms 1–3, the
//! plan check and the grip check) on each scene and prints the median / p95 time per stage,
//! Algorithm 3 split into its parts (`pregrasp_planner::clock`), cold and warm side by side:
//! cold, N fresh `pregrasp plan` processes (a part seen for the first time, [`cold`];
//! also the whole process's time); warm, N runs in this process after a warm-up (what the
//! process keeps between plans is known).
//!
//! `pregrasp bench replan SCENE.toml… [--samples N]` plans each scene once, then replans it
//! in-process at N placements drawn uniformly within ±5 mm along world x and y and ±2° of yaw
//! about the part's centre (seeded; what `pregrasp replan` does in a cell after measuring the
//! part): median / p95 time per replan and how many kept the plan's axis.

mod cold;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use pregrasp_reach::{
    run_reach, ReachProblemSet, ReachSettings, DEFAULT_MARGIN, DEFAULT_RESOLUTION,
};
use serde_json::json;

#[derive(clap::Subcommand)]
pub enum BenchCommand {
    /// Motion-planning benchmark on a reach problem set (e.g. data/reach-ur5-table-boxes.json).
    Reach(ReachArgs),
    /// The whole pipeline on each scene, repeated: median / p95 time per stage.
    Plan(PlanArgs),
    /// Replanning each scene's plan at random nearby placements: median / p95 time.
    Replan(ReplanArgs),
}

#[derive(clap::Args)]
pub struct ReplanArgs {
    /// The scene files (e.g. `examples/*.toml`).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Placements per scene (after one warm-up replan).
    #[arg(long, default_value_t = 15)]
    pub samples: usize,
    /// Largest position error along world x and y (mm).
    #[arg(long, default_value_t = 5.0)]
    pub pos_mm: f64,
    /// Largest yaw error about the part's centre (degrees).
    #[arg(long, default_value_t = 2.0)]
    pub yaw_deg: f64,
    /// Seed of the placements.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

#[derive(clap::Args)]
pub struct PlanArgs {
    /// The scene files (e.g. `examples/*.toml`).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// How many times to plan in this process after one warm-up (warm).
    #[arg(long, default_value_t = 20)]
    pub runs: usize,
    /// How many fresh `pregrasp plan` processes to time (cold; default: as many as `--runs`,
    /// 0: none, the warm runs alone).
    #[arg(long)]
    pub cold_runs: Option<usize>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args)]
pub struct ReachArgs {
    /// The problem-set JSON file.
    pub problems: PathBuf,
    /// Print the summary (and per-query outcomes) as JSON.
    #[arg(long)]
    pub json: bool,
    /// Base seed; query k uses seed + k.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// RRT-Connect iteration limit per query (the deterministic stop).
    #[arg(long, default_value_t = 20_000)]
    pub max_iterations: usize,
    /// Wall-clock safety limit per query, seconds.
    #[arg(long, default_value_t = 5.0)]
    pub max_time: f64,
    /// Edge-check resolution, metres of arm-point travel.
    #[arg(long, default_value_t = DEFAULT_RESOLUTION)]
    pub resolution: f64,
    /// Safety margin of every collision check, metres (default: half the resolution).
    #[arg(long, default_value_t = DEFAULT_MARGIN)]
    pub margin: f64,
}

pub fn run(command: BenchCommand) -> anyhow::Result<ExitCode> {
    match command {
        BenchCommand::Reach(args) => reach(args),
        BenchCommand::Plan(args) => plan(args),
        BenchCommand::Replan(args) => replan(args),
    }
}

/// The stages `bench plan` reports: Algorithms 1 and 2, Algorithm 3 with the checks after it
/// (`paths`) and its parts, the whole.
pub(crate) const PLAN_STAGES: [&str; 10] = [
    "axes", "grips", "poses", "paths", "rot", "lines", "transit", "recheck", "hold", "total",
];

fn plan(args: PlanArgs) -> anyhow::Result<ExitCode> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        builder = builder.num_threads(n.max(1));
    }
    let pool = builder.build()?;
    let runs = args.runs.max(1);
    let mut reports = Vec::new();
    for scene in &args.scenes {
        let cold_runs = args.cold_runs.unwrap_or(runs);
        let cold = (cold_runs > 0)
            .then(|| cold::cold_runs(scene, cold_runs, args.threads))
            .transpose()?;
        let (status, summary) = plan_one(scene, runs, &pool)?;
        if args.json {
            let stat = |(m, p): (f64, f64)| json!({ "median_ms": m, "p95_ms": p });
            let stages: serde_json::Map<String, serde_json::Value> = summary
                .iter()
                .map(|(n, [m, p, ..])| (n.to_string(), stat((*m, *p))))
                .collect();
            let known: serde_json::Map<String, serde_json::Value> = summary
                .iter()
                .map(|(n, [.., m, p])| (n.to_string(), stat((*m, *p))))
                .collect();
            let mut report = json!({ "scene": scene.display().to_string(), "runs": runs,
                                     "threads": pool.current_num_threads(), "status": status,
                                     "stages": stages,
                                     "known": { "runs": runs, "stages": known } });
            if let Some(cold) = &cold {
                let cold_stages: serde_json::Map<String, serde_json::Value> = PLAN_STAGES
                    .iter()
                    .enumerate()
                    .map(|(k, n)| (n.to_string(), stat(cold.stage(k))))
                    .collect();
                report["cold"] = json!({ "runs": cold_runs, "process": stat(cold.process()),
                                         "stages": cold_stages });
            }
            reports.push(report);
        } else {
            println!(
                "{}: {} runs on {} thread(s), status {}; cold: a fresh process per run, warm: \
                 runs in one process after a warm-up, known: the part's geometry and closings \
                 kept between those runs too",
                scene.display(),
                runs,
                pool.current_num_threads(),
                status
            );
            println!(
                "  {:<9} {:>21} | {:>21} | {:>21}",
                "", "cold median / p95", "warm median / p95", "known median / p95"
            );
            let blank = format!("{:>21}", "");
            if let Some(cold) = &cold {
                let (m, p) = cold.process();
                println!(
                    "  {:<9} {m:8.2} / {p:8.2} ms | {blank} | {blank}",
                    "process"
                );
            }
            for (name, [median, p95, known, known_p95]) in &summary {
                let indent = if ["rot", "lines", "transit", "recheck", "hold"].contains(name) {
                    "  "
                } else {
                    ""
                };
                let label = format!("{indent}{name}");
                let k = PLAN_STAGES.iter().position(|s| s == name);
                let cold_cell = match (&cold, k) {
                    (Some(cold), Some(k)) => {
                        let (m, p) = cold.stage(k);
                        format!("{m:8.2} / {p:8.2} ms")
                    }
                    _ => blank.clone(),
                };
                println!(
                    "  {label:<9} {cold_cell} | {median:8.2} / {p95:8.2} ms | \
                     {known:8.2} / {known_p95:8.2} ms"
                );
            }
        }
    }
    if args.json {
        // One scene: its object, as before; several: an array.
        let out = if reports.len() == 1 {
            reports.remove(0)
        } else {
            serde_json::Value::Array(reports)
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
    }
    Ok(ExitCode::SUCCESS)
}

/// A stage's name and its median and p95 (ms), warm and with the part known:
/// `[warm median, warm p95, known median, known p95]`.
type StageTime = (&'static str, [f64; 4]);

/// `runs` timed plans of one scene (after a warm-up), twice: warm (a new part every run) and
/// with the part's knowledge kept. Its status, the time loading the scene and mesh took (once:
/// `load`, median = p95), and per stage of [`PLAN_STAGES`], the medians and p95s (ms).
fn plan_one(
    path: &std::path::Path,
    runs: usize,
    pool: &rayon::ThreadPool,
) -> anyhow::Result<(String, Vec<StageTime>)> {
    use pregrasp_planner::auto_grasps::plan_auto;
    use pregrasp_planner::pipeline::PlanOptions;
    // Loading is timed once: the scene with its arms (a robot description's collision
    // geometry computed, or read from the cache) and the mesh.
    let loading = std::time::Instant::now();
    let scene = pregrasp_io::scene::Scene::load(path)?;
    let mesh = pregrasp_io::mesh_io::load_mesh(&scene.object.mesh_path, scene.object.scale)
        .with_context(|| format!("{}: object.mesh", path.display()))?
        .mesh;
    let load_ms = loading.elapsed().as_secs_f64() * 1e3;
    // Warm: a new part every run, the process's caches kept. Known: the part's knowledge
    // (its geometry, hull and every closing asked, object frame) kept between runs as well,
    // what a cell replanning one part or a batch of copies of it has.
    let known = PlanOptions {
        known: Some(std::sync::Arc::new(
            pregrasp_planner::context::PartKnowledge::new(&scene, &mesh)?,
        )),
        ..PlanOptions::default()
    };
    let mut status = String::new();
    // Each way's samples and its last run's plan file, timing aside.
    let mut timed = |options: &PlanOptions| -> anyhow::Result<(Vec<Vec<f64>>, String)> {
        let mut samples: Vec<Vec<f64>> = vec![Vec::with_capacity(runs); PLAN_STAGES.len()];
        let mut file = String::new();
        for run in 0..=runs {
            let report = pool.install(|| plan_auto(&scene, &mesh, options, &|_| {}, &|| {}))?;
            status = report.file.status.to_string();
            if run > 0 {
                for (k, stage) in PLAN_STAGES.iter().enumerate() {
                    samples[k].push(report.file.timing_ms.get(*stage).copied().unwrap_or(0.0));
                }
            }
            if run == runs {
                let mut plan = report.file;
                plan.timing_ms.clear();
                file = plan.to_json();
            }
        }
        Ok((samples, file))
    };
    let (mut warm, warm_file) = timed(&PlanOptions::default())?;
    let (mut with_known, known_file) = timed(&known)?;
    anyhow::ensure!(
        warm_file == known_file,
        "{}: the plan with the part known differs from the plan without it (a bug: please report it)",
        path.display()
    );
    let stat = |v: &mut Vec<f64>| -> (f64, f64) {
        v.sort_by(f64::total_cmp);
        (quantile(v, 0.5), quantile(v, 0.95))
    };
    let mut summary: Vec<StageTime> = vec![("load", [load_ms; 4])];
    summary.extend(
        PLAN_STAGES
            .iter()
            .zip(warm.iter_mut().zip(with_known.iter_mut()))
            .map(|(name, (w, k))| {
                let ((wm, wp), (km, kp)) = (stat(w), stat(k));
                (*name, [wm, wp, km, kp])
            }),
    );
    Ok((status, summary))
}

fn replan(args: ReplanArgs) -> anyhow::Result<ExitCode> {
    use pregrasp_planner::pipeline::PlanOptions;
    use pregrasp_planner::replan::{replan, ReplanRoute};
    use pregrasp_planner::robustness::{displaced, part_centre};
    if !(args.pos_mm >= 0.0 && args.pos_mm.is_finite() && args.pos_mm <= 100.0) {
        anyhow::bail!("--pos-mm must be in [0, 100], got {}", args.pos_mm);
    }
    if !(args.yaw_deg >= 0.0 && args.yaw_deg.is_finite() && args.yaw_deg <= 45.0) {
        anyhow::bail!("--yaw-deg must be in [0, 45], got {}", args.yaw_deg);
    }
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        builder = builder.num_threads(n.max(1));
    }
    let pool = builder.build()?;
    // SplitMix64: uniform numbers in [−1, 1), the same for the same seed.
    let mut state = args.seed;
    let mut uniform = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for path in &args.scenes {
        let scene = pregrasp_io::scene::Scene::load(path)?;
        let mesh = pregrasp_io::mesh_io::load_mesh(&scene.object.mesh_path, scene.object.scale)
            .with_context(|| format!("{}: object.mesh", path.display()))?
            .mesh;
        let nominal = pool.install(|| {
            pregrasp_planner::plan_scene(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        })?;
        if nominal.file.plans.is_empty() {
            println!("{}: no plan to replan", path.display());
            continue;
        }
        // An auto scene's placements keep the grasps its search chose.
        let scene = scene.with_grasps_of(&nominal.file.grasps);
        let centre = part_centre(&mesh, &scene.object.pose);
        // What the cell keeps between measurements: the part's geometry and the closings at
        // its grasps (object frame), built once.
        let options = PlanOptions {
            known: Some(std::sync::Arc::new(
                pregrasp_planner::context::PartKnowledge::new(&scene, &mesh)?,
            )),
            ..PlanOptions::default()
        };
        let mut times = Vec::with_capacity(args.samples);
        let (mut kept, mut planned) = (0usize, 0usize);
        for k in 0..=args.samples {
            let (dx, dy) = (
                uniform() * args.pos_mm * 1e-3,
                uniform() * args.pos_mm * 1e-3,
            );
            let dyaw = uniform() * args.yaw_deg.to_radians();
            let pose = displaced(&scene.object.pose, &centre, dx, dy, dyaw);
            let started = std::time::Instant::now();
            let result =
                pool.install(|| replan(&scene, &mesh, &nominal.file, 0, pose, &options))?;
            let ms = started.elapsed().as_secs_f64() * 1e3;
            if k == 0 {
                continue; // warm-up: the first query builds the models' caches
            }
            times.push(ms);
            planned += usize::from(!result.report.file.plans.is_empty());
            kept += usize::from(result.route == ReplanRoute::KeptCandidate);
        }
        times.sort_by(f64::total_cmp);
        if times.is_empty() {
            println!("{}: no samples", path.display());
            continue;
        }
        println!(
            "{}: {} placements (±{} mm, ±{}°, seed {}) on {} thread(s): {planned} planned, {kept} \
             kept the plan's axis; replan median {:.2} ms, p95 {:.2} ms, max {:.2} ms",
            path.display(),
            times.len(),
            args.pos_mm,
            args.yaw_deg,
            args.seed,
            pool.current_num_threads(),
            quantile(&times, 0.5),
            quantile(&times, 0.95),
            times[times.len() - 1]
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The `q` quantile of sorted, non-empty `values`: the nearest rank.
pub(crate) fn quantile(values: &[f64], q: f64) -> f64 {
    values[((values.len() - 1) as f64 * q).round() as usize]
}

fn reach(args: ReachArgs) -> anyhow::Result<ExitCode> {
    if !(args.resolution > 0.0 && args.resolution.is_finite()) {
        anyhow::bail!(
            "--resolution must be a positive number of metres, got {}",
            args.resolution
        );
    }
    if !(args.max_time > 0.0 && args.max_time.is_finite()) {
        anyhow::bail!(
            "--max-time must be a positive number of seconds, got {}",
            args.max_time
        );
    }
    if !(args.margin >= 0.0 && args.margin.is_finite()) {
        anyhow::bail!("--margin must be >= 0 metres, got {}", args.margin);
    }
    let set = ReachProblemSet::load(&args.problems).context("cannot use the problem set")?;
    let mut settings = ReachSettings {
        resolution: args.resolution,
        margin: args.margin,
        ..ReachSettings::default()
    };
    settings.rrt.seed = args.seed;
    settings.rrt.max_iterations = args.max_iterations;
    settings.rrt.max_time = Some(Duration::from_secs_f64(args.max_time));
    let report = run_reach(&set, &settings);
    if args.json {
        let outcomes: Vec<_> = report
            .outcomes
            .iter()
            .map(|o| {
                json!({
                    "status": format!("{:?}", o.status),
                    "time_ms": o.time.as_secs_f64() * 1e3,
                    "waypoints": o.waypoints,
                    "length": o.length,
                    "iterations": o.iterations,
                    "states_checked": o.states_checked,
                })
            })
            .collect();
        let out = json!({
            "problems": args.problems.display().to_string(),
            "model": set.model.name(),
            "queries": report.queries,
            "solved": report.solved,
            "success_rate": report.success_rate,
            "median_ms": report.median_ms,
            "p95_ms": report.p95_ms,
            "mean_ms": report.mean_ms,
            "max_ms": report.max_ms,
            "settings": {
                "seed": args.seed,
                "max_iterations": args.max_iterations,
                "max_time_s": args.max_time,
                "resolution": args.resolution,
                "margin": args.margin,
            },
            "outcomes": outcomes,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "problem set  {} ({}, {} obstacles)",
            args.problems.display(),
            set.model.name(),
            set.obstacles.len()
        );
        println!(
            "solved       {}/{} ({:.1} %)",
            report.solved,
            report.queries,
            100.0 * report.success_rate
        );
        println!(
            "planning     median {:.3} ms, p95 {:.3} ms, mean {:.3} ms, max {:.3} ms",
            report.median_ms, report.p95_ms, report.mean_ms, report.max_ms
        );
        println!(
            "settings     seed {}, {} iterations, resolution {} m, margin {} m",
            args.seed, args.max_iterations, args.resolution, args.margin
        );
    }
    Ok(ExitCode::SUCCESS)
}
