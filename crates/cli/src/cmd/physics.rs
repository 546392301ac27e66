//! `pregrasp physics PLAN.json`: will the part hold while it turns? The quasi-static check of
//! every plan's `rot` segment (`pregrasp-physics`): the smallest grip force per state, the
//! worst state, and the grip force to set.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::{GraspKind, PlanFile};
use pregrasp_io::scene::Scene;
use pregrasp_physics::{
    analyse_plan, PartMass, PhysicsSettings, PlanPhysics, StateStatus, Verdict,
};
use pregrasp_planner::hold::physics_settings;

use super::{EXIT_NO_PLAN, EXIT_OK};

#[derive(clap::Args)]
#[command(
    after_help = "Friction and safety factor: the flags, else the scene file's [physics] table (mu_pad, mu_support, safety_factor, pad_torsion_radius, density, max_twist_arm; the scene the plan names, when it can be found), else mu_pad 0.8, mu_support 0.4, safety factor 2.0. Mass: --mass, else the plan's object.mass, else 700 kg/m^3 x the mesh's volume.\n\nExit status: 0 every plan holds, 2 some plan cannot be held, slides at the support or lifts off it, 1 unreadable or malformed plan file, mesh or scene."
)]
pub struct Args {
    /// The plan file to check.
    pub plan: PathBuf,
    /// Check only this plan (index into the file's `plans`, 0 = best).
    #[arg(long = "plan", value_name = "K")]
    pub plan_index: Option<usize>,
    /// Coulomb friction coefficient between the gripper pads and the part.
    #[arg(long)]
    pub mu_pad: Option<f64>,
    /// Coulomb friction coefficient between the part and the support.
    #[arg(long)]
    pub mu_support: Option<f64>,
    /// Recommended grip force = this × the largest minimum grip force.
    #[arg(long)]
    pub safety_factor: Option<f64>,
    /// The part's mass (kg), overriding the plan's `object.mass`.
    #[arg(long)]
    pub mass: Option<f64>,
    /// The object mesh, when it is not at the path the plan file names.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Interpolate 4 states in every interval of `rot` (default: only in the intervals where
    /// the worst state can lie — next to a local maximum of the grip force, or where the status
    /// or the support contacts change).
    #[arg(long)]
    pub all_states: bool,
    /// Print the reports as JSON (one array, one object per plan, every state included).
    #[arg(long)]
    pub json: bool,
}

/// Prints one table per plan; exit 0 iff every plan holds, 2 if not.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let file = PlanFile::read(&args.plan)?;
    let mesh_path = args
        .mesh
        .clone()
        .unwrap_or_else(|| file.mesh_path(&args.plan));
    let mesh = load_mesh(&mesh_path, file.object.scale)
        .with_context(|| format!("{}: object.mesh", args.plan.display()))?
        .mesh;

    let mut settings = PhysicsSettings::default();
    let scene_path = file.scene_path(&args.plan);
    let scene_note = if scene_path.is_file() {
        // The scene's own errors name the file and the key.
        let scene = Scene::load(&scene_path).map_err(|e| anyhow::anyhow!("{e}"))?;
        settings = physics_settings(&scene.physics);
        format!("scene {}", scene_path.display())
    } else {
        "scene not found: defaults".to_string()
    };
    if let Some(v) = args.mu_pad {
        settings.mu_pad = v;
    }
    if let Some(v) = args.mu_support {
        settings.mu_support = v;
    }
    if let Some(v) = args.safety_factor {
        settings.safety_factor = v;
    }
    settings.refine_all = args.all_states;
    settings.validate().context("bad argument")?;
    if let Some(m) = args.mass {
        pregrasp_io::scene::check_physics_value("mass", m)
            .map_err(|problem| anyhow::anyhow!("--mass: {problem}"))?;
    }
    let set = file
        .to_model()
        .with_context(|| format!("{}", args.plan.display()))?;
    let part = PartMass::resolve(
        set.object.mass,
        &mesh,
        args.mass.map(|m| (m, "--mass")),
        settings.density,
    )
    .with_context(|| format!("{}", args.plan.display()))?;

    let indices: Vec<usize> = match args.plan_index {
        Some(k) => {
            anyhow::ensure!(
                k < file.plans.len(),
                "--plan {k}: the file has {} plan(s)",
                file.plans.len()
            );
            vec![k]
        }
        None => (0..file.plans.len()).collect(),
    };
    // The supportive arm's gripper decides the force range (a jaw gripper's is its own).
    let grippers = file
        .grippers(Some(&args.plan))
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("{}", args.plan.display()))?;
    let settings_of = |k: usize| PhysicsSettings {
        grip_force: grippers
            .get(set.plans[k].roles.supportive)
            .map_or(settings.grip_force, |g| g.grip_force_range()),
        ..settings
    };
    let reports = indices
        .iter()
        .map(|&k| analyse_plan(&set, k, &part, &settings_of(k)))
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{}", args.plan.display()))?;
    let all_hold = reports.iter().all(|r| r.verdict == Verdict::Holds);
    let robot = |r: &PlanPhysics| set.arms[r.arm].name.as_str();

    if args.json {
        // Each report with its supportive arm's name.
        #[derive(serde::Serialize)]
        struct Named<'a> {
            #[serde(flatten)]
            report: &'a PlanPhysics,
            robot: &'a str,
        }
        let named: Vec<Named> = reports
            .iter()
            .map(|report| Named {
                report,
                robot: robot(report),
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&named)?);
    } else {
        println!(
            "{}: mass {:.3} kg ({}), mu_pad {}, mu_support {}, safety factor {} ({scene_note})",
            args.plan.display(),
            part.mass,
            part.source,
            settings.mu_pad,
            settings.mu_support,
            settings.safety_factor
        );
        if reports.is_empty() {
            println!("no plans in the file: nothing to check");
        }
        let names: Vec<&str> = set.arms.iter().map(|a| a.name.as_str()).collect();
        for r in &reports {
            print_report(r, robot(r));
            print_closings(r, &names);
        }
    }
    Ok(ExitCode::from(if all_hold {
        EXIT_OK
    } else {
        EXIT_NO_PLAN
    }))
}

