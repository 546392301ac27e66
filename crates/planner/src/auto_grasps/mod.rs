//! `[grasps] mode = "auto"`: the grasps found from the mesh (the paper's future work, §VII).
//!
//! 1. [`bars`]: where the arms' grippers can close across the part from above (bar sites), for
//!    the dimensions of both hands ([`hand`]: the 2F-85's linkage, or a jaw gripper's parts).
//! 2. Grasp sets, per rotation axis of Algorithm 1 (the best [`AXES_CONSIDERED`] by S_rot):
//!    two power grasps from representative sites beyond Δd_a (+2 cm), at least
//!    [`POWER_SPREAD`] apart, scored by their distances from the axis plus their spread (a
//!    stable hold; both on the far side, so one rotation frees both); each arm takes the one
//!    nearer its base, and the arm whose grasp is nearer the axis will support. The support
//!    grasp G_s is a fingertip pinch across the site farthest from the axis (the far side,
//!    where the pinch lifts the part with the most leverage) at least [`GRIPPER_SPACING`] from
//!    the master's power grasp (both are held at once), with the fingertips
//!    [`SUPPORT_TIP_HEIGHT`] above the support. Power grasps sit at mid-height, fingers across
//!    the bar, from above.
//!    Only sites the fully open hand fits around (the real finger geometry,
//!    [`crate::open_fingers`], and the whole hand, palm included, nowhere more than 0.5 mm
//!    inside the whole part along the last 20 mm of the approach) take a grasp. A set loses
//!    rank for material near its power grasps' sites along the bar ([`JUNCTION_WEIGHT`]):
//!    sites away from junctions first.
//! 3. Cheap ranking ([`cheap`]): sets by how many cheap tests they fail — IK at P_init, the
//!    open fingers' approach clearance, the pinch's balance (centre of mass inside the
//!    triangle of the axis' ends and G_s) — then by the axis' S_rot plus the power grasps'
//!    distances from the axis; then, in that order until the first batches are filled, the
//!    goal test (collision-free IK of the three grasps at an estimated θ_goal, the arms'
//!    skeletons [`GOAL_ARM_CLEARANCE`] apart): sets failing it go last.
//! 4. The sets go through the whole pipeline in batches of 1, 2, 4 ([`FIRST_BATCHES`]), then
//!    [`SETS_PLANNED`] (in parallel, results in set order) until a batch has a plan; the plan
//!    with the best score in that batch wins (ties: the earlier set). Deterministic.

pub mod bars;
pub mod cheap;
pub mod hand;

use std::cell::RefCell;

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, UnitQuaternion};
use parry3d_f64::shape::TriMesh;
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{AutoGraspsJson, PlanStatus};
use pregrasp_io::scene::{AutoGrasps, Scene};
use rayon::prelude::*;

use crate::axes::{rotation_axis_candidates, RotationAxisCandidate};
use crate::context::{arm_models, distinct_ik};
use crate::error::{check_mesh, PlanError};
use crate::output::plan_file_header;
use crate::pipeline::{plan, PlanOptions, PlanReport};
use crate::poses::{distance_to_line, ROLE_TOLERANCE};
use bars::{bar_sites, BarSite, Slab, JUNCTION_REACH};
use cheap::GraspTests;
use hand::BarHand;
use pregrasp_collision::CollisionError;

