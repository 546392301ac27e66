//! `pregrasp export PLAN.json --format F -o DIR [--plan K]`: the plan for the cell — URScript
//! per arm, CSV, ROS 2 trajectories, glTF (`docs/export.md`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use pregrasp_export::{export, Drawing, Format, Options, OutFile};
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::output::{OutputError, Outputs};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_model::Timeline;

use super::EXIT_OK;

#[derive(clap::Args)]
#[command(
    after_help = "Writes into DIR: <arm>.script (URScript, one per controller), <arm>.csv, \
<arm>_<segment>.yaml (ROS 2 JointTrajectory), plan.glb (glTF 2.0). Nothing is written unless \
every file could be made. See docs/export.md.\nExit status: 0 written, 1 bad input (no plan, \
--plan out of range, unknown format, bad option, unreadable file)."
)]
pub struct Args {
    /// The plan file.
    pub plan: PathBuf,
    /// urscript, csv, ros2, gltf or all (a comma-separated list works too).
    #[arg(long, short = 'f', default_value = "all")]
    pub format: String,
    /// Output directory (created if missing).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Which plan of the file's ranked `plans` (0 = best).
    #[arg(long = "plan", default_value_t = 0)]
    pub plan_index: usize,
    /// CSV sample rate (Hz; 125 is the RTDE rate).
    #[arg(long, default_value_t = 125.0)]
    pub rate: f64,
    /// servoj lookahead_time (s), 0.03..0.2.
    #[arg(long, default_value_t = 0.1)]
    pub lookahead: f64,
    /// servoj gain, 100..2000.
    #[arg(long, default_value_t = 300.0)]
    pub gain: f64,
    /// Hand-off I/O: this controller's standard digital OUT, and the IN wired to the other's OUT.
    #[arg(long, default_value = "0,0")]
    pub sync_io: String,
    /// Joint speed (rad/s) of the first movej to the plan's first point.
    #[arg(long, default_value_t = 0.3)]
    pub movej_speed: f64,
    /// Joint acceleration (rad/s²) of that movej.
    #[arg(long, default_value_t = 0.5)]
    pub movej_accel: f64,
    /// Robotiq speed register (SET SPE, 0..255).
    #[arg(long, default_value_t = 128)]
    pub grip_speed: u8,
    /// Robotiq force register (SET FOR, 0..255) of the power grasps [default: each power
    /// grasp's own grip_force in the plan (20..235 N mapped to 0..255), else 255].
    #[arg(long, value_name = "REGISTER")]
    pub grip_force: Option<u8>,
    /// Force register of the support grasp's fingertip pinch; default: from sup1's grip_force,
    /// else the plan's physics.grip_force_recommended (20..235 N mapped to 0..255), else
    /// --grip-force.
    #[arg(long, value_name = "REGISTER")]
    pub support_grip_force: Option<u8>,
    /// A close is commanded this much (m) narrower than the plan's grip_width.
    #[arg(long, default_value_t = 0.01)]
    pub grip_squeeze: f64,
    /// Prefix of the ROS joint names (e.g. `left_`).
    #[arg(long, default_value = "")]
    pub ros_prefix: String,
    /// The part mesh for glTF, when it is not where the plan's `object.mesh` says (taken
    /// relative to the current directory, then to the plan file's directory).
    #[arg(long)]
    pub mesh: Option<PathBuf>,
}

