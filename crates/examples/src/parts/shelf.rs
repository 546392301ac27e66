//! Side panel of a shelf: a board with cut-out hand-holes and rows of shelf-pin holes.
//!
//! Object frame: `x` along the panel's height when standing (floor end at `x = 0`), `y`
//! across its depth (back edge `y = 0`, front edge `y = depth`), `z` through the board. The
//! front top corner is chamfered, so the back edge is the single longest edge of the bottom
//! face's convex hull: Algorithm 1 ranks it first, and the panel is tilted about its back
//! edge, lifted by the front.
//!
//! The board itself is far wider than the gripper's stroke; the hand-holes leave bars
//! between hole and edge that the fingers can close around:
//! - hole A runs along the floor end, leaving a bar along that end (the nearer power grasp);
//! - holes B and C run along the front edge near either end, leaving bars along the front
//!   edge (the support grasp on B's bar, the farther power grasp on C's).

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::Point2;
use pregrasp_geometry::Mesh;

use crate::design::{GraspSite, PartDesign};

/// Dimensions of a shelf side panel (metres).
#[derive(Clone, Debug, PartialEq)]
pub struct ShelfSideParams {
    /// Board thickness (object `z`).
    pub thickness: f64,
    /// Panel length (object `x`).
    pub length: f64,
    /// Panel depth (object `y`).
    pub depth: f64,
    /// Leg length of the 45° chamfer at the front top corner.
    pub chamfer: f64,
    /// Width of the bar a hand-hole leaves between itself and the panel edge.
    pub handle_bar_width: f64,
    /// Hand-hole size: length along the edge and width across it.
    pub hand_hole_length: f64,
    pub hand_hole_width: f64,
    /// Centre of hole A along `y`, and of holes B and C along `x`.
    pub hole_a_centre_y: f64,
    pub hole_b_centre_x: f64,
    pub hole_c_centre_x: f64,
    /// Shelf-pin holes: diameter, rows (`y` of each row), first `x`, pitch and count per row.
    pub pin_diameter: f64,
    pub pin_rows_y: [f64; 2],
    pub pin_first_x: f64,
    pub pin_pitch: f64,
    pub pins_per_row: usize,
    /// Segments of each pin hole's polygon.
    pub pin_segments: usize,
}

impl Default for ShelfSideParams {
    fn default() -> Self {
        Self {
            thickness: 0.018,
            length: 0.80,
            depth: 0.36,
            chamfer: 0.06,
            handle_bar_width: 0.050,
            hand_hole_length: 0.14,
            hand_hole_width: 0.075,
            hole_a_centre_y: 0.15,
            hole_b_centre_x: 0.19,
            hole_c_centre_x: 0.59,
            pin_diameter: 0.005,
            pin_rows_y: [0.06, 0.22],
            // 32 mm system pitch, between hole B and hole C.
            pin_first_x: 0.32,
            pin_pitch: 0.032,
            pins_per_row: 5,
            pin_segments: 12,
        }
    }
}

/// Clockwise axis-aligned rectangle `[x0, x1] × [y0, y1]`.
fn rect_cw(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<Point2<f64>> {
    vec![
        Point2::new(x0, y0),
        Point2::new(x0, y1),
        Point2::new(x1, y1),
        Point2::new(x1, y0),
    ]
}

impl ShelfSideParams {
    /// Outline, holes, axis and grasps of the panel.
    pub fn design(&self) -> PartDesign {
        let p = Point2::new;
        let (l, d, c) = (self.length, self.depth, self.chamfer);
        let (bar, hl, hw) = (
            self.handle_bar_width,
            self.hand_hole_length,
            self.hand_hole_width,
        );
        let outline = vec![p(0.0, 0.0), p(l, 0.0), p(l, d - c), p(l - c, d), p(0.0, d)];
        let hole_a = rect_cw(
            bar,
            bar + hw,
            self.hole_a_centre_y - hl / 2.0,
            self.hole_a_centre_y + hl / 2.0,
        );
        let front_hole = |cx: f64| rect_cw(cx - hl / 2.0, cx + hl / 2.0, d - bar - hw, d - bar);
        let mut holes = vec![
            hole_a,
            front_hole(self.hole_b_centre_x),
            front_hole(self.hole_c_centre_x),
        ];
        for &y in &self.pin_rows_y {
            for k in 0..self.pins_per_row {
                let centre = p(self.pin_first_x + k as f64 * self.pin_pitch, y);
                holes.push(self.pin_hole(centre));
            }
        }
        let front_bar_y = d - bar / 2.0;
        PartDesign {
            outline,
            holes,
            thickness: self.thickness,
            axis: [p(0.0, 0.0), p(l, 0.0)],
            support: GraspSite {
                bar: "front bar of hand-hole B",
                point: p(self.hole_b_centre_x, front_bar_y),
                closing_angle: FRAC_PI_2,
                bar_width: bar,
            },
            power_near: GraspSite {
                bar: "end bar of hand-hole A",
                point: p(bar / 2.0, self.hole_a_centre_y),
                closing_angle: PI,
                bar_width: bar,
            },
            power_far: GraspSite {
                bar: "front bar of hand-hole C",
                point: p(self.hole_c_centre_x, front_bar_y),
                closing_angle: FRAC_PI_2,
                bar_width: bar,
            },
        }
    }

    /// A shelf-pin hole as a regular polygon inscribed in the pin circle (clockwise).
    fn pin_hole(&self, centre: Point2<f64>) -> Vec<Point2<f64>> {
        let r = self.pin_diameter / 2.0;
        let n = self.pin_segments;
        (0..n)
            .map(|k| {
                let a = -2.0 * PI * k as f64 / n as f64;
                Point2::new(centre.x + r * a.cos(), centre.y + r * a.sin())
            })
            .collect()
    }
}

/// The shelf side panel as a closed triangle mesh (see [`ShelfSideParams`]).
pub fn shelf_side(params: &ShelfSideParams) -> Mesh {
    params.design().mesh()
}
