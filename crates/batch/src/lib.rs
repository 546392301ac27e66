//! Many parts at once: every scene under a folder planned in parallel, each with its plan
//! file and viewer page, and a summary a person (HTML) and a program (CSV, JSON) can read.
//!
//! - [`discover`]: the scene files (`*.toml`) under a folder, sorted, the output folder left out;
//! - [`plan_one`]: one scene → one [`Record`] (a scene that cannot be loaded is a row with its
//!   error, never the end of the batch); a scene whose inputs have not changed since its plan
//!   was written (the same scene text, mesh bytes and pregrasp version: [`Stamp`]) is not
//!   planned again;
//! - [`run`]: all of them with rayon, records in discovery order (deterministic);
//! - [`report`]: `summary.csv`, `summary.json`, `report.html`.

pub mod report;

use std::path::{Path, PathBuf};
use std::time::Instant;

use pregrasp_io::mesh_io::{parse_mesh, read_mesh_bytes};
use pregrasp_io::plan_file::{write_atomic, PlanFile};
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::plan_scene;
use rayon::prelude::*;

/// What became of one scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Record {
    /// The scene file, relative to the batch folder.
    pub scene: String,
    /// `planned`, `no_plan` or `error` (the scene or its mesh could not be used).
    pub status: String,
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
    #[error("{path}: {error}")]
    Io { path: String, error: std::io::Error },
}

/// The scene files under `dir` (recursively), sorted, without anything under `exclude`.
pub fn discover(dir: &Path, exclude: Option<&Path>) -> Result<Vec<PathBuf>, BatchError> {
    if !dir.is_dir() {
        return Err(BatchError::NotADir(dir.display().to_string()));
    }
    let exclude = exclude.and_then(|e| e.canonicalize().ok());
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        if exclude
            .as_ref()
            .is_some_and(|e| d.canonicalize().ok().as_ref() == Some(e))
        {
            continue;
        }
        let entries = std::fs::read_dir(&d).map_err(|error| BatchError::Io {
            path: d.display().to_string(),
            error,
        })?;
        for entry in entries.flatten() {
            let path = entry.path();
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() {
                stack.push(path);
            } else if kind.is_file() && path.extension().is_some_and(|e| e == "toml") {
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

/// Where the outputs of scene `rel` (relative path of the scene) go under `out`.
fn outputs(out: &Path, rel: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let stem = rel.with_extension("");
    let base = out.join(&stem);
    (
        base.with_extension("plan.json"),
        base.with_extension("html"),
        base.with_extension("stamp"),
    )
}

/// Plans one scene (`dir`: the batch folder, for relative names) into `out`.
pub fn plan_one(dir: &Path, out: &Path, scene_path: &Path, options: &PlanOptions) -> Record {
    let rel = scene_path
        .strip_prefix(dir)
        .unwrap_or(scene_path)
        .to_path_buf();
    let (plan_path, view_path, stamp_path) = outputs(out, &rel);
    let rel_out = |p: &Path| p.strip_prefix(out).unwrap_or(p).display().to_string();
    let mut record = Record {
        scene: rel.display().to_string(),
        status: "error".into(),
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
    let fail = |mut r: Record, e: String| {
        r.reason = Some(e);
        r
    };
    let started = Instant::now();
    let scene = match Scene::load(scene_path) {
        Ok(s) => s,
        Err(e) => return fail(record, e.to_string()),
    };
    // The mesh is read once (refused unless a regular file), for the stamp and to parse.
    let mesh_path = &scene.object.mesh_path;
    let loaded = read_mesh_bytes(mesh_path).and_then(|bytes| {
        parse_mesh(&bytes, mesh_path, scene.object.scale).map(|m| (bytes, m.mesh))
    });
    let (mesh_bytes, mesh) = match loaded {
        Ok(x) => x,
        Err(e) => {
            return fail(
                record,
                format!("{}: object.mesh: {e}", scene_path.display()),
            )
        }
    };
    let scene_text = match std::fs::read(scene_path) {
        Ok(t) => t,
        Err(e) => return fail(record, format!("{}: {e}", scene_path.display())),
    };
    let stamp = Stamp::of(&scene_text, &mesh_bytes);
    let up_to_date = std::fs::read_to_string(&stamp_path).is_ok_and(|s| s.trim() == stamp.0)
        && view_path.is_file();
    let reused = if up_to_date {
        PlanFile::read(&plan_path).ok()
    } else {
        None
    };
    let (file, reused) = match reused {
        Some(file) => (file, true),
        None => {
            let report = match plan_scene(&scene, &mesh, options, &|_| {}, &|| {}) {
                Ok(r) => r,
                Err(e) => return fail(record, format!("{}: {e}", scene_path.display())),
            };
            let mut file = report.file;
            file.timing_ms
                .insert("process".into(), started.elapsed().as_secs_f64() * 1e3);
            let page = pregrasp_viewer::render_html(&file, &mesh, &Default::default());
            let written = plan_path
                .parent()
                .map_or(Ok(()), std::fs::create_dir_all)
                .map_err(|e| e.to_string())
                .and_then(|_| file.write_atomic(&plan_path).map_err(|e| e.to_string()))
                .and_then(|_| write_atomic(&view_path, page.as_bytes()).map_err(|e| e.to_string()))
                .and_then(|_| {
                    write_atomic(&stamp_path, format!("{}\n", stamp.0).as_bytes())
                        .map_err(|e| e.to_string())
                });
            if let Err(e) = written {
                return fail(record, e);
            }
            (file, false)
        }
    };
    record.status = file.status.clone();
    record.reason = file.reason.clone();
    record.plans = file.plans.len();
    record.reused = reused;
    record.time_ms = file.timing_ms.get("process").copied().unwrap_or(0.0);
    record.plan_file = Some(rel_out(&plan_path));
    record.view_file = Some(rel_out(&view_path));
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
    record
}

/// Plans every scene of `scenes` (under `dir`) into `out`, in parallel; records in the order
/// of `scenes`. `progress` is called once per scene finished.
pub fn run(
    dir: &Path,
    out: &Path,
    scenes: &[PathBuf],
    options: &PlanOptions,
    progress: &(dyn Fn(&Record) + Sync),
) -> Result<Vec<Record>, BatchError> {
    std::fs::create_dir_all(out).map_err(|error| BatchError::Io {
        path: out.display().to_string(),
        error,
    })?;
    Ok(scenes
        .par_iter()
        .map(|s| {
            let r = plan_one(dir, out, s, options);
            progress(&r);
            r
        })
        .collect())
}
