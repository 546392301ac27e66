//! `pregrasp axes`: the rotation-axis candidates of a scene (Algorithm 1), as a table or JSON.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::anyhow;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::CandidateJson;
use pregrasp_io::scene::Scene;
use pregrasp_planner::axes::rotation_axis_candidates;

use super::{EXIT_NO_PLAN, EXIT_OK};

const AFTER_HELP: &str = "\
Algorithm 1 of the paper: every feature edge of the part's convex hull (where two
non-coplanar hull faces meet) whose ends are both within planner.support_distance (Δd_s)
of the support at P_init (object.pose raised by planner.lift) and which is longer than
planner.min_axis_length (Δl) is a rotation axis. For each axis and each sense (ccw =
positive about axis[1] - axis[0], right-hand rule; cw = negative) θ_max is the largest
angle the part turns before going below the support, capped at planner.max_angle_deg
(φ_obj), computed exactly; 'stepped' is θ_max rounded down to planner.step_deg (Δφ).
Score = weight_length · length + weight_angle · θ_max. Best first.

Exit status: 0 at least one candidate, 2 none, 1 the scene or its mesh cannot be used.";

/// Arguments of `pregrasp axes`.
#[derive(clap::Args)]
#[command(after_help = AFTER_HELP)]
pub struct Args {
    /// The scene file (TOML, see scene-format.md); its mesh path is relative to it.
    pub scene: PathBuf,
    /// Print the plan format's `candidates` array (JSON, angles in radians) instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let scene = Scene::load(&args.scene)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let loaded = load_mesh(&scene.object.mesh_path, scene.object.scale)
        .map_err(|e| anyhow!("{}: object.mesh: {e}", scene.file.display()))?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let result = rotation_axis_candidates(
        &loaded.mesh,
        &scene.object.pose,
        scene.support_height,
        &scene.planner,
    );
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        let json: Vec<CandidateJson> = result.candidates.iter().map(|c| c.to_json()).collect();
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        println!(
            "{:>3}  {:<30}  {:<30}  {:>3}  {:>8}  {:>9}  {:>9}  {:>8}",
            "id", "axis[0] (m)", "axis[1] (m)", "dir", "length", "θmax°", "stepped°", "score"
        );
        for c in &result.candidates {
            let p = |q: &nalgebra::Point3<f64>| format!("({:.4}, {:.4}, {:.4})", q.x, q.y, q.z);
            println!(
                "{:>3}  {:<30}  {:<30}  {:>3}  {:>8.4}  {:>9.4}  {:>9.2}  {:>8.4}",
                c.id,
                p(&c.axis[0]),
                p(&c.axis[1]),
                c.direction,
                c.length,
                c.theta_max.to_degrees(),
                c.theta_max_stepped.to_degrees(),
                c.score
            );
        }
        println!(
            "{} candidate(s) from {} hull feature edge(s); support z = {}, lift {} m",
            result.candidates.len(),
            result.hull.feature_edges.len(),
            scene.support_height,
            scene.planner.lift
        );
    }
    if result.candidates.is_empty() {
        eprintln!("no rotation-axis candidates");
        return Ok(ExitCode::from(EXIT_NO_PLAN));
    }
    Ok(ExitCode::from(EXIT_OK))
}
