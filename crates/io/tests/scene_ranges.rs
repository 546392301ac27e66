//! Every number of a scene is checked for range, not only for type: start configurations
//! within the arm's joint limits (a 9.5 rad shoulder pan on a UR5e is refused), gripper points
//! inside the hand, lengths in metres, and each `[planner]` key within its documented range.
//! Each refusal names the file, the key and, for joints, the robot and the joint.

use std::f64::consts::{PI, TAU};
use std::path::Path;

use pregrasp_io::scene::{Scene, SceneError, GRIPPER_POINT_RANGE, MAX_COORDINATE, ROBOT_MODELS};
use pregrasp_robot::UrModel;

/// A valid scene; the tests replace one line of it.
const SCENE: &str = r#"
name = "ranges"

[support]
height = 0.0

[object]
mesh = "meshes/part.stl"
scale = 1.0
pose = { xyz = [0.55, 0.0, 0.0], rpy_deg = [0, 0, 90] }

[grasps]
power = [
  { xyz = [0.02, 0.10, 0.40], rpy_deg = [180, 0, 90] },
  { xyz = [0.02, 0.70, 0.40], rpy_deg = [180, 0, 90] },
]
support = { xyz = [0.20, 0.42, 0.03], rpy_deg = [180, 0, 0] }

[[robot]]
name = "left"
model = "ur5e"
base = { xyz = [0.0, 0.45, 0.0] }
start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]

[[robot]]
name = "right"
model = "ur5e"
base = { xyz = [0.0, -0.45, 0.0] }
start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]

[planner]
step_deg = 1.0
max_angle_deg = 90.0
"#;

const RIGHT_START: &str = "name = \"right\"\nmodel = \"ur5e\"\nbase = { xyz = [0.0, -0.45, 0.0] }\nstart = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]";

fn load(text: &str) -> Result<Scene, SceneError> {
    Scene::from_str(text, Path::new("scene.toml"))
}

/// SCENE with `from` replaced by `to` (which must occur once).
fn with(from: &str, to: &str) -> String {
    assert_eq!(SCENE.matches(from).count(), 1, "{from:?}");
    SCENE.replacen(from, to, 1)
}

/// The right arm (robot[1]) with `model` and start `line` (`start = [...]` or `start_deg = [...]`).
fn right_arm(model: &str, line: &str) -> String {
    with(
        RIGHT_START,
        &format!(
            "name = \"right\"\nmodel = \"{model}\"\nbase = {{ xyz = [0.0, -0.45, 0.0] }}\n{line}"
        ),
    )
}

#[test]
fn the_scene_loads() {
    let s = load(SCENE).unwrap();
    assert_eq!(s.robots[1].name, "right");
}

#[test]
fn a_shoulder_pan_of_9_5_rad_on_a_ur5e_is_refused_naming_robot_and_joint() {
    let err = load(&right_arm(
        "ur5e",
        "start = [9.5, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]",
    ))
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "scene.toml: robot[1].start[0]: 9.5 rad is outside the ur5e joint limits [-6.283, 6.283] \
         (shoulder_pan of robot \"right\")"
    );
    assert_eq!(err.key(), Some("robot[1].start[0]"));
}

#[test]
fn every_joint_of_every_model_is_checked_against_its_limits() {
    for model in UrModel::ALL {
        let limits = model.joint_limits();
        for (j, &(lo, hi)) in limits.iter().enumerate() {
            for (value, inside) in [
                (lo, true),
                (hi, true),
                (0.5 * (lo + hi), true),
                (hi + 1e-6, false),
                (lo - 1e-6, false),
                (hi + 3.0, false),
            ] {
                let mut q = [0.0; 6];
                q[j] = value;
                let line = format!("start = [{}]", q.map(|v| format!("{v:?}")).join(", "));
                let result = load(&right_arm(model.name(), &line));
                if inside {
                    let s = result.unwrap_or_else(|e| panic!("{model} joint {j} = {value}: {e}"));
                    assert_eq!(s.robots[1].start[j], value);
                } else {
                    let msg = result
                        .expect_err(&format!("{model} joint {j} = {value}"))
                        .to_string();
                    assert!(
                        msg.starts_with(&format!("scene.toml: robot[1].start[{j}]: {value} rad is outside the {model} joint limits")),
                        "{msg}"
                    );
                    assert!(msg.contains(pregrasp_robot::JOINT_NAMES[j]), "{msg}");
                    assert!(msg.contains("robot \"right\""), "{msg}");
                }
            }
        }
    }
}

#[test]
fn the_elbow_is_kept_within_pi_and_start_deg_is_checked_in_degrees() {
    // ±2π is allowed on the shoulder but not on the elbow (±π).
    let err = load(&right_arm(
        "ur5e",
        "start = [0.0, -1.5708, 3.3, -1.5708, -1.5708, 0.0]",
    ))
    .unwrap_err()
    .to_string();
    assert_eq!(
        err,
        "scene.toml: robot[1].start[2]: 3.3 rad is outside the ur5e joint limits [-3.142, 3.142] \
         (elbow of robot \"right\")"
    );
    let err = load(&right_arm(
        "ur10e",
        "start_deg = [0, -90, 90, -90, -90, 400]",
    ))
    .unwrap_err()
    .to_string();
    assert!(
        err.starts_with("scene.toml: robot[1].start_deg[5]: 400")
            && err.contains("° is outside the ur10e joint limits [-360, 360]°")
            && err.ends_with("(wrist_3 of robot \"right\")"),
        "{err}"
    );
    // Exactly ±360° and ±180° (2π and π give or take rounding) are inside.
    let s = load(&right_arm(
        "ur5e",
        "start_deg = [360, -360, 180, -180, 0, 0]",
    ))
    .unwrap();
    assert!((s.robots[1].start[0] - TAU).abs() < 1e-12);
    assert!((s.robots[1].start[2] - PI).abs() < 1e-12);
}

