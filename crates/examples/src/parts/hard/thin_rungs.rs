//! Thin rungs beside thick rails: two rails along the axis and the far side (40–60 mm wide)
//! joined by 3–5 rungs only 12–20 mm wide, the end rungs at the part's ends. Length
//! 0.60–0.95 m, depth 0.35–0.50 m.
//!
//! Grasps: the power grasps across the thin end rungs — the left one at 55 % of the depth,
//! the right one 20–40 mm below the far rail, so the inner finger has the thick rail's corner
//! beside it; the support pinch across the far rail in the middle of the window nearest the
//! centre (the ladder's rule).

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::{next_to, Drawn, NEXT_TO};
use crate::design::PartDesign;
use crate::parts::kit::{chamfered, end_bar_design, rect_cw, site};

/// Narrowest and widest rung (m).
pub const RUNG: (f64, f64) = (0.012, 0.020);
/// Narrowest and widest rail (m).
pub const RAIL: (f64, f64) = (0.040, 0.060);

/// The design: length `l`, depth `d`, stock `t`, rungs `w` wide; rails `[near, far]` wide,
/// `rungs` rungs, the right power grasp `right` below the far rail (m).
pub fn design(
    [l, d, t, w]: [f64; 4],
    [near, far]: [f64; 2],
    rungs: usize,
    right: f64,
) -> PartDesign {
    let pitch = (l - w) / (rungs - 1) as f64;
    let holes: Vec<_> = (0..rungs - 1)
        .map(|k| rect_cw(k as f64 * pitch + w, (k + 1) as f64 * pitch, near, d - far))
        .collect();
    let k = (rungs - 2) / 2;
    let x = k as f64 * pitch + (w + pitch) / 2.0;
    let support = site("far rail, middle", x, d - far / 2.0, false, far);
    let mut design = end_bar_design(chamfered(l, d), holes, [l, d, t, w], support);
    design.power_near.bar = "left end rung (thin)";
    design.power_near.point.y = 0.55 * d;
    design.power_far.bar = "right end rung (thin), below the far rail";
    design.power_far.point.y = d - far - right;
    design
}

pub(super) fn draw(rng: &mut ChaCha8Rng, t: f64) -> Drawn {
    let l = rng.random_range(0.60..=0.95);
    let d = rng.random_range(0.35..=0.50);
    let w = rng.random_range(RUNG.0..=RUNG.1);
    let near = rng.random_range(RAIL.0..=RAIL.1);
    let far = rng.random_range(RAIL.0..=RAIL.1);
    let rungs = rng.random_range(3..=5);
    let right = next_to(rng, NEXT_TO.0, NEXT_TO.1);
    Drawn {
        design: design([l, d, t, w], [near, far], rungs, right),
        size: [l, d],
        bar: w,
    }
}
