//! A realistic demo plan file, built from the robot's real FK/IK, for the viewer's tests and
//! the browser test (`cargo run -p pregrasp-viewer --example fixture_plan -- DIR`, which
//! includes this file).
//!
//! Scene: a 0.6 × 0.4 × 0.03 m plate (object frame at the centre of its bottom face) lying on
//! the support `z = 0`, lifted by 1 mm (P_init); two UR5e with 2F-85 grippers on the near
//! side (`y = −0.6`), "left" (robot 0, master) and "right" (robot 1, supportive). The plan
//! rotates the plate about its far bottom edge so its near edge rises (μ_rot), and both arms
//! end with power grasps on that edge. It is a fixture for drawing, not a checked plan: the
//! trajectories follow the segment rules of the plan format, but no collision test was run.

use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;

use nalgebra::{
    Isometry3, Matrix3, Point3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3,
};
use pregrasp_geometry::rotation::rotation_about_line;
use pregrasp_geometry::shapes::cuboid;
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{
    CandidateJson, GraspsJson, ObjectJson, Outcome, PlanFile, PlanJson, PlanStatus, PlannerJson,
    PointJson, PoseJson, RobotJson, RobotModel, RotationDirection, SceneRef, SegmentJson,
    SegmentName, PLAN_FORMAT,
};
use pregrasp_robot::{Gripper2F85, Joints, UrKinematics, UrModel, JOINT_NAMES};

/// Plate size (m): x, y, z.
pub const PLATE: [f64; 3] = [0.6, 0.4, 0.03];
/// P_init lift (m).
pub const LIFT: f64 = 0.001;
/// Stand-off distance before a straight approach (m).
pub const APPROACH: f64 = 0.05;
/// Joint speed used to time-stamp the fixture's points (rad/s).
const SPEED: f64 = 0.6;

/// A fixture could not be built (an IK target out of reach).
#[derive(Debug, thiserror::Error)]
pub enum FixtureError {
    #[error("fixture: no IK solution for {0}")]
    Unreachable(String),
}

/// The plate as a mesh in its object frame (12 triangles, welded corners).
pub fn plate_mesh() -> Mesh {
    let [x, y, z] = PLATE;
    cuboid(
        Point3::new(-x / 2.0, -y / 2.0, 0.0),
        Point3::new(x / 2.0, y / 2.0, z),
    )
}

/// The demo plan (status `planned`, two plans) with `object.mesh = mesh_path`.
pub fn demo_plan(mesh_path: &str) -> Result<PlanFile, FixtureError> {
    let mut plan = base_file(mesh_path);
    let setup = Setup::new(&plan);
    let first = build_plan(&setup, &plan.candidates[0], 0.7)?;
    plan.candidates[0].theta_goal = Some(0.7);
    plan.candidates[0].outcome = Outcome::Planned;
    plan.plans.push(first);
    // A second, lower-scored plan for the page's plan selector, when reachable.
    if let Ok(second) = build_plan(&setup, &plan.candidates[2], 0.45) {
        plan.candidates[2].theta_goal = Some(0.45);
        plan.candidates[2].outcome = Outcome::Planned;
        plan.plans.push(second);
    }
    plan.status = PlanStatus::Planned;
    Ok(plan)
}

/// The same scene with no plan: status `no_plan`, every candidate rejected.
pub fn no_plan(mesh_path: &str) -> PlanFile {
    let mut plan = base_file(mesh_path);
    plan.status = PlanStatus::NoPlan;
    plan.reason = Some("no candidate axis admits a collision-free pre-grasp pose".into());
    plan
}

/// Unit vectors of the grasp frames in the object frame: approach `z` tilted 45° down
/// towards +y, fingers closing along `x` (across the plate's thickness), `y` = object x.
fn grasp_rotation() -> UnitQuaternion<f64> {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let x = Vector3::new(0.0, s, s);
    let y = Vector3::new(1.0, 0.0, 0.0);
    let z = Vector3::new(0.0, s, -s);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(Matrix3::from_columns(
        &[x, y, z],
    )))
}

fn grasp(x: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, -PLATE[1] / 2.0 + 0.01, PLATE[2] / 2.0),
        grasp_rotation(),
    )
}

fn robot(name: &str, x: f64, start: Joints) -> RobotJson {
    let g = Gripper2F85::default();
    let base = Isometry3::from_parts(
        Translation3::new(x, -0.6, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -FRAC_PI_2),
    );
    RobotJson {
        name: name.into(),
        model: RobotModel::Builtin(UrModel::Ur5e),
        base: PoseJson::from(&base),
        joint_names: JOINT_NAMES.iter().map(|s| s.to_string()).collect(),
        start,
        precision_point: PoseJson::from(&g.precision_point()),
        power_point: PoseJson::from(&g.power_point()),
        urdf: None,
        gripper: None,
    }
}

