//! `bench plan`'s cold side: every run a fresh process (`pregrasp plan SCENE -o … --quiet`,
//! this same binary), so nothing a process keeps between plans — a part's closings, the
//! grippers' pieces, the posed-arm buffers — is known: what a user planning one part from the
//! command line, or each part of a batch, meets. Per run: the whole process's wall-clock time
//! (start-up, loading, planning, checking, writing) and the plan file's own `timing_ms` (the
//! stages inside the process).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context};

use super::{quantile, PLAN_STAGES};

/// Cold runs of one scene: per run the process's wall-clock time and the plan file's stage
/// times (ms, [`PLAN_STAGES`] order).
pub struct ColdRuns {
    pub process_ms: Vec<f64>,
    pub stages_ms: Vec<Vec<f64>>,
}

impl ColdRuns {
    /// Median and p95 (ms) of the process times.
    pub fn process(&self) -> (f64, f64) {
        median_p95(&self.process_ms)
    }

    /// Median and p95 (ms) of stage `k` of [`PLAN_STAGES`].
    pub fn stage(&self, k: usize) -> (f64, f64) {
        median_p95(&self.stages_ms[k])
    }
}

fn median_p95(values: &[f64]) -> (f64, f64) {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    (quantile(&v, 0.5), quantile(&v, 0.95))
}

/// `runs` fresh `pregrasp plan` processes on `scene` with `threads` worker threads (all cores
/// when `None`), one after the other; the plan file goes to the temporary folder, removed
/// after.
pub fn cold_runs(scene: &Path, runs: usize, threads: Option<usize>) -> anyhow::Result<ColdRuns> {
    let exe = std::env::current_exe().context("the pregrasp binary's path")?;
    // The runs' plan file, in the temporary folder under this process's id; removed after.
    let out = std::env::temp_dir().join(format!("pregrasp-bench-cold-{}.json", std::process::id()));
    let result = runs_into(&exe, scene, runs, threads, &out);
    let _ = std::fs::remove_file(&out);
    result
}

fn runs_into(
    exe: &Path,
    scene: &Path,
    runs: usize,
    threads: Option<usize>,
    out: &Path,
) -> anyhow::Result<ColdRuns> {
    let mut process_ms = Vec::with_capacity(runs);
    let mut stages_ms = vec![Vec::with_capacity(runs); PLAN_STAGES.len()];
    for _ in 0..runs {
        let mut cmd = Command::new(exe);
        cmd.arg("plan").arg(scene).arg("-o").arg(out).arg("--quiet");
        if let Some(n) = threads {
            cmd.arg("--threads").arg(n.to_string());
        }
        let start = Instant::now();
        let done = cmd
            .output()
            .with_context(|| format!("running {} plan", exe.display()))?;
        process_ms.push(start.elapsed().as_secs_f64() * 1e3);
        // 0: planned, 2: no plan (both write the file); anything else is the scene's error.
        if !matches!(done.status.code(), Some(0 | 2)) {
            bail!(
                "{}: pregrasp plan failed: {}",
                scene.display(),
                String::from_utf8_lossy(&done.stderr).trim()
            );
        }
        let text = std::fs::read_to_string(out)
            .with_context(|| format!("{}: the cold run's plan file", scene.display()))?;
        let file: serde_json::Value = serde_json::from_str(&text)?;
        for (k, stage) in PLAN_STAGES.iter().enumerate() {
            let ms = file["timing_ms"][*stage].as_f64().unwrap_or(0.0);
            stages_ms[k].push(ms);
        }
    }
    Ok(ColdRuns {
        process_ms,
        stages_ms,
    })
}
