//! The plan as a sequence of world states: what both arms, both grippers and the object do at
//! every instant of the four segments (μ_sup1, μ_rot, μ_mas1, μ_sup2).
//!
//! The plan format fixes the semantics (plan-format.md, "Segments"): one arm moves per segment,
//! linearly in joint space between neighbouring points; the other arm holds its last
//! configuration. A gripper is open at the start of every `reach`/`regrasp`, closes at its last
//! point and stays closed while its arm holds the part; `sup2` opens it at its first point. The
//! object sits at `P_init` until `rot`, follows `object_pose` during `rot` (interpolated between
//! points), and stays at `P_obj` afterwards.
//!
//! Gripper–object contact is allowed only for a gripper that holds the part, and within the last
//! [`CONTACT_ZONE`] of a straight approach and the first [`CONTACT_ZONE`] of the `sup2` retreat.
//! Both the planner (to validate what it produces) and `pregrasp check` walk this timeline.

use nalgebra::{Isometry3, Point3};
use pregrasp_robot::{GripperState, Joints};

/// Length of the straight approach (and retreat) within which a gripper may touch the part it
/// closes on or releases (plan-format.md, rule 2): 2 cm.
pub const CONTACT_ZONE: f64 = 0.02;

/// Everything the collision model needs at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct Moment {
    pub q: [Joints; 2],
    pub gripper: [GripperState; 2],
    /// The object's world pose.
    pub object: Isometry3<f64>,
    /// Whether gripper `i` may touch the object at this instant.
    pub contact_allowed: [bool; 2],
}

impl Moment {
    /// Both arms at `q` with their grippers open, the object at `object`, no contact allowed.
    pub fn at_rest(q: [Joints; 2], object: Isometry3<f64>) -> Moment {
        Moment {
            q,
            gripper: [GripperState::Open; 2],
            object,
            contact_allowed: [false; 2],
        }
    }

    /// The same moment with arm `arm` at `q` holding the part: gripper closed on it (`grip`,
    /// where its closing stopped), contact between that gripper and the part allowed.
    pub fn holding(mut self, arm: usize, q: Joints, grip: GripperState) -> Moment {
        self.q[arm] = q;
        self.gripper[arm] = grip;
        self.contact_allowed[arm] = true;
        self
    }
}

/// A straight tool line: the tool point starts at `from` and the line ends at `to`, moving
/// along the tool's own z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolLine {
    pub from: Point3<f64>,
    pub to: Point3<f64>,
}

impl ToolLine {
    /// Distance of `p` from the end of the line that touches the part.
    pub fn distance_to_contact_end(&self, p: &Point3<f64>, contact_at_end: bool) -> f64 {
        if contact_at_end {
            (p - self.to).norm()
        } else {
            (p - self.from).norm()
        }
    }
}

/// Interpolates two joint vectors linearly, `s` in `[0, 1]`.
pub fn lerp_joints(a: &Joints, b: &Joints, s: f64) -> Joints {
    let mut q = *a;
    for i in 0..6 {
        q[i] = a[i] + (b[i] - a[i]) * s;
    }
    q
}

/// Interpolates two poses: translation linearly, rotation by slerp, `s` in `[0, 1]`.
pub fn lerp_pose(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    a.lerp_slerp(b, s)
}

/// Number of sub-steps needed so that no point of the arm moves more than `resolution` per
/// step, given per-joint sweep radii `w` (any point moves at most Σ w_i |Δq_i|).
pub fn substeps(a: &Joints, b: &Joints, w: &Joints, resolution: f64) -> usize {
    let bound: f64 = (0..6).map(|i| w[i] * (b[i] - a[i]).abs()).sum();
    ((bound / resolution).ceil() as usize).max(1)
}
