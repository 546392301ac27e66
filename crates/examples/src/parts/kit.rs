//! What the generated families share (`crate::parts::families`, `crate::parts::hard`): the
//! family names, a generated part, the stock and bar ranges, and the pieces of the families'
//! hand rule (rectangular holes, grasp sites, the chamfered outline, the end-bar design).
//! Object frame and hand rule: see `crate::parts::families`.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Point2;

use crate::design::{GraspSite, PartDesign};
#[cfg(doc)]
use crate::parts::stool::StoolSideParams;

/// The six families ([`crate::parts::families::FAMILIES`]) and the six hard-case families
/// ([`crate::parts::hard::HARD_FAMILIES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// A rectangular frame: four bars around one window.
    Frame,
    /// Two rails along the axis joined by 3–5 rungs.
    Ladder,
    /// Two legs standing on the axis joined by a bar at the far side.
    UFrame,
    /// A board with hand holes leaving bars along its ends and far edge.
    Panel,
    /// A stool side ([`StoolSideParams`]): splayed legs, top rail, stretcher.
    Stool,
    /// Two legs standing on the axis joined by a crossbar half-way up.
    HFrame,
    /// Hard case ([`crate::parts::hard::t_junction`]): legs, far bar and a crossbar meeting
    /// the legs in T-junctions; the power grasps 20–40 mm from the crossbar.
    TJunction,
    /// Hard case ([`crate::parts::hard::l_corner`]): legs and a wide far rail; the power
    /// grasps 20–40 mm below the inner corners.
    LCorner,
    /// Hard case ([`crate::parts::hard::hand_hole`]): a board with narrow hand holes; the power
    /// grasps on the end bars beside the holes, 20–40 mm from a hole's end.
    HandHole,
    /// Hard case ([`crate::parts::hard::parallel_bars`]): a frame with a second stile beside each
    /// end bar, the slot between them as narrow as the open fingers allow.
    ParallelBars,
    /// Hard case ([`crate::parts::hard::chamfered`]): tapered legs, chamfered inner corners;
    /// the power grasps just below the chamfers.
    Chamfered,
    /// Hard case ([`crate::parts::hard::thin_rungs`]): thick rails, rungs 12–20 mm wide; the
    /// power grasps on the thin end rungs, one 20–40 mm from the far rail.
    ThinRungs,
}
/// Thinnest and thickest stock (m).
pub const STOCK: (f64, f64) = (0.018, 0.045);
/// Narrowest and widest bar (m).
pub const BAR: (f64, f64) = (0.020, 0.060);
/// Leg length (m) of the chamfer at the far corner.
pub(crate) const CHAMFER: f64 = 0.012;
impl Family {
    /// Lower-case name, e.g. `"u_frame"`.
    pub fn name(self) -> &'static str {
        match self {
            Family::Frame => "frame",
            Family::Ladder => "ladder",
            Family::UFrame => "u_frame",
            Family::Panel => "panel",
            Family::Stool => "stool",
            Family::HFrame => "h_frame",
            Family::TJunction => "t_junction",
            Family::LCorner => "l_corner",
            Family::HandHole => "hand_hole",
            Family::ParallelBars => "parallel_bars",
            Family::Chamfered => "chamfered",
            Family::ThinRungs => "thin_rungs",
        }
    }
}
/// One generated part: its family, seed, the drawn stock and bar width, and its design (with
/// the hand-placed grasps).
#[derive(Clone, Debug, PartialEq)]
pub struct GeneratedPart {
    pub family: Family,
    pub seed: u64,
    /// Stock thickness (m).
    pub thickness: f64,
    /// Bar width (m).
    pub bar: f64,
    /// Length along the axis and depth away from it (m).
    pub size: [f64; 2],
    pub design: PartDesign,
}

impl GeneratedPart {
    /// A one-line description, e.g. `"ladder #3: 0.86 × 0.41 m, 25 mm stock, 40 mm bars"`.
    pub fn label(&self) -> String {
        format!(
            "{} #{}: {:.2} × {:.2} m, {:.0} mm stock, {:.0} mm bars",
            self.family.name(),
            self.seed,
            self.size[0],
            self.size[1],
            self.thickness * 1e3,
            self.bar * 1e3
        )
    }
}

/// Clockwise axis-aligned rectangle `[x0, x1] × [y0, y1]` (a hole ring).
pub(crate) fn rect_cw(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<Point2<f64>> {
    let p = Point2::new;
    vec![p(x0, y0), p(x0, y1), p(x1, y1), p(x1, y0)]
}

/// A grasp across a bar closing along `x` (the end bars) or `y` (bars along the axis).
pub(crate) fn site(bar: &'static str, x: f64, y: f64, along_x: bool, width: f64) -> GraspSite {
    GraspSite {
        bar,
        point: Point2::new(x, y),
        closing_angle: if along_x { 0.0 } else { FRAC_PI_2 },
        bar_width: width,
    }
}

/// The outer rectangle `length × depth` with its far corner chamfered (counter-clockwise).
pub(crate) fn chamfered(l: f64, d: f64) -> Vec<Point2<f64>> {
    let p = Point2::new;
    vec![
        p(0.0, 0.0),
        p(l, 0.0),
        p(l, d - CHAMFER),
        p(l - CHAMFER, d),
        p(0.0, d),
    ]
}

/// The hand rule's power grasps on the end bars (centred `b / 2` in from either end) and the
/// support pinch at `support` on the far bar.
pub(crate) fn end_bar_design(
    outline: Vec<Point2<f64>>,
    holes: Vec<Vec<Point2<f64>>>,
    [l, d, t, b]: [f64; 4],
    support: GraspSite,
) -> PartDesign {
    PartDesign {
        outline,
        holes,
        thickness: t,
        axis: [Point2::new(0.0, 0.0), Point2::new(l, 0.0)],
        support,
        power_near: site("left end bar", b / 2.0, 0.6 * d, true, b),
        power_far: site("right end bar", l - b / 2.0, 0.7 * d, true, b),
    }
}
