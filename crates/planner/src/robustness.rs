//! Robustness to placement error (issue 16): Monte-Carlo over where the part really lies.
//!
//! For every error level (position in the table plane ±`pos`, yaw ±`yaw` about the vertical
//! through the part's bounding-box centre, both uniform), `samples` poses are drawn; at each the
//! whole pipeline plans the part again (as the cell re-plans from a measured pose,
//! [`crate::replan`]). Per sample: did any plan come out, did the nominal plan's rotation axis
//! (the same hull edge and sense, [`crate::replan::matching_candidate`]) plan again, why not,
//! and how close the best plan's grasping gripper comes to the table (re-checked). Samples run
//! in parallel; each draws from its own generator seeded by (seed, level, sample), and results
//! are collected in order, so the report is the same for any thread count.

use std::collections::BTreeMap;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{
    CandidateJson, Outcome, PlanFile, RobustnessJson, RobustnessLevelJson,
};
use pregrasp_io::scene::Scene;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::axes::rotation_axis_candidates;
use crate::error::PlanError;
use crate::paths::motion_seed;
use crate::pipeline::{plan, PlanOptions};
use crate::replan::matching_candidate;

/// One placement error level: the largest offset in each direction.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PlacementError {
    /// Largest position error along world x and along world y (m).
    pub pos: f64,
    /// Largest yaw error (rad).
    pub yaw: f64,
}

impl PlacementError {
    /// `5 mm, 2°`, `5 mm`, `2°` or `none`.
    pub fn label(&self) -> String {
        match (self.pos > 0.0, self.yaw > 0.0) {
            (true, true) => format!("{:.0} mm, {:.0}°", self.pos * 1e3, self.yaw.to_degrees()),
            (true, false) => format!("{:.0} mm", self.pos * 1e3),
            (false, true) => format!("{:.0}°", self.yaw.to_degrees()),
            (false, false) => "none".into(),
        }
    }
}

/// The levels of docs/replan.md's table: position alone (2–50 mm), yaw alone (1–20°), both.
pub fn default_levels() -> Vec<PlacementError> {
    let mm = |x: f64| x * 1e-3;
    let deg = |x: f64| x.to_radians();
    let mut v = Vec::new();
    for p in [2.0, 5.0, 10.0, 20.0, 50.0] {
        v.push(PlacementError {
            pos: mm(p),
            yaw: 0.0,
        });
    }
    for y in [1.0, 2.0, 5.0, 10.0, 20.0] {
        v.push(PlacementError {
            pos: 0.0,
            yaw: deg(y),
        });
    }
    for (p, y) in [(2.0, 1.0), (5.0, 2.0), (10.0, 5.0), (20.0, 10.0)] {
        v.push(PlacementError {
            pos: mm(p),
            yaw: deg(y),
        });
    }
    v
}

/// One sampled placement and what planning made of it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Sample {
    pub level: usize,
    /// Offsets drawn: x, y (m), yaw (rad).
    pub dx: f64,
    pub dy: f64,
    pub dyaw: f64,
    /// Some plan came out.
    pub planned: bool,
    /// The nominal plan's rotation axis planned again.
    pub same_axis: bool,
    /// Indices into the nominal file's `plans` whose rotation axis planned again.
    pub plans_again: Vec<usize>,
    /// The nominal axis is still a rotation-axis candidate at this pose.
    pub axis_found: bool,
    /// Why no plan, when none (the plan file's reason).
    pub reason: Option<String>,
    /// Closest approach of a grasping gripper to the support in the best plan (m).
    pub closest_grasp_to_support: Option<f64>,
}

/// Summary of one level.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LevelSummary {
    pub error: PlacementError,
    pub samples: usize,
    /// Samples with some plan.
    pub planned: usize,
    /// Samples where the nominal axis planned again.
    pub same_axis: usize,
    /// Failure stage (the no-plan reason up to its first ':') → count.
    pub stages: BTreeMap<String, usize>,
    /// Smallest and median gripper-to-support clearance over the planned samples (m).
    pub clearance_min: Option<f64>,
    pub clearance_median: Option<f64>,
}

