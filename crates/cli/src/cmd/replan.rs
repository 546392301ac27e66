//! `pregrasp replan PLAN.json --object-pose "x y z qx qy qz qw"`: the part was measured at
//! another pose; keep the plan's rotation axis where it still works (else the full pipeline),
//! recompute θ_goal, μ_rot and the reaches, re-check, write a new plan. `--from rot`: sup1 has
//! run, keep it and plan the rest from where the arms stand.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::output::Outputs;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::context::PartKnowledge;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::replan::{replan, replan_from_rot};
use pregrasp_planner::resume::{replan_remaining, Resume};
use pregrasp_planner::settle::{settle, settle_on_hull, SettleTolerance};

use super::{EXIT_NO_PLAN, EXIT_OK};

#[derive(clap::Args)]
#[command(
    after_help = "The scene is the one the plan names (scene.file, found as written or beside the plan file) unless --scene is given; only the object's pose changes. The measured pose is the part as it lies on the support, without the lift (a plan's object.initial_pose includes it, and is brought down by it); unless --as-measured (or --from mas1 / sup2, where the part is held turned), it is brought onto the support first (the hull face nearest to facing down turned to face down, the part lowered or raised onto the support) and refused if that is more than 10 mm or 5° away.\n\nExit status: 0 planned, 2 no plan at the measured pose (the file says why), 1 bad input (nothing written)."
)]
pub struct Args {
    /// The nominal plan file.
    pub plan: PathBuf,
    /// The measured object pose in world: "x y z qx qy qz qw" (metres; quaternion x, y, z, w),
    /// the part as it lies (without the planner's lift). It is first brought onto the support:
    /// the nearest resting pose, at most 10 mm and 5° away.
    #[arg(long, value_name = "POSE")]
    pub object_pose: String,
    /// Plan at the pose exactly as given, not brought onto the support first.
    #[arg(long)]
    pub as_measured: bool,
    /// Follow this plan of the file (index into `plans`, 0 = best).
    #[arg(long = "plan", value_name = "K", default_value_t = 0)]
    pub plan_index: usize,
    /// The scene file, when it is not where the plan file says.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Where to write the new plan file.
    #[arg(short, long, default_value = "replanned.json")]
    pub output: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The first segment to plan again: `sup1` (everything); `rot` (sup1 has run: it is kept
    /// as executed, the gripper holds the part at the measured pose, and rot, mas1 and sup2
    /// start from the arms' joints now); `mas1` (rot has run too: the part is measured turned,
    /// in the supportive gripper, as it is: not brought onto the support); `sup2` (mas1 has run
    /// too: both grippers hold it).
    #[arg(long, value_enum, default_value_t = From::Sup1)]
    pub from: From,
}

/// Where re-planning starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum From {
    Sup1,
    Rot,
    Mas1,
    Sup2,
}

