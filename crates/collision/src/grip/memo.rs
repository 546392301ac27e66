//! The 2F-85's closings on one part, remembered: a closing depends on the part and the flange
//! pose alone (the 2F-85's shapes are built in), and a plan asks for the same one several
//! times — each hold the pipeline tries seats the scene's grasps afresh, closing again where
//! an earlier hold closed already, and every hold closes at G_s.
//!
//! Keyed by the flange pose's bits (object frame): the same pose, the same closing, so a
//! remembered answer is the answer ([`close_on_part`](super::close_on_part) is a pure
//! function of its inputs). At most [`CAPACITY`] closings are kept per part; beyond, closings
//! are computed and not kept (a replan loop over many poses of one part stays bounded).

use std::collections::HashMap;
use std::sync::Mutex;

use nalgebra::Isometry3;

use super::{Grip, GripFailure};

/// Closings kept per part.
pub const CAPACITY: usize = 256;

/// The bits of a flange pose: translation, then the unit quaternion's coordinates.
type Key = [u64; 7];

fn key(flange: &Isometry3<f64>) -> Key {
    let t = flange.translation.vector;
    let q = flange.rotation.coords;
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f64::to_bits)
}

/// Remembered 2F-85 closings of one part, by flange pose.
#[derive(Debug, Default)]
pub struct ClosingMemo {
    kept: Mutex<HashMap<Key, Result<Grip, GripFailure>>>,
}

impl ClosingMemo {
    /// The closing at `flange`: remembered, else `close` computed (outside the lock, so that
    /// closings run side by side) and kept.
    pub fn get_or(
        &self,
        flange: &Isometry3<f64>,
        close: impl FnOnce() -> Result<Grip, GripFailure>,
    ) -> Result<Grip, GripFailure> {
        let key = key(flange);
        if let Some(known) = self.lock().get(&key) {
            return known.clone();
        }
        let closing = close();
        let mut kept = self.lock();
        if kept.len() < CAPACITY {
            kept.entry(key).or_insert_with(|| closing.clone());
        }
        closing
    }

    /// How many closings are kept.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether none is kept.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<Key, Result<Grip, GripFailure>>> {
        // A closing that panicked kept nothing half-written: the map is whole.
        self.kept.lock().unwrap_or_else(|e| e.into_inner())
    }
}
