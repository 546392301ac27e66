//! Exports a plan of a plan set (`docs/plan-format.md`) for the cell (`docs/export.md`):
//!
//! - [`urscript`]: one URScript program per arm — `servoj` at 500 Hz, Robotiq 2F-85 commands
//!   through the URCap's socket, a digital-I/O hand-off between the two controllers;
//! - [`csv`]: per arm, `t,q1..q6,gripper` at a fixed rate (plus every plan point);
//! - [`ros2`]: per arm and segment it moves in, a `trajectory_msgs/msg/JointTrajectory` as YAML;
//! - [`gltf`]: one binary glTF 2.0 file, both arms, grippers, table and part, animated.
//!
//! The plan comes as the typed model (`pregrasp_model::PlanSet`) and is walked on its one time
//! line (`pregrasp_model::Timeline`). Everything is produced in memory ([`export`]); the caller
//! writes the files (the CLI all or none). Output is deterministic: the same plan and options
//! give the same bytes.

pub mod csv;
pub mod gltf;
pub mod ros2;
pub mod urscript;

use pregrasp_geometry::Mesh;
use pregrasp_model::{PlanSet, Timeline, TimelineError};
use pregrasp_robot::{ArmDescription, Gripper, UrModel};

/// Everything that can go wrong in an export. Messages are complete sentences for the CLI.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The plan cannot be laid on one time line ([`TimelineError`]): no plan, an index out of
    /// range, a segment naming no arm, without points or not continuous.
    #[error(transparent)]
    Timeline(#[from] TimelineError),
    #[error("unknown export format {0:?} (expected urscript, csv, ros2, gltf or all)")]
    Format(String),
    #[error("bad option: {0}")]
    Option(String),
    #[error(
        "plan cannot be exported: robot name {name:?} cannot name a file (letters, digits, `_`, \
         `-` only)"
    )]
    ArmName { name: String },
    #[error(
        "plan cannot be exported: URScript export needs exactly two robots, the plan has {count}"
    )]
    ArmCount { count: usize },
    #[error(
        "plan cannot be exported: {models} arm models and {grippers} grippers for {arms} arms"
    )]
    Drawing {
        models: usize,
        grippers: usize,
        arms: usize,
    },
    #[error(
        "plan cannot be exported: two plan points are too close in time for glTF's 32-bit key \
         times"
    )]
    KeyTimes,
    #[error("plan cannot be exported: glTF document does not serialise: {0}")]
    Gltf(String),
    #[error("the glTF export needs the part's mesh")]
    NoMesh,
    #[error(
        "{format}: arm {arm:?} is not a Universal Robots arm (it comes from its robot \
         description); {why} (csv, ros2 and gltf export any arm)"
    )]
    NotUr {
        arm: String,
        format: &'static str,
        why: &'static str,
    },
}

/// Each arm's built-in model, or [`ExportError::NotUr`] for `format` (which needs them, for
/// `why`).
pub fn ur_models(
    set: &PlanSet,
    format: &'static str,
    why: &'static str,
) -> Result<Vec<UrModel>, ExportError> {
    set.arms
        .iter()
        .map(|a| {
            a.model.builtin().ok_or_else(|| ExportError::NotUr {
                arm: a.name.clone(),
                format,
                why,
            })
        })
        .collect()
}

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Format {
    UrScript,
    Csv,
    Ros2,
    Gltf,
}

impl Format {
    /// Every format, in the order `all` writes them.
    pub const ALL: [Format; 4] = [Format::UrScript, Format::Csv, Format::Ros2, Format::Gltf];

    /// Parses `urscript`, `csv`, `ros2`, `gltf`, `all`, or a comma-separated list of them.
    pub fn parse_list(s: &str) -> Result<Vec<Format>, ExportError> {
        let mut out = Vec::new();
        for word in s.split(',') {
            match word.trim().to_ascii_lowercase().as_str() {
                "urscript" => out.push(Format::UrScript),
                "csv" => out.push(Format::Csv),
                "ros2" => out.push(Format::Ros2),
                "gltf" | "glb" => out.push(Format::Gltf),
                "all" => out.extend(Format::ALL),
                _ => return Err(ExportError::Format(word.trim().to_string())),
            }
        }
        out.sort();
        out.dedup();
        Ok(out)
    }
}

