//! The check of one plan of a plan set: every state of its `rot` segment as a quasi-static
//! problem ([`crate::statics`]), the worst state, and the grip force to set.

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_model::{Plan, PlanSet, Segment, SegmentName};

use crate::error::PhysicsError;
use crate::grip_force::{min_grip_force_from, WarmStart};
use crate::part_mass::PartMass;
use crate::plan_report::{
    ClosingForce, GripWarning, PlanPhysics, StateReport, StateStatus, Verdict,
};
use crate::settings::{PhysicsSettings, GRAVITY};
use crate::statics::{Pads, StaticOutcome, StaticProblem};
use crate::twist::twist_arm;

/// Support contacts are the rotation axis' endpoints (at each state's pose) that lie at most
/// this far (m) from the support plane, beyond the plan's `lift` (P_init hovers `lift` above it).
pub const SUPPORT_CONTACT_TOLERANCE: f64 = 0.001;

/// How far (m) a point of the part that rests on the support slides along it while it stays
/// there during `rot`, if more than [`SLIDE_TOLERANCE`]: kinematics alone, whatever the forces.
/// A rotation about the part's real edge keeps the edge's points where they are; a rotation
/// about a line off the edge drags them over the table.
fn edge_slide(
    rot: &Segment,
    plan: usize,
    part: &PartMass,
    support: f64,
    above_max: f64,
) -> Result<Option<f64>, PhysicsError> {
    let states = rot_states(rot, plan, 4)?;
    // Per hull vertex: where it first touched the support (x, y), while it still does.
    let mut touch: Vec<Option<(f64, f64)>> = vec![None; part.hull.len()];
    let mut worst: f64 = 0.0;
    for s in &states {
        for (v, anchor) in part.hull.iter().zip(touch.iter_mut()) {
            let w = s.pose * v;
            if w.z - support > above_max {
                *anchor = None;
                continue;
            }
            match anchor {
                None => *anchor = Some((w.x, w.y)),
                Some((x, y)) => worst = worst.max((w.x - *x).hypot(w.y - *y)),
            }
        }
    }
    Ok((worst > SLIDE_TOLERANCE).then_some(worst))
}

/// A point resting on the support that moves farther than this along it slides (m).
pub const SLIDE_TOLERANCE: f64 = 0.001;

/// One state of `rot` before it is checked.
struct State {
    point: Option<usize>,
    t: f64,
    pose: Isometry3<f64>,
}

fn rot_states(seg: &Segment, plan: usize, substeps: usize) -> Result<Vec<State>, PhysicsError> {
    let mut poses = Vec::with_capacity(seg.points.len());
    for (i, p) in seg.points.iter().enumerate() {
        let pose = p
            .object_pose
            .ok_or(PhysicsError::NoObjectPose { plan, point: i })?;
        poses.push((p.t, pose));
    }
    let mut states = Vec::new();
    for (i, &(t, pose)) in poses.iter().enumerate() {
        if i > 0 {
            let (t0, p0) = poses[i - 1];
            for s in 1..=substeps {
                let f = s as f64 / (substeps + 1) as f64;
                states.push(State {
                    point: None,
                    t: t0 + f * (t - t0),
                    pose: p0.lerp_slerp(&pose, f),
                });
            }
        }
        states.push(State {
            point: Some(i),
            t,
            pose,
        });
    }
    Ok(states)
}

/// Checks plan `plan_index` of `set`: every point of its `rot` segment, plus
/// `settings.substeps` interpolated states in each interval between neighbouring points where
/// the worst state may lie (all of them with `settings.refine_all`).
pub fn analyse_plan(
    set: &PlanSet,
    plan_index: usize,
    part: &PartMass,
    settings: &PhysicsSettings,
) -> Result<PlanPhysics, PhysicsError> {
    analyse(set, plan_index, part, settings, false)
}

