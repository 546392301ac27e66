//! The whole method: Algorithm 1 → 2 → 3 for every candidate, ranked into a plan file.
//!
//! Candidates are independent, so Algorithms 2 and 3 run over them in parallel (rayon); each
//! candidate's random choices come from its own seed ([`crate::paths::motion_seed`]) and results
//! are collected in candidate order, so the plan is the same for any thread count.
//!
//! One pass (`pass.rs`) plans the scene's power grasps seated by one rule ([`crate::seat`]);
//! [`plan`] tries the holds in turn until one carries the part: held at the fingertips, slid
//! towards the centre of mass, wrapped (`[planner] power_hold`). A pass whose plan may still
//! be replaced probes: it asks the carry check of every pose Algorithm 2 found, plans the
//! candidates whose power grasps carry the part first, and stops where none of them gets a
//! plan (the next hold is tried); the verdicts and those plans are reused by the rest of the
//! pass.

use std::sync::OnceLock;
use std::time::Instant;

use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::{PowerHold, Scene};

use crate::axes::RotationAxisCandidate;
use crate::error::PlanError;
use crate::hold::Unchecked;
use crate::seat::SeatRule;

mod pass;
#[cfg(test)]
mod recheck;

pub(crate) use pass::axes_of;
use pass::{plan_grasps_as_given, Built};

/// Settings of one `plan` run beyond the scene's `[planner]` table.
#[derive(Clone, Debug)]
pub struct PlanOptions {
    /// Keep at most this many plans (best first).
    pub max_plans: usize,
    /// Plan only these candidates (ids of Algorithm 1's list); the others are reported as
    /// skipped. `None`: every candidate. Re-planning uses it to keep a plan's candidate.
    pub only: Option<Vec<usize>>,
    /// `sup1` has already run: (supportive arm, its joints now). μ_rot must start there and
    /// that arm must be the supportive one ([`crate::replan`] `--from rot`).
    pub fixed_rot_start: Option<(usize, pregrasp_robot::Joints)>,
    /// Algorithm 3 runs over the candidates with a pose in waves of this many, best S_rot
    /// first (each wave in parallel); it stops once `max_plans` plans are kept whose scores
    /// are above every candidate not yet run, so no later one could be kept. The waves do not
    /// depend on the thread count: the plan file does not either.
    pub wave: usize,
    /// The part's geometry and gripper closings from an earlier context of the same part
    /// (object frame, so any pose): used when they fit the scene's mesh, grasps and tool
    /// points, built afresh otherwise. `replan` in a loop passes them.
    pub known: Option<std::sync::Arc<crate::context::PartKnowledge>>,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            max_plans: 3,
            only: None,
            fixed_rot_start: None,
            wave: DEFAULT_WAVE,
            known: None,
        }
    }
}

/// Candidates per wave of Algorithm 3 ([`PlanOptions::wave`]): a few more than the usual
/// `max_plans`, and a multiple of two cores.
pub const DEFAULT_WAVE: usize = 4;

pub use crate::outcome::CandidateOutcome;

impl PlanReport {
    /// Whether the carry check found that plan `k` of the file's power grasps lift the part
    /// (`true` also where it could not run: nothing says otherwise).
    pub fn carries(&self, k: usize) -> bool {
        let Some(candidate) = self.file.plans.get(k).map(|p| p.candidate) else {
            return false;
        };
        self.candidates
            .iter()
            .position(|c| c.id == candidate)
            .and_then(|i| self.outcomes.get(i))
            .is_none_or(|o| {
                !matches!(
                    o,
                    CandidateOutcome::Planned {
                        carry: Some(Err(_)),
                        ..
                    }
                )
            })
    }

    /// How close a grasping gripper comes to the support along plan `k` of the file (m), as
    /// the plan check measured it before the plan was kept.
    pub fn closest_grasp_to_support(&self, k: usize) -> Option<f64> {
        let candidate = self.file.plans.get(k)?.candidate;
        self.candidates
            .iter()
            .position(|c| c.id == candidate)
            .and_then(|i| match self.outcomes.get(i)? {
                CandidateOutcome::Planned {
                    closest_grasp_to_support,
                    ..
                } => *closest_grasp_to_support,
                _ => None,
            })
    }
}

