//! The planner's re-check of its own plans (`check::Transits::Proven`, what [`plan`] runs on
//! each plan before it keeps it) held to the full check that `pregrasp check` runs on any plan
//! file.

use std::path::Path;

use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;

use pregrasp_examples::generated::generated_scene;
use pregrasp_examples::parts::families;

use super::{plan, PlanOptions};
use crate::check::{check_plan, CheckReport, PlanChecker};

fn planned(name: &str) -> (PlanFile, Mesh) {
    let ex = pregrasp_examples::by_name(name).expect("built-in example");
    planned_from(&ex.scene_toml, &format!("examples/{name}.toml"), ex.mesh)
}

fn planned_from(toml: &str, path: &str, mesh: Mesh) -> (PlanFile, Mesh) {
    let scene = Scene::from_str(toml, Path::new(path)).expect("scene parses");
    let file = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .expect("plans")
        .file;
    (file, mesh)
}

/// The examples and the first generated part of every family.
fn scenes() -> Vec<(String, PlanFile, Mesh)> {
    let examples = pregrasp_examples::NAMES.iter().map(|&name| {
        let (file, mesh) = planned(name);
        (name.to_string(), file, mesh)
    });
    let generated = families::FAMILIES.iter().map(|&family| {
        let part = generated_scene(&families::generate(family, 1));
        let (file, mesh) =
            planned_from(&part.scene_toml, &format!("{}.toml", part.stem), part.mesh);
        (part.stem, file, mesh)
    });
    examples.chain(generated).collect()
}

fn checker(file: &PlanFile, mesh: &Mesh) -> PlanChecker {
    let set = file.to_model().expect("a plan file of the planner's");
    let (arms, grippers) = file.arms_and_grippers(None).expect("built-in arms");
    PlanChecker::sharing_part(&set, mesh, &arms, &grippers, None, None, None).expect("a checker")
}

/// The number of states rule 2 reports it checked.
fn states(report: &CheckReport) -> u64 {
    let detail = &report.rules[2].detail;
    detail
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count in {detail:?}"))
}

/// On the plans of the examples and of a generated part of every family the two checks give
/// the same verdict on every rule, the same closest grasping gripper to the support (the
/// robustness ranking reads it), and the same words but for rule 2's count of states: the
/// planner's own check skips its transits'.
#[test]
fn the_planners_own_check_judges_its_plans_as_the_full_check_does() {
    let mut plans = 0;
    for (name, file, mesh) in scenes() {
        plans += file.plans.len();
        if file.plans.is_empty() {
            continue;
        }
        let set = file.to_model().expect("model");
        let checker = checker(&file, &mesh);
        let full = checker.check_plans(&set, &set.plans);
        let own = checker.check_own_plans(&set, &set.plans);
        assert!(full.is_valid(), "{name}: {:?}", full.rules);
        assert!(own.is_valid(), "{name}: {:?}", own.rules);
        assert_eq!(
            full.closest_grasp_to_support, own.closest_grasp_to_support,
            "{name}"
        );
        for (f, o) in full.rules.iter().zip(&own.rules) {
            assert_eq!(f.ok, o.ok, "{name}: rule {}", f.rule);
            if f.rule != 2 {
                assert_eq!(f.detail, o.detail, "{name}: rule {}", f.rule);
            }
        }
        let (all, skipped) = (states(&full), states(&own));
        assert!(
            skipped * 2 < all,
            "{name}: {skipped} of {all} states checked again"
        );
    }
    assert!(plans >= 10, "only {plans} plans compared");
}

/// The transits are trusted only where the planner has just proved them: a plan file whose
/// transit runs through the part fails `pregrasp check`, which checks every state.
#[test]
fn a_plan_file_is_checked_whole_whoever_wrote_it() {
    let (mut file, mesh) = planned("stool_side");
    let sup1 = &mut file.plans[0].segments[0];
    let from = sup1.approach_from.expect("a reach");
    assert!(from >= 4, "a transit of {from} points");
    // A transit point in the middle, the shoulder turned by a radian: the gripper passes
    // through the part on the way there.
    sup1.points[from / 2].q[1] += 1.0;
    let set = file.to_model().expect("model");
    let checker = checker(&file, &mesh);
    let collides = |report: &CheckReport| report.rules[2].ok == Some(false);
    assert!(collides(&checker.check_plans(&set, &set.plans)));
    let whole = check_plan(&file, &mesh);
    assert!(collides(&whole));
    assert!(
        whole.rules[2].detail.contains("sup1 point") && whole.rules[2].detail.contains("object"),
        "{}",
        whole.rules[2].detail
    );
    // What the planner's own check skips: the states of its transits.
    assert!(!collides(&checker.check_own_plans(&set, &set.plans)));
}
