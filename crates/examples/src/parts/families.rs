//! Generated parts of six families (frame, ladder, U-frame, panel with cut-outs, stool,
//! H-frame) with hand-placed grasps made by a rule, for sweeps that compare automatic grasps
//! with a person's (issue 35).
//!
//! [`generate`] draws a part of a family from a seed (ChaCha8): stock 18–45 mm thick, bars
//! 20–60 mm wide, outer sizes within each family's range. Object frame as the examples': the
//! part in its `x-y` plane, `z = 0` its bottom face. Every family but the stool lies with its
//! intended axis along `y = 0` (`x` from 0 to `length`), the part towards `+y`; its far corner
//! `(length, depth)` is chamfered, so the axis edge is the single longest edge of the bottom
//! face's hull. The stool is [`StoolSideParams`] with drawn dimensions (axis between its feet).
//!
//! The hand rule, as in the examples: the two power grasps across the bars at the arms' sides
//! (the end bars, at 0.6 and 0.7 of the depth: one nearer the axis than the other), closing
//! along `x`; the support pinch across the bar farthest from the axis, near its middle (the
//! stool: its own rule).
//!
//! Six more families, the hard cases ([`crate::parts::hard`], [`HARD_FAMILIES`]), put material
//! next to those grasps (T-junctions, L-corners, hand holes, parallel bars, chamfers and
//! tapers, thin rungs); [`generate`] draws them too, but [`FAMILIES`] and [`sweep`] leave them
//! out, so the sweeps and tables over the six stay as they are.

use nalgebra::Point2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::design::PartDesign;
#[cfg(doc)]
use crate::parts::hard::HARD_FAMILIES;
pub(crate) use crate::parts::kit::{chamfered, end_bar_design, rect_cw, site, CHAMFER};
pub use crate::parts::kit::{Family, GeneratedPart, BAR, STOCK};
use crate::parts::stool::StoolSideParams;

/// Every family, in sweep order.
pub const FAMILIES: [Family; 6] = [
    Family::Frame,
    Family::Ladder,
    Family::UFrame,
    Family::Panel,
    Family::Stool,
    Family::HFrame,
];

/// Hand holes of the panel: length along the bar and width across it (m); 75 mm leave the
/// open fingers room beside any bar of [`BAR`].
const HAND_HOLE: (f64, f64) = (0.14, 0.075);

fn frame(l: f64, d: f64, t: f64, b: f64) -> PartDesign {
    let window = rect_cw(b, l - b, b, d - b);
    let support = site("far rail, middle", l / 2.0, d - b / 2.0, false, b);
    end_bar_design(chamfered(l, d), vec![window], [l, d, t, b], support)
}

fn ladder(l: f64, d: f64, t: f64, b: f64, rungs: usize) -> PartDesign {
    let pitch = (l - b) / (rungs - 1) as f64;
    let holes: Vec<_> = (0..rungs - 1)
        .map(|k| rect_cw(k as f64 * pitch + b, (k + 1) as f64 * pitch, b, d - b))
        .collect();
    // The pinch on rail B in the middle of the hole nearest the centre (room for a finger).
    let k = (rungs - 2) / 2;
    let x = k as f64 * pitch + (b + pitch) / 2.0;
    let support = site("rail B, middle", x, d - b / 2.0, false, b);
    end_bar_design(chamfered(l, d), holes, [l, d, t, b], support)
}

fn u_frame(l: f64, d: f64, t: f64, b: f64) -> PartDesign {
    let p = Point2::new;
    let outline = vec![
        p(0.0, 0.0),
        p(b, 0.0),
        p(b, d - b),
        p(l - b, d - b),
        p(l - b, 0.0),
        p(l, 0.0),
        p(l, d - CHAMFER),
        p(l - CHAMFER, d),
        p(0.0, d),
    ];
    let support = site("far bar, middle", l / 2.0, d - b / 2.0, false, b);
    end_bar_design(outline, Vec::new(), [l, d, t, b], support)
}

fn panel(l: f64, d: f64, t: f64, b: f64) -> PartDesign {
    let (hl, hw) = HAND_HOLE;
    let (ya, yc) = (0.6 * d, 0.7 * d);
    let holes = vec![
        rect_cw(b, b + hw, ya - hl / 2.0, ya + hl / 2.0),
        rect_cw(l / 2.0 - hl / 2.0, l / 2.0 + hl / 2.0, d - b - hw, d - b),
        rect_cw(l - b - hw, l - b, yc - hl / 2.0, yc + hl / 2.0),
    ];
    let support = site("far bar of the middle hole", l / 2.0, d - b / 2.0, false, b);
    end_bar_design(chamfered(l, d), holes, [l, d, t, b], support)
}

