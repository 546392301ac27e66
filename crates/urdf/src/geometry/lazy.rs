//! [`LazyGeometry`]: a description's collision geometry loaded when first needed, then kept, so
//! that describing its arm and its gripper reads and hashes the meshes once.

use std::cell::OnceCell;

use super::{GeometryOptions, UrdfGeometry};
use crate::arm::UrdfArm;
use crate::error::UrdfError;
use crate::model::UrdfModel;

/// The collision geometry of one description ([`UrdfGeometry::load`] per the options), loaded
/// at the first [`LazyGeometry::get`] and kept for the next. One per description: every `get`
/// must name the same model.
pub struct LazyGeometry {
    opts: GeometryOptions,
    loaded: OnceCell<UrdfGeometry>,
}

impl LazyGeometry {
    /// Nothing loaded yet.
    pub fn new(opts: GeometryOptions) -> Self {
        LazyGeometry {
            opts,
            loaded: OnceCell::new(),
        }
    }

    /// Nothing loaded yet; what is loaded is the geometry of `arm`'s links and what hangs
    /// below its tool link only ([`GeometryOptions::arm`]), all that describing the arm
    /// ([`crate::describe_arm_from`]) and its gripper ([`crate::describe_gripper`]) use.
    pub fn for_arm(arm: &UrdfArm, opts: GeometryOptions) -> Self {
        LazyGeometry::new(GeometryOptions {
            arm: Some((arm.base_link.clone(), arm.tool_link.clone())),
            ..opts
        })
    }

    /// The geometry of `model`, loaded now if it was not yet.
    pub fn get(&self, model: &UrdfModel) -> Result<&UrdfGeometry, UrdfError> {
        if let Some(g) = self.loaded.get() {
            return Ok(g);
        }
        let geometry = UrdfGeometry::load(model, &self.opts)?.geometry;
        Ok(self.loaded.get_or_init(|| geometry))
    }
}
