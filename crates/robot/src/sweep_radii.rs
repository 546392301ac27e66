//! How far the points of an arm can move when its joints turn: per joint and shape group, an
//! upper bound on the distance from the joint's axis (for edge-validation resolution and the
//! swept checks). Built from the link shapes ([`crate::links`]) and the gripper's shapes at
//! every opening ([`crate::gripper`]).

use crate::arm::{ArmDescription, ArmKinematics};
use crate::fk::UrKinematics;
use crate::gripper::Gripper;
use crate::links::{arm_geometry, ArmGeometry, SHAPE_GROUPS};
use crate::model::{Joints, UrModel};

/// For edge-validation resolution: for each joint i, an upper bound on the distance from
/// joint axis i to any point of the arm links beyond it plus the gripper (m), open or
/// closed. Moving joint i by Δ rad moves any point by at most `radius_i·|Δ|`, so
/// `Σ radius_i·|Δq_i|` bounds any point's displacement.
///
/// The largest of [`group_sweep_radii`] over the shape groups.
pub fn joint_sweep_radii(model: UrModel, gripper: &Gripper) -> Joints {
    largest_per_joint(&group_sweep_radii(model, gripper))
}

/// Per joint, the largest of its group radii ([`group_sweep_radii`] →
/// [`joint_sweep_radii`], for any arm's groups).
pub fn largest_per_joint(groups: &[[f64; SHAPE_GROUPS]; 6]) -> Joints {
    std::array::from_fn(|i| groups[i].iter().copied().fold(0.0, f64::max))
}

/// Per joint i and shape group g (the link shapes of DH frame g, or g = 7 the gripper at any
/// opening with its precision and power points), an upper bound `R[i][g]` on the distance
/// from joint axis i to any point of the group (m). Under any joint motion a point of group g
/// moves at most `Σ_i R[i][g]·|Δq_i|`: the proximal links' bounds are much smaller than the
/// whole arm's ([`joint_sweep_radii`]).
///
/// Bound: joint i's axis passes through the origin of DH frame i−1; a point of a shape in
/// frame f ≥ i is within `Σ_{j=i..f} √(a_j² + d_j²)` (origin-to-origin link offsets) plus
/// the shape's largest distance from its own frame origin (its exact pieces' slack included).
/// Frames a joint does not move get 0.
pub fn group_sweep_radii(model: UrModel, gripper: &Gripper) -> [[f64; SHAPE_GROUPS]; 6] {
    cached(model.name(), gripper, || {
        let offsets = ArmKinematics::frame_offsets(&UrKinematics::new(model));
        compute_group_sweep_radii(&offsets, &arm_geometry(model), gripper)
    })
}

/// [`group_sweep_radii`] of any arm: joint `i`'s axis passes through the origin of frame `i`
/// ([`ArmKinematics`]'s frames), so the origin-to-origin distances
/// [`ArmKinematics::frame_offsets`] take the place of the DH link offsets.
pub fn group_sweep_radii_of(arm: &ArmDescription, gripper: &Gripper) -> [[f64; SHAPE_GROUPS]; 6] {
    cached(&arm.key, gripper, || {
        compute_group_sweep_radii(&arm.kin.frame_offsets(), &arm.geometry, gripper)
    })
}

/// The radii of the arm named `key` with `gripper`, computed by `compute` once per process
/// (every opening's shapes are posed).
fn cached(key: &str, gripper: &Gripper, compute: impl FnOnce() -> GroupRadii) -> GroupRadii {
    type Key = (String, String, u64, u64);
    static CACHE: std::sync::OnceLock<std::sync::Mutex<Vec<(Key, GroupRadii)>>> =
        std::sync::OnceLock::new();
    let key = (
        key.to_string(),
        gripper.shape_key().to_string(),
        gripper.precision_point_z().to_bits(),
        gripper.power_point_z().to_bits(),
    );
    let cache = CACHE.get_or_init(Default::default);
    if let Some((_, r)) = cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|(k, _)| *k == key)
    {
        return *r;
    }
    let radii = compute();
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((key, radii));
    radii
}

