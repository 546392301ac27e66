//! A URDF arm as the planner uses it: [`describe_arm`] turns a description, the joints held
//! still and the collision pieces of its links ([`UrdfGeometry`]) into a
//! `pregrasp_robot::ArmDescription`.
//!
//! # Which links are the arm's
//!
//! A link with collision pieces belongs to the arm when it is rigid (through fixed joints
//! only) with a link on the path from the base link to the tool link, and does not hang below
//! the tool link: what is mounted on the flange is the gripper's, which the planner models
//! itself (a hand the description carries, as `fr3.urdf` does, is left out). A link moved by
//! a joint off the path (a finger) is left out too.
//!
//! # Shapes
//!
//! Each arm link becomes one link shape in the [`ArmKinematics`](pregrasp_robot::ArmKinematics)
//! frame that moves with it ([`SixJointArm`]'s frames 0..=6): its pieces moved into that frame
//! are the exact tier, their bounding box in that frame the primitive (so the pieces reach
//! nowhere outside it: slack 0). The self-collision pairs are those of the geometry between
//! arm links. An arm with more links with pieces than
//! [`MAX_LINK_SHAPES`](pregrasp_robot::MAX_LINK_SHAPES) (the collision model's room once the
//! largest gripper is in) has links that move with one frame merged into one shape
//! ([`crate::merge`]); one that fits is never merged.
//!
//! Link shapes name their links with `&'static` strings and pieces, as the built-in arms'
//! do: [`describe_arm`] keeps one description per distinct key for the life of the process,
//! so loading a scene again costs no memory.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

use nalgebra::Isometry3;
use pregrasp_robot::{
    ArmDescription, ArmGeometry, ArmKinematics, ConvexPieces, LinkShape, MAX_LINK_SHAPES,
};

use crate::arm::UrdfArm;
use crate::chain::origin_isometry;
use crate::error::UrdfError;
use crate::geometry::{GeometryOptions, LazyGeometry, UrdfGeometry};
use crate::merge::{self, Draft};
use crate::six::SixJointArm;

/// The arm `arm` with the joints `held` fixed at their values, as the planner uses it, with
/// the collision geometry of its links loaded (and cached) per `opts`
/// ([`LazyGeometry::for_arm`]: `opts.arm` is the arm's), and the link pairs `allowed` not
/// checked for self-collision (an allowed-collision list, [`UrdfGeometry::allow`]). Errors:
/// what [`SixJointArm::new`], [`UrdfGeometry::load`] and [`UrdfGeometry::allow`] report, or
/// an arm with no collision geometry at all.
pub fn describe_arm(
    arm: &UrdfArm,
    held: &[(&str, f64)],
    allowed: &[(&str, &str)],
    opts: &GeometryOptions,
) -> Result<ArmDescription, UrdfError> {
    describe_arm_from(
        arm,
        held,
        allowed,
        &LazyGeometry::for_arm(arm, opts.clone()),
    )
}

/// [`describe_arm`] with the description's geometry from `geometry` (loaded there once for
/// the arm and its gripper, [`crate::describe_gripper`]).
pub fn describe_arm_from(
    arm: &UrdfArm,
    held: &[(&str, f64)],
    allowed: &[(&str, &str)],
    geometry: &LazyGeometry,
) -> Result<ArmDescription, UrdfError> {
    let kin = SixJointArm::new(arm.model.name(), &arm.chain, held)?;
    let mut geometry = geometry.get(&arm.model)?.clone();
    // A pair naming a link with collision elements that the geometry left out (not the arm's,
    // [`GeometryOptions::arm`]) cannot concern the arm's shapes: skipped, not an error.
    let left_out = |link: &str| {
        geometry.index_of(link).is_none()
            && arm
                .model
                .robot()
                .links
                .iter()
                .any(|l| l.name == link && !l.collision.is_empty())
    };
    let kept: Vec<(&str, &str)> = allowed
        .iter()
        .copied()
        .filter(|(a, b)| !left_out(a) && !left_out(b))
        .collect();
    geometry.allow_all(kept)?;
    let mut allowed_key: Vec<String> = allowed
        .iter()
        .map(|(a, b)| format!("{}+{}", a.min(b), a.max(b)))
        .collect();
    allowed_key.sort();
    let held_key: Vec<String> = kin
        .held()
        .iter()
        .map(|(i, v)| format!("{i}={:016x}", v.to_bits()))
        .collect();
    let key = format!(
        "urdf:{}:{}:{}:{}:{}",
        geometry.key,
        arm.base_link,
        arm.tool_link,
        held_key.join(","),
        allowed_key.join(",")
    );
    static KNOWN: OnceLock<Mutex<BTreeMap<String, ArmDescription>>> = OnceLock::new();
    let known = KNOWN.get_or_init(Default::default);
    if let Some(d) = known.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(d.clone());
    }
    let shapes = arm_shapes(arm, &kin, &geometry)?;
    let description = ArmDescription {
        key: key.clone(),
        joint_names: std::array::from_fn(|i| kin.chain().joint_names()[i].to_string()),
        kin: Arc::new(kin),
        geometry: Arc::new(shapes),
        ur: None,
    };
    known
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, description.clone());
    Ok(description)
}

