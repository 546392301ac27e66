//! `pregrasp kin`: forward and inverse kinematics of the built-in arms, as text or JSON.
//!
//! Numbers are taken as Python or a UR controller log prints them: exponent form with a
//! negative exponent or sign (`-3.3e-05`, `1E+02`), a leading `+` or `.`, and list punctuation
//! around them (`[0.0, -1.5708, ...]` pasted as it is), with no `--` needed before negative
//! ones. clap's own test for a negative number knows no signed exponent (it takes `-3.3e-05`
//! for a cluster of short options), so [`normalize_args`] first rewrites such words after
//! `kin` into plain decimals of exactly the same value.

use std::ffi::OsString;

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
    #[arg(num_args = 6, required = true, value_parser = number,
          value_names = ["Q1", "Q2", "Q3", "Q4", "Q5", "Q6"])]
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
    #[arg(long, num_args = 7, required = true, allow_negative_numbers = true, value_parser = number,
          value_names = ["X", "Y", "Z", "QX", "QY", "QZ", "QW"])]
    pub pose: Vec<f64>,
    /// Order solutions by joint distance to this configuration (rad); default all zero.
    /// At the wrist singularity its q6 is kept.
    #[arg(long, num_args = 6, allow_negative_numbers = true, value_parser = number,
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

/// One number argument: anything Rust's `f64` parser takes (`-3.3e-05`, `1E+02`, `+.5`,
/// `inf`), after stripping the list punctuation of a pasted Python or UR log line: a leading
/// `[`, a trailing `,` and a trailing `]` (`[0.0,` … `-1.5708,` … `0.0]`).
pub fn number(word: &str) -> Result<f64, String> {
    let trimmed = word.trim();
    let trimmed = trimmed.strip_prefix('[').unwrap_or(trimmed);
    let trimmed = trimmed.strip_suffix(',').unwrap_or(trimmed);
    let trimmed = trimmed.strip_suffix(']').unwrap_or(trimmed).trim();
    trimmed
        .parse::<f64>()
        .map_err(|_| format!("{word:?} is not a number"))
}

/// The command line with every word after `kin` that starts with `-` and is a finite
/// [`number`] written as a plain decimal (`-3.3e-05` → `-0.000033`, `-1.57,` → `-1.57`): the
/// form clap recognises as a negative number. Rust prints the shortest decimal that reads
/// back as the same `f64`, so no value changes. Other words (options, `--`) stay as they are.
pub fn normalize_args(args: impl IntoIterator<Item = OsString>) -> Vec<OsString> {
    // Some(is_kin) once the subcommand (the first word after the program that is not an
    // option) has been seen; `escaped` after a `--`.
    let mut command: Option<bool> = None;
    let mut escaped = false;
    args.into_iter()
        .enumerate()
        .map(|(i, arg)| {
            let Some(word) = arg.to_str() else {
                return arg;
            };
            if i == 0 || escaped {
                return arg;
            }
            match command {
                None => {
                    if !word.starts_with('-') {
                        command = Some(word == "kin");
                    }
                    return arg;
                }
                Some(false) => return arg,
                Some(true) => {}
            }
            if word == "--" {
                escaped = true;
            }
            if !word.starts_with('-') || word.starts_with("--") {
                return arg;
            }
            match number(word) {
                Ok(v) if v.is_finite() => OsString::from(format!("{v}")),
                _ => arg,
            }
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    fn normalized(args: &[&str]) -> Vec<String> {
        normalize_args(args.iter().map(OsString::from))
            .into_iter()
            .map(|a| a.into_string().unwrap())
            .collect()
    }

    #[test]
    fn signed_exponents_after_kin_become_plain_decimals_of_the_same_value() {
        let out = normalized(&[
            "pregrasp",
            "kin",
            "fk",
            "--json",
            "-3.3e-05",
            "-1.5707963267948966",
            "1e-05",
            "-2.5E+00",
            "-1.57,",
            "-7e-300",
            "-inf",
            "-x",
            "--",
            "-1e-3",
        ]);
        assert_eq!(&out[..4], ["pregrasp", "kin", "fk", "--json"]);
        assert_eq!(out[4], "-0.000033");
        assert_eq!(out[5], "-1.5707963267948966");
        assert_eq!(out[6], "1e-05", "a positive number is left as written");
        assert_eq!(out[7], "-2.5");
        assert_eq!(out[8], "-1.57");
        assert_eq!(out[9].parse::<f64>().unwrap(), -7e-300);
        assert_eq!(&out[10..], ["-inf", "-x", "--", "-1e-3"], "left to clap");
        for w in ["-3.3e-05", "-7e-300", "-2.5E+00"] {
            let v = number(w).unwrap();
            assert_eq!(format!("{v}").parse::<f64>().unwrap(), v, "{w}");
        }
    }

    #[test]
    fn only_kin_is_rewritten() {
        let args = ["pregrasp", "plan", "-3e-05.toml", "-o", "-1e-3"];
        assert_eq!(normalized(&args), args);
        let args = ["pregrasp", "--help", "example", "write", "kin", "-1e-3"];
        assert_eq!(normalized(&args), args);
    }

    #[test]
    fn number_takes_python_and_log_spellings() {
        for (word, v) in [
            ("-3.3e-05", -3.3e-05),
            ("1E+02", 100.0),
            ("+.5", 0.5),
            ("[0.25,", 0.25),
            ("-1.25,", -1.25),
            ("0.0]", 0.0),
            ("6.283185307179586]", std::f64::consts::TAU),
        ] {
            assert_eq!(number(word), Ok(v), "{word}");
        }
        assert!(number("1.5x")
            .unwrap_err()
            .contains("\"1.5x\" is not a number"));
        assert!(number("--json").is_err());
    }
}
