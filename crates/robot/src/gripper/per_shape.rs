//! Values worked out once per gripper shape and shared process-wide by every arm that carries
//! a gripper of that shape ([`Gripper::shape_key`]): the open hand's solids, the exact pieces of
//! its links, its bounding sphere.

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use super::Gripper;

/// A process-wide table from gripper shape to a value built from it, for a `static`:
///
/// ```
/// # use pregrasp_robot::{Gripper, PerShape};
/// static FINGERS: PerShape<usize> = PerShape::new();
/// let gripper = Gripper::default();
/// let n = FINGERS.get_or_build(&gripper, |g| g.static_count());
/// assert_eq!(n, FINGERS.get_or_build(&gripper, |_| unreachable!("built once")));
/// ```
///
/// `build` runs outside the lock, so two threads asking for a new shape at once may both
/// build it; the first value stored is the one every caller gets.
pub struct PerShape<T> {
    values: OnceLock<Mutex<HashMap<String, T>>>,
}

impl<T: Clone> PerShape<T> {
    /// An empty table.
    pub const fn new() -> PerShape<T> {
        PerShape {
            values: OnceLock::new(),
        }
    }

    /// The value of `gripper`'s shape: the stored one, else `build(gripper)`, stored.
    pub fn get_or_build(&self, gripper: &Gripper, build: impl FnOnce(&Gripper) -> T) -> T {
        let values = self.values.get_or_init(Default::default);
        let key = gripper.shape_key();
        let lock = || values.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(value) = lock().get(key) {
            return value.clone();
        }
        let value = build(gripper);
        lock().entry(key.to_string()).or_insert(value).clone()
    }
}

impl<T: Clone> Default for PerShape<T> {
    fn default() -> PerShape<T> {
        PerShape::new()
    }
}
