//! Many parts at once: every scene under a folder planned in parallel, each with its plan
//! file and viewer page, and a summary a person (HTML) and a program (CSV, JSON) can read.
//!
//! - [`discover`]: the scene files (`*.toml`) under a folder, sorted, the output folder left out;
//! - [`plan_one`]: one scene → one [`Record`] (a scene that cannot be loaded is a row with its
//!   error, never the end of the batch; so is one the planner refuses); a scene whose inputs
//!   have not changed since its plan was written (the same scene text, mesh bytes and pregrasp
//!   version: [`Stamp`]) is not planned again;
//! - [`run`]: all of them with rayon, records in discovery order (deterministic), the outputs
//!   staged in one [`Outputs`] that the caller commits with the summary: all or nothing;
//! - [`report`]: `summary.csv`, `summary.json`, `report.html`.
//!
//! Outputs of scene `a/b.toml` are `a/b.plan.json`, `a/b.html` and `a/b.stamp` under the
//! output folder (the name with `.toml` cut off and the suffix added, so `x.toml` and
//! `x.plan.toml` never share a file); a scene whose outputs would be one of the summary files
//! (`report.toml`'s page is `report.html`) is an error row that says so.

pub mod page;
pub mod report;

use std::path::{Path, PathBuf};
use std::time::Instant;

use pregrasp_io::mesh_io::{parse_mesh, read_mesh_bytes};
use std::sync::Mutex;

use pregrasp_io::output::{OutputError, Outputs};
use pregrasp_io::plan_file::{PlanFile, PlanStatus};
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::plan_scene as plan_scene_report;
use rayon::prelude::*;

/// A scene's status in a batch: its plan file's, or `error` (the scene or its mesh could not
/// be used).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SceneStatus {
    Planned,
    NoPlan,
    Error,
}

impl SceneStatus {
    pub fn as_str(self) -> &'static str {
        match self {
            SceneStatus::Planned => PlanStatus::Planned.as_str(),
            SceneStatus::NoPlan => PlanStatus::NoPlan.as_str(),
            SceneStatus::Error => "error",
        }
    }
}

impl std::fmt::Display for SceneStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.as_str())
    }
}

impl From<PlanStatus> for SceneStatus {
    fn from(status: PlanStatus) -> SceneStatus {
        match status {
            PlanStatus::Planned => SceneStatus::Planned,
            PlanStatus::NoPlan => SceneStatus::NoPlan,
        }
    }
}

/// What became of one scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Record {
    /// The scene file, relative to the batch folder.
    pub scene: String,
    pub status: SceneStatus,
    /// Why no plan, or the error.
    pub reason: Option<String>,
    /// S_rot of the best plan and its θ_goal (degrees).
    pub best_score: Option<f64>,
    pub theta_goal_deg: Option<f64>,
    pub plans: usize,
    /// The best plan's recommended grip force (N), when it has a physics check.
    pub grip_force: Option<f64>,
    /// `valid` / `invalid` (re-checked with `pregrasp check`'s rules), `-` without plans.
    pub check: String,
    /// Planning time (ms) when planned in this run; the time recorded in the plan otherwise.
    pub time_ms: f64,
    /// `true`: the plan was up to date and reused.
    pub reused: bool,
    /// Plan file and viewer page, relative to the output folder.
    pub plan_file: Option<String>,
    pub view_file: Option<String>,
}

/// Why a batch cannot start.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    #[error("{0}: not a folder")]
    NotADir(String),
    #[error("{0}: no scene files (*.toml) in it")]
    NoScenes(String),
    #[error("{0}: the output folder is the scene folder itself; give -o another folder")]
    OutIsDir(String),
    #[error("{path}: {error}")]
    Io { path: String, error: std::io::Error },
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// The files of the batch's summary, directly under the output folder.
pub const SUMMARY_FILES: [&str; 3] = ["summary.csv", "summary.json", "report.html"];

/// Longest reason a record keeps (characters): an error that quotes a line of a binary file
/// would otherwise fill a cell of the report with it.
pub const MAX_REASON: usize = 400;

/// The entries of a batch under `dir` (recursively), sorted, without anything under `exclude`:
/// every file named `*.toml` (a symbolic link to a file counts as that file; a pipe or device
/// with such a name is listed too, and its row says it is no regular file) and every folder that
/// cannot be read (its row says why). Links to folders are not followed, so a cycle of links
/// cannot loop.
pub fn discover(dir: &Path, exclude: Option<&Path>) -> Result<Vec<PathBuf>, BatchError> {
    if !dir.is_dir() {
        return Err(BatchError::NotADir(dir.display().to_string()));
    }
    let exclude = exclude.and_then(|e| e.canonicalize().ok());
    if exclude.is_some() && dir.canonicalize().ok() == exclude {
        return Err(BatchError::OutIsDir(dir.display().to_string()));
    }
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        if exclude
            .as_ref()
            .is_some_and(|e| d.canonicalize().ok().as_ref() == Some(e))
        {
            continue;
        }
        let entries = match std::fs::read_dir(&d) {
            Ok(entries) => entries,
            // The top folder was readable as a folder a moment ago: a failure below it is one
            // row, not the end of the batch.
            Err(_) if d != dir => {
                found.push(d);
                continue;
            }
            Err(error) => {
                return Err(BatchError::Io {
                    path: d.display().to_string(),
                    error,
                })
            }
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "toml") {
                // Regular files, links (to whatever they name: `plan_one` says if it is no
                // file) and special files with a scene's name.
                found.push(path);
            }
        }
    }
    found.sort();
    if found.is_empty() {
        return Err(BatchError::NoScenes(dir.display().to_string()));
    }
    Ok(found)
}

