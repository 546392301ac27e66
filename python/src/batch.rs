//! The batch's building blocks for Python: `pregrasp.batch` runs them locally (the Rust batch,
//! rayon) or one scene per Ray task, and writes the same summary either way.

use std::path::PathBuf;

use pregrasp_batch::Record;
use pregrasp_planner::pipeline::PlanOptions;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::PregraspError;

fn options(max_plans: usize) -> PlanOptions {
    PlanOptions {
        max_plans: max_plans.max(1),
        ..PlanOptions::default()
    }
}

/// The scene files under `dir` (sorted; `out` left out). Raises if `dir` is not a folder or
/// holds no scene.
#[pyfunction]
#[pyo3(signature = (dir, out = None))]
pub fn batch_discover(dir: PathBuf, out: Option<PathBuf>) -> PyResult<Vec<PathBuf>> {
    pregrasp_batch::discover(&dir, out.as_deref())
        .map_err(|e| PregraspError::new_err(e.to_string()))
}

/// Plans one scene of a batch into `out` (plan file, viewer page, stamp) and returns its
/// summary record as JSON. Never raises for a bad scene: that is an `error` record.
#[pyfunction]
#[pyo3(signature = (dir, out, scene, max_plans = 3))]
pub fn batch_plan_one(
    py: Python<'_>,
    dir: PathBuf,
    out: PathBuf,
    scene: PathBuf,
    max_plans: usize,
) -> PyResult<String> {
    let record = py.detach(|| {
        std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        Ok::<_, String>(pregrasp_batch::plan_one(
            &dir,
            &out,
            &scene,
            &options(max_plans),
        ))
    });
    let record = record.map_err(PregraspError::new_err)?;
    serde_json::to_string(&record).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Plans every scene in parallel (rayon, `threads` workers, default all cores) and returns
/// the records as JSON, in the order of `scenes`.
#[pyfunction]
#[pyo3(signature = (dir, out, scenes, max_plans = 3, threads = None))]
pub fn batch_run(
    py: Python<'_>,
    dir: PathBuf,
    out: PathBuf,
    scenes: Vec<PathBuf>,
    max_plans: usize,
    threads: Option<usize>,
) -> PyResult<String> {
    let records = py.detach(|| {
        crate::plan::thread_pool(threads)?
            .install(|| pregrasp_batch::run(&dir, &out, &scenes, &options(max_plans), &|_| {}))
            .map_err(|e| e.to_string())
    });
    let records = records.map_err(PregraspError::new_err)?;
    serde_json::to_string(&records).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Writes `summary.csv`, `summary.json` and `report.html` into `out` for `records` (JSON).
#[pyfunction]
pub fn batch_write_report(out: PathBuf, records: &str, title: &str) -> PyResult<()> {
    let records: Vec<Record> = serde_json::from_str(records)
        .map_err(|e| PyValueError::new_err(format!("records: {e}")))?;
    pregrasp_batch::report::write(&out, &records, title).map_err(PregraspError::new_err)
}