/// Parses "x y z qx qy qz qw" (spaces or commas) into a pose.
pub fn parse_pose(text: &str, what: &str) -> anyhow::Result<Isometry3<f64>> {
    let v: Vec<f64> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| anyhow::anyhow!("{what}: {s:?} is not a number"))
        })
        .collect::<anyhow::Result<_>>()?;
    anyhow::ensure!(
        v.len() == 7,
        "{what}: expected 7 numbers \"x y z qx qy qz qw\", found {}",
        v.len()
    );
    anyhow::ensure!(
        v.iter().all(|x| x.is_finite()),
        "{what}: every number must be finite"
    );
    anyhow::ensure!(
        v[..3]
            .iter()
            .all(|x| x.abs() <= pregrasp_io::scene::MAX_COORDINATE),
        "{what}: a coordinate is more than {} m from the origin (lengths are in metres)",
        pregrasp_io::scene::MAX_COORDINATE
    );
    // Scaled by its largest component first, so a quaternion of huge (finite) components
    // normalises instead of overflowing its norm to infinity.
    let largest = v[3..].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    anyhow::ensure!(largest > 0.0, "{what}: the quaternion is zero");
    let q = Quaternion::new(v[6], v[3], v[4], v[5]) / largest;
    Ok(Isometry3::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        UnitQuaternion::from_quaternion(q),
    ))
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let pose = parse_pose(&args.object_pose, "--object-pose")?;
    let nominal = PlanFile::read(&args.plan)?;
    anyhow::ensure!(
        args.plan_index < nominal.plans.len(),
        "--plan {}: {} has {} plan(s)",
        args.plan_index,
        args.plan.display(),
        nominal.plans.len()
    );
    let scene_path = args
        .scene
        .clone()
        .unwrap_or_else(|| nominal.scene_path(&args.plan));
    // The plan's grasps (for an auto scene, the ones its search chose) are the ones followed.
    let scene = Scene::load(&scene_path)?.with_grasps_of(&nominal.grasps);
    let mut outputs = Outputs::new();
    outputs
        .reading(&args.plan, "the nominal plan")
        .reading(&scene_path, "the scene")
        .reading(&scene.object.mesh_path, "the mesh");
    let out = outputs.declare(&args.output)?;
    let mesh = load_mesh(&scene.object.mesh_path, scene.object.scale)
        .with_context(|| format!("{}: object.mesh", scene_path.display()))?
        .mesh;
    // The part's BVH, hull and closings, built once for settling and every plan below.
    let known = Arc::new(PartKnowledge::new(&scene, &mesh)?);
    // A part held turned (after rot) does not lie on the support: it is taken as measured.
    let held_turned = matches!(args.from, From::Mas1 | From::Sup2);
    let pose = if args.as_measured || held_turned {
        pose
    } else {
        let tolerance = SettleTolerance::default();
        let settled = match known.hull() {
            Some(hull) => settle_on_hull(hull, &pose, scene.support_height, &tolerance),
            None => settle(&mesh, &pose, scene.support_height, &tolerance),
        }
        .context("--object-pose")?;
        println!(
            "measured pose brought onto the support: moved {:.2} mm, turned {:.2}°",
            settled.moved * 1e3,
            settled.turned.to_degrees()
        );
        settled.pose
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()?;
    let started = Instant::now();
    let result = pool.install(|| -> anyhow::Result<_> {
        Ok(match args.from {
            From::Sup1 => replan(
                &scene,
                &mesh,
                &nominal,
                args.plan_index,
                pose,
                &PlanOptions {
                    known: Some(known),
                    ..PlanOptions::default()
                },
            )?,
            From::Rot => replan_from_rot(&scene, &mesh, &nominal, args.plan_index, pose)?,
            From::Mas1 | From::Sup2 => {
                let resume = if args.from == From::Mas1 {
                    Resume::Mas1
                } else {
                    Resume::Sup2
                };
                replan_remaining(&scene, &mesh, &nominal, args.plan_index, pose, resume)?
            }
        })
    })?;
    let ms = started.elapsed().as_secs_f64() * 1e3;
    let mut file = result.report.file;
    file.timing_ms.insert("replan".into(), ms);
    file.locate_inputs(&args.output);
    outputs.write(out, file.to_json().as_bytes())?;
    outputs.commit()?;
    match file.plans.first() {
        Some(best) => println!(
            "{}: candidate {} (θ_goal {:.1}°), {:.1} ms",
            result.route.describe(),
            best.candidate,
            file.candidates[best.candidate]
                .theta_goal
                .unwrap_or(0.0)
                .to_degrees(),
            ms
        ),
        None => println!(
            "no plan at the measured pose: {} ({:.1} ms)",
            file.reason.as_deref().unwrap_or("-"),
            ms
        ),
    }
    println!("wrote {}", args.output.display());
    Ok(ExitCode::from(if file.plans.is_empty() {
        EXIT_NO_PLAN
    } else {
        EXIT_OK
    }))
}
