//! `pregrasp kin`: forward and inverse kinematics of the built-in arms, as text or JSON.

use std::process::ExitCode;

use anyhow::{bail, Context};
use nalgebra::Isometry3;
use pregrasp_io::plan_file::PoseJson;
use pregrasp_robot::{Joints, UrKinematics, UrModel, JOINT_NAMES};
use serde_json::json;

use super::{EXIT_NO_PLAN, EXIT_OK};

/// Kinematics of a UR arm (standard DH in the controller's base frame; the flange frame is
/// tool0, z out of the flange). Lengths in metres, angles in radians.
#[derive(clap::Subcommand)]
pub enum KinCommand {
    /// Forward kinematics: the flange pose for six joint angles.
    Fk(FkArgs),
    /// Inverse kinematics: every joint solution for a flange pose (exit status 2 when the
    /// pose is unreachable).
    Ik(IkArgs),
}

/// Arguments of `kin fk`.
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct FkArgs {
    /// Arm model: ur3e, ur5e, ur10e, ur16e or ur5.
    #[arg(long, default_value = "ur5e")]
    pub model: String,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// The six joint angles (rad): shoulder_pan shoulder_lift elbow wrist_1 wrist_2 wrist_3.
    #[arg(num_args = 6, required = true, value_names = ["Q1", "Q2", "Q3", "Q4", "Q5", "Q6"])]
    pub q: Vec<f64>,
}

/// Arguments of `kin ik`.
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct IkArgs {
    /// Arm model: ur3e, ur5e, ur10e, ur16e or ur5.
    #[arg(long, default_value = "ur5e")]
    pub model: String,
    /// Flange pose in the base frame: position (m) and quaternion (x, y, z, w; normalised).
    #[arg(long, num_args = 7, required = true, allow_negative_numbers = true,
          value_names = ["X", "Y", "Z", "QX", "QY", "QZ", "QW"])]
    pub pose: Vec<f64>,
    /// Order solutions by joint distance to this configuration (rad); default all zero.
    /// At the wrist singularity its q6 is kept.
    #[arg(long, num_args = 6, allow_negative_numbers = true,
          value_names = ["Q1", "Q2", "Q3", "Q4", "Q5", "Q6"])]
    pub seed: Option<Vec<f64>>,
    /// Also list every ±2π alternate the joint limits allow (elbow ±π, others ±2π).
    #[arg(long)]
    pub alternates: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(command: KinCommand) -> anyhow::Result<ExitCode> {
    match command {
        KinCommand::Fk(args) => run_fk(args),
        KinCommand::Ik(args) => run_ik(args),
    }
}

fn parse_model(name: &str) -> anyhow::Result<UrModel> {
    Ok(name.parse::<UrModel>()?)
}

fn joints(values: &[f64], what: &str) -> anyhow::Result<Joints> {
    let q: Joints = values
        .try_into()
        .with_context(|| format!("{what}: expected 6 joint angles, got {}", values.len()))?;
    if let Some(i) = q.iter().position(|v| !v.is_finite()) {
        bail!("{what}: {} is not a finite number", JOINT_NAMES[i]);
    }
    Ok(q)
}

fn pose_from_args(v: &[f64]) -> anyhow::Result<Isometry3<f64>> {
    if v.len() != 7 || v.iter().any(|x| !x.is_finite()) {
        bail!("--pose: expected 7 finite numbers X Y Z QX QY QZ QW");
    }
    let norm = v[3..].iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm < 1e-9 {
        bail!("--pose: the quaternion is zero");
    }
    if (norm - 1.0).abs() > 1e-6 {
        eprintln!("warning: --pose quaternion has norm {norm:.9}; normalised");
    }
    let pose = PoseJson {
        xyz: [v[0], v[1], v[2]],
        quat_xyzw: [v[3], v[4], v[5], v[6]],
    };
    Ok(pose.to_isometry())
}

fn fmt_joints(q: &Joints) -> String {
    q.iter()
        .map(|v| format!("{:>13.6}", v + 0.0)) // + 0.0 prints −0 as 0
        .collect::<Vec<_>>()
        .join(" ")
}

fn run_fk(args: FkArgs) -> anyhow::Result<ExitCode> {
    let model = parse_model(&args.model)?;
    let q = joints(&args.q, "joint angles")?;
    let pose = PoseJson::from(&UrKinematics::new(model).fk(&q));
    if args.json {
        let out =
            json!({ "model": model.name(), "q": q, "xyz": pose.xyz, "quat_xyzw": pose.quat_xyzw });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let [x, y, z] = pose.xyz.map(|v| v + 0.0); // + 0.0 prints −0 as 0
        let [qx, qy, qz, qw] = pose.quat_xyzw.map(|v| v + 0.0);
        println!("model      {model}");
        println!("xyz        {x:.9} {y:.9} {z:.9}");
        println!("quat_xyzw  {qx:.9} {qy:.9} {qz:.9} {qw:.9}");
    }
    Ok(ExitCode::from(EXIT_OK))
}

fn run_ik(args: IkArgs) -> anyhow::Result<ExitCode> {
    let model = parse_model(&args.model)?;
    let pose = pose_from_args(&args.pose)?;
    let seed = match &args.seed {
        Some(s) => joints(s, "--seed")?,
        None => [0.0; 6],
    };
    let kin = UrKinematics::new(model);
    let solutions: Vec<Joints> = if args.alternates {
        kin.ik(&pose, &seed)
    } else {
        // One entry per analytic solution, in (−π, π], nearest to the seed first.
        let raw = kin.ik_raw_with_q6_hint(&pose, seed[5]);
        let mut sols: Vec<Joints> = raw.as_slice().to_vec();
        sols.sort_by(|a, b| {
            let (da, db) = (
                pregrasp_robot::joint_distance(a, &seed),
                pregrasp_robot::joint_distance(b, &seed),
            );
            da.total_cmp(&db)
        });
        sols
    };
    if args.json {
        let out = json!({
            "model": model.name(),
            "joint_names": JOINT_NAMES,
            "solutions": solutions,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else if solutions.is_empty() {
        println!("no solution: the pose is out of reach of the {model}");
    } else {
        println!(
            "{:>3}  {}",
            "#",
            JOINT_NAMES.map(|n| format!("{n:>13}")).join(" ")
        );
        for (i, q) in solutions.iter().enumerate() {
            println!("{i:>3}  {}", fmt_joints(q));
        }
    }
    Ok(ExitCode::from(if solutions.is_empty() {
        EXIT_NO_PLAN
    } else {
        EXIT_OK
    }))
}
