//! Which links' collision geometry one arm of a description needs
//! ([`GeometryOptions::arm`](super::GeometryOptions::arm)).
//!
//! The arm from base link `B` to tool link `T` uses:
//!
//! * the links on the path from `B` down to `T`;
//! * the links hanging from a path link through fixed joints only (covers, brackets, a
//!   camera: `describe_arm` takes them as the arm's);
//! * every link below `T` (the hand and its fingers, which `describe_gripper` takes).
//!
//! Other links (another arm, the cell's fixtures, a finger moved off the path) are left out:
//! their pieces are not derived and no pair with them is sampled. The pairs among the kept
//! links, and why each is excluded, are exactly what the whole file gives them: the sample
//! stream still draws every tree variable, and adjacency among the kept links depends only
//! on the kept links (they form a subtree hanging from `B`, so every tree path between two of
//! them runs through kept links only).

use std::collections::BTreeSet;

use crate::error::UrdfError;
use crate::model::UrdfModel;

/// The links of the arm from `base` to `tool` (see the module documentation); the path is
/// the one [`UrdfModel::chain`] walks. Errors: what that reports (an unknown link, `tool` not
/// below `base`, …), never for an arm already made from the same links.
pub fn arm_links(model: &UrdfModel, base: &str, tool: &str) -> Result<BTreeSet<String>, UrdfError> {
    let chain = model.chain(base, tool)?;
    let path: Vec<String> = chain.links().iter().map(|l| l.name.clone()).collect();
    let mut keep: BTreeSet<String> = path.iter().cloned().collect();
    // Below the path: through fixed joints only, except below the tool link (everything).
    let mut stack: Vec<(String, bool)> = path.iter().map(|l| (l.clone(), l == tool)).collect();
    while let Some((link, below_tool)) = stack.pop() {
        for j in model
            .robot()
            .joints
            .iter()
            .filter(|j| j.parent.link == link)
        {
            let fixed = j.joint_type == urdf_rs::JointType::Fixed;
            if (below_tool || fixed) && keep.insert(j.child.link.clone()) {
                stack.push((j.child.link.clone(), below_tool));
            }
        }
    }
    Ok(keep)
}

/// The links [`super::GeometryOptions::arm`] selects, `None` for every link (no arm named).
pub(super) fn selected(
    model: &UrdfModel,
    arm: Option<&(String, String)>,
) -> Result<Option<BTreeSet<String>>, UrdfError> {
    arm.map(|(base, tool)| arm_links(model, base, tool))
        .transpose()
}