fn h_frame(l: f64, d: f64, t: f64, b: f64) -> PartDesign {
    let p = Point2::new;
    let c = CHAMFER.min(b / 2.0);
    let (y0, y1) = (0.45 * d - b / 2.0, 0.45 * d + b / 2.0);
    let outline = vec![
        p(0.0, 0.0),
        p(b, 0.0),
        p(b, y0),
        p(l - b, y0),
        p(l - b, 0.0),
        p(l, 0.0),
        p(l, d - c),
        p(l - c, d),
        p(l - b, d),
        p(l - b, y1),
        p(b, y1),
        p(b, d),
        p(0.0, d),
    ];
    let mut design = end_bar_design(
        outline,
        Vec::new(),
        [l, d, t, b],
        site("crossbar, middle", l / 2.0, 0.45 * d, false, b),
    );
    design.power_near.point.y = 0.75 * d;
    design.power_far.point.y = 0.85 * d;
    design
}

fn stool(rng: &mut ChaCha8Rng, t: f64, b: f64) -> (PartDesign, [f64; 2]) {
    let params = StoolSideParams {
        thickness: t,
        height: rng.random_range(0.42..=0.50),
        top_width: rng.random_range(0.28..=0.34),
        bottom_width: rng.random_range(0.48..=0.56),
        leg_width: b,
        top_rail_width: (b + 0.010).min(BAR.1),
        stretcher_height: rng.random_range(0.13..=0.17),
        stretcher_width: b,
    };
    let size = [params.bottom_width, params.height];
    (params.design(), size)
}

/// The part of `family` drawn from `seed` (same seed, same part); the hard families
/// ([`HARD_FAMILIES`]) are drawn by
/// [`crate::parts::hard::generate_hard`].
pub fn generate(family: Family, seed: u64) -> GeneratedPart {
    if !FAMILIES.contains(&family) {
        return crate::parts::hard::generate_hard(family, seed);
    }
    // Each family its own stream: seed k of two families draws different stock.
    let index = FAMILIES.iter().position(|&f| f == family).unwrap_or(0) as u64;
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(FAMILIES.len() as u64) + index);
    let t = rng.random_range(STOCK.0..=STOCK.1);
    let b = rng.random_range(BAR.0..=BAR.1);
    let mut size =
        |l: (f64, f64), d: (f64, f64)| [rng.random_range(l.0..=l.1), rng.random_range(d.0..=d.1)];
    let (design, size) = match family {
        Family::Frame => {
            let [l, d] = size((0.60, 0.90), (0.40, 0.55));
            (frame(l, d, t, b), [l, d])
        }
        Family::Ladder => {
            let [l, d] = size((0.80, 1.00), (0.35, 0.45));
            let rungs = rng.random_range(3..=5);
            (ladder(l, d, t, b, rungs), [l, d])
        }
        Family::UFrame => {
            let [l, d] = size((0.55, 0.80), (0.40, 0.55));
            (u_frame(l, d, t, b), [l, d])
        }
        Family::Panel => {
            let [l, d] = size((0.60, 0.90), (0.35, 0.50));
            (panel(l, d, t, b), [l, d])
        }
        Family::Stool => stool(&mut rng, t, b),
        Family::HFrame => {
            let [l, d] = size((0.55, 0.80), (0.40, 0.55));
            (h_frame(l, d, t, b), [l, d])
        }
        _ => unreachable!("hard families are drawn by parts::hard"),
    };
    GeneratedPart {
        family,
        seed,
        thickness: t,
        bar: b,
        size,
        design,
    }
}

/// `per_family` parts of every family, seeds `first_seed`, `first_seed + 1`, … (family after
/// family: the k-th part of a family has seed `first_seed + k`).
pub fn sweep(first_seed: u64, per_family: usize) -> Vec<GeneratedPart> {
    FAMILIES
        .iter()
        .flat_map(|&f| (0..per_family as u64).map(move |k| generate(f, first_seed + k)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_makes_closed_deterministic_meshes_of_drawn_stock() {
        for part in sweep(1, 3) {
            let mesh = part.design.mesh();
            crate::mesh_check::check_closed_oriented(&mesh).unwrap();
            assert!(
                crate::mesh_check::signed_volume(&mesh) > 0.0,
                "{}",
                part.label()
            );
            assert!((STOCK.0..=STOCK.1).contains(&part.thickness));
            assert_eq!(generate(part.family, part.seed), part, "deterministic");
        }
    }

    #[test]
    fn the_hard_families_are_drawn_by_their_own_generator() {
        for family in crate::parts::hard::HARD_FAMILIES {
            for seed in 1..4 {
                let part = generate(family, seed);
                assert_eq!(part, crate::parts::hard::generate_hard(family, seed));
                assert_eq!(part.family, family);
            }
        }
    }
}
