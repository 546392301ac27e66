//! The grip check held to a dynamic replay (`tools/gripper_truth/replay.py`): MuJoCo, the
//! Menagerie 2F-85 pinching each example's part free on the table and turning it along the
//! plan's `rot`, squeezed at 0.5×, 1×, 1.5× and 2× the minimum force pregrasp reports
//! (`crates/physics/data/replay_truth/replay_2f85*.json`: the examples, the bench end and the
//! ladder, a generated part of each family).
//!
//! The table belongs to the plans and forces pregrasp makes now: every row's plan is planned
//! again here and its N_min must be the table's (else the replay is of another model and must
//! be run again). Against the replay with torsional friction at the pads (condim 4, the
//! counterpart of the soft-finger model) the force must hold at 1.5× and not at 0.5×.

use std::path::Path;

use pregrasp_examples::parts::families::{generate, FAMILIES};
use pregrasp_examples::scene::{scene_toml, SceneLayout};
use pregrasp_examples::{BenchEndParams, LadderParams};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_physics::{analyse_plan, PartMass, PhysicsSettings};
use pregrasp_planner::pipeline::{plan, PlanOptions};
use serde_json::Value;

/// Rows where pregrasp's N_min is known to be more than twice the force the replay needs, so
/// 0.5× still holds there: (example, plan index, why).
///
/// The two generated parts here pinch the part nearer the axis than its centre of mass (H-frame
/// 0.238 against 0.255 m, stool 0.114 against 0.196 m): the pads must hold the part from tipping
/// about the pinch. Our pads do that by their tangential forces (a couple over half the pad gap)
/// and their torsion about the closing axis; MuJoCo's pad boxes, touching at up to four points,
/// also shift their pressure across the bar's thickness — a tilt that soft-finger pads do not
/// have. Ours is then the cautious side.
const CONSERVATIVE: &[(&str, u64, &str)] = &[
    (
        "h_frame",
        0,
        "the pinch on the crossbar lies 17 mm nearer the axis than the centre of mass; N_min \
         26.1 N, the replay holds from 7.1 N (0.27×)",
    ),
    (
        "h_frame",
        1,
        "the second axis candidate, planned since b367d9d; N_min 22.6 N, the replay holds \
         from 5.5 N (0.24×)",
    ),
    (
        "stool",
        0,
        "the pinch lies 82 mm nearer the axis than the centre of mass; N_min 77.1 N, the \
         replay holds from 37.4 N (0.48×)",
    ),
];

/// The plan of the example `name` (a built-in one, or the bench end or the ladder as the
/// replay's scenes were written), planned now.
fn planned(name: &str) -> (PlanFile, Mesh) {
    match name {
        "bench_end" | "ladder" => {
            // As the replay's scenes were written: the part laid out as the examples are.
            let design = match name {
                "bench_end" => BenchEndParams::default().design(),
                _ => LadderParams::default().design(),
            };
            let mesh_path = format!("meshes/{name}.stl");
            let layout = SceneLayout::default();
            let text = scene_toml(name, name, &mesh_path, &design, &layout);
            plan_scene(name, &text, design.mesh())
        }
        _ => {
            let ex = pregrasp_examples::by_name(name).expect("built-in example");
            plan_scene(name, &ex.scene_toml, ex.mesh)
        }
    }
}

/// The plan of the generated part of family `name` drawn from seed 0, as
/// `pregrasp_examples::generated_example` lays it out, planned now on the mesh as its binary
/// STL gives it back (single-precision vertices, welded): the replay's plans were made from the
/// STL files, and the stool's two best candidates tie in score, so rounding orders them.
fn generated(name: &str) -> (PlanFile, Mesh) {
    let family = FAMILIES
        .into_iter()
        .find(|f| f.name() == name)
        .expect("a family's name");
    let ex = pregrasp_examples::generated_example(&generate(family, 0));
    let stl = pregrasp_io::mesh_io::stl_bytes(&ex.mesh);
    let mesh = pregrasp_io::mesh_io::parse_stl(&stl, name, 1.0)
        .expect("the STL reads back")
        .mesh;
    plan_scene(name, &ex.scene_toml, mesh)
}