fn num(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.digits$}"))
}

fn print_report(r: &PlanPhysics, robot: &str) {
    println!(
        "plan {} (candidate {}): {robot} holds G_s, pad gap {:.1} mm, {} states ({} interpolated)",
        r.plan,
        r.candidate,
        r.grip_width * 1e3,
        r.states.len(),
        r.states.iter().filter(|s| s.point.is_none()).count()
    );
    println!("  point  θ°      N_min N  support n N  support t N  use support  use pads  status");
    for (i, s) in r.states.iter().enumerate() {
        if s.point.is_none() && i != r.worst {
            continue;
        }
        let status = match s.status {
            StateStatus::Held => "held",
            StateStatus::Slides => "slides at the support",
            StateStatus::CannotHold => "cannot hold",
        };
        println!(
            "  {:>5}  {:6.2}  {:>7}  {:>11}  {:>11}  {:>11}  {:>8}  {status}{}",
            s.point.map_or_else(|| "~".to_string(), |p| p.to_string()),
            s.theta_deg,
            num(s.n_min, 2),
            num(s.support_normal, 2),
            num(s.support_tangential, 2),
            num(s.support_friction_use, 2),
            num(s.pad_friction_use, 2),
            if i == r.worst { "  <- worst" } else { "" }
        );
    }
    let w = &r.states[r.worst];
    let (lo, hi) = r.settings.grip_force;
    match (r.verdict, r.n_max, r.required, r.recommended) {
        (Verdict::Holds, Some(n), Some(req), Some(rec)) => println!(
            "  worst θ {:.2}°: N_min {n:.2} N; set the grip force to {rec:.1} N ({} × {n:.2} = {req:.2} N, within {lo}–{hi} N): holds",
            w.theta_deg, r.settings.safety_factor
        ),
        (Verdict::LiftsOffSupport, Some(n), Some(req), _) => println!(
            "  worst θ {:.2}°: N_min {n:.2} N ({} × {n:.2} = {req:.2} N), but the part hangs on the pads' twist ({:.1} mm): LIFTS OFF THE SUPPORT",
            w.theta_deg,
            r.settings.safety_factor,
            r.twist_arm * 1e3
        ),
        (Verdict::CannotHold, Some(n), Some(req), _) => println!(
            "  worst θ {:.2}°: N_min {n:.2} N; {} × {n:.2} = {req:.1} N exceeds the gripper's {hi} N: CANNOT HOLD",
            w.theta_deg, r.settings.safety_factor
        ),
        (verdict, _, _, _) => println!(
            "  at θ {:.2}° no grip force holds the part: {}",
            w.theta_deg,
            verdict.describe().to_uppercase()
        ),
    }
    for warning in &r.warnings {
        println!("  warning: {warning}");
    }
}

/// One line: each closing's grip force as the plan gives it (what the export commands), and,
/// when the pinch's differs from this check's recommendation, that.
fn print_closings(r: &PlanPhysics, names: &[&str]) {
    if r.closings.is_empty() {
        return;
    }
    let items: Vec<String> = r
        .closings
        .iter()
        .map(|c| {
            let arm = names.get(c.arm).copied().unwrap_or("?");
            let force = c
                .grip_force
                .map_or_else(|| "not given".to_string(), |f| format!("{f:.1} N"));
            let differs = match (c.grasp, c.grip_force, r.recommended) {
                (GraspKind::Support, Some(f), Some(rec)) if (f - rec).abs() > 0.05 => {
                    format!(" (this check: {rec:.1} N)")
                }
                _ => String::new(),
            };
            format!("{} {arm} {force}{differs}", c.segment)
        })
        .collect();
    println!("  grip force per closing: {}", items.join(", "));
}
