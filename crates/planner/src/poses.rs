//! Algorithm 2 of the paper: object poses for power grasping.
//!
//! For one rotation-axis candidate λ (with its direction and θ_max):
//! 1. `DistRotPow`: the distances d_g1, d_g2 of the power grasps G_p1, G_p2 from the axis line;
//!    the candidate is skipped when either is within Δd_a (`min_grasp_axis_distance`).
//! 2. Gripper dummies — the housing and the fingers in every pose of their real closing on the
//!    bar ([`pregrasp_collision::Grip`]) — sit at both power grasps and rotate with the part in
//!    steps of Δφ until neither comes within the finger–support clearance (plus the planning
//!    margin) of the support, then n_ext further steps, each still clear. That pose is P_obj,
//!    the angle θ_goal. Never beyond θ_max.
//! 3. Roles (§V-B): `robot[0]` is the master R_mas if d_g1 > d_g2 (+1 µm), otherwise `robot[1]`.
//! 4. IK: every collision-free solution of each arm at its power grasp on the part at P_obj
//!    (C_IK^p), and of the supportive arm's precision point at G_s (C_IK^s), whose closing at
//!    P_init must clear the support as the dummies do.

use nalgebra::Isometry3;
use pregrasp_collision::GripFailure;
use pregrasp_robot::GripperState;

use crate::axes::RotationAxisCandidate;
use crate::context::{IkSet, PlanningContext, FINE_PLANNING_MARGIN};
use crate::dummies::lowest_point;

/// Tolerance on d_g1 > d_g2 when choosing the master arm (plan-format.md).
pub const ROLE_TOLERANCE: f64 = 1e-6;

/// What Algorithm 2 found for one candidate (one element of the paper's set Ω).
#[derive(Clone, Debug)]
pub struct PowerGraspPose {
    /// θ_goal: rotation from P_init to P_obj (rad, ≥ 0, a multiple of Δφ).
    pub theta_goal: f64,
    /// P_obj: the object's world pose at θ_goal.
    pub p_obj: Isometry3<f64>,
    /// d_g1, d_g2: distances of the power grasps from the axis line (m).
    pub grasp_axis_distance: [f64; 2],
    /// Index of R_mas.
    pub master: usize,
    /// Index of R_sup.
    pub supportive: usize,
    /// C_IK^p: IK solutions of each arm at its power grasp at P_obj (collision-free ones:
    /// [`IkSet::free`]; each set has at least one).
    pub power_ik: [IkSet; 2],
    /// C_IK^s: IK solutions of the supportive arm at G_s at P_obj (at least one free).
    pub support_ik: IkSet,
}

/// Why Algorithm 2 found no pose for a candidate.
#[derive(Clone, Debug, PartialEq)]
pub enum PoseRejection {
    /// A power grasp lies within Δd_a of the axis line.
    GraspNearAxis { arm: usize, distance: f64 },
    /// The dummies still touch the support at θ_max (or the n_ext extra steps do not fit);
    /// `fingers`: at the last angle tried it is the closing fingers, not the housing, that
    /// reach the support.
    DummiesNeverClear { theta_max: f64, fingers: bool },
    /// No collision-free IK solution for `arm` at its power grasp at P_obj.
    PowerGraspUnreachable { arm: usize },
    /// No collision-free IK solution for the supportive arm at G_s at P_obj.
    SupportGraspUnreachable { arm: usize },
    /// The fingers of the supportive arm, closing on G_s at P_init, come within the
    /// finger–support clearance of the support (`height` above it, m).
    SupportClosingMeetsSupport { arm: usize, height: f64 },
    /// The gripper of `arm` cannot close on the part at a grasp (`support`: G_s, else its
    /// power grasp).
    CannotClose {
        arm: usize,
        support: bool,
        failure: GripFailure,
    },
}

impl PoseRejection {
    /// The words of the plan file's `outcome` (after `"rejected: "`), naming the arms by
    /// `names`.
    pub fn named<'a>(&'a self, names: &'a [String; 2]) -> impl std::fmt::Display + 'a {
        NamedRejection(self, names)
    }
}

struct NamedRejection<'a>(&'a PoseRejection, &'a [String; 2]);