/// A fingerprint of what a plan depends on: scene text, mesh bytes, pregrasp's version
/// (FNV-1a, 64 bit, hex).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stamp(pub String);

impl Stamp {
    pub fn of(scene_text: &[u8], mesh_bytes: &[u8]) -> Stamp {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let version = env!("CARGO_PKG_VERSION").as_bytes();
        for part in [scene_text, &[0xff], mesh_bytes, &[0xff], version] {
            for &b in part {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        Stamp(format!("{h:016x}"))
    }
}

/// Where the outputs of scene `rel` (relative path of the scene) go under `out`: its name
/// with the `.toml` cut off and `.plan.json`, `.html`, `.stamp` added.
fn outputs(out: &Path, rel: &Path) -> [PathBuf; 3] {
    let mut stem = rel.as_os_str().to_owned();
    if rel.extension().is_some_and(|e| e == "toml") {
        stem = rel.with_extension("").into_os_string();
    }
    let with = |suffix: &str| {
        let mut name = stem.clone();
        name.push(suffix);
        out.join(name)
    };
    [with(".plan.json"), with(".html"), with(".stamp")]
}

/// What planning one scene produced: its record, and the files to write (plan, page, stamp;
/// none when the plan was reused or the scene failed).
struct Planned {
    record: Record,
    files: Option<[(PathBuf, Vec<u8>); 3]>,
}

/// Plans one scene (`dir`: the batch folder, for relative names) into `out`, writing its three
/// files at once (each scene on its own: what the Python batch's Ray tasks call).
pub fn plan_one(dir: &Path, out: &Path, scene_path: &Path, options: &PlanOptions) -> Record {
    let mut planned = plan_isolated(dir, out, scene_path, options);
    if let Some(files) = planned.files.take() {
        let mut outputs = Outputs::new();
        if let Err(e) = stage(&mut outputs, files).and_then(|_| outputs.commit().map(drop)) {
            return failed(planned.record, e.to_string());
        }
    }
    planned.record
}

/// Declares and writes `files` into `outputs` (folders made as needed).
fn stage(outputs: &mut Outputs, files: [(PathBuf, Vec<u8>); 3]) -> Result<(), OutputError> {
    for (path, bytes) in files {
        let id = outputs.declare_creating_dirs(&path)?;
        outputs.write(id, &bytes)?;
    }
    Ok(())
}

/// The record of a scene that failed, its reason clipped to [`MAX_REASON`].
fn failed(mut record: Record, reason: String) -> Record {
    record.status = SceneStatus::Error;
    record.plans = 0;
    record.plan_file = None;
    record.view_file = None;
    record.reason = Some(pregrasp_io::text::clip(
        &pregrasp_io::text::readable_numbers(&reason),
        MAX_REASON,
    ));
    record
}

/// [`plan_scene`] of one scene: a scene that cannot be planned is an error row, and the batch
/// goes on.
fn plan_isolated(dir: &Path, out: &Path, scene_path: &Path, options: &PlanOptions) -> Planned {
    let rel = scene_path
        .strip_prefix(dir)
        .unwrap_or(scene_path)
        .to_path_buf();
    let blank = Record {
        scene: rel.display().to_string(),
        status: SceneStatus::Error,
        reason: None,
        best_score: None,
        theta_goal_deg: None,
        plans: 0,
        grip_force: None,
        check: "-".into(),
        time_ms: 0.0,
        reused: false,
        plan_file: None,
        view_file: None,
    };
    match plan_scene(out, &rel, scene_path, options) {
        Ok(planned) => planned,
        Err(reason) => Planned {
            record: failed(blank, reason),
            files: None,
        },
    }
}

/// Plans one scene; `Err` is the reason of its error row.
fn plan_scene(
    out: &Path,
    rel: &Path,
    scene_path: &Path,
    options: &PlanOptions,
) -> Result<Planned, String> {
    if scene_path.is_dir() {
        let why = std::fs::read_dir(scene_path).err().map_or_else(
            || "changed while the batch ran".to_string(),
            |e| e.to_string(),
        );
        return Err(format!(
            "{}: cannot read folder: {why}",
            scene_path.display()
        ));
    }
    let [plan_path, view_path, stamp_path] = outputs(out, rel);
    for path in [&plan_path, &view_path, &stamp_path] {
        if SUMMARY_FILES.iter().any(|f| *path == out.join(f)) {
            return Err(format!(
                "{}: its output {} would be the batch's own summary file; rename the scene",
                scene_path.display(),
                path.strip_prefix(out).unwrap_or(path).display()
            ));
        }
    }
    let rel_out = |p: &Path| p.strip_prefix(out).unwrap_or(p).display().to_string();
    let started = Instant::now();
    let scene = Scene::load(scene_path).map_err(|e| e.to_string())?;
    // The mesh is read once (refused unless a regular file), for the stamp and to parse.
    let mesh_path = &scene.object.mesh_path;
    let (mesh_bytes, mesh) = read_mesh_bytes(mesh_path)
        .and_then(|bytes| {
            parse_mesh(&bytes, mesh_path, scene.object.scale).map(|m| (bytes, m.mesh))
        })
        .map_err(|e| format!("{}: object.mesh: {e}", scene_path.display()))?;
    let scene_text =
        pregrasp_io::limits::read_limited(scene_path, pregrasp_io::limits::MAX_SCENE_BYTES)
            .map_err(|e| format!("{}: {e}", scene_path.display()))?;
    let stamp = Stamp::of(&scene_text, &mesh_bytes);
    // The stamp is read only as a small regular file: a FIFO or device planted under its
    // name is not waited on (it is then written through, as every output is).
    let up_to_date = pregrasp_io::limits::read_limited(&stamp_path, 4096)
        .is_ok_and(|s| String::from_utf8_lossy(&s).trim() == stamp.0)
        && view_path.is_file();
    let reused = if up_to_date {
        PlanFile::read(&plan_path).ok()
    } else {
        None
    };
    let (file, files) = match reused {
        Some(file) => (file, None),
        None => {
            let report = plan_scene_report(&scene, &mesh, options, &|_| {}, &|| {})
                .map_err(|e| format!("{}: {e}", scene_path.display()))?;
            let mut file = report.file;
            file.timing_ms
                .insert("process".into(), started.elapsed().as_secs_f64() * 1e3);
            file.locate_inputs(&plan_path);
            let page = page::page_html(
                &file,
                None,
                &mesh,
                report.hull.as_ref(),
                &Default::default(),
            )
            .map_err(|e| format!("{}: {e}", scene_path.display()))?;
            let files = [
                (plan_path.clone(), file.to_json().into_bytes()),
                (view_path.clone(), page.into_bytes()),
                (stamp_path, format!("{}\n", stamp.0).into_bytes()),
            ];
            (file, Some(files))
        }
    };
    let mut record = Record {
        scene: rel.display().to_string(),
        status: file.status.into(),
        reason: file
            .reason
            .as_deref()
            .map(|r| pregrasp_io::text::clip(r, MAX_REASON)),
        best_score: None,
        theta_goal_deg: None,
        plans: file.plans.len(),
        grip_force: None,
        check: "-".into(),
        time_ms: file.timing_ms.get("process").copied().unwrap_or(0.0),
        reused: files.is_none(),
        plan_file: Some(rel_out(&plan_path)),
        view_file: Some(rel_out(&view_path)),
    };
    if let Some(best) = file.plans.first() {
        record.best_score = Some(best.score);
        record.theta_goal_deg = file
            .candidates
            .get(best.candidate)
            .and_then(|c| c.theta_goal)
            .map(f64::to_degrees);
        record.grip_force = best.physics.as_ref().and_then(|p| p.grip_force_recommended);
        record.check = if check_plan(&file, &mesh).is_valid() {
            "valid".into()
        } else {
            "invalid".into()
        };
    }
    Ok(Planned { record, files })
}

/// Plans every scene of `scenes` (under `dir`) into `out`, in parallel; records in the order
/// of `scenes`. Each planned scene's files are staged in `outputs` as it finishes (a scene
/// whose files cannot be staged is an error row); nothing is written until the caller commits
/// `outputs`. `progress` is called once per scene finished.
pub fn run_staged(
    dir: &Path,
    out: &Path,
    scenes: &[PathBuf],
    options: &PlanOptions,
    outputs: &mut Outputs,
    progress: &(dyn Fn(&Record) + Sync),
) -> Vec<Record> {
    let shared = Mutex::new(outputs);
    scenes
        .par_iter()
        .map(|s| {
            let mut planned = plan_isolated(dir, out, s, options);
            if let Some(files) = planned.files.take() {
                let mut outputs = shared.lock().unwrap_or_else(|e| e.into_inner());
                if let Err(e) = stage(&mut outputs, files) {
                    planned.record = failed(planned.record, e.to_string());
                }
            }
            progress(&planned.record);
            planned.record
        })
        .collect()
}

/// [`run_staged`] with its own outputs, committed at the end: the scenes' files are written
/// together (the summary is written by [`report::write`]).
pub fn run(
    dir: &Path,
    out: &Path,
    scenes: &[PathBuf],
    options: &PlanOptions,
    progress: &(dyn Fn(&Record) + Sync),
) -> Result<Vec<Record>, BatchError> {
    let mut outputs = Outputs::new();
    let records = run_staged(dir, out, scenes, options, &mut outputs, progress);
    outputs.commit()?;
    Ok(records)
}
