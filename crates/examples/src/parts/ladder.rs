//! A ladder lying on the table: two rails joined by rungs of the same section.
//!
//! Object frame: `x` along the rails (foot at `x = 0`), `y` across (rail A along `y = 0`, rail B
//! along `y = width`), `z` through the stock. One top corner is chamfered, so the outer edge of
//! rail A is the single longest edge of the bottom face's hull: the rotation axis. Both power
//! grasps and the support pinch are on rail B, across it.
//!
//! With the default 40 × 25 mm rails the 2F-85's fingers, closing on rail B, cage it (the tips
//! meet under it, 155 mm from the flange) and reach 169.8 mm from the flange on the way — 39 mm
//! below the rail, as deep as MuJoCo's closing of the Menagerie model gets there. With the
//! 2.6 mm finger–support clearance the rail must rise 42 mm: 5.6° about the axis 0.43 m away, so
//! θ_goal = 6° + n_ext (3°) = 9°.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Point2;

use crate::design::{GraspSite, PartDesign};

/// Dimensions of a ladder (metres).
#[derive(Clone, Debug, PartialEq)]
pub struct LadderParams {
    /// Length along the rails (object `x`).
    pub length: f64,
    /// Width over both rails (object `y`).
    pub width: f64,
    /// Width of a rail or rung in the part plane.
    pub bar: f64,
    /// Stock thickness (object `z`).
    pub thickness: f64,
    /// Leg length of the 45° chamfer at the top corner of rail B.
    pub chamfer: f64,
    /// `x` of the rungs' lower edges (the first and last close the ends).
    pub rungs_x: Vec<f64>,
    /// `x` of the support grasp and of the two power grasps on rail B.
    pub support_x: f64,
    pub power_x: [f64; 2],
}

impl Default for LadderParams {
    fn default() -> Self {
        Self {
            length: 1.0,
            width: 0.45,
            bar: 0.040,
            thickness: 0.025,
            chamfer: 0.03,
            rungs_x: vec![0.0, 0.32, 0.64, 0.96],
            support_x: 0.48,
            power_x: [0.16, 0.80],
        }
    }
}

impl LadderParams {
    /// Outline, holes, axis and grasps of the ladder.
    pub fn design(&self) -> PartDesign {
        let p = Point2::new;
        let (l, w, bar, c) = (self.length, self.width, self.bar, self.chamfer);
        let outline = vec![p(0.0, 0.0), p(l, 0.0), p(l, w - c), p(l - c, w), p(0.0, w)];
        let holes = self
            .rungs_x
            .windows(2)
            .map(|r| {
                let (x0, x1, y0, y1) = (r[0] + bar, r[1], bar, w - bar);
                vec![p(x0, y0), p(x0, y1), p(x1, y1), p(x1, y0)]
            })
            .collect();
        let on_rail_b = |name: &'static str, x: f64| GraspSite {
            bar: name,
            point: p(x, w - bar / 2.0),
            closing_angle: FRAC_PI_2,
            bar_width: bar,
        };
        PartDesign {
            outline,
            holes,
            thickness: self.thickness,
            axis: [p(0.0, 0.0), p(l, 0.0)],
            support: on_rail_b("rail B, middle", self.support_x),
            power_near: on_rail_b("rail B, near the foot", self.power_x[0]),
            power_far: on_rail_b("rail B, near the top", self.power_x[1]),
        }
    }
}