/// The whole report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RobustnessReport {
    pub seed: u64,
    pub samples_per_level: usize,
    pub levels: Vec<LevelSummary>,
    pub samples: Vec<Sample>,
    /// The largest position error and the largest yaw error among the levels at which every
    /// sample planned with the nominal axis, if any: how carefully the part must be placed.
    pub axis_tolerance: Option<PlacementError>,
}

/// The centre of the part's bounding box (object frame) in the world, the part at `pose`: the
/// point placement errors turn the part about.
pub fn part_centre(mesh: &Mesh, pose: &Isometry3<f64>) -> Point3<f64> {
    let (mut lo, mut hi) = (
        Vector3::repeat(f64::INFINITY),
        Vector3::repeat(f64::NEG_INFINITY),
    );
    for v in &mesh.vertices {
        lo = lo.inf(&v.coords);
        hi = hi.sup(&v.coords);
    }
    pose * Point3::from((lo + hi) / 2.0)
}

/// The pose of the part displaced by (dx, dy) and turned by `dyaw` about the vertical through
/// `centre` (world).
pub fn displaced(
    pose: &Isometry3<f64>,
    centre: &Point3<f64>,
    dx: f64,
    dy: f64,
    dyaw: f64,
) -> Isometry3<f64> {
    let turn = Isometry3::from_parts(
        Translation3::from(centre.coords),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), dyaw),
    ) * Isometry3::from_parts(
        Translation3::from(-centre.coords),
        UnitQuaternion::identity(),
    );
    Isometry3::translation(dx, dy, 0.0) * turn * pose
}

/// Runs the Monte-Carlo: `nominal` is the plan file of `scene` (its best plan's axis is the
/// one followed). `progress` is called once per sample. An error is a scene or mesh the
/// planner cannot work on.
pub fn robustness(
    scene: &Scene,
    mesh: &Mesh,
    nominal: &PlanFile,
    levels: &[PlacementError],
    samples: usize,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<RobustnessReport, PlanError> {
    let centre = part_centre(mesh, &scene.object.pose);
    let plan_candidates: Vec<Option<&CandidateJson>> = nominal
        .plans
        .iter()
        .map(|p| nominal.candidates.iter().find(|c| c.id == p.candidate))
        .collect();
    let nominal_p_init = nominal.object.initial_pose.to_isometry();
    let jobs: Vec<(usize, usize)> = (0..levels.len())
        .flat_map(|l| (0..samples).map(move |s| (l, s)))
        .collect();
    // The part's geometry and closings hold for every placement (object frame): built once.
    let known = std::sync::Arc::new(crate::context::PartKnowledge::new(scene, mesh)?);
    let samples_out: Vec<Sample> = jobs
        .par_iter()
        .map(|&(level, k)| {
            let err = levels[level];
            let mut rng = ChaCha8Rng::seed_from_u64(motion_seed(seed, level, k as u64));
            let mut draw = |m: f64| {
                if m > 0.0 {
                    rng.random_range(-m..=m)
                } else {
                    0.0
                }
            };
            let (dx, dy, dyaw) = (draw(err.pos), draw(err.pos), draw(err.yaw));
            let mut moved = scene.clone();
            moved.object.pose = displaced(&scene.object.pose, &centre, dx, dy, dyaw);
            let axes = rotation_axis_candidates(
                mesh,
                &moved.object.pose,
                moved.support_height,
                &moved.planner,
            );
            let matched: Vec<Option<usize>> = plan_candidates
                .iter()
                .map(|c| {
                    c.and_then(|c| {
                        matching_candidate(c, &nominal_p_init, &axes.candidates, &axes.p_init)
                    })
                })
                .collect();
            let options = PlanOptions {
                max_plans: usize::MAX,
                known: Some(known.clone()),
                ..PlanOptions::default()
            };
            let report = plan(&moved, mesh, &options, &|_| {}, &|| {})?;
            let closest = report.closest_grasp_to_support(0);
            let file = report.file;
            let plans_again: Vec<usize> = (0..matched.len())
                .filter(|&k| {
                    matched[k].is_some_and(|id| file.plans.iter().any(|p| p.candidate == id))
                })
                .collect();
            progress();
            Ok(Sample {
                level,
                dx,
                dy,
                dyaw,
                planned: !file.plans.is_empty(),
                same_axis: plans_again.first() == Some(&0),
                plans_again,
                axis_found: matched.first().is_some_and(Option::is_some),
                reason: file.reason.clone(),
                closest_grasp_to_support: closest,
            })
        })
        .collect::<Result<_, PlanError>>()?;
    let summaries: Vec<LevelSummary> = levels
        .iter()
        .enumerate()
        .map(|(l, &error)| summarise(error, samples_out.iter().filter(|s| s.level == l)))
        .collect();
    let always: Vec<PlacementError> = summaries
        .iter()
        .filter(|s| s.samples > 0 && s.same_axis == s.samples)
        .map(|s| s.error)
        .collect();
    let axis_tolerance = (!always.is_empty()).then(|| PlacementError {
        pos: always.iter().map(|e| e.pos).fold(0.0, f64::max),
        yaw: always.iter().map(|e| e.yaw).fold(0.0, f64::max),
    });
    Ok(RobustnessReport {
        seed,
        samples_per_level: samples,
        levels: summaries,
        samples: samples_out,
        axis_tolerance,
    })
}

fn summarise<'a>(error: PlacementError, samples: impl Iterator<Item = &'a Sample>) -> LevelSummary {
    let mut s = LevelSummary {
        error,
        samples: 0,
        planned: 0,
        same_axis: 0,
        stages: BTreeMap::new(),
        clearance_min: None,
        clearance_median: None,
    };
    let mut clearances = Vec::new();
    for x in samples {
        s.samples += 1;
        s.planned += usize::from(x.planned);
        s.same_axis += usize::from(x.same_axis);
        if let Some(r) = &x.reason {
            let stage = r.split(':').next().unwrap_or(r).trim().to_string();
            *s.stages.entry(stage).or_insert(0) += 1;
        }
        clearances.extend(x.closest_grasp_to_support);
    }
    clearances.sort_by(f64::total_cmp);
    s.clearance_min = clearances.first().copied();
    s.clearance_median = (!clearances.is_empty()).then(|| clearances[clearances.len() / 2]);
    s
}