fn parse_sync_io(s: &str) -> anyhow::Result<(u8, u8)> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || anyhow::anyhow!("--sync-io {s:?}: expected OUT,IN, two numbers 0..7");
    if parts.len() != 2 {
        return Err(bad());
    }
    let out = parts[0].parse::<u8>().map_err(|_| bad())?;
    let inp = parts[1].parse::<u8>().map_err(|_| bad())?;
    Ok((out, inp))
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let formats = Format::parse_list(&args.format)?;
    let (sync_out, sync_in) = parse_sync_io(&args.sync_io)?;
    let options = Options {
        rate: args.rate,
        lookahead: args.lookahead,
        gain: args.gain,
        sync_out,
        sync_in,
        movej_speed: args.movej_speed,
        movej_accel: args.movej_accel,
        grip_speed: args.grip_speed,
        grip_force: args.grip_force.unwrap_or(Options::default().grip_force),
        support_grip_force: args.support_grip_force,
        power_grip_force: args.grip_force,
        grip_squeeze: args.grip_squeeze,
        ros_prefix: args.ros_prefix.clone(),
    };
    options.validate()?;
    let file = PlanFile::read(&args.plan)?;
    let shown = args.plan.display().to_string();
    let set = file.to_model().with_context(|| shown.clone())?;
    // Refuse a plan-less file or a bad index before reading any mesh.
    Timeline::new(&set, args.plan_index).with_context(|| shown.clone())?;
    let drawn = if formats.contains(&Format::Gltf) {
        let path = args
            .mesh
            .clone()
            .unwrap_or_else(|| file.mesh_path(&args.plan));
        let loaded =
            load_mesh(&path, file.object.scale).with_context(|| format!("{shown}: object.mesh"))?;
        for w in &loaded.warnings {
            eprintln!("warning: {w}");
        }
        match file.arms_and_grippers(Some(&args.plan)) {
            Ok((arms, grippers)) => Some((loaded.mesh, arms, grippers)),
            Err(e) => {
                // The other formats' refusals come first, as glTF is made last.
                let others: Vec<Format> = formats
                    .iter()
                    .copied()
                    .filter(|f| *f != Format::Gltf)
                    .collect();
                export(&set, args.plan_index, &others, &options, None)
                    .with_context(|| shown.clone())?;
                anyhow::bail!("{shown}: plan cannot be exported: {e}");
            }
        }
    } else {
        None
    };
    let drawing = drawn.as_ref().map(|(mesh, arms, grippers)| Drawing {
        mesh,
        arms,
        grippers,
    });
    let files = export(&set, args.plan_index, &formats, &options, drawing.as_ref())
        .with_context(|| shown.clone())?;
    let written = write_all(&args.output, &files, &[(args.plan.as_path(), "the plan")])?;
    for p in &written {
        println!("wrote {}", p.display());
    }
    Ok(ExitCode::from(EXIT_OK))
}

/// Writes `files` into `dir` (created if missing) as one set of outputs ([`Outputs`]): each is
/// staged beside its name first and only when all are written are they renamed to their
/// names; on failure nothing named has been touched and no temporary file or folder made
/// stays. `inputs` are the files the export read (`(path, what)`), which it must not
/// overwrite.
pub fn write_all(
    dir: &Path,
    files: &[OutFile],
    inputs: &[(&Path, &str)],
) -> Result<Vec<PathBuf>, OutputError> {
    let mut out = Outputs::new();
    for (path, what) in inputs {
        out.reading(path, what);
    }
    for f in files {
        let id = out.declare_creating_dirs(&dir.join(&f.name))?;
        out.write(id, &f.bytes)?;
    }
    out.commit()?;
    Ok(files.iter().map(|f| dir.join(&f.name)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_written_all_or_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let files = |names: [&str; 2]| -> Vec<OutFile> {
            names
                .iter()
                .map(|n| OutFile {
                    name: n.to_string(),
                    bytes: n.as_bytes().to_vec(),
                })
                .collect()
        };
        let out = tmp.path().join("out");
        let written = write_all(&out, &files(["a.csv", "b.csv"]), &[]).unwrap();
        assert_eq!(written, vec![out.join("a.csv"), out.join("b.csv")]);
        assert_eq!(std::fs::read(out.join("b.csv")).unwrap(), b"b.csv");
        // A target that cannot be written: nothing else is written, no temporary file is left.
        let out2 = tmp.path().join("out2");
        std::fs::create_dir_all(out2.join("b.csv")).unwrap();
        assert!(write_all(&out2, &files(["a.csv", "b.csv"]), &[]).is_err());
        let left: Vec<String> = std::fs::read_dir(&out2)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            left,
            vec!["b.csv".to_string()],
            "only the directory in the way"
        );
    }
}