/// Rotation axes (best S_rot first) around which grasp sets are built.
pub const AXES_CONSIDERED: usize = 4;
/// Power-grasp pairs tried per axis.
pub const PAIRS_PER_AXIS: usize = 6;
/// Representative sites (far from the axis, at least [`REPRESENTATIVE_SPACING`] apart) from
/// which power-grasp pairs are made.
pub const MAX_REPRESENTATIVES: usize = 14;
pub const REPRESENTATIVE_SPACING: f64 = 0.05;
/// Smallest distance (m) between the two power grasps: the part is held at two places.
pub const POWER_SPREAD: f64 = 0.20;
/// Grasp sets planned in full at a time (in parallel) once the first batches
/// ([`FIRST_BATCHES`]) had no plan; the next batch only when none planned.
pub const SETS_PLANNED: usize = 6;
/// The first batches' sizes: the best-tested set alone, then the next two, then four.
pub const FIRST_BATCHES: [usize; 3] = [1, 2, 4];
/// Smallest distance (m) between the centres of two grasps held at the same time.
pub const GRIPPER_SPACING: f64 = 0.16;
/// Height (m) of the pinching fingertips above the support at G_s.
pub const SUPPORT_TIP_HEIGHT: f64 = 0.003;
/// Smallest distance (m) between the arms' skeletons (joint origins to fingertips) at the
/// estimated goal for a set without doubt: two link radii (~5 cm each) and a margin.
pub const GOAL_ARM_CLEARANCE: f64 = 0.15;
/// Smallest barycentric margin of the centre of mass in the triangle (axis ends, G_s).
pub const COM_MARGIN: f64 = 0.05;
/// Width (m) the goal test closes a pinned grasp's fingers to (its bar is not measured).
pub const PINNED_WIDTH: f64 = 0.04;
/// What a set's rank loses (m per m) for each metre of bar a power grasp's site lacks beyond
/// the fingers' sides, up to [`JUNCTION_REACH`]: among the sets kept (the pairs by their
/// distances and spread alone), those with sites away from junctions, where the closing meets
/// no other material, are tried first.
pub const JUNCTION_WEIGHT: f64 = 2.0;

/// One choice of the three grasps (object frame).
#[derive(Clone, Debug, PartialEq)]
pub struct GraspSet {
    pub support: Isometry3<f64>,
    pub power: [Isometry3<f64>; 2],
    /// Bar widths across support, `power[0]`, `power[1]` (m; 0 for a pinned grasp).
    pub widths: [f64; 3],
    /// The Algorithm 1 candidate the set was built around.
    pub axis: usize,
    /// The arm that holds G_s (Algorithm 2's supportive arm: its power grasp is nearer the
    /// axis).
    pub supportive: usize,
    /// All three grasps have IK solutions at P_init.
    pub reachable: bool,
    /// How many of the cheap tests the set fails (IK at P_init, the open fingers' approach
    /// clearance, IK and arm–arm clearance at the goal, the pinch's balance; [`cheap`]).
    pub doubts: usize,
    /// S_rot of the axis + distances of the power grasps from it (m).
    pub rank: f64,
}

/// The grasp frame of a site: `x` across the bar, `z` down along `−up`, origin at `height`
/// above the part's bottom on the site's vertical.
fn site_pose(site: &BarSite, slab: &Slab, height: f64) -> Isometry3<f64> {
    let x = site.across.into_inner();
    let z = -slab.up.into_inner();
    let y = z.cross(&x);
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    let mid = (slab.bottom + slab.top) / 2.0;
    let origin = site.centre + slab.up.into_inner() * (slab.bottom + height - mid);
    Isometry3::from_parts(
        origin.coords.into(),
        UnitQuaternion::from_rotation_matrix(&rot),
    )
}

/// The open fingers at a site: (straddle the bar, approach clear).
type FingerTest = (bool, bool);

/// A test of a site per arm, computed once.
struct Memo<'f> {
    cache: RefCell<Vec<[Option<FingerTest>; 2]>>,
    f: &'f dyn Fn(usize, usize) -> (bool, bool),
}

impl<'f> Memo<'f> {
    fn new(n: usize, f: &'f dyn Fn(usize, usize) -> (bool, bool)) -> Self {
        Memo {
            cache: RefCell::new(vec![[None; 2]; n]),
            f,
        }
    }

    fn get(&self, i: usize, arm: usize) -> (bool, bool) {
        if let Some(r) = self.cache.borrow()[i][arm] {
            return r;
        }
        let r = (self.f)(i, arm);
        self.cache.borrow_mut()[i][arm] = Some(r);
        r
    }
}