/// [`analyse_plan`] for a yes-or-no answer: it stops at the first point of `rot` that cannot
/// be held (the part slides at the support, no grip force holds it, or the force it needs
/// with the safety factor is more than the gripper's most), and that state is the report's
/// last and worst one — the rotation is refused from there on, whatever follows. A rotation
/// that hangs on the pads' twist (a geometric measure over all its states, [`crate::twist`])
/// is refused for it after its first point's state. A rotation with neither gets the whole
/// analysis, the same report as [`analyse_plan`]'s.
pub fn screen_plan(
    set: &PlanSet,
    plan_index: usize,
    part: &PartMass,
    settings: &PhysicsSettings,
) -> Result<PlanPhysics, PhysicsError> {
    analyse(set, plan_index, part, settings, true)
}

fn analyse(
    set: &PlanSet,
    plan_index: usize,
    part: &PartMass,
    settings: &PhysicsSettings,
    stop_at_failure: bool,
) -> Result<PlanPhysics, PhysicsError> {
    let plan = set.plans.get(plan_index).ok_or(PhysicsError::NoSuchPlan {
        index: plan_index,
        count: set.plans.len(),
    })?;
    run(set, plan, plan_index, part, settings, stop_at_failure)
}

/// [`screen_plan`] of `plan` as the plan numbered `plan_index` of `set` (whose own `plans` are
/// not read; only its candidates, object, support grasp, support height and lift): the planner
/// asks about one rotation at a time, `plan` holding its `rot` segment alone.
pub fn screen_one(
    set: &PlanSet,
    plan: &Plan,
    plan_index: usize,
    part: &PartMass,
    settings: &PhysicsSettings,
) -> Result<PlanPhysics, PhysicsError> {
    run(set, plan, plan_index, part, settings, true)
}

/// [`analyse_plan`] of `plan`, as [`screen_one`] reads it.
pub fn analyse_one(
    set: &PlanSet,
    plan: &Plan,
    plan_index: usize,
    part: &PartMass,
    settings: &PhysicsSettings,
) -> Result<PlanPhysics, PhysicsError> {
    run(set, plan, plan_index, part, settings, false)
}

