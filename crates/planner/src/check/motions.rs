//! The motions of a plan against rules 2, 3 and 4: reaches and regrasps with their straight
//! lines, and the rotation about its axis.

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_model::Segment;
use pregrasp_robot::{GripperState, Joints};

use pregrasp_model::timeline::{lerp_joints, lerp_pose, CONTACT_ZONE};

use super::open::OpenAt;
use super::walk::{at, edge, grasp_error, pose_error, PlanCheck, Queued};
use super::{
    Rule, Transits, AXIS_MOTION_TOLERANCE, BELOW_SUPPORT_TOLERANCE, CHECK_RESOLUTION,
    FINE_CHECK_RESOLUTION, GRASP_POSITION_TOLERANCE, LINE_ANGLE_TOLERANCE, LINE_POSITION_TOLERANCE,
};

/// Which straight line a point of a reach/regrasp segment lies on, if any.
#[derive(Clone, Copy)]
struct Line {
    /// The tool pose at the end that touches the part (the grasp end).
    grasp_end: Isometry3<f64>,
}

/// Rule 4: a tool pose vs the straight line ending at `line.grasp_end`.
fn line_error(rule: &mut Rule, tool: &Isometry3<f64>, line: &Line, at: impl Fn() -> String) {
    let end = &line.grasp_end;
    let dir: Vector3<f64> = end.rotation * Vector3::z();
    let v = tool.translation.vector - end.translation.vector;
    let off = (v - dir * v.dot(&dir)).norm();
    let angle = tool.rotation.angle_to(&end.rotation);
    let worst = (off / LINE_POSITION_TOLERANCE).max(angle / LINE_ANGLE_TOLERANCE);
    rule.value(worst, 1.0, || {
        format!(
            "{}: {:.3} mm off the line, {:.4} rad",
            at(),
            off * 1e3,
            angle
        )
    });
}