/// The grasp sets of `scene` (whose grasps may be placeholders) for the sites found, best
/// first: sets whose grasps the open fingers cannot straddle are left out; the others are
/// ordered by how many cheap tests ([`cheap`]) they fail, then by rank.
pub fn grasp_sets(
    scene: &Scene,
    slab: &Slab,
    sites: &[BarSite],
    axes: &[RotationAxisCandidate],
    tests: &GraspTests,
    p_init: &Isometry3<f64>,
) -> Result<Vec<GraspSet>, PlanError> {
    // A scene with hand-placed grasps pins none here: every grasp is searched.
    let pins = scene.grasps.auto.unwrap_or(AutoGrasps {
        support_pinned: false,
        power_pinned: false,
    });
    let arms = arm_models(scene)?;
    let hands = [0, 1].map(|arm| BarHand::of(&arms[arm].gripper));
    // How far the fingertips reach below the precision point, the deeper of the two hands.
    let tip_depth = |w: f64| {
        (0..2)
            .map(|arm| hands[arm].tip_z(w) - arms[arm].gripper.precision_point_z())
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let support_height = |w: f64| {
        // Rounded up to 0.1 mm: the tips never end lower than SUPPORT_TIP_HEIGHT.
        ((SUPPORT_TIP_HEIGHT + tip_depth(w)) * 1e4).ceil() / 1e4
    };
    let min_axis = scene.planner.min_grasp_axis_distance + 0.02;
    let reachable = |arm: usize, grasp: &Isometry3<f64>, point: &Isometry3<f64>| {
        let flange = arms[arm].base.inverse() * p_init * grasp * point.inverse();
        !distinct_ik(&*arms[arm].kin, &flange, &scene.robots[arm].start).is_empty()
    };
    let world = |s: &BarSite| p_init * s.centre;
    let base = |arm: usize| Point3::from(arms[arm].base.translation.vector);
    let power_pose = |i: usize| site_pose(&sites[i], slab, slab.height() / 2.0);
    let support_pose = |i: usize| site_pose(&sites[i], slab, support_height(sites[i].width));
    // The open hand at a site, per arm (its gripper and tool point): (fits, approach clear).
    let power_fn =
        |i: usize, arm: usize| tests.fingers(arm, &power_pose(i), &arms[arm].gripper.power_point());
    let support_fn = |i: usize, arm: usize| {
        tests.fingers(arm, &support_pose(i), &arms[arm].gripper.precision_point())
    };
    let power_fingers = Memo::new(sites.len(), &power_fn);
    let support_fingers = Memo::new(sites.len(), &support_fn);
    // Arms with the same gripper and tool point share one test.
    let same = |p: fn(&pregrasp_robot::Gripper) -> Isometry3<f64>| {
        let (a, b) = (&arms[0].gripper, &arms[1].gripper);
        a.shape_key() == b.shape_key() && p(a) == p(b)
    };
    let (power_same, support_same) = (
        same(pregrasp_robot::Gripper::power_point),
        same(pregrasp_robot::Gripper::precision_point),
    );
    let power_fingers =
        |i: usize, arm: usize| power_fingers.get(i, if power_same { 0 } else { arm });
    let support_fingers =
        |i: usize, arm: usize| support_fingers.get(i, if support_same { 0 } else { arm });
    let mut sets = Vec::new();
    for axis in axes.iter().take(AXES_CONSIDERED) {
        let dist = |s: &BarSite| distance_to_line(&world(s), &axis.axis[0], &axis.axis[1]);
        let mut order: Vec<usize> = (0..sites.len()).collect();
        order.sort_by(|&a, &b| dist(&sites[b]).total_cmp(&dist(&sites[a])).then(a.cmp(&b)));
        let apart = |a: usize, b: &Point3<f64>| (sites[a].centre - b).norm();
        // Power grasps: pairs of representative sites (far from the axis, on different parts
        // of the part, straddled by the open fingers), scored by their distances from the
        // axis plus their spread.
        // (site, site, score, junction penalty).
        let pairs: Vec<(usize, usize, f64, f64)> = if pins.power_pinned {
            vec![(usize::MAX, usize::MAX, 0.0, 0.0)]
        } else {
            // Sites whose approach is clear too first; the others only if too few are.
            let mut reps: Vec<usize> = Vec::new();
            for need_clear in [true, false] {
                for &i in order.iter().filter(|&&i| dist(&sites[i]) >= min_axis) {
                    if reps.len() >= MAX_REPRESENTATIVES || (!need_clear && reps.len() >= 2) {
                        break;
                    }
                    let spaced = reps
                        .iter()
                        .all(|&r| apart(i, &sites[r].centre) >= REPRESENTATIVE_SPACING);
                    if !spaced || reps.contains(&i) {
                        continue;
                    }
                    let [a, b] = [0, 1].map(|arm| power_fingers(i, arm));
                    if a.0 && b.0 && (!need_clear || (a.1 && b.1)) {
                        reps.push(i);
                    }
                }
            }
            let mut pairs = Vec::new();
            for (k, &a) in reps.iter().enumerate() {
                for &b in &reps[k + 1..] {
                    let spread = apart(a, &sites[b].centre);
                    if spread >= POWER_SPREAD {
                        let junction = |i: usize| {
                            JUNCTION_WEIGHT * (JUNCTION_REACH - sites[i].clear_along).max(0.0)
                        };
                        let score = dist(&sites[a]) + dist(&sites[b]) + 0.5 * spread.min(0.5);
                        pairs.push((a, b, score, junction(a) + junction(b)));
                    }
                }
            }
            pairs.sort_by(|x, y| y.2.total_cmp(&x.2).then((x.0, x.1).cmp(&(y.0, y.1))));
            pairs.truncate(PAIRS_PER_AXIS);
            pairs
        };
        for &(a, b, pair_score, junction) in &pairs {
            let (power, widths_p, clear_p) = if pins.power_pinned {
                (scene.grasps.power, [0.0, 0.0], true)
            } else {
                // Each arm takes the grasp nearer its base.
                let d = |arm: usize, i: usize| (base(arm) - world(&sites[i])).norm();
                let (i0, i1) = if d(0, a) + d(1, b) <= d(0, b) + d(1, a) {
                    (a, b)
                } else {
                    (b, a)
                };
                let clear = power_fingers(i0, 0).1 && power_fingers(i1, 1).1;
                (
                    [power_pose(i0), power_pose(i1)],
                    [sites[i0].width, sites[i1].width],
                    clear,
                )
            };
            let power_dist = |g: &Isometry3<f64>| {
                distance_to_line(
                    &(p_init * Point3::from(g.translation.vector)),
                    &axis.axis[0],
                    &axis.axis[1],
                )
            };
            // Roles as Algorithm 2 gives them: the master holds the grasp farther from the axis
            // (arm 1 unless arm 0's is farther by more than ROLE_TOLERANCE), the other supports.
            let sup = if power_dist(&power[0]) > power_dist(&power[1]) + ROLE_TOLERANCE {
                1
            } else {
                0
            };
            let master_at = Point3::from(power[1 - sup].translation.vector);
            // G_s: the site farthest from the axis that leaves room for the master's gripper
            // and that the open fingers straddle; one that balances the part on the pinch
            // ([`COM_MARGIN`]) first.
            let (support, support_w, clear_s) = if pins.support_pinned {
                (scene.grasps.support, 0.0, true)
            } else {
                let fits =
                    |i: usize| apart(i, &master_at) >= GRIPPER_SPACING && support_fingers(i, sup).0;
                let balanced = |i: usize| tests.com_margin(axis, &support_pose(i)) >= COM_MARGIN;
                let clear = |i: usize| support_fingers(i, sup).1;
                let Some(&i) = order
                    .iter()
                    .find(|&&i| fits(i) && balanced(i) && clear(i))
                    .or_else(|| order.iter().find(|&&i| fits(i) && clear(i)))
                    .or_else(|| order.iter().find(|&&i| fits(i) && balanced(i)))
                    .or_else(|| order.iter().find(|&&i| fits(i)))
                else {
                    continue;
                };
                (support_pose(i), sites[i].width, support_fingers(i, sup).1)
            };
            let ok = (0..2)
                .all(|arm| reachable(arm, &power[arm], &arms[arm].gripper.power_point()))
                && reachable(sup, &support, &arms[sup].gripper.precision_point());
            let widths = [support_w, widths_p[0], widths_p[1]];
            let doubts = [
                !ok,
                !(clear_p && clear_s),
                tests.com_margin(axis, &support) < COM_MARGIN,
            ];
            let set = GraspSet {
                support,
                power,
                widths,
                axis: axis.id,
                supportive: sup,
                reachable: ok,
                doubts: doubts.iter().filter(|&&d| d).count(),
                rank: axis.score + pair_score - junction,
            };
            if !sets
                .iter()
                .any(|s: &GraspSet| s.support == set.support && s.power == set.power)
            {
                sets.push(set);
            }
        }
    }
    // Fewest failed cheap tests first, then by rank; stable for equal keys.
    sets.sort_by(|a, b| a.doubts.cmp(&b.doubts).then(b.rank.total_cmp(&a.rank)));
    // The goal test (IK with collisions, arm–arm distance) in that order until the first
    // batches are filled with sets that pass it; those that fail it go last.
    let wanted: usize = FIRST_BATCHES.iter().sum();
    let (mut passed, mut failed) = (Vec::new(), Vec::new());
    let mut rest = sets.into_iter();
    while passed.len() < wanted {
        let Some(mut set) = rest.next() else {
            break;
        };
        let axis = axes
            .iter()
            .find(|a| a.id == set.axis)
            .expect("the set's axis");
        let widths = set.widths.map(|w| if w > 0.0 { w } else { PINNED_WIDTH });
        let goal = tests.at_goal(axis, &set.support, &set.power, widths, set.supportive);
        if goal.is_some_and(|c| c >= GOAL_ARM_CLEARANCE) {
            passed.push(set);
        } else {
            set.doubts += 1;
            failed.push(set);
        }
    }
    passed.extend(rest);
    passed.extend(failed);
    Ok(passed)
}

/// The pipeline on an auto scene: grasps found, the best few sets planned, the best plan kept.
/// On a scene with hand-placed grasps it is [`plan`]. An error is a scene or mesh the planner
/// cannot work on.
pub fn plan_auto(
    scene: &Scene,
    mesh: &Mesh,
    options: &PlanOptions,
    on_candidates: &(dyn Fn(usize) + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<PlanReport, PlanError> {
    let Some(pins) = scene.grasps.auto else {
        return plan(scene, mesh, options, on_candidates, progress);
    };
    check_mesh(mesh)?;
    let t0 = std::time::Instant::now();
    let arms = arm_models(scene)?;
    let [h0, h1] = [0, 1].map(|arm| BarHand::of(&arms[arm].gripper));
    let hand = BarHand::both(&h0, &h1);
    let (slab, sites) = bar_sites(mesh, &scene.object.pose, &hand);
    let axes = rotation_axis_candidates(
        mesh,
        &scene.object.pose,
        scene.support_height,
        &scene.planner,
    );
    let t_sites = t0.elapsed().as_secs_f64() * 1e3;
    let sets = if sites.is_empty() && !(pins.power_pinned && pins.support_pinned) {
        Vec::new()
    } else {
        let part = TriMesh::new(mesh.vertices.clone(), mesh.triangles.clone())
            .map_err(|e| PlanError::Mesh(CollisionError::Mesh(e)))?;
        let tests = GraspTests::new(scene, mesh, &part, &arms, axes.p_init);
        grasp_sets(scene, &slab, &sites, &axes.candidates, &tests, &axes.p_init)?
    };
    let t_sets = t0.elapsed().as_secs_f64() * 1e3 - t_sites;
    let summary =
        |tried: usize, planned: usize, chosen: Option<usize>, widths: [f64; 3]| AutoGraspsJson {
            sites: sites.len(),
            sets: sets.len(),
            tried,
            planned,
            chosen,
            widths,
            support_pinned: pins.support_pinned,
            power_pinned: pins.power_pinned,
        };
    if sets.is_empty() {
        let reason = if sites.is_empty() {
            format!(
                "no graspable bar: nowhere on the part (height {:.0} mm) can the grippers close \
                 across {:.0}–{:.0} mm of material with room for the open fingers on both sides",
                slab.height() * 1e3,
                bars::MIN_BAR_WIDTH * 1e3,
                hand.max_bar_width() * 1e3,
            )
        } else {
            format!(
                "no grasp set: {} bar sites, but no two power grasps {:.0} mm apart and farther \
                 than Δd_a from any of the best {AXES_CONSIDERED} rotation axes",
                sites.len(),
                GRIPPER_SPACING * 1e3
            )
        };
        let mut file = plan_file_header(scene, PlanStatus::NoPlan, Some(reason));
        file.candidates = axes
            .candidates
            .iter()
            .map(RotationAxisCandidate::to_json)
            .collect();
        file.grasps.auto = Some(summary(0, 0, None, [0.0; 3]));
        file.timing_ms
            .insert("total".into(), t0.elapsed().as_secs_f64() * 1e3);
        return Ok(PlanReport {
            file,
            physics_note: None,
            candidates: axes.candidates,
            outcomes: Vec::new(),
            hull: (!axes.hull.vertices.is_empty()).then_some(axes.hull),
        });
    }
    // Batches of 1, 2, 4, then SETS_PLANNED sets, in order, until a batch has a plan.
    on_candidates(sets.len());
    let mut reports: Vec<PlanReport> = Vec::new();
    let mut from = 0;
    for size in FIRST_BATCHES
        .into_iter()
        .chain(std::iter::repeat(SETS_PLANNED))
    {
        if from >= sets.len() {
            break;
        }
        let batch = &sets[from..(from + size).min(sets.len())];
        from += batch.len();
        let planned: Vec<PlanReport> = batch
            .par_iter()
            .map(|set| {
                let mut s = scene.clone();
                s.grasps.support = set.support;
                s.grasps.power = set.power;
                let r = plan(&s, mesh, options, &|_| {}, &|| {});
                progress();
                r
            })
            .collect::<Result<_, PlanError>>()?;
        reports.extend(planned);
        // A set whose plan the power grasps carry ends the search; one that only plans does
        // once every set has been tried.
        if reports.iter().any(|r| r.carries(0)) {
            break;
        }
    }
    let tried = &sets[..reports.len()];
    // The best plan among the sets whose power grasps carry the part, else among all.
    let best = (0..reports.len())
        .filter(|&k| !reports[k].file.plans.is_empty())
        .max_by(|&a, &b| {
            let score = |k: usize| reports[k].file.plans[0].score;
            let carries = |k: usize| reports[k].carries(0);
            carries(a)
                .cmp(&carries(b))
                .then(score(a).total_cmp(&score(b)))
                .then(b.cmp(&a))
        });
    let planned = reports.iter().filter(|r| !r.file.plans.is_empty()).count();
    let k = best.unwrap_or(0);
    let mut report = reports.into_iter().nth(k).expect("at least one set");
    let file = &mut report.file;
    file.grasps.auto = Some(summary(tried.len(), planned, best, tried[k].widths));
    if best.is_none() {
        file.reason = Some(format!(
            "auto grasps: none of the {} grasp sets tried planned (best set: {})",
            tried.len(),
            file.reason.clone().unwrap_or_default()
        ));
    }
    file.timing_ms.insert("auto_sites".into(), t_sites);
    file.timing_ms.insert("auto_sets".into(), t_sets);
    file.timing_ms
        .insert("total".into(), t0.elapsed().as_secs_f64() * 1e3);
    Ok(report)
}