#[test]
fn the_model_list_is_the_robot_crates() {
    let names: Vec<&str> = UrModel::ALL.iter().map(|m| m.name()).collect();
    assert_eq!(names, ROBOT_MODELS);
}

#[test]
fn gripper_points_lie_in_the_hand_power_deeper_than_precision() {
    let (lo, hi) = GRIPPER_POINT_RANGE;
    assert!(lo < 0.115 && 0.150 < hi, "the defaults are inside");
    let arm = |extra: &str| {
        with(
            "start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]\n\n[[robot]]\nname = \"right\"",
            &format!("start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]\n{extra}\n\n[[robot]]\nname = \"right\""),
        )
    };
    let s = load(&arm("precision_point_z = 0.1735\npower_point_z = 0.1008")).unwrap();
    assert_eq!(
        (s.robots[0].precision_point_z, s.robots[0].power_point_z),
        (0.1735, 0.1008)
    );
    for (extra, key, words) in [
        (
            "precision_point_z = 0.25",
            "robot[0].precision_point_z",
            "0.25 m is outside [0.1008, 0.1735] m",
        ),
        (
            "precision_point_z = -0.15",
            "robot[0].precision_point_z",
            "outside",
        ),
        (
            "power_point_z = 0.05",
            "robot[0].power_point_z",
            "0.05 m is outside [0.1008, 0.1735] m, the robotiq_2f85's",
        ),
        (
            "power_point_z = 0.16",
            "robot[0].power_point_z",
            "beyond precision_point_z = 0.15 m",
        ),
        (
            "precision_point_z = 0.12\npower_point_z = 0.13",
            "robot[0].power_point_z",
            "deeper in the hand",
        ),
    ] {
        let msg = load(&arm(extra)).expect_err(extra).to_string();
        assert!(
            msg.starts_with(&format!("scene.toml: {key}: ")),
            "{extra}: {msg}"
        );
        assert!(msg.contains(words), "{extra}: {msg}");
    }
}

#[test]
fn lengths_are_in_metres() {
    assert_eq!(MAX_COORDINATE, 100.0);
    for (from, to, key) in [
        ("height = 0.0", "height = -250.0", "support.height"),
        (
            "xyz = [0.55, 0.0, 0.0]",
            "xyz = [550.0, 0.0, 0.0]",
            "object.pose.xyz[0]",
        ),
        (
            "xyz = [0.20, 0.42, 0.03]",
            "xyz = [0.20, 420, 0.03]",
            "grasps.support.xyz[1]",
        ),
        (
            "base = { xyz = [0.0, 0.45, 0.0] }",
            "base = { xyz = [0.0, 0.45, 1e3] }",
            "robot[0].base.xyz[2]",
        ),
    ] {
        let msg = load(&with(from, to)).expect_err(to).to_string();
        assert!(
            msg.starts_with(&format!("scene.toml: {key}: "))
                && msg.contains("m from the origin (lengths are in metres)"),
            "{to}: {msg}"
        );
    }
    // 100 m itself is accepted.
    load(&with("height = 0.0", "height = -100.0")).unwrap();
}

#[test]
fn planner_keys_have_ranges() {
    let planner = |lines: &str| with("step_deg = 1.0\nmax_angle_deg = 90.0", lines);
    for (lines, key, words) in [
        (
            "weight_length = -1.0",
            "planner.weight_length",
            "must be >= 0, found -1",
        ),
        (
            "weight_angle = -0.5",
            "planner.weight_angle",
            "must be >= 0",
        ),
        (
            "max_angle_deg = 200.0",
            "planner.max_angle_deg",
            "must be at most 180°",
        ),
        (
            "max_angle = 4.0",
            "planner.max_angle",
            "must be at most 180°",
        ),
        (
            "step_deg = 10.0\nmax_angle_deg = 5.0",
            "planner.step_deg",
            "larger than max_angle",
        ),
        (
            "max_joint_step_deg = 270",
            "planner.max_joint_step_deg",
            "must be at most 180°",
        ),
        (
            "max_joint_step = 0",
            "planner.max_joint_step",
            "must be > 0",
        ),
        ("lift = -0.001", "planner.lift", "must be >= 0"),
        (
            "approach_distance = -0.05",
            "planner.approach_distance",
            "must be >= 0",
        ),
        (
            "min_grasp_axis_distance = -1",
            "planner.min_grasp_axis_distance",
            "must be >= 0",
        ),
        (
            "min_axis_length = -0.05",
            "planner.min_axis_length",
            "must be >= 0",
        ),
        ("extra_steps = -1", "planner.extra_steps", "must be >= 0"),
        (
            "extra_steps = 5000000000",
            "planner.extra_steps",
            "too large",
        ),
    ] {
        let msg = load(&planner(lines)).expect_err(lines).to_string();
        assert!(
            msg.starts_with(&format!("scene.toml: {key}: ")),
            "{lines}: {msg}"
        );
        assert!(msg.contains(words), "{lines}: expected {words:?} in {msg}");
    }
    // The ends of the ranges are accepted.
    let s = load(&planner(
        "step_deg = 180\nmax_angle_deg = 180\nmax_joint_step_deg = 180\nweight_length = 0\nweight_angle = 0\nlift = 0\napproach_distance = 0",
    ))
    .unwrap();
    assert!((s.planner.max_angle - PI).abs() < 1e-15 && s.planner.step == s.planner.max_angle);
}
