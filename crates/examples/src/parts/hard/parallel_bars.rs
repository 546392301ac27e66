//! Parallel bars: a frame (length 0.60–0.90 m, depth 0.40–0.55 m, bars `b` 36–60 mm wide)
//! with a second stile (20–60 mm wide) beside each end bar, parallel to it across a slot as
//! narrow as the open fingers allow: [`FINGER_REACH`] − `b`/2 + 2–6 mm,
//! 47–63 mm. (A narrower slot beside a bar of 20–60 mm would hold an open finger: the fully
//! open 2F-85 reaches 74 mm from the bar's centre line.)
//!
//! Grasps: the power grasps across the end bars at 60 % (left) and 70 % (right) of the depth,
//! the inner finger in the slot with the stile just beyond its reach; the support pinch across
//! the far rail at its middle.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::{Drawn, FINGER_REACH};
use crate::parts::kit::{chamfered, end_bar_design, rect_cw, site, BAR};

/// Narrowest end bar (m).
const BAR_MIN: f64 = 0.036;

/// The design: length `l`, depth `d`, stock `t`, bars `b`; stiles `s` wide across slots of
/// `g` (m).
pub fn design([l, d, t, b]: [f64; 4], [s, g]: [f64; 2]) -> crate::design::PartDesign {
    let holes = vec![
        rect_cw(b, b + g, b, d - b),
        rect_cw(b + g + s, l - b - g - s, b, d - b),
        rect_cw(l - b - g, l - b, b, d - b),
    ];
    let support = site("far rail, middle", l / 2.0, d - b / 2.0, false, b);
    let mut design = end_bar_design(chamfered(l, d), holes, [l, d, t, b], support);
    design.power_near.bar = "left end bar, beside the parallel stile";
    design.power_far.bar = "right end bar, beside the parallel stile";
    design
}

pub(super) fn draw(rng: &mut ChaCha8Rng, t: f64, b: f64) -> Drawn {
    // The drawn bar, moved into 36–60 mm: the slot beside it then stays near 60 mm or under.
    let b = BAR_MIN + (b - BAR.0) / (BAR.1 - BAR.0) * (BAR.1 - BAR_MIN);
    let l = rng.random_range(0.60..=0.90);
    let d = rng.random_range(0.40..=0.55);
    let s = rng.random_range(BAR.0..=BAR.1);
    let g = FINGER_REACH - b / 2.0 + rng.random_range(0.002..=0.006);
    Drawn {
        design: design([l, d, t, b], [s, g]),
        size: [l, d],
        bar: b,
    }
}