/// The result of [`plan`]: the plan file plus per-candidate details for reports.
pub struct PlanReport {
    pub file: PlanFile,
    /// Why the plans carry no `physics` object (the mesh is not a closed solid), if so.
    pub physics_note: Option<Unchecked>,

    pub candidates: Vec<RotationAxisCandidate>,
    pub outcomes: Vec<CandidateOutcome>,
    /// Algorithm 1's convex hull of the part (object frame), for a viewer of the plan; `None`
    /// when the mesh has none.
    pub hull: Option<ConvexHull>,
}

/// Runs the pipeline on a loaded scene and mesh. `on_candidates` is told how many candidates
/// Algorithm 1 found; `progress` is called once per candidate finished (from worker threads).
///
/// Every plan is re-verified by a [`crate::check::PlanChecker`] (the rules of `check`) before it
/// is kept; a plan that fails (which would be a bug) is dropped and its candidate says which
/// rule failed. An error is a scene or mesh the planner cannot work on ([`PlanError`]).
///
/// Where no plan carries the part because the carry check finds the power grasps cannot, the
/// scene is planned again with them slid along their bars towards the centre of mass
/// ([`crate::slide`]: together, and after every hold's together, one at a time); that plan is
/// kept when it carries (`grasps.slid` says how far). A plan
/// that carries but leaves the weight hanging more than [`crate::slide::HANGING_ARM`] off the
/// line through the grasps gives way to the slid grasps' plan where that carries with a
/// shorter arm. With
/// `[planner] power_hold = "auto"`, grasps held at the fingertips ([`crate::seat`]) that
/// cannot carry the part, even slid, give way to the wraps ([`SeatRule::WRAPS`]), as given and
/// then slid. Where no hold carries the part, the plan is the last hold's grasps as given,
/// flagged by the carry check; where those get no plan at all, the first hold's.
pub fn plan(
    scene: &Scene,
    mesh: &Mesh,
    options: &PlanOptions,
    on_candidates: &(dyn Fn(usize) + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<PlanReport, PlanError> {
    let t0 = Instant::now();
    let hold = scene.planner.power_hold;
    let first = SeatRule::first_for(hold);
    // Every pass whose plan may still be replaced probes: it plans the candidates whose power
    // grasps carry the part first, and stops where none of them gets a plan.
    let (pass, built) = plan_grasps_as_given(
        scene,
        mesh,
        options,
        (None, first, true),
        on_candidates,
        progress,
    )?;
    // The grasps slid towards the centre of mass: one scene for every hold that asks.
    let slid = SlidGrasps::new(scene, mesh, &built);
    let (fingertips, first_report) = match pass {
        Pass::Planned(report) if !uncarried(&report.outcomes) => {
            return nearer_the_centre(options, &slid, first, *report).map(|r| with_total(r, t0));
        }
        Pass::Planned(report) => (report.file.grasps.fingertips.is_some(), Some(*report)),
        Pass::NoneCarries { fingertips } => (fingertips, None),
    };
    // The holds tried in turn until one carries: the first rule's grasps slid together; then,
    // for `"auto"` where the first held some grasp at the fingertips, the wraps, and the wraps
    // slid together; then each of them slid one at a time (`SlidGrasps`' second way): the
    // wraps that carry as given or slid together lift with less tilt in the replay than the
    // pinches slid alone (hand_hole_36: 0.04° and 5.2°). Where none carries, the last grasps
    // as given (the first's where those get no plan).
    let wraps = hold == PowerHold::Auto && fingertips;
    let mut tries = vec![(Some(0), first)];
    if wraps {
        tries.extend([(None, SeatRule::WRAPS), (Some(0), SeatRule::WRAPS)]);
    }
    tries.push((Some(1), first));
    if wraps {
        tries.push((Some(1), SeatRule::WRAPS));
    }
    // One try's pass: `None` where the grasps do not slide that way (no slid scene) or no
    // candidate whose grasps carry the part got a plan.
    let attempt =
        |(way, rule): (Option<usize>, SeatRule)| -> Result<Option<PlanReport>, PlanError> {
            let on = match way {
                Some(way) => match slid.get(way) {
                    Some((slid_scene, _)) => slid_scene,
                    None => return Ok(None),
                },
                None => scene,
            };
            let by = (Some(built.clone()), rule, true);
            let (pass, _) = plan_grasps_as_given(on, mesh, options, by, &|_| {}, &|| {})?;
            Ok(match pass {
                Pass::Planned(report) => Some(*report),
                Pass::NoneCarries { .. } => None,
            })
        };
    let mut fallback = (first_report, first);
    let mut ahead = None;
    for (k, &(way, rule)) in tries.iter().enumerate() {
        // With a second thread the next try runs beside this one: a pass's answer does not
        // depend on what runs beside it (the part's closings are remembered by pose, the rest
        // they share is read only), and where this one does not carry the next is needed.
        let report = match ahead.take() {
            Some(report) => report?,
            None if k + 1 < tries.len() && rayon::current_num_threads() > 1 => {
                let (this, next) = rayon::join(|| attempt(tries[k]), || attempt(tries[k + 1]));
                ahead = Some(next);
                this?
            }
            None => attempt(tries[k])?,
        };
        let shifts = way.and_then(|way| slid.get(way)).map(|(_, shifts)| shifts);
        if way.is_some() && shifts.is_none() {
            continue;
        }
        match (shifts, report) {
            (Some(shifts), Some(mut report))
                if !report.file.plans.is_empty() && !uncarried(&report.outcomes) =>
            {
                report.file.grasps.slid = Some(*shifts);
                return Ok(with_total(report, t0));
            }
            (None, Some(report)) if !uncarried(&report.outcomes) => {
                return nearer_the_centre(options, &slid, rule, report).map(|r| with_total(r, t0));
            }
            (None, report) => fallback = (report, rule),
            _ => {}
        }
    }
    let report = match fallback {
        (Some(report), _) => report,
        (None, rule) => {
            // The last hold's grasps as given, all candidates planned; where they get no plan
            // at all (the wraps' paths blocked), the first hold's: a plan the carry check
            // flags rather than none.
            let as_given = |rule: SeatRule| -> Result<PlanReport, PlanError> {
                let by = (Some(built.clone()), rule, false);
                match plan_grasps_as_given(scene, mesh, options, by, &|_| {}, &|| {})?.0 {
                    Pass::Planned(report) => Ok(*report),
                    Pass::NoneCarries { .. } => unreachable!("a pass that does not probe plans"),
                }
            };
            let last = as_given(rule)?;
            if last.file.plans.is_empty() && rule != first {
                let earlier = as_given(first)?;
                if earlier.file.plans.is_empty() {
                    last
                } else {
                    earlier
                }
            } else {
                last
            }
        }
    };
    Ok(with_total(report, t0))
}

/// `report` with `timing_ms.total`: the time since `t0`, every pass of [`plan`] counted.
fn with_total(mut report: PlanReport, t0: Instant) -> PlanReport {
    let total = t0.elapsed().as_secs_f64() * 1e3;
    report.file.timing_ms.insert("total".into(), total);
    report
}

/// The scene's power grasps slid along their bars towards the centre of mass
/// ([`crate::slide`]), with how far each slid: worked out when a hold first asks for them, then
/// kept for the others. Two ways, tried in this order: both slid together
/// ([`crate::slide::slide_together`]), and one at a time where together they do not slide the
/// whole way ([`crate::slide::slide_alone`]).
struct SlidGrasps<'a> {
    scene: &'a Scene,
    mesh: &'a Mesh,
    /// The part's geometry and the arm models, as the first pass built them.
    built: &'a Built,
    /// The centre of mass the carry check uses (uniform density: the mass does not move it),
    /// object frame; `None` without mass properties.
    com: Option<nalgebra::Point3<f64>>,
    together: OnceLock<Option<crate::slide::Together>>,
    /// The slid scenes and their shifts: together, one at a time.
    slid: [OnceLock<Option<SlidScene>>; SLID_WAYS],
}

/// A scene with its power grasps slid, and how far each slid (m).
type SlidScene = (Scene, [f64; 2]);

/// How many ways the grasps are slid ([`SlidGrasps`]).
const SLID_WAYS: usize = 2;

impl<'a> SlidGrasps<'a> {
    fn new(scene: &'a Scene, mesh: &'a Mesh, built: &'a Built) -> SlidGrasps<'a> {
        SlidGrasps {
            scene,
            mesh,
            built,
            com: pregrasp_physics::MassProperties::from_mesh(mesh)
                .ok()
                .map(|p| p.centroid),
            together: OnceLock::new(),
            slid: Default::default(),
        }
    }

    /// The grasps slid together, when sliding is worth a plan.
    fn together(&self) -> Option<&crate::slide::Together> {
        self.together
            .get_or_init(|| {
                let com = self.com?;
                let full = crate::slide::shifts_worth_trying(self.scene, &com)?;
                crate::slide::slide_together(self.scene, &self.built.part, &self.built.arms, full)
            })
            .as_ref()
    }

    /// The slid scene of the `way`-th way and its shifts, if that way slides them.
    fn get(&self, way: usize) -> Option<&SlidScene> {
        self.slid[way]
            .get_or_init(|| {
                let together = self.together()?;
                let shifts = match way {
                    0 => together.shifts?,
                    _ => {
                        let (part, arms) = (&self.built.part, &self.built.arms);
                        crate::slide::slide_alone(self.scene, part, arms, &self.com?, together)?
                    }
                };
                Some((crate::slide::slid_scene(self.scene, shifts), shifts))
            })
            .as_ref()
    }
}

/// `report` (a plan of the scene's grasps held by `rule` that carries the part), or the plan of
/// the grasps slid towards the centre of mass where its best plan leaves the weight hanging
/// more than [`crate::slide::HANGING_ARM`] off the line through them and the slid grasps'
/// plan carries the part with a shorter arm (`grasps.slid` says how far).
fn nearer_the_centre(
    options: &PlanOptions,
    slid: &SlidGrasps,
    rule: SeatRule,
    report: PlanReport,
) -> Result<PlanReport, PlanError> {
    let Some(com) = slid.com else {
        return Ok(report);
    };
    let arm = best_plan_arm(&report, &com);
    let Some(arm) = arm.filter(|&a| a > crate::slide::HANGING_ARM) else {
        return Ok(report);
    };
    // Each way the grasps slide, in turn, until one carries with a shorter arm.
    for way in 0..SLID_WAYS {
        let Some((on, shifts)) = slid.get(way) else {
            continue;
        };
        let by = (Some(slid.built.clone()), rule, true);
        let mut moved = match plan_grasps_as_given(on, slid.mesh, options, by, &|_| {}, &|| {})?.0 {
            Pass::Planned(moved) => *moved,
            Pass::NoneCarries { .. } => continue,
        };
        let carried = moved
            .outcomes
            .iter()
            .any(CandidateOutcome::planned_and_carried);
        let shorter = best_plan_arm(&moved, &com).is_some_and(|a| a < arm);
        if carried && !uncarried(&moved.outcomes) && shorter {
            moved.file.grasps.slid = Some(*shifts);
            return Ok(moved);
        }
    }
    Ok(report)
}

/// The moment arm (m) of the part's weight about the line through the power grasps at the best
/// plan's P_obj ([`crate::slide::weight_arm`]), the centre of mass at `com` (object frame);
/// `None` without a plan.
fn best_plan_arm(report: &PlanReport, com: &nalgebra::Point3<f64>) -> Option<f64> {
    let best = report.file.plans.first()?;
    let CandidateOutcome::Planned { pose, .. } = report.outcomes.get(best.candidate)? else {
        return None;
    };
    let power = report.file.grasps.power.each_ref().map(|g| g.to_isometry());
    Some(crate::slide::weight_arm(&pose.p_obj, &power, com))
}

/// What a pass of [`plan_grasps_as_given`] ends with.
enum Pass {
    /// The plan report.
    Planned(Box<PlanReport>),
    /// A probing pass stopped: no candidate whose power grasps carry the part at its P_obj
    /// got a plan (`fingertips`: the seating held some grasp at the fingertips).
    NoneCarries { fingertips: bool },
}

/// Whether no candidate's plan carries the part, and the carry check is why: some candidate
/// is refused by it ([`CandidateOutcome::Uncarried`]) or planned with power grasps it finds
/// cannot carry the part.
fn uncarried(outcomes: &[CandidateOutcome]) -> bool {
    outcomes.iter().any(CandidateOutcome::carry_refused)
        && !outcomes.iter().any(CandidateOutcome::planned_and_carried)
}
