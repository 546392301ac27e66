//! The end of a bench: a board with hand holes that leave handle bars along its edges, laid
//! out as the shelf side ([`crate::ShelfSideParams`]) with thicker stock and narrower bars.
//!
//! The support grasp pinches the handle bar of hole B, one finger outside the board and the
//! other in the hole, which is narrower than the others (50 mm by default): the open finger
//! fits there. The power grasps wrap the bars of holes A and C, wider (75 mm): a power grasp's
//! open fingers reach 35 mm past a 35 mm bar at the height of its top face, so a 50 mm hole
//! would leave them no room.

use nalgebra::Point2;

use crate::design::PartDesign;
use crate::parts::shelf::ShelfSideParams;

/// Dimensions of a bench end (metres).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchEndParams {
    /// The board and its holes A and C (and B's position and length).
    pub board: ShelfSideParams,
    /// Width of hole B, where the pinch puts a finger.
    pub pinch_hole_width: f64,
}

impl Default for BenchEndParams {
    fn default() -> Self {
        Self {
            board: ShelfSideParams {
                thickness: 0.025,
                handle_bar_width: 0.035,
                hand_hole_width: 0.075,
                pins_per_row: 0,
                ..ShelfSideParams::default()
            },
            pinch_hole_width: 0.050,
        }
    }
}

impl BenchEndParams {
    /// Outline, holes, axis and grasps of the bench end.
    pub fn design(&self) -> PartDesign {
        let b = &self.board;
        let mut design = b.design();
        let (cx, hl, d, bar) = (
            b.hole_b_centre_x,
            b.hand_hole_length,
            b.depth,
            b.handle_bar_width,
        );
        let (x0, x1) = (cx - hl / 2.0, cx + hl / 2.0);
        let (y0, y1) = (d - bar - self.pinch_hole_width, d - bar);
        let p = Point2::new;
        // Holes are listed A, B, C (then pin holes): B is the second.
        design.holes[1] = vec![p(x0, y0), p(x0, y1), p(x1, y1), p(x1, y0)];
        design
    }
}