/// Plans the scene `text` (as `examples/<name>.toml`) on `mesh` with the default options, the
/// twist rule off.
fn plan_scene(name: &str, text: &str, mesh: Mesh) -> (PlanFile, Mesh) {
    let mut scene =
        Scene::from_str(text, Path::new(&format!("examples/{name}.toml"))).expect("scene parses");
    // The tables replay rotations the twist rule now refuses (the stool side's plan 1): they
    // hold N_min to the replay whatever the twist.
    scene.physics.max_twist_arm = Some(1.0);
    let file = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    (file, mesh)
}

/// The examples' seven plans (the twist rule off; the stool side's grasps held at the fingertips
/// give it a third): all hold at 1.5× and fail at 0.5×.
#[test]
fn the_minimum_grip_force_holds_at_1_5x_and_not_at_0_5x_in_the_replay() {
    let table: Value =
        serde_json::from_str(include_str!("../data/replay_truth/replay_2f85.json")).unwrap();
    let checked = hold_to(&table, &["chair_side", "shelf_side", "stool_side"], planned);
    assert_eq!(checked, 7, "rows with torsional pads");
}

/// The same on the bench end and the ladder (`replay_2f85_more.json`): both plans of the bench
/// end and the ladder's one hold at 1.5× and fail at 0.5×.
#[test]
fn on_the_bench_end_and_the_ladder_too() {
    let table: Value =
        serde_json::from_str(include_str!("../data/replay_truth/replay_2f85_more.json")).unwrap();
    let checked = hold_to(&table, &["bench_end", "ladder"], planned);
    assert_eq!(checked, 3, "rows with torsional pads");
}

/// The same on a generated part of each family, seed 0 (`replay_2f85_families.json`): all eight
/// plans hold at 1.5×; five fail at 0.5×, and the three that do not are in [`CONSERVATIVE`].
#[test]
fn on_a_generated_part_of_each_family() {
    let table: Value = serde_json::from_str(include_str!(
        "../data/replay_truth/replay_2f85_families.json"
    ))
    .unwrap();
    let names = FAMILIES.map(|f| f.name());
    let checked = hold_to(&table, &names, generated);
    assert_eq!(checked, 8, "rows with torsional pads");
}

/// Holds the rows of `table` for the parts `names`, planned by `plan_of` (see the module
/// documentation); returns how many rows with torsional pads it checked.
fn hold_to(table: &Value, names: &[&str], plan_of: fn(&str) -> (PlanFile, Mesh)) -> usize {
    let rows = table["rows"].as_array().unwrap();
    let settings = PhysicsSettings::default();
    let mut checked = 0;
    for &name in names {
        let (file, mesh) = plan_of(name);
        let part = PartMass::resolve(file.object.mass, &mesh, None, settings.density).unwrap();
        let set = file.to_model().unwrap();
        for row in rows.iter().filter(|r| r["example"] == name) {
            let k = row["plan"].as_u64().unwrap();
            let plan = &file.plans[k as usize];
            assert_eq!(
                plan.candidate as u64,
                row["candidate"].as_u64().unwrap(),
                "{name} plan {k}: the table replays another plan; run the replay again"
            );
            let ours = analyse_plan(&set, k as usize, &part, &settings)
                .unwrap()
                .n_max
                .expect("the rotation holds");
            let theirs = row["N_min"].as_f64().unwrap();
            assert!(
                (ours - theirs).abs() <= 1e-3 * theirs,
                "{name} plan {k}: N_min {ours} N, the table's {theirs} N; run the replay again"
            );
            if row["condim"] != 4 {
                continue;
            }
            let verdict = |m: &str| row["verdict"][m].as_str().unwrap().to_string();
            assert_eq!(verdict("1.5"), "holds", "{name} plan {k} at 1.5× N_min");
            let known = CONSERVATIVE.iter().any(|(n, p, _)| *n == name && *p == k);
            assert_eq!(
                verdict("0.5") == "holds",
                known,
                "{name} plan {k} at 0.5× N_min: {}",
                verdict("0.5")
            );
            checked += 1;
        }
    }
    checked
}
