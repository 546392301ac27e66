//! Cheap tests of a grasp set, run before the pipeline so that the sets most likely to plan
//! are planned first (issue 35: the pipeline costs 10–40 ms a set, these well under 1 ms).
//!
//! - The open hand ([`GraspTests::fingers`]): the arm's open gripper at the grasp has no
//!   finger link in the part (real finger geometry, [`OpenFingers`]); the whole open hand,
//!   palm included, is nowhere more than 0.5 mm inside the whole part from the grasp back
//!   through the contact zone (the planner's rule, [`open_approach_inside`]); and from the
//!   end of the contact zone ([`CONTACT_ZONE`]) to the stand-off (`approach_distance`) the
//!   hand keeps `link_clearance` (+ the planner's margin) from the part: the straight
//!   approach the pipeline will build.
//! - The goal ([`GraspTests::at_goal`]): the part turned about the set's axis by an estimate
//!   of θ_goal (what lifts the nearer power grasp [`FINGER_RISE`] off the table, at most
//!   θ_max, plus the `n_ext` steps Algorithm 2 adds); collision-free IK, nearest the start,
//!   for the supportive arm at G_s and the master at its power grasp, then both at their
//!   power grasps; the smallest arm–arm (and self) distance of the two states (an arms-only
//!   [`CollisionWorld`]).
//! - The pinch's balance ([`GraspTests::com_margin`]): the part's centre of mass, seen from
//!   above at P_init, inside the triangle of the axis' ends and G_s (else the pinch must hold
//!   a torque about its own normal: hundreds of newtons); the margin is the smallest
//!   barycentric coordinate.

use nalgebra::{Isometry3, Point2, Point3, Vector3};
use parry3d_f64::shape::TriMesh;
use pregrasp_collision::distance::segment_segment_sq;
use pregrasp_collision::{
    open_approach_inside, ArmModel, CollisionWorld, ObjectPlacement, WorldState,
};
use pregrasp_geometry::Mesh;
use pregrasp_io::scene::Scene;
use pregrasp_physics::MassProperties;
use pregrasp_robot::Joints;

use crate::axes::RotationAxisCandidate;
use crate::context::{distinct_ik, FINE_PLANNING_MARGIN, PLANNING_MARGIN};
use crate::open_fingers::OpenFingers;
use pregrasp_model::timeline::CONTACT_ZONE;

/// How far (m) the nearer power grasp must rise for the fingers to close under the bar (the
/// ladder of the examples needs 42 mm for a 25 mm rail).
pub const FINGER_RISE: f64 = 0.045;

/// The part and the arms, for the tests of many sets.
pub struct GraspTests<'a> {
    scene: &'a Scene,
    part: &'a TriMesh,
    arms: &'a [ArmModel; 2],
    /// The arms, the support and the part: collision-free IK.
    cell: CollisionWorld,
    p_init: Isometry3<f64>,
    /// The part's centre of mass (object frame).
    com: Point3<f64>,
}

/// The centre of mass of the solid `mesh` bounds ([`MassProperties`]), or its vertex mean
/// when it bounds none (an open mesh: the pinch's balance is then only a guess).
fn centre_of_mass(mesh: &Mesh) -> Point3<f64> {
    MassProperties::from_mesh(mesh).map_or_else(
        |_| {
            let n = mesh.vertices.len().max(1) as f64;
            Point3::from(mesh.vertices.iter().map(|v| v.coords).sum::<Vector3<f64>>() / n)
        },
        |m| m.centroid,
    )
}

/// Smallest barycentric coordinate of `p` in the triangle `t` (negative: outside).
fn barycentric_margin(t: [Point2<f64>; 3], p: Point2<f64>) -> f64 {
    let cross = |a: Point2<f64>, b: Point2<f64>, c: Point2<f64>| (b - a).perp(&(c - a));
    let area = cross(t[0], t[1], t[2]);
    if area.abs() < 1e-12 {
        return -1.0;
    }
    let l0 = cross(p, t[1], t[2]) / area;
    let l1 = cross(t[0], p, t[2]) / area;
    l0.min(l1).min(1.0 - l0 - l1)
}

impl<'a> GraspTests<'a> {
    pub fn new(
        scene: &'a Scene,
        mesh: &Mesh,
        part: &'a TriMesh,
        arms: &'a [ArmModel; 2],
        p_init: Isometry3<f64>,
    ) -> Self {
        let cell = CollisionWorld::try_new(Some(scene.support_height), Some(mesh), arms.clone())
            .unwrap_or_else(|_| CollisionWorld::with_part(None, None, arms.clone()))
            .with_margin(scene.planner.link_clearance + PLANNING_MARGIN)
            .with_grasp_support_margin(
                scene.planner.finger_support_clearance + FINE_PLANNING_MARGIN,
            );
        GraspTests {
            scene,
            part,
            arms,
            cell,
            p_init,
            com: centre_of_mass(mesh),
        }
    }

    /// Whether arm `arm`'s open hand at `grasp` (object frame), held by `point` (its tool
    /// point in the flange frame), fits around the bar, and whether its straight approach
    /// keeps the link clearance outside the contact zone: `(fits, approach_clear)`.
    pub fn fingers(
        &self,
        arm: usize,
        grasp: &Isometry3<f64>,
        point: &Isometry3<f64>,
    ) -> (bool, bool) {
        let gripper = &self.arms[arm].gripper;
        let open = OpenFingers::of(gripper);
        let flange = grasp * point.inverse();
        if open.touch(self.part, &flange).is_some() {
            return (false, false);
        }
        // The cell's part (its geometry for the open-hand rule, built once with the cell).
        if let Some(object) = self.cell.object() {
            if open_approach_inside(object, gripper, &flange).is_some() {
                return (false, false);
            }
        }
        let p = &self.scene.planner;
        let clear = open.approach_clear(
            self.part,
            &flange,
            [CONTACT_ZONE, p.approach_distance],
            p.link_clearance + PLANNING_MARGIN,
        );
        (true, clear)
    }