/// Everything but the plans: robots, grasps and the 8 (edge, direction) candidates of the
/// plate's bottom face, best first.
fn base_file(mesh_path: &str) -> PlanFile {
    let home = [0.0, -1.9, 1.9, -1.6, -FRAC_PI_2, 0.0];
    let p_init = Isometry3::translation(0.0, 0.0, LIFT);
    PlanFile {
        format: PLAN_FORMAT.into(),
        scene: SceneRef {
            name: Some("viewer fixture: plate".into()),
            file: "fixture.toml".into(),
            file_from_plan: None,
        },
        status: PlanStatus::NoPlan,
        reason: None,
        support_height: 0.0,
        planner: PlannerJson {
            support_distance: 0.01,
            min_axis_length: 0.1,
            step_deg: 1.0,
            max_angle_deg: 90.0,
            weight_length: 1.0,
            weight_angle: 1.0,
            extra_steps: 5,
            min_grasp_axis_distance: 0.1,
            lift: LIFT,
            approach_distance: APPROACH,
            max_joint_step_deg: 10.0,
            seed: 0,
            link_clearance: None,
            finger_support_clearance: None,
            robustness_samples: None,
            power_hold: None,
            robustness_pos: None,
            robustness_yaw_deg: None,
        },
        object: ObjectJson {
            mesh: mesh_path.into(),
            mesh_from_plan: None,
            scale: 1.0,
            initial_pose: PoseJson::from(&p_init),
            mass: Some(4.5),
        },
        robots: vec![robot("left", -0.45, home), robot("right", 0.45, home)],
        grasps: GraspsJson {
            power: [PoseJson::from(&grasp(-0.2)), PoseJson::from(&grasp(0.2))],
            support: PoseJson::from(&grasp(0.1)),
            auto: None,
            seated: None,
            fingertips: None,
            centred: None,
            slid: None,
        },
        candidates: candidates(),
        plans: Vec::new(),
        timing_ms: BTreeMap::from([
            ("axes".to_string(), 0.1),
            ("paths".to_string(), 0.0),
            ("poses".to_string(), 0.0),
            ("total".to_string(), 0.1),
        ]),
    }
}

/// Bottom-face edges at P_init with both directions. The direction that lifts the plate
/// reaches φ_obj = 90°; the other is stopped by the lift: θ_max = asin(lift / w), w the
/// plate width across the edge.
fn candidates() -> Vec<CandidateJson> {
    use RotationDirection::{Ccw, Cw};
    let (hx, hy, z) = (PLATE[0] / 2.0, PLATE[1] / 2.0, LIFT);
    // (axis, direction that lifts, width across the edge)
    let edges = [
        ([[-hx, hy, z], [hx, hy, z]], Cw, PLATE[1]),
        ([[-hx, -hy, z], [hx, -hy, z]], Ccw, PLATE[1]),
        ([[-hx, -hy, z], [-hx, hy, z]], Cw, PLATE[0]),
        ([[hx, -hy, z], [hx, hy, z]], Ccw, PLATE[0]),
    ];
    let mut out = Vec::new();
    for lifting in [true, false] {
        for (axis, up, width) in edges {
            let length = (axis[1][0] - axis[0][0]).hypot(axis[1][1] - axis[0][1]);
            let (direction, theta_max) = if lifting {
                (up, FRAC_PI_2)
            } else {
                (if up == Cw { Ccw } else { Cw }, (LIFT / width).asin())
            };
            let outcome = Outcome::rejected(if lifting {
                "no collision-free pre-grasp pose"
            } else {
                "θ_max leaves no room for a power grasp"
            });
            out.push(CandidateJson {
                id: out.len(),
                axis,
                direction,
                length,
                theta_max,
                score: length + theta_max,
                theta_goal: None,
                outcome,
            });
        }
    }
    out
}

/// Kinematics and poses shared by every plan of the fixture.
struct Setup {
    kin: UrKinematics,
    bases: [Isometry3<f64>; 2],
    starts: [Joints; 2],
    precision: Isometry3<f64>,
    power: Isometry3<f64>,
    p_init: Isometry3<f64>,
    g_s: Isometry3<f64>,
    g_p: [Isometry3<f64>; 2],
}

impl Setup {
    fn new(plan: &PlanFile) -> Setup {
        let g = Gripper2F85::default();
        Setup {
            kin: UrKinematics::new(UrModel::Ur5e),
            bases: [
                plan.robots[0].base.to_isometry(),
                plan.robots[1].base.to_isometry(),
            ],
            starts: [plan.robots[0].start, plan.robots[1].start],
            precision: g.precision_point(),
            power: g.power_point(),
            p_init: plan.object.initial_pose.to_isometry(),
            g_s: plan.grasps.support.to_isometry(),
            g_p: [
                plan.grasps.power[0].to_isometry(),
                plan.grasps.power[1].to_isometry(),
            ],
        }
    }

