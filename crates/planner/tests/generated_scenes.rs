//! Valid scenes, generated: every one is planned or answered with `no plan` and a reason,
//! never a panic, and its plan file follows the format.
//!
//! The generator varies what a user's cell varies: two arms of any of the five built-in
//! models (mixed), bases anywhere around the part and yawed, start configurations anywhere
//! within the joint limits (so some start in collision), the part at any yaw, gripper points
//! anywhere in the hand, and every `[planner]` setting — weights included — within plausible
//! ranges. `PREGRASP_GENERATED_SCENES` sets how many (default 1000).

use std::fmt::Write as _;
use std::path::Path;

use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::PlanOptions;

/// SplitMix64: a tiny deterministic generator, so every run sees the same scenes.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[(self.next() % items.len() as u64) as usize]
    }
    fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }
}

const MODELS: [&str; 5] = ["ur3e", "ur5e", "ur10e", "ur16e", "ur5"];

/// Scene `k`: the part, grasps and support of one built-in example, everything else drawn.
fn scene_text(k: u64, example: &pregrasp_examples::Example) -> String {
    let mut rng = Rng(0x5eed_0000 + k);
    let text = &example.scene_toml;
    let head = &text[..text.find("[[robot]]").expect("an example has robots")];
    let mut out = String::new();
    for line in head.lines() {
        if line.starts_with("pose = ") {
            // The example's pose, moved up to 10 cm and turned up to 30° (or anywhere, at times).
            let numbers: Vec<f64> = line
                .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
                .filter_map(|t| t.parse().ok())
                .collect();
            let (x, y, yaw) = if rng.chance(0.8) {
                (
                    numbers[0] + rng.uniform(-0.1, 0.1),
                    numbers[1] + rng.uniform(-0.1, 0.1),
                    numbers[5] + rng.uniform(-30.0, 30.0),
                )
            } else {
                (
                    rng.uniform(0.3, 0.9),
                    rng.uniform(-0.4, 0.4),
                    rng.uniform(-180.0, 180.0),
                )
            };
            writeln!(
                out,
                "pose = {{ xyz = [{x}, {y}, 0.0], rpy_deg = [0, 0, {yaw}] }}"
            )
            .unwrap();
        } else {
            writeln!(out, "{line}").unwrap();
        }
    }
    for (name, side) in [("left", 1.0), ("right", -1.0)] {
        let model = rng.pick(&MODELS);
        let (bx, by) = (rng.uniform(-0.15, 0.15), side * rng.uniform(0.3, 0.6));
        // A yawed base whose start turns the shoulder back by the same angle (the arm then
        // starts over the table as in the examples), a start nearby, or one anywhere.
        let yaw = rng.uniform(-180.0, 180.0);
        let shoulder = (180.0 - yaw + 180.0).rem_euclid(360.0) - 180.0;
        let default = [shoulder, -103.1, 103.1, -90.0, -90.0, 0.0];
        let q: Vec<String> = match rng.next() % 10 {
            0 => (0..6)
                .map(|j| {
                    let limit = if j == 2 { 179.0 } else { 359.0 };
                    rng.uniform(-limit, limit)
                })
                .map(|x| format!("{x:.3}"))
                .collect(),
            1..=4 => default.iter().map(|x| format!("{x:.3}")).collect(),
            _ => default
                .iter()
                .map(|x| format!("{:.3}", x + rng.uniform(-20.0, 20.0)))
                .collect(),
        };
        let start = format!("start_deg = [{}]", q.join(", "));
        let power = rng.uniform(0.105, 0.13);
        let precision = rng.uniform(0.14, 0.16);
        writeln!(
            out,
            "[[robot]]\nname = \"{name}\"\nmodel = \"{model}\"\n\
             base = {{ xyz = [{bx}, {by}, 0.0], rpy_deg = [0, 0, {yaw}] }}\n{start}\n\
             gripper = \"robotiq_2f85\"\npower_point_z = {power}\nprecision_point_z = {precision}\n"
        )
        .unwrap();
    }
    let max_angle = rng.uniform(10.0, 180.0);
    writeln!(
        out,
        "[planner]\nsupport_distance = {}\nmin_axis_length = {}\nstep_deg = {}\n\
         max_angle_deg = {max_angle}\nweight_length = {}\nweight_angle = {}\nextra_steps = {}\n\
         min_grasp_axis_distance = {}\nlift = {}\napproach_distance = {}\n\
         max_joint_step_deg = {}\nseed = {}\nlink_clearance = {}\nfinger_support_clearance = {}",
        rng.uniform(0.0, 0.05),
        rng.uniform(0.0, 0.2),
        rng.uniform(0.5, 5.0).min(max_angle),
        rng.uniform(0.0, 5.0),
        rng.uniform(0.0, 5.0),
        rng.next() % 7,
        rng.uniform(0.0, 0.2),
        rng.uniform(0.0, 0.01),
        rng.uniform(0.0, 0.1),
        rng.uniform(1.0, 30.0),
        rng.next() % 1000,
        rng.uniform(0.0, 0.01),
        rng.uniform(0.0, 0.005),
    )
    .unwrap();
    out
}

#[test]
fn generated_valid_scenes_plan_or_say_why_never_panic() {
    let count: u64 = std::env::var("PREGRASP_GENERATED_SCENES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000);
    let examples = pregrasp_examples::all();
    let options = PlanOptions {
        max_plans: 1,
        ..PlanOptions::default()
    };
    let (mut planned, mut no_plan) = (0, 0);
    let mut models_mixed = 0;
    for k in 0..count {
        let example = &examples[(k % examples.len() as u64) as usize];
        let text = scene_text(k, example);
        let scene = Scene::from_str(&text, Path::new("generated.toml"))
            .unwrap_or_else(|e| panic!("generated scene {k} is not valid: {e}\n{text}"));
        if scene.robots[0].arm != scene.robots[1].arm {
            models_mixed += 1;
        }
        let report = pregrasp_planner::plan_scene(&scene, &example.mesh, &options, &|_| {}, &|| {})
            .unwrap_or_else(|e| panic!("generated scene {k} cannot be planned: {e}\n{text}"));
        let file = report.file;
        pregrasp_planner::plan_format::validate(&file)
            .unwrap_or_else(|e| panic!("scene {k}: the plan file breaks the format: {e}"));
        assert_eq!(file.candidates.len(), report.outcomes.len(), "scene {k}");
        if std::env::var_os("PREGRASP_GENERATED_VERBOSE").is_some() {
            eprintln!("scene {k}: {}", file.reason.as_deref().unwrap_or("planned"));
        }
        if file.plans.is_empty() {
            assert!(
                file.reason.as_deref().is_some_and(|r| !r.is_empty()),
                "scene {k}: no plan and no reason"
            );
            no_plan += 1;
        } else {
            planned += 1;
        }
    }
    eprintln!(
        "{count} generated scenes: {planned} planned, {no_plan} no plan; {models_mixed} with two \
         different arm models"
    );
    assert!(models_mixed > 0 || count < 10);
}
