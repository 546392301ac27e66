//! The baked hull table (`crates/collision/data/baked_hulls.bin`, see
//! `pregrasp_collision::baked_hulls`) is parry's answers for the points the planner hulls: this
//! test plans the three examples and a generated part of each family with every hull asked of
//! parry and recorded, and compares the records with the file, bit for bit. A different parry
//! or other model data fails it; `PREGRASP_BLESS=1` writes the file again. It runs alone in its
//! binary: recording must start before the process hulls anything.
//!
//! The set of hulls asked must be the same on every run, or the comparison fails by chance. Two
//! things made it vary (a CI run on four threads asked for one hull more than the file held):
//! a piece building its vertex graph once scanned `BUILD_AFTER` times, a count that depends on
//! how many scans the collision queries' warm starts save (their cache is keyed by addresses),
//! and so on the run — such hulls now come from parry, never the table (`Hulled::Scanned`);
//! and the 2F-85 finger shapes' shared hull, which the first query's thread built one way or
//! another — now given when the gripper's pieces are built. The plans also run on one thread,
//! so that no order of first queries can matter. 80 runs in a row gave the same table.

mod common;

use std::path::Path;

use common::scenes::example_files;
use pregrasp_collision::baked_hulls::{recorded_table, start_recording};
use pregrasp_examples::generated::generated_scene;
use pregrasp_examples::parts::families::{generate, FAMILIES};
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::PlanOptions;

#[test]
fn the_baked_hulls_are_what_parry_gives_for_the_planned_points() {
    start_recording();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool of one thread");
    let planned = one.install(plan_the_examples_and_a_part_of_each_family);
    assert_eq!(planned, 3 + FAMILIES.len(), "every scene plans or says why");
    let text = recorded_table();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../collision/data/baked_hulls.bin");
    if std::env::var_os("PREGRASP_BLESS").is_some() {
        std::fs::write(&path, &text).unwrap();
        return;
    }
    let want = std::fs::read(&path).unwrap();
    assert!(
        want == text,
        "{} is not what parry gives for the planned points ({} bytes now, {} in the file): \
         PREGRASP_BLESS=1 cargo test --release -p pregrasp-planner --test baked_hulls",
        path.display(),
        text.len(),
        want.len()
    );
}

/// Plans the three examples and the first generated part of every family; how many planned or
/// said why.
fn plan_the_examples_and_a_part_of_each_family() -> usize {
    let options = PlanOptions {
        max_plans: 5,
        ..PlanOptions::default()
    };
    // The open hand's pieces (the auto grasps' and the one-at-a-time slide's approach test).
    pregrasp_planner::open_fingers::OpenFingers::of(&pregrasp_robot::Gripper::default()).prepare();
    let mut planned = 0;
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let (scene, mesh) = example_files(name);
        let report = pregrasp_planner::plan_scene(&scene, &mesh, &options, &|_| {}, &|| {});
        planned += usize::from(report.is_ok());
    }
    for family in FAMILIES {
        let generated = generated_scene(&generate(family, 1));
        let scene = Scene::from_str(
            &generated.scene_toml,
            Path::new(&format!("{}.toml", generated.stem)),
        )
        .unwrap();
        let report =
            pregrasp_planner::plan_scene(&scene, &generated.mesh, &options, &|_| {}, &|| {});
        planned += usize::from(report.is_ok());
    }
    planned
}