    /// IK (nearest to `seed`) of a world flange pose for robot `r`.
    fn ik(
        &self,
        r: usize,
        flange_world: &Isometry3<f64>,
        seed: &Joints,
        what: &str,
    ) -> Result<Joints, FixtureError> {
        let local = self.bases[r].inverse() * flange_world;
        self.kin
            .ik_nearest(&local, seed)
            .ok_or_else(|| FixtureError::Unreachable(what.into()))
    }

    /// Straight tool motion from `a` to `b` (world flange poses, same orientation): `n`
    /// further points after `seed`'s configuration (which is at `a`).
    fn straight(
        &self,
        r: usize,
        a: &Isometry3<f64>,
        b: &Isometry3<f64>,
        n: usize,
        seed: Joints,
        what: &str,
    ) -> Result<Vec<Joints>, FixtureError> {
        let mut q = seed;
        let mut out = Vec::new();
        for k in 1..=n {
            let s = k as f64 / n as f64;
            let p = a.lerp_slerp(b, s);
            q = self.ik(r, &p, &q, what)?;
            out.push(q);
        }
        Ok(out)
    }
}

/// `n` further points linearly interpolated from `a` to `b` in joint space.
fn joint_path(a: &Joints, b: &Joints, n: usize) -> Vec<Joints> {
    (1..=n)
        .map(|k| {
            let s = k as f64 / n as f64;
            std::array::from_fn(|i| a[i] + (b[i] - a[i]) * s)
        })
        .collect()
}

/// Time stamps: each step takes its largest joint change at [`SPEED`] (at least 20 ms).
fn timed(qs: &[Joints], object: Option<&[Isometry3<f64>]>) -> Vec<PointJson> {
    let mut t = 0.0;
    qs.iter()
        .enumerate()
        .map(|(k, q)| {
            if k > 0 {
                let dq = (0..6)
                    .map(|i| (q[i] - qs[k - 1][i]).abs())
                    .fold(0.0, f64::max);
                t += (dq / SPEED).max(0.02);
            }
            PointJson {
                t,
                q: *q,
                object_pose: object.map(|o| PoseJson::from(&o[k])),
            }
        })
        .collect()
}

/// `pose` moved back by `d` along its own z axis (the stand-off before an approach).
fn backed_off(pose: &Isometry3<f64>, d: f64) -> Isometry3<f64> {
    pose * Translation3::new(0.0, 0.0, -d)
}

