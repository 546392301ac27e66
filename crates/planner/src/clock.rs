//! Where Algorithm 3's time goes: per part of it, the time spent summed over candidates, for
//! the plan file's `timing_ms` and `pregrasp bench plan` (docs/performance.md).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A part of Algorithm 3 and of the checks after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// μ_rot: IK along the turn and its states checked.
    Rot,
    /// The straight approach and retreat lines of the reach motions.
    Lines,
    /// The reach motions' transits: RRT-Connect and shortcutting.
    Transit,
    /// The plan check (every rule of the plan format, again, with our own models).
    Recheck,
    /// Will the pinch hold the part (quasi-static grip force along μ_rot).
    Hold,
}

impl Stage {
    pub const ALL: [Stage; 5] = [
        Stage::Rot,
        Stage::Lines,
        Stage::Transit,
        Stage::Recheck,
        Stage::Hold,
    ];

    /// The key in `timing_ms`.
    pub fn key(self) -> &'static str {
        match self {
            Stage::Rot => "rot",
            Stage::Lines => "lines",
            Stage::Transit => "transit",
            Stage::Recheck => "recheck",
            Stage::Hold => "hold",
        }
    }
}

/// Nanoseconds per [`Stage`], added to from any thread.
#[derive(Debug, Default)]
pub struct StageClock {
    nanos: [AtomicU64; 5],
}

impl StageClock {
    /// Runs `f`, adding its wall time to `stage`.
    pub fn time<T>(&self, stage: Stage, f: impl FnOnce() -> T) -> T {
        let t = Instant::now();
        let out = f();
        let index = Stage::ALL
            .iter()
            .position(|s| *s == stage)
            .expect("a stage");
        let ns = u64::try_from(t.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.nanos[index].fetch_add(ns, Ordering::Relaxed);
        out
    }

    /// `(timing_ms key, milliseconds)` per stage.
    pub fn ms(&self) -> [(&'static str, f64); 5] {
        std::array::from_fn(|k| {
            let ns = self.nanos[k].load(Ordering::Relaxed);
            (Stage::ALL[k].key(), ns as f64 * 1e-6)
        })
    }
}