/// The link shapes and self-collision pairs of the arm (see the module documentation).
fn arm_shapes(
    arm: &UrdfArm,
    kin: &SixJointArm,
    geometry: &UrdfGeometry,
) -> Result<ArmGeometry, UrdfError> {
    let chain = kin.chain();
    let zero = [0.0; 6];
    let frames = kin.fk_frames(&zero);
    let link_frames = chain.link_frames(&zero);
    // Per path link: the frame it moves with and its pose at q = 0.
    let on_path = |name: &str| -> Option<InFrame> {
        let k = chain.links().iter().position(|l| l.name == name)?;
        let frame = chain.links()[k].after_joint.map_or(0, |j| j + 1);
        Some((frame, link_frames[k]))
    };
    let mut drafts = Vec::new();
    let mut index_of_piece_link = vec![None; geometry.links.len()];
    for (g, lp) in geometry.links.iter().enumerate() {
        let Some((frame, in_frame)) = attachment(arm, &lp.link, &on_path, &frames) else {
            continue;
        };
        let Some(draft) = Draft::new(&lp.link, frame, lp.placed(&in_frame)) else {
            continue;
        };
        index_of_piece_link[g] = Some(drafts.len());
        drafts.push(draft);
    }
    if drafts.is_empty() {
        return Err(UrdfError::NoCollisionGeometry {
            file: arm.model.source().to_string(),
            chain: format!("from `{}` to `{}`", arm.base_link, arm.tool_link),
        });
    }
    let pairs: Vec<(usize, usize)> = geometry
        .self_collision_pairs
        .iter()
        .filter_map(|&(a, b)| Some((index_of_piece_link[a]?, index_of_piece_link[b]?)))
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    let (drafts, self_collision_pairs) = if drafts.len() <= MAX_LINK_SHAPES {
        (drafts, pairs)
    } else {
        let count = drafts.len();
        merge::fit(drafts, &pairs, MAX_LINK_SHAPES).map_err(|link| {
            UrdfError::TooManyLinkShapes {
                file: arm.model.source().to_string(),
                link,
                count,
                max: MAX_LINK_SHAPES,
            }
        })?
    };
    let links = drafts
        .into_iter()
        .filter_map(|d| {
            let name = Box::leak(d.name().into_boxed_str());
            let (pieces, primitive) = ConvexPieces::leak_boxed(d.pieces)?;
            Some(LinkShape {
                name,
                frame: d.frame,
                primitive,
                pieces: Some(pieces),
            })
        })
        .collect();
    Ok(ArmGeometry {
        links,
        self_collision_pairs,
    })
}

/// A frame index (0..=6) and a pose in it.
type InFrame = (usize, Isometry3<f64>);

/// The frame link `name` moves with and its pose in that frame, if it is one of the arm's
/// links: the first link on the path found walking up from it through fixed joints, unless
/// that is the tool link (and `name` is not) or a moving joint comes first.
fn attachment(
    arm: &UrdfArm,
    name: &str,
    on_path: &dyn Fn(&str) -> Option<InFrame>,
    frames: &[Isometry3<f64>; 7],
) -> Option<InFrame> {
    // The pose of `name` in the frame of the link reached so far.
    let mut below = Isometry3::identity();
    let mut link = name.to_string();
    loop {
        if let Some((frame, pose)) = on_path(&link) {
            if link == arm.tool_link && link != name {
                return None;
            }
            return Some((frame, frames[frame].inv_mul(&(pose * below))));
        }
        let joint = arm.model.parent_joint(&link)?;
        if joint.joint_type != urdf_rs::JointType::Fixed {
            return None;
        }
        below = origin_isometry(&joint.origin) * below;
        link = joint.parent.link.clone();
    }
}