impl std::fmt::Display for NamedRejection<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names = self.1;
        match self.0 {
            PoseRejection::GraspNearAxis { arm, distance } => write!(
                f,
                "power grasp of arm {} is {:.3} m from the axis, within Δd_a",
                names[*arm], distance
            ),
            PoseRejection::DummiesNeverClear {
                theta_max,
                fingers: true,
            } => write!(
                f,
                "the power grasps' closing fingers reach the support at every angle up to θ_max \
                 = {:.1}° (gripper dummies)",
                theta_max.to_degrees()
            ),
            PoseRejection::DummiesNeverClear {
                theta_max,
                fingers: false,
            } => write!(
                f,
                "gripper dummies do not clear the support within θ_max = {:.1}°",
                theta_max.to_degrees()
            ),
            PoseRejection::PowerGraspUnreachable { arm } => write!(
                f,
                "IK: power grasp unreachable for arm {} at P_obj",
                names[*arm]
            ),
            PoseRejection::SupportGraspUnreachable { arm } => write!(
                f,
                "IK: support grasp unreachable for arm {} at P_obj",
                names[*arm]
            ),
            PoseRejection::SupportClosingMeetsSupport { arm, height } if *height < 0.0 => write!(
                f,
                "support grasp of arm {}: its closing fingers reach {:.1} mm into the support \
                 at P_init",
                names[*arm],
                -height * 1e3
            ),
            PoseRejection::SupportClosingMeetsSupport { arm, height } => write!(
                f,
                "support grasp of arm {}: its closing fingers come within {:.1} mm of the support \
                 at P_init",
                names[*arm],
                height * 1e3
            ),
            PoseRejection::CannotClose {
                arm,
                support,
                failure,
            } => write!(
                f,
                "{} grasp of arm {}: {failure}",
                if *support { "support" } else { "power" },
                names[*arm]
            ),
        }
    }
}

/// Distance of point `p` from the infinite line through `a` and `b`.
pub fn distance_to_line(
    p: &nalgebra::Point3<f64>,
    a: &nalgebra::Point3<f64>,
    b: &nalgebra::Point3<f64>,
) -> f64 {
    let d = (b - a).normalize();
    let v = p - a;
    (v - d * v.dot(&d)).norm()
}