/// Each nominal plan's `robustness` object: per level the share of samples in which its
/// rotation axis planned again, and the largest level at which it did in every sample.
pub fn per_plan(report: &RobustnessReport, plans: usize) -> Vec<RobustnessJson> {
    (0..plans)
        .map(|k| {
            let levels: Vec<RobustnessLevelJson> = report
                .levels
                .iter()
                .enumerate()
                .map(|(l, summary)| {
                    let of_level = report.samples.iter().filter(|s| s.level == l);
                    let again = of_level
                        .clone()
                        .filter(|s| s.plans_again.contains(&k))
                        .count();
                    let n = of_level.count();
                    RobustnessLevelJson {
                        pos: summary.error.pos,
                        yaw_deg: summary.error.yaw.to_degrees(),
                        share: if n > 0 { again as f64 / n as f64 } else { 0.0 },
                    }
                })
                .collect();
            let always: Vec<&RobustnessLevelJson> =
                levels.iter().filter(|l| l.share >= 1.0).collect();
            let tolerance = (!always.is_empty()).then(|| {
                [
                    always.iter().map(|l| l.pos).fold(0.0, f64::max),
                    always.iter().map(|l| l.yaw_deg).fold(0.0, f64::max),
                ]
            });
            RobustnessJson {
                samples: report.samples_per_level,
                seed: report.seed,
                levels,
                tolerance,
            }
        })
        .collect()
}

