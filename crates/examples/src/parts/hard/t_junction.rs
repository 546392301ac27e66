//! T-junctions: two legs standing on the axis (bar width `b`, 20–60 mm), a far bar across
//! their tops and a crossbar (20–60 mm wide) between them whose ends meet the legs in
//! T-junctions at 50–60 % of the depth. Length 0.55–0.85 m, depth 0.40–0.55 m.
//!
//! Grasps: the power grasps across the legs next to the crossbar, on either side of it — the
//! left one 20–40 mm below its lower edge (nearer the axis), the right one 20–40 mm above its
//! upper edge — so the open finger on the inner side of each leg has the crossbar beside it;
//! the support pinch across the far bar at its middle.

use nalgebra::Point2;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::{next_to, Drawn, NEXT_TO};
use crate::parts::kit::{end_bar_design, rect_cw, site, BAR, CHAMFER};

/// The design: length `l`, depth `d`, stock `t`, legs and far bar `b`, crossbar `w` wide
/// centred at `yc`, the power grasps `below` under and `above` over the crossbar (m).
pub fn design(
    [l, d, t, b]: [f64; 4],
    [w, yc]: [f64; 2],
    [below, above]: [f64; 2],
) -> crate::design::PartDesign {
    let p = Point2::new;
    let (y0, y1) = (yc - w / 2.0, yc + w / 2.0);
    let outline = vec![
        p(0.0, 0.0),
        p(b, 0.0),
        p(b, y0),
        p(l - b, y0),
        p(l - b, 0.0),
        p(l, 0.0),
        p(l, d - CHAMFER),
        p(l - CHAMFER, d),
        p(0.0, d),
    ];
    let window = rect_cw(b, l - b, y1, d - b);
    let support = site("far bar, middle", l / 2.0, d - b / 2.0, false, b);
    let mut design = end_bar_design(outline, vec![window], [l, d, t, b], support);
    design.power_near.bar = "left leg, below the crossbar's T";
    design.power_near.point.y = y0 - below;
    design.power_far.bar = "right leg, above the crossbar's T";
    design.power_far.point.y = y1 + above;
    design
}

pub(super) fn draw(rng: &mut ChaCha8Rng, t: f64, b: f64) -> Drawn {
    let l = rng.random_range(0.55..=0.85);
    let d = rng.random_range(0.40..=0.55);
    let w = rng.random_range(BAR.0..=BAR.1);
    let yc = rng.random_range(0.50..=0.60) * d;
    let below = next_to(rng, NEXT_TO.0, NEXT_TO.1);
    let above = next_to(rng, NEXT_TO.0, NEXT_TO.1);
    Drawn {
        design: design([l, d, t, b], [w, yc], [below, above]),
        size: [l, d],
        bar: b,
    }
}
