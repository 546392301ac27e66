//! Answers about a part remembered by pose: what a gripper does with its flange at a pose of
//! the part's frame depends on the part and that pose alone, and a plan asks for the same ones
//! again — each hold the pipeline tries seats the scene's grasps afresh, closing again where an
//! earlier hold closed already, and every hold closes at G_s.
//!
//! Keyed by the pose's bits (translation, then the unit quaternion's coordinates) and the
//! answer's type: the same pose, the same answer, so a remembered answer is the computed one
//! for any pure computation. At most [`CAPACITY`] answers are kept per part; beyond, answers
//! are computed and not kept (a replan loop over many poses of one part stays bounded).

use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use nalgebra::Isometry3;

/// Answers kept per part.
pub const CAPACITY: usize = 256;

type Key = (TypeId, [u64; 7]);
type Kept = HashMap<Key, Arc<dyn Any + Send + Sync>>;

/// Answers of pure computations at poses of one part (its object frame).
#[derive(Default)]
pub struct PoseMemo {
    kept: Mutex<Kept>,
}

impl std::fmt::Debug for PoseMemo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PoseMemo")
            .field("kept", &self.len())
            .finish()
    }
}

impl PoseMemo {
    /// The answer of `compute` at `pose`: remembered, else computed (outside the lock, so that
    /// computations run side by side) and kept. `compute` must depend on nothing but the part
    /// and `pose` (and its type, `T`).
    pub fn get_or<T: Clone + Send + Sync + 'static>(
        &self,
        pose: &Isometry3<f64>,
        compute: impl FnOnce() -> T,
    ) -> T {
        let t = pose.translation.vector;
        let q = pose.rotation.coords;
        let key = (
            TypeId::of::<T>(),
            [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f64::to_bits),
        );
        if let Some(known) = self.lock().get(&key).and_then(|a| a.downcast_ref::<T>()) {
            return known.clone();
        }
        let answer = compute();
        let mut kept = self.lock();
        if kept.len() < CAPACITY {
            kept.entry(key).or_insert_with(|| Arc::new(answer.clone()));
        }
        answer
    }

    /// How many answers are kept.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    fn lock(&self) -> MutexGuard<'_, Kept> {
        // A computation that panicked kept nothing half-written: the map is whole.
        self.kept.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::{PoseMemo, CAPACITY};
    use nalgebra::{Isometry3, Vector3};
    use std::cell::Cell;

    #[test]
    fn an_answer_is_computed_once_per_pose_and_type_up_to_the_capacity() {
        let memo = PoseMemo::default();
        let calls = Cell::new(0);
        let at = |x: f64| Isometry3::translation(x, 0.0, 0.0);
        let count = |v: u32| {
            calls.set(calls.get() + 1);
            v
        };
        assert_eq!(memo.get_or(&at(0.1), || count(7)), 7);
        assert_eq!(memo.get_or(&at(0.1), || count(8)), 7);
        assert_eq!(calls.get(), 1);
        // Another pose (the smallest step of one coordinate), another type: computed.
        assert_eq!(
            memo.get_or(&at(f64::from_bits(0.1f64.to_bits() + 1)), || count(9)),
            9
        );
        assert_eq!(memo.get_or(&at(0.1), || "other"), "other");
        assert_eq!(calls.get(), 2);
        let turned = Isometry3::new(Vector3::x() * 0.1, Vector3::z() * 0.3);
        assert_eq!(memo.get_or(&turned, || count(10)), 10);
        assert_eq!(memo.len(), 4);
        // Full: answers are still given, no longer kept.
        for k in 0..2 * CAPACITY {
            assert_eq!(memo.get_or(&at(1.0 + k as f64), || k), k);
        }
        assert_eq!(memo.len(), CAPACITY);
        assert_eq!(memo.get_or(&at(1.0 + (2 * CAPACITY - 1) as f64), || 0), 0);
    }
}
