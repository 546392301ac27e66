//! Issue 17: `[grasps] mode = "auto"`. The three examples plan with no grasp given and their
//! plans pass the checker; a sweep over generated parts of the example families (random sizes,
//! 18–45 mm stock, 20–60 mm bars); a solid plate has no graspable bar and says so.
//!
//! `cargo test --release -p pregrasp-planner --test auto_grasps -- --nocapture` prints the
//! README's numbers.

mod common;

use common::scenes::auto_scene;
use pregrasp_io::plan_file::PlanStatus;
use std::path::Path;
use std::time::Instant;

use pregrasp_examples::{with_design, ChairSideParams, ShelfSideParams, StoolSideParams};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::auto_grasps::plan_auto;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::PlanOptions;
use rand::{Rng, SeedableRng};

fn plan_text(text: &str, mesh: &pregrasp_geometry::Mesh) -> (Scene, PlanFile) {
    let scene = Scene::from_str(text, Path::new("auto.toml")).unwrap();
    let file = plan_auto(&scene, mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    (scene, file)
}

#[test]
fn the_examples_plan_from_auto_grasps_and_pass_the_check() {
    for name in pregrasp_examples::NAMES {
        let ex = pregrasp_examples::by_name(name).unwrap();
        let text = auto_scene(&ex.scene_toml, "");
        let (scene, file) = plan_text(&text, &ex.mesh);
        assert!(scene.grasps.auto.is_some());
        assert_eq!(
            file.status,
            PlanStatus::Planned,
            "{name}: {:?}",
            file.reason
        );
        let auto = file.grasps.auto.as_ref().expect("the search is reported");
        assert!(auto.sites > 0 && auto.planned > 0 && auto.chosen.is_some());
        let check = check_plan(&file, &ex.mesh);
        assert!(check.is_valid(), "{name}: {:?}", check.rules);
        // The hand-placed scene's best plan, for the README's comparison.
        let hand = Scene::from_str(&ex.scene_toml, Path::new("hand.toml")).unwrap();
        let hand_file = plan_auto(&hand, &ex.mesh, &PlanOptions::default(), &|_| {}, &|| {})
            .unwrap()
            .file;
        println!(
            "{name}: auto score {:.3} (candidate {}), hand-placed {:.3} (candidate {}); widths {:?} mm",
            file.plans[0].score,
            file.plans[0].candidate,
            hand_file.plans[0].score,
            hand_file.plans[0].candidate,
            auto.widths.map(|w| (w * 1e3).round())
        );
        let show = |g: &pregrasp_io::plan_file::PoseJson| {
            format!("({:.3}, {:.3}, {:.4})", g.xyz[0], g.xyz[1], g.xyz[2])
        };
        for (what, a, h) in [
            ("support", &file.grasps.support, &hand_file.grasps.support),
            (
                "power[0]",
                &file.grasps.power[0],
                &hand_file.grasps.power[0],
            ),
            (
                "power[1]",
                &file.grasps.power[1],
                &hand_file.grasps.power[1],
            ),
        ] {
            println!("  {what}: auto {} hand {}", show(a), show(h));
        }
    }
}

#[test]
fn an_auto_scene_may_pin_the_support_grasp() {
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let support = ex
        .scene_toml
        .lines()
        .find(|l| l.trim_start().starts_with("support ="))
        .unwrap()
        .to_string();
    let text = auto_scene(&ex.scene_toml, &format!("{support}\n"));
    let (scene, file) = plan_text(&text, &ex.mesh);
    let pins = scene.grasps.auto.unwrap();
    assert!(pins.support_pinned && !pins.power_pinned);
    assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
    let hand = Scene::from_str(&ex.scene_toml, Path::new("hand.toml")).unwrap();
    assert_eq!(
        file.grasps.support.to_isometry(),
        hand.grasps.support,
        "the pinned grasp is kept"
    );
    assert!(check_plan(&file, &ex.mesh).is_valid());
}

/// A solid 400 × 400 × 25 mm plate: nowhere can the fingers close across it.
#[test]
fn a_solid_plate_has_no_graspable_bar() {
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let plate = pregrasp_examples::extrude(
        &[
            nalgebra::Point2::new(0.0, 0.0),
            nalgebra::Point2::new(0.4, 0.0),
            nalgebra::Point2::new(0.4, 0.4),
            nalgebra::Point2::new(0.0, 0.4),
        ],
        &[],
        0.025,
    );
    let (_, file) = plan_text(&auto_scene(&ex.scene_toml, ""), &plate);
    assert_eq!(file.status, PlanStatus::NoPlan);
    let reason = file.reason.unwrap();
    assert!(reason.starts_with("no graspable bar"), "{reason}");
    assert_eq!(file.grasps.auto.unwrap().sites, 0);
}

/// Generated parts: the three families with random stock (18–45 mm) and bars (20–60 mm) and
/// random outer sizes (±10 %). Every plan passes the check; at least half of them plan.
#[test]
fn a_sweep_over_generated_parts() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let (mut planned, mut total, mut times) = (0, 0, Vec::new());
    let mut failures = Vec::new();
    for k in 0..12 {
        let family = pregrasp_examples::NAMES[k % 3];
        let t: f64 = rng.random_range(0.018..=0.045);
        let bar: f64 = rng.random_range(0.020..=0.060);
        let s: f64 = rng.random_range(0.9..=1.1);
        let design = match family {
            "chair_side" => {
                let d = ChairSideParams::default();
                ChairSideParams {
                    thickness: t,
                    front_leg_width: bar,
                    back_leg_width: bar,
                    seat_rail_width: bar,
                    stretcher_width: bar,
                    seat_height: d.seat_height * s,
                    depth: d.depth * s,
                    ..d
                }
                .design()
            }
            "shelf_side" => {
                let d = ShelfSideParams::default();
                ShelfSideParams {
                    thickness: t,
                    handle_bar_width: bar,
                    length: d.length * s,
                    ..d
                }
                .design()
            }
            _ => {
                let d = StoolSideParams::default();
                StoolSideParams {
                    thickness: t,
                    leg_width: bar,
                    top_rail_width: bar,
                    stretcher_width: bar,
                    height: d.height * s,
                    ..d
                }
                .design()
            }
        };
        let ex = with_design(family, design).unwrap();
        let text = auto_scene(&ex.scene_toml, "");
        let started = Instant::now();
        let (_, file) = plan_text(&text, &ex.mesh);
        times.push(started.elapsed().as_secs_f64() * 1e3);
        total += 1;
        let label = format!(
            "{family} ×{s:.2}, {:.0} mm stock, {:.0} mm bars",
            t * 1e3,
            bar * 1e3
        );
        if file.status == PlanStatus::Planned {
            planned += 1;
            let check = check_plan(&file, &ex.mesh);
            assert!(check.is_valid(), "{label}: {:?}", check.rules);
        } else {
            failures.push(format!("{label}: {}", file.reason.unwrap_or_default()));
        }
    }
    times.sort_by(f64::total_cmp);
    println!(
        "auto grasps: {planned} of {total} generated parts planned; time per scene median {:.0} ms, max {:.0} ms",
        times[times.len() / 2],
        times[times.len() - 1]
    );
    for f in &failures {
        println!("  no plan: {f}");
    }
    assert!(2 * planned >= total, "{failures:#?}");
}