/// Per joint and shape group, the bound of [`group_sweep_radii`].
type GroupRadii = [[f64; SHAPE_GROUPS]; 6];

fn compute_group_sweep_radii(
    offsets: &[f64; 6],
    geometry: &ArmGeometry,
    gripper: &Gripper,
) -> GroupRadii {
    let mut reach_in_group = [0.0f64; SHAPE_GROUPS];
    for shape in &geometry.links {
        let r = shape.primitive.max_origin_distance() + shape.pieces.map_or(0.0, |p| p.slack);
        reach_in_group[shape.frame] = reach_in_group[shape.frame].max(r);
    }
    let reach_gripper = gripper
        .precision_point_z()
        .abs()
        .max(gripper.power_point_z().abs())
        .max(gripper_shape_reach(gripper));
    reach_in_group[7] = reach_gripper;
    std::array::from_fn(|i| {
        // Joint i (0-based) moves frames i+1..=6; its axis passes through frame i's origin.
        std::array::from_fn(|g| {
            let f = g.min(6);
            if f <= i {
                0.0
            } else {
                offsets[i..f].iter().sum::<f64>() + reach_in_group[g]
            }
        })
    })
}

/// The 2F-85's [`shape_reach_of`] (its bits), kept: its sampled openings cost 1.2 M
/// instructions, most of a process's sweep radii. The test `the_2f85_reach_is_the_computed_one`
/// computes it again.
const ROBOTIQ_2F85_SHAPE_REACH: u64 = 0x3fc6_ae7d_76ed_aed2;

/// The farthest any of `gripper`'s shapes reaches from the flange origin at any opening (m).
fn gripper_shape_reach(gripper: &Gripper) -> f64 {
    match gripper {
        Gripper::Robotiq2F85(_) => f64::from_bits(ROBOTIQ_2F85_SHAPE_REACH),
        Gripper::Jaws(_) => shape_reach_of(gripper),
    }
}

/// [`gripper_shape_reach`], computed: every finger pose (the fingers move on arcs: an
/// intermediate one may reach farthest), the static shapes with their pieces' slack as
/// `Gripper::shapes` gives them, the finger links without (their pieces are in the links' own
/// frames).
fn shape_reach_of(gripper: &Gripper) -> f64 {
    let (pieces, statics) = (gripper.shape_pieces(), gripper.static_count());
    let mut reach: f64 = 0.0;
    for state in gripper.sample_states() {
        gripper.for_each_shape(state, |k, _, primitive| {
            let slack = if k < statics {
                pieces[k].map_or(0.0, |p| p.slack)
            } else {
                0.0
            };
            reach = reach.max(primitive.max_origin_distance() + slack);
        });
    }
    reach
}

/// Per joint i, an upper bound on the distance from joint axis i to the flange origin (m): a
/// part rigid with the flange within `r` of its origin moves at most `Σ_i (F[i] + r)·|Δq_i|`.
pub fn flange_sweep_radii(model: UrModel) -> Joints {
    flange_sweep_radii_of(&UrKinematics::new(model))
}

/// [`flange_sweep_radii`] of any arm (see [`group_sweep_radii_of`]).
pub fn flange_sweep_radii_of(kin: &dyn ArmKinematics) -> Joints {
    let offsets = kin.frame_offsets();
    std::array::from_fn(|i| offsets[i..6].iter().sum::<f64>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_2f85_reach_is_the_computed_one() {
        let gripper: Gripper = crate::Gripper2F85::default().into();
        let reach = shape_reach_of(&gripper);
        assert_eq!(
            reach.to_bits(),
            ROBOTIQ_2F85_SHAPE_REACH,
            "the 2F-85 changed: its shapes reach {reach} m ({:#x})",
            reach.to_bits()
        );
        assert_eq!(gripper_shape_reach(&gripper), reach);
    }
}
