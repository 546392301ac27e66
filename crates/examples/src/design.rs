//! A planar part together with the grasps and rotation axis its scene is designed around.

use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion, Vector2, Vector3};
use pregrasp_geometry::Mesh;

use crate::extrude::extrude;
use crate::triangulate::signed_area;

/// The Robotiq 2F-85 stroke (m): bars a gripper closes on must be narrower (condition c2).
pub const GRIPPER_STROKE: f64 = 0.085;

/// Robotiq 2F-85 numbers the part design must respect (gripper frame, metres; measured on
/// the MuJoCo Menagerie model, `docs/hardware-facts.md`). Where the fingers are at a given
/// opening comes from the robot crate's finger model.
pub mod gripper_2f85 {
    /// Default precision point (between the pads) on the approach axis `z`.
    pub const PRECISION_POINT_Z: f64 = 0.150;
    /// Default power point (bar axis when wrapped against the palm) on `z`.
    pub const POWER_POINT_Z: f64 = 0.115;
    /// Top of the housing between the fingers (the palm), on `z`.
    pub const PALM_Z: f64 = 0.1008;
    /// Fingertips (top of the pads) of the open gripper, on `z`.
    pub const FINGERTIP_Z: f64 = 0.1603;
    /// Half the gap between the open fingers' inner surfaces just above the palm
    /// (`z` 0.10–0.11): a power-grasped bar must be narrower than twice this.
    pub const HALF_GAP_AT_PALM: f64 = 0.031;
    /// The power point sits this far above the palm plus half the bar's thickness, so the bar
    /// lies against the palm without reaching into it.
    pub const POWER_POINT_CLEARANCE: f64 = 0.004;
}

/// Height of the pinching fingertips above the part's bottom face (the table) at the support
/// grasp (m): the pads (37.5 mm long) reach down the bar's sides to 3 mm above the table
/// (condition c2: the part is high enough to be precision-grasped).
pub const SUPPORT_PAD_TIP_HEIGHT: f64 = 0.003;

/// Height (m, object `z`) of the support grasp's precision point for a pinch across a bar of
/// `bar_width`: the fingers closed on the bar put their tips [`SUPPORT_PAD_TIP_HEIGHT`] above
/// the bottom face. The pads' real depth depends on the width (they rise as they close), so it
/// comes from the 2F-85 finger model, with the scene's default precision point.
pub fn support_grasp_height(bar_width: f64) -> f64 {
    let fingers = pregrasp_robot::FingerKinematics::robotiq_2f85();
    let tip = fingers.at(bar_width).tip_z;
    SUPPORT_PAD_TIP_HEIGHT + tip - gripper_2f85::PRECISION_POINT_Z
}

/// A grasp on a bar of a planar part, in the object frame.
///
/// A power grasp frame sits at `(point, thickness / 2)` (on the bar's centre line,
/// mid-thickness), the support grasp at [`support_grasp_height`]; `z` (approach) along the
/// object's `−z` (from above while the part lies flat) and its `x`
/// (the fingers' closing direction) at `closing_angle` from the object's `x` in the part
/// plane, across the bar. As a pose: `R = Rz(closing_angle) · Rx(π)`.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspSite {
    /// Where it is, for comments in scene files, e.g. "seat rail".
    pub bar: &'static str,
    /// Point on the bar's centre line in the part plane (m).
    pub point: Point2<f64>,
    /// Angle of the closing direction from object `x` (rad); perpendicular to the bar.
    pub closing_angle: f64,
    /// Width of the bar along the closing direction (m), `< GRIPPER_STROKE`.
    pub bar_width: f64,
}

/// A flat part — outline and holes extruded by `thickness` — with the grasps of its scene:
/// the support grasp G_s (precision, far from the axis), and two power grasps, one nearer the
/// intended axis (its arm becomes the supportive arm) and one farther (the master arm's).
#[derive(Clone, Debug, PartialEq)]
pub struct PartDesign {
    /// Outer ring in the object's x-y plane (m), counter-clockwise.
    pub outline: Vec<Point2<f64>>,
    /// Hole rings (m), clockwise.
    pub holes: Vec<Vec<Point2<f64>>>,
    /// Extent along object `z` (m): bottom face `z = 0`, top face `z = thickness`.
    pub thickness: f64,
    /// The bottom-face hull edge Algorithm 1 ranks best (longest): the intended rotation axis.
    pub axis: [Point2<f64>; 2],
    /// G_s: a precision (fingertip) grasp far from the axis.
    pub support: GraspSite,
    /// The power grasp nearer the axis (the supportive arm's, paper §V-B).
    pub power_near: GraspSite,
    /// The power grasp farther from the axis (the master arm's).
    pub power_far: GraspSite,
}

impl PartDesign {
    /// The part as a closed, outward-oriented triangle mesh (object frame, metres).
    pub fn mesh(&self) -> Mesh {
        extrude(&self.outline, &self.holes, self.thickness)
    }

    /// Area of the part's face (outline minus holes), m².
    pub fn face_area(&self) -> f64 {
        signed_area(&self.outline).abs()
            - self.holes.iter().map(|h| signed_area(h).abs()).sum::<f64>()
    }

    /// The grasp frame of `site` in the object frame (see [`GraspSite`]).
    pub fn grasp_pose(&self, site: &GraspSite) -> Isometry3<f64> {
        let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), site.closing_angle)
            * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        let height = if std::ptr::eq(site, &self.support) {
            // Rounded up to 0.1 mm, as the scene file writes it: the tips never end lower.
            (support_grasp_height(site.bar_width) * 1e4).ceil() / 1e4
        } else {
            self.thickness / 2.0
        };
        Isometry3::from_parts(
            Translation3::new(site.point.x, site.point.y, height),
            rotation,
        )
    }

    /// The power point (flange `z`, m) for a bar of this part's thickness held against the
    /// palm: palm + thickness / 2 + clearance, to the millimetre (facts: a bar of diameter D rests
    /// with its axis at 0.101 + D/2).
    pub fn power_point_z(&self) -> f64 {
        use gripper_2f85::{PALM_Z, POWER_POINT_CLEARANCE};
        ((PALM_Z + self.thickness / 2.0 + POWER_POINT_CLEARANCE) * 1000.0).ceil() / 1000.0
    }

    /// Unit normal of the axis in the part plane, pointing into the part (towards the
    /// outline's centroid of vertices).
    pub fn axis_inward_normal(&self) -> Vector2<f64> {
        let d = (self.axis[1] - self.axis[0]).normalize();
        let n = Vector2::new(-d.y, d.x);
        let centroid =
            self.outline.iter().map(|p| p.coords).sum::<Vector2<f64>>() / self.outline.len() as f64;
        if n.dot(&(centroid - self.axis[0].coords)) >= 0.0 {
            n
        } else {
            -n
        }
    }

    /// Distance (m) from a point of the part plane to the axis line.
    pub fn distance_to_axis(&self, p: &Point2<f64>) -> f64 {
        self.axis_inward_normal().dot(&(p - self.axis[0])).abs()
    }
}