/// The pipeline with `[planner] robustness_samples` honoured: when it is > 0, every plan is
/// found first (Algorithms 1–3 as usual), then each plan's rotation axis is followed through
/// that many placements of the part within ±`robustness_pos` / ±`robustness_yaw`, and the plans
/// are ranked by the share of placements in which their axis planned again (ties: the
/// pipeline's order, by S_rot) before the best `max_plans` are kept. Each kept plan carries its
/// `robustness` object. Costs `robustness_samples` full pipeline runs.
pub fn plan_ranked_by_robustness(
    scene: &Scene,
    mesh: &Mesh,
    options: &PlanOptions,
    on_candidates: &(dyn Fn(usize) + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<crate::pipeline::PlanReport, PlanError> {
    let samples = scene.planner.robustness_samples as usize;
    if samples == 0 {
        return plan(scene, mesh, options, on_candidates, progress);
    }
    let t0 = std::time::Instant::now();
    let all = PlanOptions {
        max_plans: usize::MAX,
        ..options.clone()
    };
    let mut report = plan(scene, mesh, &all, on_candidates, progress)?;
    let level = PlacementError {
        pos: scene.planner.robustness_pos,
        yaw: scene.planner.robustness_yaw,
    };
    let mc = robustness(
        scene,
        mesh,
        &report.file,
        &[level],
        samples,
        scene.planner.seed,
        &|| {},
    )?;
    let per = per_plan(&mc, report.file.plans.len());
    let file = &mut report.file;
    let mut order: Vec<usize> = (0..file.plans.len()).collect();
    // Stable: equal shares keep the pipeline's order.
    order.sort_by(|&a, &b| per[b].levels[0].share.total_cmp(&per[a].levels[0].share));
    let mut plans = Vec::with_capacity(options.max_plans.min(order.len()));
    for (rank, &k) in order.iter().enumerate() {
        let mut p = file.plans[k].clone();
        if rank < options.max_plans {
            p.robustness = Some(per[k].clone());
            plans.push(p);
        } else {
            file.candidates[p.candidate].outcome = Outcome::rejected(format!(
                "outranked (only the best {} plans are kept, ranked by robustness: \
                 axis planned again in {:.0} % of {samples} placements)",
                options.max_plans,
                100.0 * per[k].levels[0].share
            ));
        }
    }
    file.plans = plans;
    file.timing_ms.insert(
        "robustness".into(),
        t0.elapsed().as_secs_f64() * 1e3 - file.timing_ms.get("total").copied().unwrap_or(0.0),
    );
    file.timing_ms
        .insert("total".into(), t0.elapsed().as_secs_f64() * 1e3);
    Ok(report)
}

/// An SVG bar chart of the report: per level, the share of placements that planned (light)
/// and that planned with the nominal axis (dark), 0–100 %.
pub fn svg(report: &RobustnessReport, title: &str) -> String {
    use std::fmt::Write as _;
    let n = report.levels.len().max(1);
    let (w, h, left, top, bottom) = (80.0 + 70.0 * n as f64, 300.0, 50.0, 40.0, 70.0);
    let plot_h = h - top - bottom;
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(
        out,
        r#"<text x="{left}" y="20" font-size="14">{}</text>"#,
        esc(title)
    );
    for pct in [0, 50, 100] {
        let y = top + plot_h * (1.0 - pct as f64 / 100.0);
        let _ = writeln!(
            out,
            r##"<line x1="{left}" x2="{}" y1="{y}" y2="{y}" stroke="#ccc"/><text x="8" y="{}">{pct} %</text>"##,
            w - 10.0,
            y + 4.0
        );
    }
    for (k, l) in report.levels.iter().enumerate() {
        let x = left + 10.0 + 70.0 * k as f64;
        let share = |c: usize| c as f64 / l.samples.max(1) as f64;
        for (dx, value, colour) in [
            (0.0, share(l.planned), "#9ecae1"),
            (26.0, share(l.same_axis), "#3182bd"),
        ] {
            let bh = plot_h * value;
            let _ = writeln!(
                out,
                r#"<rect x="{}" y="{}" width="24" height="{bh}" fill="{colour}"/>"#,
                x + dx,
                top + plot_h - bh
            );
        }
        let label = l.error.label();
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" text-anchor="middle">±{}</text>"#,
            x + 25.0,
            h - bottom + 16.0,
            esc(&label)
        );
    }
    let _ = writeln!(
        out,
        r##"<rect x="{left}" y="{}" width="12" height="12" fill="#9ecae1"/><text x="{}" y="{}">some plan</text><rect x="{}" y="{}" width="12" height="12" fill="#3182bd"/><text x="{}" y="{}">the plan's own rotation axis</text>"##,
        h - 30.0,
        left + 16.0,
        h - 20.0,
        left + 100.0,
        h - 30.0,
        left + 116.0,
        h - 20.0
    );
    out.push_str("</svg>\n");
    out
}