    /// The margin of the centre of mass inside the triangle (axis ends, G_s) seen from above.
    pub fn com_margin(&self, axis: &RotationAxisCandidate, support: &Isometry3<f64>) -> f64 {
        let flat = |p: Point3<f64>| Point2::new(p.x, p.y);
        let s = self.p_init * Point3::from(support.translation.vector);
        let com = self.p_init * self.com;
        barycentric_margin([flat(axis.axis[0]), flat(axis.axis[1]), flat(s)], flat(com))
    }

    /// The estimate of θ_goal (rad): what lifts the nearer power grasp [`FINGER_RISE`], plus
    /// the `n_ext` steps Algorithm 2 adds, at most θ_max.
    pub fn goal_angle(&self, axis: &RotationAxisCandidate, power: &[Isometry3<f64>; 2]) -> f64 {
        let near = power
            .iter()
            .map(|g| {
                let at = self.p_init * Point3::from(g.translation.vector);
                crate::poses::distance_to_line(&at, &axis.axis[0], &axis.axis[1])
            })
            .fold(f64::INFINITY, f64::min);
        let p = &self.scene.planner;
        ((FINGER_RISE / near.max(FINGER_RISE)).asin() + (p.extra_steps + 1) as f64 * p.step)
            .min(axis.theta_max.max(p.step))
    }

    /// The smallest arm–arm (or self) distance at the estimated goal (m), `None` when an arm
    /// has no collision-free IK solution there; `sup` is the arm that holds G_s, `power[arm]`
    /// each arm's grasp, `widths` the bars' widths at G_s, `power[0]`, `power[1]`.
    pub fn at_goal(
        &self,
        axis: &RotationAxisCandidate,
        support: &Isometry3<f64>,
        power: &[Isometry3<f64>; 2],
        widths: [f64; 3],
        sup: usize,
    ) -> Option<f64> {
        let theta = self.goal_angle(axis, power);
        let goal = axis.rotated_pose(&self.p_init, theta);
        let starts = [0, 1].map(|arm| self.scene.robots[arm].start);
        // The first collision-free IK solution (nearest the start first), the other arm at its
        // start, the gripper closed to `width` and allowed to touch the part.
        let ik = |arm: usize, grasp: &Isometry3<f64>, point: &Isometry3<f64>, width: f64| {
            let a = &self.arms[arm];
            let flange = a.base.inverse() * goal * grasp * point.inverse();
            distinct_ik(&*a.kin, &flange, &starts[arm])
                .into_iter()
                .find(|q| {
                    let mut state = WorldState::new(starts);
                    state.q[arm] = *q;
                    state.gripper[arm] = a.gripper.at_gap(width);
                    state.object = ObjectPlacement::Fixed(goal);
                    state.grasping[arm] = true;
                    self.cell.is_arm_free(arm, &state)
                })
        };
        let g = |arm: usize| &self.arms[arm].gripper;
        let master = 1 - sup;
        let q_master = ik(
            master,
            &power[master],
            &g(master).power_point(),
            widths[1 + master],
        )?;
        let q_sup_s = ik(sup, support, &g(sup).precision_point(), widths[0])?;
        let q_sup_p = ik(sup, &power[sup], &g(sup).power_point(), widths[1 + sup])?;
        let apart = |q_sup: &Joints| self.skeleton_distance(sup, q_sup, master, &q_master);
        Some(apart(&q_sup_s).min(apart(&q_sup_p)))
    }
}

impl GraspTests<'_> {
    /// The arm's skeleton in world: its joint origins (DH frames 1–6) and the tip of the
    /// gripper (the precision point).
    fn skeleton(&self, arm: usize, q: &Joints) -> [Point3<f64>; 7] {
        let a = &self.arms[arm];
        let frames = a.kin.fk_frames(q);
        let mut points = [Point3::origin(); 7];
        for (k, f) in frames.iter().skip(1).enumerate() {
            points[k] = a.base * Point3::from(f.translation.vector);
        }
        points[6] =
            a.base * frames[6] * Point3::from(a.gripper.precision_point().translation.vector);
        points
    }

    /// Smallest distance (m) between the two arms' skeletons (segments between their joint
    /// origins, out to the fingertips) in configurations `qa` of `a` and `qb` of `b`.
    fn skeleton_distance(&self, a: usize, qa: &Joints, b: usize, qb: &Joints) -> f64 {
        let (sa, sb) = (self.skeleton(a, qa), self.skeleton(b, qb));
        let mut best = f64::INFINITY;
        for u in sa.windows(2) {
            for v in sb.windows(2) {
                best = best.min(segment_segment_sq(&u[0], &u[1], &v[0], &v[1]));
            }
        }
        best.sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_margin_is_the_smallest_barycentric_coordinate() {
        let t = [
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(0.0, 1.0),
        ];
        assert!((barycentric_margin(t, Point2::new(0.25, 0.25)) - 0.25).abs() < 1e-12);
        assert!(barycentric_margin(t, Point2::new(1.0, 1.0)) < 0.0);
    }
}