fn run(
    set: &PlanSet,
    plan: &Plan,
    plan_index: usize,
    part: &PartMass,
    settings: &PhysicsSettings,
    stop_at_failure: bool,
) -> Result<PlanPhysics, PhysicsError> {
    let rot = plan
        .segment(SegmentName::Rot)
        .ok_or(PhysicsError::NoRotation { plan: plan_index })?;
    let candidate = set
        .candidates
        .iter()
        .find(|c| c.id == plan.candidate)
        .ok_or(PhysicsError::NoCandidate {
            plan: plan_index,
            id: plan.candidate,
        })?;
    let p_init_inv = set.object.initial_pose.inverse();
    // The axis endpoints as points of the part (object frame): they move with it.
    let axis_obj = candidate.axis.map(|a| p_init_inv * a);
    let g_s = set.grasps.support;
    let width = rot.closing.width.unwrap_or(0.0).max(0.0);
    let weight = part.mass * GRAVITY;
    // Where the pads really bear on the part (the plan's `pad_contact`, from the closing on the
    // mesh): the contacts sit there, and each resists a twist as its patch does (unless the
    // settings give a torsion radius of their own). Without it: at the precision point, as
    // points.
    let contact = rot.closing.pad_contact;
    let mut model = settings.contact_model();
    if model.pad_torsion_radius <= 0.0 {
        model.pad_torsion_radius = contact.map_or(0.0, |c| c.torsion_radius);
    }
    let h = set.support_height;
    let above_max = set.lift.max(0.0) + SUPPORT_CONTACT_TOLERANCE;
    // Where the pads bear on the part with the part at `pose` (world frame).
    let pads_centre = |pose: &Isometry3<f64>| {
        let tool = pose * g_s;
        contact.map_or(Point3::from(tool.translation.vector), |c| {
            tool * Point3::from(c.center)
        })
    };

    // Each state starts its solver from the optimum of the state before it along `rot`.
    let solve = |s: &State, warm: &mut WarmStart| -> Result<StateReport, PhysicsError> {
        let support: Vec<Point3<f64>> = axis_obj
            .iter()
            .map(|a| s.pose * a)
            .filter(|p| {
                let above = p.z - h;
                (-SUPPORT_CONTACT_TOLERANCE..=above_max).contains(&above)
            })
            .collect();
        let tool = s.pose * g_s;
        let problem = StaticProblem {
            com: s.pose * part.centroid,
            weight,
            pads: Pads {
                centre: pads_centre(&s.pose),
                closing_axis: tool.rotation * Vector3::x(),
                width_axis: tool.rotation * Vector3::y(),
                width,
            },
            support,
        };
        let outcome =
            min_grip_force_from(&problem, &model, warm).map_err(|error| PhysicsError::Solver {
                plan: plan_index,
                t: s.t,
                error,
            })?;
        let theta_deg = (s.pose * p_init_inv).rotation.angle().to_degrees();
        let base = StateReport {
            point: s.point,
            t: s.t,
            theta_deg,
            support_contacts: problem.support.len(),
            status: StateStatus::Held,
            n_min: None,
            support_normal: None,
            support_tangential: None,
            support_friction_use: None,
            pad_friction_use: None,
            equilibrium: None,
        };
        Ok(match outcome {
            StaticOutcome::Held(eq) => StateReport {
                n_min: Some(eq.grip_force),
                support_normal: Some(eq.support_normal_total()),
                support_tangential: Some(eq.support_tangential_total()),
                support_friction_use: Some(eq.support_friction_use(model.mu_support)),
                equilibrium: Some(eq),
                ..base
            },
            StaticOutcome::Slides => StateReport {
                status: StateStatus::Slides,
                ..base
            },
            StaticOutcome::CannotHold => StateReport {
                status: StateStatus::CannotHold,
                ..base
            },
        })
    };

    // The plan's own points first; then `substeps` states inside every interval where the worst
    // can hide: next to a local maximum of N_min, or where the status or the number of support
    // contacts changes between its ends (N_min is smooth in θ elsewhere) — not between two
    // states that fail the same way. `refine_all` refines every interval.
    let all = rot_states(rot, plan_index, settings.substeps)?;
    let stride = settings.substeps + 1;
    // The twist arm over every state (`crate::twist`): the part hanging from a pinch nearer
    // the axis than its centre of mass, on the pads' twist. Geometry alone: a screening that
    // finds it too long refuses the rotation for it after the first point's state.
    let twist = all
        .iter()
        .map(|s| {
            let axis = axis_obj.map(|a| s.pose * a);
            let closing = (s.pose * g_s).rotation * Vector3::x();
            twist_arm(axis, s.pose * part.centroid, pads_centre(&s.pose), closing)
        })
        .fold(0.0, f64::max);
    let hangs = twist > settings.max_twist_arm;
    let (_, most) = settings.grip_force;
    let mut at_points = Vec::new();
    let mut warm = WarmStart::default();
    // The start each interval's states take: the optimum at the point that opens it.
    let mut warm_at_points = Vec::new();
    // A screening stops at the first point that cannot be held: none holds it, or the grip it
    // needs with the safety factor is more than the gripper's most.
    let mut stopped = false;
    for s in all.iter().step_by(stride) {
        let report = solve(s, &mut warm)?;
        warm_at_points.push(warm.clone());
        let failed = report.status != StateStatus::Held
            || report
                .n_min
                .is_some_and(|n| settings.safety_factor * n > most);
        at_points.push(report);
        if stop_at_failure && (failed || hangs) {
            stopped = true;
            break;
        }
    }
    let n = at_points.len();
    let force = |i: usize| at_points[i].n_min.unwrap_or(f64::INFINITY);
    let local_max =
        |i: usize| (i == 0 || force(i) >= force(i - 1)) && (i + 1 == n || force(i) >= force(i + 1));
    let refine = |k: usize| {
        // interval k lies between points k and k + 1
        let (a, b) = (&at_points[k], &at_points[k + 1]);
        // Between two states that both fail in the same way the verdict is known already.
        let both_fail = a.status == b.status && a.status != StateStatus::Held;
        settings.refine_all
            || a.status != b.status
            || (!both_fail
                && (a.support_contacts != b.support_contacts || local_max(k) || local_max(k + 1)))
    };
    // Stopped at a failure: that state decides, nothing between the points is needed.
    let refined: Vec<bool> = (0..n.saturating_sub(1))
        .map(|k| !stopped && refine(k))
        .collect();
    let mut states = Vec::with_capacity(all.len());
    for (k, report) in at_points.into_iter().enumerate() {
        states.push(report);
        if refined.get(k) == Some(&true) {
            let mut warm = warm_at_points[k].clone();
            for s in &all[k * stride + 1..(k + 1) * stride] {
                states.push(solve(s, &mut warm)?);
            }
        }
    }

    let severity = |s: &StateReport| match s.status {
        StateStatus::CannotHold => 2,
        StateStatus::Slides => 1,
        StateStatus::Held => 0,
    };
    let worst = (0..states.len())
        .max_by(|&a, &b| {
            let (sa, sb) = (&states[a], &states[b]);
            severity(sa)
                .cmp(&severity(sb))
                .then(sa.n_min.unwrap_or(0.0).total_cmp(&sb.n_min.unwrap_or(0.0)))
        })
        .unwrap_or(0);
    let all_held = states.iter().all(|s| s.status == StateStatus::Held);
    let n_max = all_held.then(|| states.iter().filter_map(|s| s.n_min).fold(0.0, f64::max));
    let required = n_max.map(|n| settings.safety_factor * n);
    let (lo, hi) = settings.grip_force;
    let verdict = match (states.get(worst).map(|s| s.status), required) {
        (Some(StateStatus::CannotHold), _) => Verdict::CannotHold,
        (Some(StateStatus::Slides), _) => Verdict::SlidesAtSupport,
        (_, Some(r)) if r > hi => Verdict::CannotHold,
        _ => Verdict::Holds,
    };
    let recommended = match (verdict, required) {
        (Verdict::Holds, Some(r)) => Some(r.clamp(lo, hi)),
        _ => None,
    };
    let squeeze = recommended.unwrap_or(hi);
    for s in &mut states {
        if let Some(eq) = &s.equilibrium {
            s.pad_friction_use = Some(eq.pad_friction_use(&model, squeeze));
        }
    }

    let mut warnings = Vec::new();
    let mut verdict = verdict;
    let mut recommended = recommended;
    if verdict == Verdict::Holds && hangs {
        verdict = Verdict::LiftsOffSupport;
        warnings.push(GripWarning::HangsOnTwist {
            arm: twist,
            max: settings.max_twist_arm,
        });
    }
    if let Some(slide) = edge_slide(rot, plan_index, part, h, above_max)? {
        verdict = Verdict::SlidesAtSupport;
        recommended = None;
        warnings.push(GripWarning::EdgeSlides { distance: slide });
    }
    let off = states.iter().filter(|s| s.support_contacts == 0).count();
    if off > 0 {
        warnings.push(GripWarning::NoSupportContact {
            states: off,
            of: states.len(),
            within: above_max,
        });
    }
    let one = states.iter().filter(|s| s.support_contacts == 1).count();
    if one > 0 {
        warnings.push(GripWarning::OneSupportContact {
            states: one,
            of: states.len(),
        });
    }
    if rot.closing.width.is_none() {
        warnings.push(GripWarning::NoGripWidth);
    }

    Ok(PlanPhysics {
        plan: plan_index,
        candidate: plan.candidate,
        part: part.clone(),
        settings: *settings,
        arm: rot.arm,
        grip_width: width,
        states,
        worst,
        n_max,
        required,
        recommended,
        verdict,
        twist_arm: twist,
        warnings,
        closings: plan
            .segments
            .iter()
            .filter(|seg| seg.kind.closes_at_end())
            .map(|seg| ClosingForce {
                segment: seg.name,
                arm: seg.arm,
                grasp: seg.grasp,
                grip_force: plan.closing_force(seg),
            })
            .collect(),
        stopped_at_failure: stopped,
    })
}