impl<'a> PlanCheck<'a> {
    /// Rules 2 and 4 along a reach (`sup1`, `mas1`) or regrasp (`sup2`) segment.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn check_reach(
        &mut self,
        arm: usize,
        seg: &Segment,
        q: &[Joints; 2],
        gripper: &[GripperState; 2],
        holding: &[bool; 2],
        object: &Isometry3<f64>,
        precision: bool,
        goal: &Isometry3<f64>,
        closed: GripperState,
    ) {
        let index = self.index;
        let pts = &seg.points;
        let n = pts.len();
        let approach_from = seg.approach_from.unwrap_or(n - 1);
        let retreat_to = seg.retreat_to;
        let weights = self.arms[arm].joint_sweep_radii();
        // The retreat leaves the support grasp (precision point) the arm held at its first point.
        let retreat_line = retreat_to.map(|_| Line {
            grasp_end: self.tool(arm, &pts[0].q, true),
        });
        let approach_line = Line {
            grasp_end: self.tool(arm, &pts[n - 1].q, precision),
        };

        // Rule 4: the tool meets the grasp, and the stand-off is approach_distance back.
        let end = self.tool(arm, &pts[n - 1].q, precision);
        let (dp, da) = pose_error(&end, goal);
        grasp_error(self.grasps, dp, da, || {
            format!("{}: tool vs grasp", at(index, seg, n - 1))
        });
        let standoff = self.tool(arm, &pts[approach_from].q, precision);
        let d = (standoff.translation.vector - end.translation.vector).norm();
        let expected = self.set.settings.approach_distance;
        self.grasps
            .value((d - expected).abs() / GRASP_POSITION_TOLERANCE, 1.0, || {
                format!(
                    "{}: stand-off {:.2} mm from the grasp",
                    at(index, seg, approach_from),
                    d * 1e3
                )
            });

        // The straight lines may bring the gripper within millimetres of the support.
        let resolution = |k: usize| {
            let grasping_edge = k >= approach_from || retreat_to.is_some_and(|r| k < r);
            if grasping_edge {
                FINE_CHECK_RESOLUTION
            } else {
                CHECK_RESOLUTION
            }
        };
        // Edge k's end and the states checked on it: of a transit the planner proved
        // (`Transits::Proven`), its first state alone.
        let transit = retreat_to.unwrap_or(0)..approach_from;
        let transits = self.transits;
        let edge_of = |k: usize| {
            let (edge_end, steps) = edge(pts, k, &weights, resolution(k));
            match transits {
                Transits::Proven if transit.contains(&k) => {
                    (edge_end, usize::from(k == transit.start))
                }
                _ => (edge_end, steps),
            }
        };
        let total = (0..n).map(|k| edge_of(k).1).sum();
        let mut queue = Queued::with_capacity(total);
        // The flange (object frame) where the open hand was last judged, and its memo.
        let mut judged = (None, pregrasp_collision::OpenMemo::default());
        for k in 0..n {
            let (edge_end, steps) = edge_of(k);
            for s in 0..steps {
                let f = s as f64 / steps as f64;
                let qi = lerp_joints(&pts[k].q, &pts[edge_end].q, f);
                let mut all = *q;
                all[arm] = qi;
                let on_approach = k >= approach_from;
                let on_retreat = retreat_to.is_some_and(|r| edge_end <= r && (k < r || s == 0));
                let mut contact = *holding;
                contact[arm] = false;
                if on_approach {
                    let tool = self.tool(arm, &qi, precision);
                    line_error(self.grasps, &tool, &approach_line, || {
                        format!("{} (+{f:.2})", at(index, seg, k))
                    });
                    let dist = (tool.translation.vector
                        - approach_line.grasp_end.translation.vector)
                        .norm();
                    contact[arm] = dist <= CONTACT_ZONE + 1e-9;
                }
                if on_retreat {
                    let line = retreat_line.expect("retreat has a line");
                    let tool = self.tool(arm, &qi, true);
                    line_error(self.grasps, &tool, &line, || {
                        format!("{} (+{f:.2}) retreat", at(index, seg, k))
                    });
                    let dist = (tool.translation.vector - line.grasp_end.translation.vector).norm();
                    contact[arm] = contact[arm] || dist <= CONTACT_ZONE + 1e-9;
                }
                // Where the open hand may touch the part, it must not be in it; the last
                // point is the grasp, where the closing starts from the open hand.
                if contact[arm] || k == n - 1 {
                    let place = if k == n - 1 {
                        OpenAt::Grasp
                    } else if on_approach {
                        OpenAt::Approach
                    } else {
                        OpenAt::Retreat
                    };
                    self.open_hand(arm, &qi, object, place, &mut judged, || {
                        format!("{} (+{f:.2})", at(index, seg, k))
                    });
                }
                // The gripper closes at the last point.
                let mut grip = *gripper;
                if k == n - 1 {
                    grip[arm] = closed;
                    contact[arm] = true;
                }
                let state = self.state(all, grip, *object, contact);
                self.collide(state, (k, f), &mut queue);
            }
        }
        self.collide_all(arm, &queue, |k, f| {
            format!("plan {index} {} point {k} (+{f:.2})", seg.name)
        });
        self.check_closing(arm, seg, &pts[n - 1].q, precision);
    }

    /// Rules 2, 3 and 4 along `rot`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn check_rotation(
        &mut self,
        arm: usize,
        seg: &Segment,
        q: &[Joints; 2],
        gripper: &[GripperState; 2],
        holding: &[bool; 2],
        axis: &[Point3<f64>; 2],
        p_init: &Isometry3<f64>,
        g_s: &Isometry3<f64>,
    ) {
        let index = self.index;
        let pts = &seg.points;
        let n = pts.len();
        let weights = self.arms[arm].joint_sweep_radii();
        let support = self.set.support_height;
        let axis_band = self.set.settings.support_distance + self.set.lift + 0.001;
        let init_inv = p_init.inverse();
        let poses: Vec<Isometry3<f64>> = pts
            .iter()
            .map(|p| p.object_pose.expect("checked"))
            .collect();
        let (dp, da) = pose_error(&poses[0], p_init);
        grasp_error(self.grasps, dp, da, || {
            format!("plan {} rot: first object_pose vs P_init", index)
        });
        let total = (0..n)
            .map(|k| edge(pts, k, &weights, FINE_CHECK_RESOLUTION).1)
            .sum();
        let mut queue = Queued::with_capacity(total);
        for k in 0..n {
            // Rule 4: precision point on G_s at every point.
            let tool = self.tool(arm, &pts[k].q, true);
            let (dp, da) = pose_error(&tool, &(poses[k] * g_s));
            grasp_error(self.grasps, dp, da, || {
                format!("{}: tool vs object_pose·G_s", at(index, seg, k))
            });
            let (edge_end, steps) = edge(pts, k, &weights, FINE_CHECK_RESOLUTION);
            for s in 0..steps {
                let f = s as f64 / steps as f64;
                let object = lerp_pose(&poses[k], &poses[edge_end], f);
                // Rule 3: above the support, axis fixed and on the support.
                let lowest = self
                    .lowest_candidates
                    .iter()
                    .map(|v| (object * v).z)
                    .fold(f64::INFINITY, f64::min);
                let below = support - lowest;
                self.rotation.value(below, BELOW_SUPPORT_TOLERANCE, || {
                    format!(
                        "plan {} rot point {k} (+{f:.2}): part {:.2} mm below the support",
                        index,
                        below * 1e3
                    )
                });
                for (e, p) in axis.iter().enumerate() {
                    let moved = object * (init_inv * p);
                    let shift = (moved - p).norm();
                    self.rotation.value(shift, AXIS_MOTION_TOLERANCE, || {
                        format!(
                            "plan {} rot point {k} (+{f:.2}): axis end {e} moved {:.2} mm",
                            index,
                            shift * 1e3
                        )
                    });
                    let height = moved.z - support;
                    if height > axis_band {
                        self.rotation.fail(format!(
                            "plan {} rot point {k}: axis end {e} {:.2} mm above the support",
                            self.index,
                            height * 1e3
                        ));
                    }
                }
                let mut all = *q;
                all[arm] = lerp_joints(&pts[k].q, &pts[edge_end].q, f);
                let state = self.state(all, *gripper, object, *holding);
                self.collide(state, (k, f), &mut queue);
            }
        }
        self.collide_all(arm, &queue, |k, f| {
            format!("plan {index} rot point {k} (+{f:.2})")
        });
    }
}