/// Runs Algorithm 2 for one candidate.
pub fn object_pose_for_power_grasp(
    ctx: &PlanningContext,
    candidate: &RotationAxisCandidate,
) -> Result<PowerGraspPose, PoseRejection> {
    let params = &ctx.scene.planner;
    let grasps = &ctx.scene.grasps;

    // DistRotPow: distances of the power grasp origins (world, at P_init) from the axis line.
    let mut d = [0.0; 2];
    for (arm, dist) in d.iter_mut().enumerate() {
        let g = ctx.p_init * grasps.power[arm];
        let p = nalgebra::Point3::from(g.translation.vector);
        *dist = distance_to_line(&p, &candidate.axis[0], &candidate.axis[1]);
    }
    for (arm, &distance) in d.iter().enumerate() {
        if distance <= params.min_grasp_axis_distance {
            return Err(PoseRejection::GraspNearAxis { arm, distance });
        }
    }

    // Both power grasps must close on the part (a property of the grasps and the mesh).
    let mut power_grips = Vec::with_capacity(2);
    for (arm, grip) in ctx.grips.power.iter().enumerate() {
        match grip {
            Ok(grip) => power_grips.push(grip),
            Err(failure) => {
                return Err(PoseRejection::CannotClose {
                    arm,
                    support: false,
                    failure: *failure,
                })
            }
        }
    }

    // RotObjDummy: rotate part + dummies in steps of Δφ until the dummies clear the support,
    // then n_ext further steps that must stay clear.
    // The dummy is the gripper's housing plus its fingers in every pose they pass through
    // while closing on the part there (the adaptive closing: the finger tips may curl under a
    // bar and rise again, so the deepest pose need not be the last). They are grasping, so they
    // keep the finger–support clearance.
    let housing: [Vec<_>; 2] = [0, 1].map(|arm| {
        let g = &ctx.arm(arm).gripper;
        let mut shapes = g.shapes(GripperState::Open);
        shapes.truncate(g.static_count());
        shapes
    });
    let clearance = params.finger_support_clearance + FINE_PLANNING_MARGIN;
    let limit = ctx.scene.support_height + clearance;
    // Per arm at `theta`: (housing clear, closing fingers clear).
    let dummies = |theta: f64| -> [(bool, bool); 2] {
        let pose = candidate.rotated_pose(&ctx.p_init, theta);
        [0, 1].map(|arm| {
            let flange = pose * grasps.power[arm] * ctx.arm(arm).gripper.power_point().inverse();
            (
                lowest_point(&housing[arm], &flange) > limit,
                power_grips[arm].clears(&flange, limit),
            )
        })
    };
    // The same test, stopping at the first dummy that does not clear (housing first: cheaper).
    let dummies_clear = |theta: f64| {
        let pose = candidate.rotated_pose(&ctx.p_init, theta);
        (0..2).all(|arm| {
            let flange = pose * grasps.power[arm] * ctx.arm(arm).gripper.power_point().inverse();
            lowest_point(&housing[arm], &flange) > limit && power_grips[arm].clears(&flange, limit)
        })
    };
    let step = params.step;
    let max_steps = (candidate.theta_max / step + 1e-9).floor() as usize;
    let mut theta_goal = None;
    let mut clear_run = 0usize;
    for k in 1..=max_steps {
        let theta = k as f64 * step;
        if dummies_clear(theta) {
            clear_run += 1;
            if clear_run > params.extra_steps as usize {
                theta_goal = Some(theta);
                break;
            }
        } else {
            clear_run = 0;
        }
    }
    let Some(theta_goal) = theta_goal else {
        let last = dummies(max_steps as f64 * step);
        let fingers = last.iter().all(|&(h, _)| h) && last.iter().any(|&(_, f)| !f);
        return Err(PoseRejection::DummiesNeverClear {
            theta_max: candidate.theta_max,
            fingers,
        });
    };
    let p_obj = candidate.rotated_pose(&ctx.p_init, theta_goal);

    // Roles: the arm whose power grasp is farther from the axis is the master.
    let (master, supportive) = if d[0] > d[1] + ROLE_TOLERANCE {
        (0, 1)
    } else {
        (1, 0)
    };

    // IKSolPow: every collision-free solution of each arm at its power grasp on the part at P_obj,
    // gripper closed on the part (contact with the part allowed).
    let power_ik = [0, 1].map(|arm| {
        let tool = p_obj * grasps.power[arm] * ctx.arm(arm).gripper.power_point().inverse();
        ctx.free_ik(arm, &tool, &p_obj, ctx.power_grip(arm))
    });
    for (arm, solutions) in power_ik.iter().enumerate() {
        if solutions.none_free(ctx) {
            return Err(PoseRejection::PowerGraspUnreachable { arm });
        }
    }
    // IKSolSup: the supportive arm's precision point at G_s on the part at P_obj.
    let support_grip = match &ctx.grips.support[supportive] {
        Ok(grip) => grip,
        Err(failure) => {
            return Err(PoseRejection::CannotClose {
                arm: supportive,
                support: true,
                failure: *failure,
            })
        }
    };
    // The support grasp closes at P_init, where the part lies on the support: its fingers keep
    // the finger–support clearance in every pose of the closing.
    let flange =
        ctx.p_init * grasps.support * ctx.arm(supportive).gripper.precision_point().inverse();
    let above = support_grip.lowest(&flange) - ctx.scene.support_height;
    if above <= clearance {
        return Err(PoseRejection::SupportClosingMeetsSupport {
            arm: supportive,
            height: above,
        });
    }
    let tool = p_obj * grasps.support * ctx.arm(supportive).gripper.precision_point().inverse();
    let support_ik = ctx.free_ik(supportive, &tool, &p_obj, ctx.support_grip(supportive));
    if support_ik.none_free(ctx) {
        return Err(PoseRejection::SupportGraspUnreachable { arm: supportive });
    }

    Ok(PowerGraspPose {
        theta_goal,
        p_obj,
        grasp_axis_distance: d,
        master,
        supportive,
        power_ik,
        support_ik,
    })
}
