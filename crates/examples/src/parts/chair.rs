//! Side frame of a chair: front leg, raked back leg, seat rail and lower stretcher.
//!
//! Object frame: `x` from the front of the chair (front leg's front face at `x = 0`) to the
//! back, `y` up from the floor (`y = 0`), `z` through the frame's thickness. The back leg runs
//! straight from its foot to the top of the back rest, raked backwards. Its outer (back) edge
//! is the longest edge of the convex hull of the bottom face, so Algorithm 1 ranks it first:
//! the frame is tilted about the back leg, lifted by the front.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Point2;
use pregrasp_geometry::Mesh;

use crate::design::{GraspSite, PartDesign};

/// Dimensions of a chair side frame (metres). Bar widths are measured in the part plane,
/// across the bar.
#[derive(Clone, Debug, PartialEq)]
pub struct ChairSideParams {
    /// Frame thickness (object `z`).
    pub thickness: f64,
    /// Top of the front leg and of the seat rail above the floor.
    pub seat_height: f64,
    /// Floor distance from the front leg's front face to the back leg's back face.
    pub depth: f64,
    /// Height of the back leg (top of the back rest).
    pub back_height: f64,
    /// How far back the back leg's top sits relative to its foot (rake).
    pub back_rake: f64,
    pub front_leg_width: f64,
    pub back_leg_width: f64,
    pub seat_rail_width: f64,
    /// Height of the stretcher's lower edge above the floor.
    pub stretcher_height: f64,
    pub stretcher_width: f64,
}

impl Default for ChairSideParams {
    fn default() -> Self {
        Self {
            thickness: 0.025,
            seat_height: 0.45,
            depth: 0.42,
            back_height: 0.85,
            back_rake: 0.08,
            front_leg_width: 0.040,
            back_leg_width: 0.045,
            seat_rail_width: 0.055,
            stretcher_height: 0.14,
            stretcher_width: 0.030,
        }
    }
}

impl ChairSideParams {
    /// Back leg outer (back) edge `x` at height `y`.
    fn back_outer_x(&self, y: f64) -> f64 {
        self.depth + self.back_rake * y / self.back_height
    }

    /// Back leg inner (front) edge `x` at height `y`: the outer edge moved forward by the
    /// leg's horizontal width `w / cos(rake angle)`.
    fn back_inner_x(&self, y: f64) -> f64 {
        let horizontal =
            self.back_leg_width * self.back_rake.hypot(self.back_height) / self.back_height;
        self.back_outer_x(y) - horizontal
    }

    /// Outline, holes, axis and grasps of the frame.
    pub fn design(&self) -> PartDesign {
        let p = Point2::new;
        let wf = self.front_leg_width;
        let s0 = self.stretcher_height;
        let s1 = s0 + self.stretcher_width;
        let r0 = self.seat_height - self.seat_rail_width;
        let (hs, hb) = (self.seat_height, self.back_height);
        let outline = vec![
            p(0.0, 0.0),
            p(wf, 0.0),
            p(wf, s0),
            p(self.back_inner_x(s0), s0),
            p(self.back_inner_x(0.0), 0.0),
            p(self.back_outer_x(0.0), 0.0),
            p(self.back_outer_x(hb), hb),
            p(self.back_inner_x(hb), hb),
            p(self.back_inner_x(hs), hs),
            p(0.0, hs),
        ];
        // The window between the legs, the stretcher and the seat rail (clockwise).
        let window = vec![
            p(wf, s1),
            p(wf, r0),
            p(self.back_inner_x(r0), r0),
            p(self.back_inner_x(s1), s1),
        ];
        let rail_y = hs - self.seat_rail_width / 2.0;
        PartDesign {
            outline,
            holes: vec![window],
            thickness: self.thickness,
            axis: [p(self.back_outer_x(0.0), 0.0), p(self.back_outer_x(hb), hb)],
            // Pinched across the seat rail near the front leg: the farthest bar from the axis
            // with room for a fingertip on both sides (above the rail, and in the window).
            support: GraspSite {
                bar: "seat rail, near the front leg",
                point: p(wf + 0.07, rail_y),
                closing_angle: FRAC_PI_2,
                bar_width: self.seat_rail_width,
            },
            power_near: GraspSite {
                bar: "seat rail, near the back leg",
                point: p(self.back_inner_x(rail_y) - 0.145, rail_y),
                closing_angle: FRAC_PI_2,
                bar_width: self.seat_rail_width,
            },
            power_far: GraspSite {
                bar: "stretcher",
                point: p(wf + 0.11, (s0 + s1) / 2.0),
                closing_angle: FRAC_PI_2,
                bar_width: self.stretcher_width,
            },
        }
    }
}

/// The chair side frame as a closed triangle mesh (see [`ChairSideParams`]).
pub fn chair_side(params: &ChairSideParams) -> Mesh {
    params.design().mesh()
}
