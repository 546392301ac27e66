//! Hard cases, generated (issue 49): parts of six families that put material next to the
//! hand-placed grasps — a crossbar meeting the grasped leg in a T, a rail meeting it in an
//! L-corner, a hand hole's end beside it, a parallel stile across a narrow slot, a chamfered
//! corner above a tapered leg, a thin rung beside a thick rail. The open 2F-85 may touch such
//! material but not lie inside it; there the open hand barely fits.
//!
//! Every part is a planar design extruded to a thickness of 18–45 mm ([`STOCK`]), about
//! 0.55–1.0 m along its axis and 0.35–0.55 m deep, mass from the face area (the scene's wood
//! density), in the object frame of [`crate::parts::families`]: the intended axis along `y = 0`
//! (`x` from 0 to `length`), the part towards `+y`, its far corner `(length, depth)`
//! chamfered so the axis edge is the bottom face's longest hull edge. Chamfers and tapers are
//! in the plan (the outline), so every part is still a prism and its mesh closed.
//!
//! The hand rule is the families' (`end_bar_design` of [`crate::parts::families`]): two power
//! grasps across the bars at the arms' sides (the left one nearer the axis, the right one
//! farther), closing along `x`; the support pinch across the bar farthest from the axis near
//! its middle, closing along `y`.
//! Each family moves the power grasps next to its hard feature, but never so near that the
//! fully open 2F-85 would lie inside the part: along the bar the open finger links reach
//! [`FINGER_HALF_WIDTH`] from the grasp's centre, across it [`FINGER_REACH`]; every bar
//! grasped is narrower than the open hand's gap at the palm (62 mm) and the stroke (85 mm).
//!
//! [`generate_hard`] draws a part from a seed with the families' generator (ChaCha8): same
//! seed, same part.

pub mod chamfered;
pub mod hand_hole;
pub mod l_corner;
pub mod parallel_bars;
pub mod t_junction;
pub mod thin_rungs;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::design::PartDesign;
use crate::parts::kit::{Family, GeneratedPart, BAR, STOCK};

/// The hard-case families, in sweep order (not in [`crate::parts::families::FAMILIES`]: the
/// sweeps and tables over those stay as they are).
pub const HARD_FAMILIES: [Family; 6] = [
    Family::TJunction,
    Family::LCorner,
    Family::HandHole,
    Family::ParallelBars,
    Family::Chamfered,
    Family::ThinRungs,
];

/// Half the extent (m) of the fully open 2F-85's finger links along the grasped bar, from the
/// grasp's centre, in the slab of the part (flange `z` 0.105–0.150 for a power grasp): the
/// bounding boxes of the finger solids' convex pieces (`FingerSolids::robotiq_2f85`, open
/// linkage) reach ±17.0 mm (the inner knuckles). Material across the bar must stay farther.
pub const FINGER_HALF_WIDTH: f64 = 0.017;

/// Reach (m) of the fully open 2F-85's finger links across the grasped bar, from the grasp's
/// centre, in the slab of the part: the finger tips' and outer fingers' pieces reach
/// ±74.2 mm. A parallel bar or a hole's far side nearer than this would be inside an open
/// finger.
pub const FINGER_REACH: f64 = 0.0745;

/// Distance (m) from a power grasp's centre to the material it is placed next to: the
/// issue's 20–40 mm, never nearer than the open finger's half width plus 3 mm.
pub const NEXT_TO: (f64, f64) = (0.020, 0.040);

/// A distance drawn from [`NEXT_TO`] (at least [`FINGER_HALF_WIDTH`] + 3 mm).
pub(crate) fn next_to(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo..=hi).max(FINGER_HALF_WIDTH + 0.003)
}

/// A drawn hard part before it is labelled: its design, size and main grasped bar's width.
pub(crate) struct Drawn {
    pub design: PartDesign,
    /// Length along the axis and depth away from it (m).
    pub size: [f64; 2],
    /// Width of the bars the power grasps close on (m).
    pub bar: f64,
}

/// The part of hard family `family` drawn from `seed` (same seed, same part). `family` must
/// be one of [`HARD_FAMILIES`].
///
/// # Panics
/// When `family` is not a hard family.
pub fn generate_hard(family: Family, seed: u64) -> GeneratedPart {
    let index = HARD_FAMILIES
        .iter()
        .position(|&f| f == family)
        .unwrap_or_else(|| panic!("{} is not a hard family", family.name())) as u64;
    // Each family its own stream, apart from the families' streams.
    let stream = seed.wrapping_mul(HARD_FAMILIES.len() as u64) + index;
    let mut rng = ChaCha8Rng::seed_from_u64(stream ^ 0x4841_5244);
    let t = rng.random_range(STOCK.0..=STOCK.1);
    let b = rng.random_range(BAR.0..=BAR.1);
    let drawn = match family {
        Family::TJunction => t_junction::draw(&mut rng, t, b),
        Family::LCorner => l_corner::draw(&mut rng, t, b),
        Family::HandHole => hand_hole::draw(&mut rng, t, b),
        Family::ParallelBars => parallel_bars::draw(&mut rng, t, b),
        Family::Chamfered => chamfered::draw(&mut rng, t),
        Family::ThinRungs => thin_rungs::draw(&mut rng, t),
        _ => unreachable!("checked above"),
    };
    GeneratedPart {
        family,
        seed,
        thickness: t,
        bar: drawn.bar,
        size: drawn.size,
        design: drawn.design,
    }
}

/// `per_family` parts of every hard family, seeds `first_seed`, `first_seed + 1`, ….
pub fn hard_sweep(first_seed: u64, per_family: usize) -> Vec<GeneratedPart> {
    HARD_FAMILIES
        .iter()
        .flat_map(|&f| (0..per_family as u64).map(move |k| generate_hard(f, first_seed + k)))
        .collect()
}

#[cfg(test)]
mod tests;