/// One plan for `cand` with final rotation θ_goal = `theta_goal`: master = left (robot 0),
/// supportive = right (robot 1).
fn build_plan(s: &Setup, cand: &CandidateJson, theta_goal: f64) -> Result<PlanJson, FixtureError> {
    let (mas, sup) = (0, 1);
    let a0 = Point3::from(cand.axis[0]);
    let d = Point3::from(cand.axis[1]) - a0;
    let axis = Unit::new_normalize(d * cand.direction.sign());
    let object_at = |theta: f64| rotation_about_line(&a0, &axis, theta) * s.p_init;
    let p_obj = object_at(theta_goal);

    // sup1: start → stand-off → straight in to G_s at P_init.
    let grasp0 = s.p_init * s.g_s * s.precision.inverse();
    let stand = backed_off(&grasp0, APPROACH);
    let q_stand = s.ik(sup, &stand, &s.starts[sup], "sup1 stand-off")?;
    let mut sup1 = vec![s.starts[sup]];
    sup1.extend(joint_path(&s.starts[sup], &q_stand, 12));
    let approach_sup1 = sup1.len() - 1;
    sup1.extend(s.straight(sup, &stand, &grasp0, 5, q_stand, "sup1 approach")?);

    // rot: the precision point follows object_pose · G_s while the plate turns about the axis.
    let n_rot = 14;
    let poses: Vec<Isometry3<f64>> = (0..=n_rot)
        .map(|k| object_at(theta_goal * k as f64 / n_rot as f64))
        .collect();
    let mut rot = vec![*sup1.last().expect("sup1 has points")];
    for pose in &poses[1..] {
        let q = s.ik(
            sup,
            &(pose * s.g_s * s.precision.inverse()),
            rot.last().unwrap(),
            "rot",
        )?;
        rot.push(q);
    }

    // mas1: start → stand-off → straight in to G_p,master at P_obj.
    let power_m = p_obj * s.g_p[mas] * s.power.inverse();
    let stand_m = backed_off(&power_m, APPROACH);
    let q_stand_m = s.ik(mas, &stand_m, &s.starts[mas], "mas1 stand-off")?;
    let mut mas1 = vec![s.starts[mas]];
    mas1.extend(joint_path(&s.starts[mas], &q_stand_m, 12));
    let approach_mas1 = mas1.len() - 1;
    mas1.extend(s.straight(mas, &stand_m, &power_m, 5, q_stand_m, "mas1 approach")?);

    // sup2: open, retreat straight back, move to the stand-off of G_p,sup, straight in.
    let held = p_obj * s.g_s * s.precision.inverse();
    let q_held = *rot.last().unwrap();
    let retreat = backed_off(&held, APPROACH);
    let mut sup2 = vec![q_held];
    sup2.extend(s.straight(sup, &held, &retreat, 5, q_held, "sup2 retreat")?);
    let retreat_to = sup2.len() - 1;
    let power_s = p_obj * s.g_p[sup] * s.power.inverse();
    let stand_s = backed_off(&power_s, APPROACH);
    let q_ret = *sup2.last().unwrap();
    let q_stand_s = s.ik(sup, &stand_s, &q_ret, "sup2 stand-off")?;
    sup2.extend(joint_path(&q_ret, &q_stand_s, 10));
    let approach_sup2 = sup2.len() - 1;
    sup2.extend(s.straight(sup, &stand_s, &power_s, 5, q_stand_s, "sup2 approach")?);

    let names = ["left", "right"];
    let segment = |name: SegmentName, r: usize, points, retreat_to, approach_from| SegmentJson {
        name,
        robot: names[r].into(),
        kind: name.kind(),
        grasp: name.grasp(),
        retreat_to,
        approach_from,
        grip_width: None,
        grip_force: None,
        fingers: None,
        pad_contact: None,
        points,
    };
    Ok(PlanJson {
        candidate: cand.id,
        score: cand.score,
        master: names[mas].into(),
        supportive: names[sup].into(),
        object_goal_pose: PoseJson::from(&p_obj),
        segments: vec![
            // A pinch force for the panel's line of grip forces (the browser test reads it).
            SegmentJson {
                grip_force: Some(40.0),
                ..segment(
                    SegmentName::Sup1,
                    sup,
                    timed(&sup1, None),
                    None,
                    Some(approach_sup1),
                )
            },
            segment(SegmentName::Rot, sup, timed(&rot, Some(&poses)), None, None),
            segment(
                SegmentName::Mas1,
                mas,
                timed(&mas1, None),
                None,
                Some(approach_mas1),
            ),
            segment(
                SegmentName::Sup2,
                sup,
                timed(&sup2, None),
                Some(retreat_to),
                Some(approach_sup2),
            ),
        ],
        physics: None,
        robustness: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_plan_tool_meets_the_grasps() {
        let plan = demo_plan("plate.stl").expect("fixture is reachable");
        assert_eq!(plan.status, PlanStatus::Planned);
        let s = Setup::new(&plan);
        let p = &plan.plans[0];
        let names: Vec<&str> = p.segments.iter().map(|g| g.name.as_str()).collect();
        assert_eq!(names, ["sup1", "rot", "mas1", "sup2"]);
        // Every rot point: precision point = object_pose · G_s (plan-format rule 4).
        for pt in &p.segments[1].points {
            let flange = s.bases[1] * s.kin.fk(&pt.q);
            let want = pt.object_pose.as_ref().unwrap().to_isometry() * s.g_s;
            let got = flange * s.precision;
            assert!((got.translation.vector - want.translation.vector).norm() < 1e-6);
            assert!(got.rotation.angle_to(&want.rotation) < 1e-6);
        }
        // mas1 ends at the master's power grasp on the part at P_obj.
        let last = p.segments[2].points.last().unwrap();
        let got = s.bases[0] * s.kin.fk(&last.q) * s.power;
        let want = p.object_goal_pose.to_isometry() * s.g_p[0];
        assert!((got.translation.vector - want.translation.vector).norm() < 1e-6);
        // Times strictly increase from 0 in every segment.
        for seg in &p.segments {
            assert_eq!(seg.points[0].t, 0.0);
            assert!(seg.points.windows(2).all(|w| w[1].t > w[0].t));
        }
    }

    #[test]
    fn candidates_follow_the_lift_closed_form() {
        let c = candidates();
        assert_eq!(c.len(), 8);
        assert!(c.windows(2).all(|w| w[0].score >= w[1].score));
        let small = c
            .iter()
            .find(|c| c.length > 0.5 && c.theta_max < 0.1)
            .unwrap();
        assert!((small.theta_max.sin() * PLATE[1] - LIFT).abs() < 1e-12);
    }
}
