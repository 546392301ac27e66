//! Chamfered and tapered sections: two legs standing on the axis, tapering from 40–60 mm at
//! the foot to 10–20 mm less under the far rail (30–60 mm wide); the window's two upper
//! corners chamfered at 45° by 20–60 mm, both outer far corners by 50–80 % of the narrower of
//! rail and leg. Length 0.55–0.85 m, depth 0.40–0.55 m.
//!
//! Grasps: the power grasps across the tapered legs (closing along `x`, the bar as wide as
//! the leg at that height) just below the chamfers — the left one 30–40 mm below where its
//! chamfer begins, the right one 20–28 mm — so the inner finger has the chamfer's slope
//! above it; the support pinch across the far rail at its middle.

use nalgebra::Point2;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::{next_to, Drawn};
use crate::design::PartDesign;
use crate::parts::kit::{end_bar_design, site, BAR};

/// Leg and rail widths of a chamfered part (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sections {
    /// Leg width at the foot (on the axis).
    pub foot: f64,
    /// Leg width under the far rail.
    pub top: f64,
    /// Far rail width.
    pub rail: f64,
    /// Leg length of the 45° chamfers of the window's upper corners.
    pub inner_chamfer: f64,
    /// Leg length of the chamfers of the two outer far corners.
    pub outer_chamfer: f64,
}

/// The design: length `l`, depth `d`, stock `t`, `sections`; the power grasps `[left, right]`
/// below where their chamfer begins (m).
pub fn design([l, d, t]: [f64; 3], s: Sections, [left, right]: [f64; 2]) -> PartDesign {
    let p = Point2::new;
    let y_rail = d - s.rail;
    // The leg's inner edge: `x` (left leg) at height `y`.
    let inner = |y: f64| s.foot + (s.top - s.foot) * y / y_rail;
    let yk = y_rail - s.inner_chamfer;
    let c = s.outer_chamfer;
    let outline = vec![
        p(0.0, 0.0),
        p(s.foot, 0.0),
        p(inner(yk), yk),
        p(s.top + s.inner_chamfer, y_rail),
        p(l - s.top - s.inner_chamfer, y_rail),
        p(l - inner(yk), yk),
        p(l - s.foot, 0.0),
        p(l, 0.0),
        p(l, d - c),
        p(l - c, d),
        p(c, d),
        p(0.0, d - c),
    ];
    let support = site("far rail, middle", l / 2.0, d - s.rail / 2.0, false, s.rail);
    let mut design = end_bar_design(outline, Vec::new(), [l, d, t, s.foot], support);
    let (ya, yb) = (yk - left, yk - right);
    design.power_near = site(
        "left tapered leg, below the chamfer",
        inner(ya) / 2.0,
        ya,
        true,
        inner(ya),
    );
    design.power_far = site(
        "right tapered leg, below the chamfer",
        l - inner(yb) / 2.0,
        yb,
        true,
        inner(yb),
    );
    design
}

pub(super) fn draw(rng: &mut ChaCha8Rng, t: f64) -> Drawn {
    let l = rng.random_range(0.55..=0.85);
    let d = rng.random_range(0.40..=0.55);
    let foot = rng.random_range(0.040..=BAR.1);
    let top = foot - rng.random_range(0.010..=0.020);
    let rail = rng.random_range(0.030..=BAR.1);
    let inner_chamfer = rng.random_range(0.020..=0.060);
    let outer_chamfer = rng.random_range(0.5..=0.8) * rail.min(top);
    let left = next_to(rng, 0.030, 0.040);
    let right = next_to(rng, 0.020, 0.028);
    let sections = Sections {
        foot,
        top,
        rail,
        inner_chamfer,
        outer_chamfer,
    };
    let design = design([l, d, t], sections, [left, right]);
    let bar = design.power_near.bar_width;
    Drawn {
        design,
        size: [l, d],
        bar,
    }
}