/// Export settings (`pregrasp export` options; defaults in [`Options::default`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// CSV sample rate (Hz): 125, the RTDE rate.
    pub rate: f64,
    /// `servoj` lookahead time (s), 0.03..0.2.
    pub lookahead: f64,
    /// `servoj` gain, 100..2000.
    pub gain: f64,
    /// Digital output this controller drives for the hand-off.
    pub sync_out: u8,
    /// Digital input wired to the other controller's output.
    pub sync_in: u8,
    /// Joint speed (rad/s) of the initial `movej` to the first point.
    pub movej_speed: f64,
    /// Joint acceleration (rad/s²) of the initial `movej`.
    pub movej_accel: f64,
    /// Robotiq speed register (`SET SPE`, 0..255).
    pub grip_speed: u8,
    /// Robotiq force register (`SET FOR`, 0..255) set at the start, and of every close whose
    /// segment the plan gives no grip force (plans of parts without mass properties, or of
    /// older planners).
    pub grip_force: u8,
    /// Force register of the support grasp (the fingertip pinch of `rot`); `None`: from `sup1`'s
    /// `grip_force`, else the plan's recommended grip force ([`urscript::force_register`]),
    /// else `grip_force`.
    pub support_grip_force: Option<u8>,
    /// Force register of the power grasps (`mas1`, `sup2`); `None`: from each segment's
    /// `grip_force` ([`urscript::force_register`]), else `grip_force`.
    pub power_grip_force: Option<u8>,
    /// How much narrower than `grip_width` a close is commanded (m), so the fingers press on
    /// the part and the gripper reports it.
    pub grip_squeeze: f64,
    /// Prefix of the ROS joint names (e.g. `left_`).
    pub ros_prefix: String,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            rate: 125.0,
            lookahead: 0.1,
            gain: 300.0,
            sync_out: 0,
            sync_in: 0,
            movej_speed: 0.3,
            movej_accel: 0.5,
            grip_speed: 128,
            grip_force: 255,
            support_grip_force: None,
            power_grip_force: None,
            grip_squeeze: 0.01,
            ros_prefix: String::new(),
        }
    }
}

impl Options {
    /// Refuses values the controller or the formats cannot take.
    pub fn validate(&self) -> Result<(), ExportError> {
        let bad = |m: String| Err(ExportError::Option(m));
        if !(self.rate.is_finite() && self.rate > 0.0 && self.rate <= 1000.0) {
            return bad(format!("--rate {} must be in (0, 1000] Hz", self.rate));
        }
        if !(0.03..=0.2).contains(&self.lookahead) {
            return bad(format!(
                "--lookahead {} must be in [0.03, 0.2] s (servoj)",
                self.lookahead
            ));
        }
        if !(100.0..=2000.0).contains(&self.gain) {
            return bad(format!(
                "--gain {} must be in [100, 2000] (servoj)",
                self.gain
            ));
        }
        if self.sync_out > 7 || self.sync_in > 7 {
            return bad(format!(
                "--sync-io {},{}: standard digital I/O are numbered 0..7",
                self.sync_out, self.sync_in
            ));
        }
        if !(self.movej_speed > 0.0 && self.movej_speed <= 1.0) {
            return bad(format!(
                "--movej-speed {} must be in (0, 1] rad/s",
                self.movej_speed
            ));
        }
        if !(self.movej_accel > 0.0 && self.movej_accel <= 1.4) {
            return bad(format!(
                "--movej-accel {} must be in (0, 1.4] rad/s²",
                self.movej_accel
            ));
        }
        if !(0.0..=0.085).contains(&self.grip_squeeze) {
            return bad(format!(
                "--grip-squeeze {} must be in [0, 0.085] m",
                self.grip_squeeze
            ));
        }
        if !self
            .ros_prefix
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/')
        {
            return bad(format!(
                "--ros-prefix {:?}: only letters, digits, `_` and `/`",
                self.ros_prefix
            ));
        }
        Ok(())
    }
}

/// One exported file: its name (no directory) and its bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutFile {
    pub name: String,
    pub bytes: Vec<u8>,
}

/// What the glTF file draws besides the plan: the part (object frame, metres) and, per arm of
/// the plan set, its description and gripper as the caller loaded them.
#[derive(Clone, Copy, Debug)]
pub struct Drawing<'a> {
    pub mesh: &'a Mesh,
    pub arms: &'a [ArmDescription],
    pub grippers: &'a [Gripper],
}

/// Exports plan `index` of `set` in `formats`. `drawing` is needed for glTF only. Nothing is
/// written: the caller writes the files (all or none).
pub fn export(
    set: &PlanSet,
    index: usize,
    formats: &[Format],
    options: &Options,
    drawing: Option<&Drawing<'_>>,
) -> Result<Vec<OutFile>, ExportError> {
    options.validate()?;
    let timeline = Timeline::new(set, index)?;
    for a in &timeline.arms {
        if a.name.is_empty()
            || !a
                .name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(ExportError::ArmName {
                name: a.name.clone(),
            });
        }
    }
    let mut out = Vec::new();
    for f in formats {
        match f {
            Format::UrScript => out.extend(urscript::export(set, &timeline, options)?),
            Format::Csv => out.extend(csv::export(&timeline, options)),
            Format::Ros2 => out.extend(ros2::export(set, &timeline, options)),
            Format::Gltf => {
                let drawing = drawing.ok_or(ExportError::NoMesh)?;
                out.push(OutFile {
                    name: "plan.glb".into(),
                    bytes: gltf::export(set, &timeline, drawing)?,
                });
            }
        }
    }
    Ok(out)
}

/// `x` as text that reads back as the same `f64` and always has a decimal point (YAML and
/// CSV readers then take it as a float): Rust's shortest round-trip form, never exponential.
pub fn float(x: f64) -> String {
    let s = format!("{x}");
    if s.contains('.') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}
