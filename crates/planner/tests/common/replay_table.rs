//! The whole-plan replay's tables (`crates/physics/data/replay_truth/`) as tests read them:
//! rows of cells by column name, and each row's part made again (an example's files, or a
//! generated part from its family and seed).

use std::collections::HashMap;
use std::path::Path;

use pregrasp_examples::Family;
use pregrasp_geometry::Mesh;
use pregrasp_io::scene::Scene;

/// The rows of `table` (a CSV file of the replay tables), each a map from column to cell.
pub fn rows(table: &str) -> Vec<HashMap<String, String>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../physics/data/replay_truth")
        .join(table);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(split_csv(l))
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

/// A CSV line's cells (the tables quote cells holding commas).
pub fn split_csv(line: &str) -> Vec<String> {
    let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => cells.push(std::mem::take(&mut cell)),
            c => cell.push(c),
        }
    }
    cells.push(cell);
    cells
}

/// The scene and mesh of a row: an example's files, or a generated part made again from its
/// family and seed.
pub fn scene_of(row: &HashMap<String, String>) -> (Scene, Mesh) {
    let family = row.get("family").map_or("example", String::as_str);
    if family == "example" {
        return super::scenes::example_files(&row["example"]);
    }
    let seed: u64 = row["seed"].parse().unwrap();
    let family = Family::from_name(family).unwrap();
    // A table of the scenes with other arms says which (the test adds the column).
    match row.get("arm_model") {
        Some(model) => super::scenes::generated_files_with_arms(family, seed, model),
        None => super::scenes::generated_files(family, seed),
    }
}

/// `scene` with the power grasps the planner plans with, as its plan file gives them: seated on
/// the palm ([`pregrasp_planner::seat`]) and, where the scene's could not carry the part, slid
/// towards the centre of mass ([`pregrasp_planner::slide`]).
pub fn planned_scene(scene: &Scene, mesh: &Mesh) -> Scene {
    use pregrasp_planner::pipeline::{plan, PlanOptions};
    let file = plan(scene, mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    let mut planned = scene.clone();
    planned.grasps.power = file.grasps.power.each_ref().map(|p| p.to_isometry());
    planned
}
