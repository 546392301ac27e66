//! L-corners: two legs standing on the axis (bar width `b`, 20–60 mm) joined at the far side
//! by a rail 40–60 mm wide (never narrower than the legs), meeting each leg in an L-corner.
//! Length 0.55–0.85 m, depth 0.40–0.55 m.
//!
//! Grasps: the power grasps across the legs just below the inner corners, the right one
//! 20–28 mm below the rail (farther from the axis), the left one 32–40 mm (nearer), so the
//! open finger inside each leg has the rail beside it; the support pinch across the rail at
//! its middle.

use nalgebra::Point2;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::{next_to, Drawn};
use crate::parts::kit::{end_bar_design, site, BAR, CHAMFER};

/// The design: length `l`, depth `d`, stock `t`, legs `b`, far rail `r` wide, the power grasps
/// `left` and `right` below the rail's inner edge (m).
pub fn design(
    [l, d, t, b]: [f64; 4],
    r: f64,
    [left, right]: [f64; 2],
) -> crate::design::PartDesign {
    let p = Point2::new;
    let outline = vec![
        p(0.0, 0.0),
        p(b, 0.0),
        p(b, d - r),
        p(l - b, d - r),
        p(l - b, 0.0),
        p(l, 0.0),
        p(l, d - CHAMFER),
        p(l - CHAMFER, d),
        p(0.0, d),
    ];
    let support = site("far rail, middle", l / 2.0, d - r / 2.0, false, r);
    let mut design = end_bar_design(outline, Vec::new(), [l, d, t, b], support);
    design.power_near.bar = "left leg, below the corner";
    design.power_near.point.y = d - r - left;
    design.power_far.bar = "right leg, below the corner";
    design.power_far.point.y = d - r - right;
    design
}

pub(super) fn draw(rng: &mut ChaCha8Rng, t: f64, b: f64) -> Drawn {
    let l = rng.random_range(0.55..=0.85);
    let d = rng.random_range(0.40..=0.55);
    let r = rng.random_range(b.max(0.040)..=BAR.1);
    let left = next_to(rng, 0.032, 0.040);
    let right = next_to(rng, 0.020, 0.028);
    Drawn {
        design: design([l, d, t, b], r, [left, right]),
        size: [l, d],
        bar: b,
    }
}
