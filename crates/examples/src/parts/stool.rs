//! Side of a stool: two splayed legs joined by a top rail and a stretcher.
//!
//! Object frame: `x` across the stool, centred (`x = 0` midway between the legs), `y` up from
//! the floor (`y = 0`), `z` through the thickness. The legs splay outwards towards the floor,
//! so the floor line between the two feet is the longest edge of the bottom face's convex
//! hull: Algorithm 1 ranks it first, and the side is tilted about its feet, lifted by the
//! top rail.

use nalgebra::Point2;
use pregrasp_geometry::Mesh;

use crate::design::{GraspSite, PartDesign};

/// Dimensions of a stool side (metres). Bar widths are measured in the part plane, across
/// the bar.
#[derive(Clone, Debug, PartialEq)]
pub struct StoolSideParams {
    /// Thickness (object `z`).
    pub thickness: f64,
    /// Floor to the top of the top rail.
    pub height: f64,
    /// Outer width at the top (across the top rail).
    pub top_width: f64,
    /// Outer width at the floor (feet).
    pub bottom_width: f64,
    pub leg_width: f64,
    pub top_rail_width: f64,
    /// Height of the stretcher's lower edge above the floor.
    pub stretcher_height: f64,
    pub stretcher_width: f64,
}

impl Default for StoolSideParams {
    fn default() -> Self {
        Self {
            thickness: 0.025,
            height: 0.46,
            top_width: 0.30,
            bottom_width: 0.52,
            leg_width: 0.045,
            top_rail_width: 0.055,
            stretcher_height: 0.15,
            stretcher_width: 0.035,
        }
    }
}

impl StoolSideParams {
    /// Splay angle of each leg from the vertical (rad).
    pub fn splay(&self) -> f64 {
        ((self.bottom_width - self.top_width) / 2.0).atan2(self.height)
    }

    /// Outer edge `x` of the right leg (`x > 0`) at height `y`; the left leg mirrors it.
    fn outer_x(&self, y: f64) -> f64 {
        self.bottom_width / 2.0 - (self.bottom_width - self.top_width) / 2.0 * y / self.height
    }

    /// Inner edge `x` of the right leg at height `y` (outer edge moved in by the leg's
    /// horizontal width `w / cos(splay)`).
    fn inner_x(&self, y: f64) -> f64 {
        self.outer_x(y) - self.leg_width / self.splay().cos()
    }

    /// Outline, holes, axis and grasps of the stool side.
    pub fn design(&self) -> PartDesign {
        let p = Point2::new;
        let h = self.height;
        let s0 = self.stretcher_height;
        let s1 = s0 + self.stretcher_width;
        let r0 = h - self.top_rail_width;
        let outline = vec![
            p(-self.outer_x(0.0), 0.0),
            p(-self.inner_x(0.0), 0.0),
            p(-self.inner_x(s0), s0),
            p(self.inner_x(s0), s0),
            p(self.inner_x(0.0), 0.0),
            p(self.outer_x(0.0), 0.0),
            p(self.outer_x(h), h),
            p(-self.outer_x(h), h),
        ];
        let window = vec![
            p(-self.inner_x(s1), s1),
            p(-self.inner_x(r0), r0),
            p(self.inner_x(r0), r0),
            p(self.inner_x(s1), s1),
        ];
        let rail_y = h - self.top_rail_width / 2.0;
        let stretcher_y = (s0 + s1) / 2.0;
        // The master's power grasp: across the left leg, at 0.65 of the height.
        let leg_y = 0.65 * h;
        let leg_x = -(self.outer_x(leg_y) + self.inner_x(leg_y)) / 2.0;
        let splay = self.splay();
        PartDesign {
            outline,
            holes: vec![window],
            thickness: self.thickness,
            axis: [p(-self.outer_x(0.0), 0.0), p(self.outer_x(0.0), 0.0)],
            support: GraspSite {
                bar: "top rail, right of centre",
                point: p(0.05, rail_y),
                closing_angle: std::f64::consts::FRAC_PI_2,
                bar_width: self.top_rail_width,
            },
            power_near: GraspSite {
                bar: "stretcher, right of centre",
                point: p(0.07, stretcher_y),
                closing_angle: std::f64::consts::FRAC_PI_2,
                bar_width: self.stretcher_width,
            },
            power_far: GraspSite {
                bar: "left leg",
                point: p(leg_x, leg_y),
                // Across the leg: the leg's normal, rotated from x by the splay.
                closing_angle: -splay,
                bar_width: self.leg_width,
            },
        }
    }
}

/// The stool side as a closed triangle mesh (see [`StoolSideParams`]).
pub fn stool_side(params: &StoolSideParams) -> Mesh {
    params.design().mesh()
}
