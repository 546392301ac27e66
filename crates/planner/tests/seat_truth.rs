//! The thickness below which a wrapped power grasp is not seated (`seat::MIN_SEAT_THICKNESS`),
//! held to the whole-plan replay both ways. The table
//! `plan_replay_generated_seat_all_2f85.csv` replays the examples and 30 generated parts planned
//! with every wrapped grasp seated, whatever its bar's thickness (the rule with threshold 0):
//! a plan whose seated bars are all at least the threshold thick must have both power closings
//! (`mas1`, `sup2`) squeeze from both sides in the replay, and a plan with a thinner seated bar
//! has a power closing that ends caged or one-sided — the reason thin bars are not seated.
//! A row's part is made again (family and seed), its seating decided again here.

mod common;

use common::replay_table::{rows, scene_of};
use pregrasp_collision::ObjectGeometry;
use pregrasp_planner::context::arm_models;
use pregrasp_planner::seat::{seated_scene_thicker_than, thickness_at, MIN_SEAT_THICKNESS};

/// How a replayed closing ended when it squeezes from both sides.
const SQUEEZE: &str = "both_sides";

#[test]
fn seated_thin_bars_cage_and_seated_thick_bars_squeeze_in_the_replay() {
    let table = rows("plan_replay_generated_seat_all_2f85.csv");
    let (mut thin, mut thick) = (Vec::new(), Vec::new());
    for row in table.iter().filter(|r| !r["candidate"].is_empty()) {
        let name = row.get("part").unwrap_or(&row["example"]).clone();
        let (scene, mesh) = scene_of(row);
        let part = ObjectGeometry::new(&mesh).unwrap();
        let arms = arm_models(&scene).unwrap();
        let Some((_, moved)) = seated_scene_thicker_than(&scene, &part, &arms, 0.0) else {
            continue;
        };
        let kinds = ["mas1", "sup2"].map(|s| row[&format!("{s}_close.kind")].clone());
        let thinnest = (0..2)
            .filter(|&arm| moved[arm] > 0.0)
            .map(|arm| thickness_at(&part, &scene.grasps.power[arm]).unwrap())
            .fold(f64::INFINITY, f64::min);
        let what = format!(
            "{name} plan {}: thinnest seated bar {:.0} mm, mas1 {}, sup2 {}",
            row["plan"],
            thinnest * 1e3,
            kinds[0],
            kinds[1]
        );
        if thinnest >= MIN_SEAT_THICKNESS {
            assert!(kinds.iter().all(|k| k == SQUEEZE), "{what}");
            thick.push(what);
        } else {
            assert!(
                kinds
                    .iter()
                    .any(|k| ["caged", "caged_no_contact", "one_side"].contains(&k.as_str())),
                "{what}"
            );
            thin.push(what);
        }
    }
    println!("thin: {thin:#?}\nthick: {thick:#?}");
    // Both sides of the threshold are in the table: 5 plans with a thin seated bar (4 parts,
    // 18–22 mm), 15 with thick ones only (12 parts, 25–44 mm).
    assert_eq!((thin.len(), thick.len()), (5, 15));
}
