//! Scene files: the spec's example loads with the right values and defaults, and every kind of
//! bad scene is refused with one message naming the file and the key.

use pregrasp_robot::UrModel;
use std::path::Path;

use nalgebra::{UnitQuaternion, Vector3};
use pregrasp_io::scene::{PlannerParams, Scene, SceneError};

/// The example of `scene-format.md`, with the optional robot keys on robot 0 only.
const EXAMPLE: &str = r#"
name = "chair side"

[support]
height = 0.0

[object]
mesh = "meshes/chair_side.stl"
scale = 0.001
pose = { xyz = [0.55, 0.0, 0.0], rpy_deg = [0, 0, 90] }
mass = 4.0

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
gripper = "robotiq_2f85"
precision_point_z = 0.160
power_point_z = 0.120

[[robot]]
name = "right"
model = "ur5e"
base = { xyz = [0.0, -0.45, 0.0] }
start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]

[planner]
support_distance = 0.02
min_axis_length = 0.05
step_deg = 1.0
max_angle_deg = 90.0
weight_length = 1.0
weight_angle = 2.0
extra_steps = 3
min_grasp_axis_distance = 0.10
lift = 0.001
approach_distance = 0.05
max_joint_step_deg = 10.0
seed = 7
"#;

fn file() -> &'static Path {
    Path::new("scenes/x.toml")
}

fn load(text: &str) -> Result<Scene, SceneError> {
    Scene::from_str(text, file())
}

#[test]
fn spec_example_loads_with_its_values() {
    let s = load(EXAMPLE).unwrap();
    assert_eq!(s.name.as_deref(), Some("chair side"));
    assert_eq!(s.support_height, 0.0);
    assert_eq!(
        s.object.mesh_path,
        Path::new("scenes/meshes/chair_side.stl")
    );
    assert_eq!(s.object.scale, 0.001);
    assert_eq!(s.object.mass, Some(4.0));
    let t = s.object.pose.translation.vector;
    assert_eq!(t, Vector3::new(0.55, 0.0, 0.0));
    // rpy_deg [0, 0, 90]: x of the object points along world y.
    assert!((s.object.pose.rotation * Vector3::x() - Vector3::y()).norm() < 1e-15);
    // R = Rz(yaw) · Ry(pitch) · Rx(roll), fixed axes.
    let g = s.grasps.power[1];
    let expected = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 90f64.to_radians())
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 180f64.to_radians());
    assert!(g.rotation.angle_to(&expected) < 1e-12);
    assert_eq!(g.translation.vector, Vector3::new(0.02, 0.70, 0.40));
    let [l, r] = &s.robots;
    assert_eq!((l.name.as_str(), r.name.as_str()), ("left", "right"));
    assert_eq!(l.arm.ur, Some(UrModel::Ur5e));
    assert_eq!(l.start[1], "-1.5708".parse::<f64>().unwrap());
    assert_eq!((l.precision_point_z, l.power_point_z), (0.160, 0.120));
    assert_eq!(
        (r.gripper.as_str(), r.precision_point_z, r.power_point_z),
        ("robotiq_2f85", 0.150, 0.115)
    );
    assert_eq!(r.base.translation.vector, Vector3::new(0.0, -0.45, 0.0));
    assert_eq!(s.planner.support_distance, 0.02);
    assert_eq!(s.planner.weight_angle, 2.0);
    assert_eq!(s.planner.seed, 7);
    assert!((s.planner.step - 1f64.to_radians()).abs() < 1e-18);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // The plan file echoes the degrees exactly as written.
    let j = s.planner.to_json();
    assert_eq!(
        (j.step_deg, j.max_angle_deg, j.max_joint_step_deg),
        (1.0, 90.0, 10.0)
    );
    assert_eq!(s.initial_object_pose().translation.vector.z, 0.001);
}

#[test]
fn planner_defaults_follow_the_spec() {
    let start = EXAMPLE.find("[planner]").unwrap();
    let s = load(&EXAMPLE[..start]).unwrap();
    assert_eq!(s.planner, PlannerParams::default());
    let j = s.planner.to_json();
    assert_eq!(j.support_distance, 0.01);
    assert_eq!(j.min_axis_length, 0.05);
    assert_eq!(
        (j.step_deg, j.max_angle_deg, j.max_joint_step_deg),
        (1.0, 90.0, 10.0)
    );
    assert_eq!(
        (j.weight_length, j.weight_angle, j.extra_steps),
        (1.0, 1.0, 3)
    );
    assert_eq!(
        (
            j.min_grasp_axis_distance,
            j.lift,
            j.approach_distance,
            j.seed
        ),
        (0.10, 0.001, 0.05, 0)
    );
}

#[test]
fn alternative_spellings() {
    let text = EXAMPLE
        .replace("rpy_deg = [180, 0, 0]", "quat_xyzw = [2, 0, 0, 0]")
        .replace("step_deg = 1.0", "step = 0.02")
        .replace(
            "start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]\ngripper",
            "start_deg = [0, -90, 90, -90, -90, 0]\ngripper",
        )
        .replace("scale = 0.001\n", "");
    let s = load(&text).unwrap();
    // Quaternions are normalised: [2, 0, 0, 0] is 180° about x.
    assert!((s.grasps.support.rotation * Vector3::y() + Vector3::y()).norm() < 1e-15);
    assert_eq!(s.planner.step, 0.02);
    assert!((s.robots[0].start[1] + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(s.object.scale, 1.0);
}

#[test]
fn unknown_keys_are_warnings() {
    let text = EXAMPLE
        .replace("mass = 4.0", "mass = 4.0\ncolour = \"red\"")
        .replace("seed = 7", "seed = 7\nturbo = true");
    let s = load(&text).unwrap();
    assert_eq!(
        s.warnings,
        vec![
            "scenes/x.toml: object.colour: unknown key (ignored)",
            "scenes/x.toml: planner.turbo: unknown key (ignored)"
        ]
    );
}

#[test]
fn unknown_keys_are_reported_in_key_order() {
    // Each table's keys alphabetically, depth first, whatever the file's order; an unknown
    // key's value (here a date and a table) is not looked into.
    let text = format!("zeta = 1\nalpha = {{ beta = 2 }}\n{EXAMPLE}")
        .replace("[support]", "[support]\nwhen = 1979-05-27")
        .replace(
            "base = { xyz = [0.0, 0.45, 0.0] }",
            "base = { xyz = [0.0, 0.45, 0.0], frame = \"tool\" }\ncolour = 1",
        );
    let s = load(&text).unwrap();
    let keys: Vec<&str> = s
        .warnings
        .iter()
        .map(|w| w.strip_prefix("scenes/x.toml: ").unwrap())
        .map(|w| w.strip_suffix(": unknown key (ignored)").unwrap())
        .collect();
    assert_eq!(
        keys,
        [
            "alpha",
            "robot[0].base.frame",
            "robot[0].colour",
            "support.when",
            "zeta"
        ]
    );
}

#[test]
fn mesh_path_is_relative_to_the_scene_file() {
    let s = Scene::from_str(EXAMPLE, Path::new("x.toml")).unwrap();
    assert_eq!(s.object.mesh_path, Path::new("meshes/chair_side.stl"));
    let s = Scene::from_str(EXAMPLE, Path::new("/a/b/x.toml")).unwrap();
    assert_eq!(s.object.mesh_path, Path::new("/a/b/meshes/chair_side.stl"));
    assert_eq!(s.object.mesh_entry, "meshes/chair_side.stl");
}

#[test]
fn the_briefs_example_message() {
    let text = EXAMPLE;
    let i = text.rfind("model = \"ur5e\"").unwrap();
    let text = format!(
        "{}model = \"ur7\"{}",
        &text[..i],
        &text[i + "model = \"ur5e\"".len()..]
    );
    let err = load(&text).unwrap_err();
    assert_eq!(
        err.to_string(),
        "scenes/x.toml: robot[1].model: unknown robot model \"ur7\" (expected one of ur3e, ur5e, ur10e, ur16e, ur5)"
    );
    assert_eq!(err.key(), Some("robot[1].model"));
}

/// (what to replace, replacement, key named, words in the message)
const BAD: &[(&str, &str, &str, &str)] = &[
    ("[support]\nheight = 0.0", "", "support", "missing key"),
    ("height = 0.0", "height = \"zero\"", "support.height", "expected a number, found a string"),
    ("height = 0.0", "height = nan", "support.height", "finite"),
    ("height = 0.0", "height = -inf", "support.height", "finite"),
    ("height = 0.0", "", "support.height", "missing key"),
    ("mesh = \"meshes/chair_side.stl\"", "", "object.mesh", "missing key"),
    ("mesh = \"meshes/chair_side.stl\"", "mesh = 3", "object.mesh", "expected a string"),
    ("mesh = \"meshes/chair_side.stl\"", "mesh = \"\"", "object.mesh", "empty path"),
    ("scale = 0.001", "scale = -1.0", "object.scale", "must be > 0"),
    ("scale = 0.001", "scale = 0", "object.scale", "must be > 0"),
    ("mass = 4.0", "mass = -4.0", "object.mass", "must be in (0, 10000] kg"),
    ("mass = 4.0", "mass = 2e4", "object.mass", "must be in (0, 10000] kg, found 20000"),
    ("pose = { xyz = [0.55, 0.0, 0.0], rpy_deg = [0, 0, 90] }", "", "object.pose", "missing key"),
    ("xyz = [0.55, 0.0, 0.0], rpy_deg = [0, 0, 90]", "xyz = [0.55, 0.0], rpy_deg = [0, 0, 90]", "object.pose.xyz", "expected 3 numbers, found 2"),
    ("xyz = [0.55, 0.0, 0.0], rpy_deg = [0, 0, 90]", "rpy_deg = [0, 0, 90]", "object.pose.xyz", "missing key"),
    ("rpy_deg = [0, 0, 90]", "rpy_deg = [0, 0, 90], quat_xyzw = [0, 0, 0, 1]", "object.pose", "give one rotation"),
    ("rpy_deg = [0, 0, 90]", "quat_xyzw = [0, 0, 0, 0]", "object.pose.quat_xyzw", "zero quaternion"),
    ("rpy_deg = [0, 0, 90]", "rpy_deg = [0, \"x\", 90]", "object.pose.rpy_deg[1]", "expected a number"),
    ("rpy_deg = [0, 0, 90]", "rpy = 1.0", "object.pose.rpy", "expected an array of 3 numbers"),
    ("  { xyz = [0.02, 0.70, 0.40], rpy_deg = [180, 0, 90] },\n", "", "grasps.power", "expected exactly 2 poses, found 1"),
    ("support = { xyz = [0.20, 0.42, 0.03], rpy_deg = [180, 0, 0] }", "", "grasps.support", "missing key"),
    ("[grasps]", "[grasp]", "grasps", "missing key"),
    ("name = \"left\"", "name = \"right\"", "robot[1].name", "duplicate robot name"),
    ("name = \"left\"\n", "", "robot[0].name", "missing key"),
    ("model = \"ur5e\"\nbase = { xyz = [0.0, 0.45", "model = \"UR5e\"\nbase = { xyz = [0.0, 0.45", "robot[0].model", "unknown robot model \"UR5e\""),
    ("base = { xyz = [0.0, 0.45, 0.0] }", "", "robot[0].base", "missing key"),
    ("start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]\ngripper", "start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708]\ngripper", "robot[0].start", "expected 6 numbers, found 5"),
    ("start = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]\ngripper", "gripper", "robot[0].start", "missing key"),
    ("gripper = \"robotiq_2f85\"", "gripper = \"hand-e\"", "robot[0].gripper", "unknown gripper"),
    ("[[robot]]\nname = \"right\"", "[[robot]]\nname = \"third\"\nmodel = \"ur5\"\nbase = { xyz = [1, 0, 0] }\nstart = [0, 0, 0, 0, 0, 0]\n[[robot]]\nname = \"right\"", "robot", "expected exactly two [[robot]] tables, found 3"),
    ("step_deg = 1.0", "step_deg = 0.0", "planner.step_deg", "must be > 0"),
    ("step_deg = 1.0", "step_deg = 1.0\nstep = 0.1", "planner.step", "either step or step_deg"),
    ("max_angle_deg = 90.0", "max_angle_deg = -5", "planner.max_angle_deg", "must be > 0"),
    ("support_distance = 0.02", "support_distance = -0.02", "planner.support_distance", "must be >= 0"),
    ("lift = 0.001", "lift = \"1mm\"", "planner.lift", "expected a number"),
    ("extra_steps = 3", "extra_steps = 1.5", "planner.extra_steps", "expected an integer"),
    ("seed = 7", "seed = -1", "planner.seed", "must be >= 0"),
    ("name = \"chair side\"", "name = 5", "name", "expected a string, found an integer"),
    ("[support]\nheight = 0.0", "support = 1.0", "support", "expected a table, found a float"),
    ("height = 0.0", "height = 1979-05-27", "support.height", "expected a number, found a date"),
    ("[support]\nheight = 0.0", "support = 1979-05-27", "support", "expected a table, found a date"),
    ("[grasps]", "[grasps]\nmode = 1979-05-27", "grasps.mode", "expected \"manual\" or \"auto\", found 1979-05-27"),
    ("[grasps]", "[grasps]\nmode = \"semi\"", "grasps.mode", "expected \"manual\" or \"auto\", found \"semi\""),
    ("xyz = [0.55, 0.0, 0.0], rpy_deg = [0, 0, 90]", "xyz = [\"a\", 0.0], rpy_deg = [0, 0, 90]", "object.pose.xyz", "expected 3 numbers, found 2"),
    ("  { xyz = [0.02, 0.70, 0.40], rpy_deg = [180, 0, 90] },\n", "  5,\n", "grasps.power[1]", "expected a table, found an integer"),
    ("power = [", "power = true\nunused = [", "grasps.power", "expected an array of 2 poses, found a boolean"),
    ("seed = 7", "seed = 7\n[physics]\nreject = \"yes\"", "physics.reject", "expected true or false, found a string"),
    ("seed = 7", "seed = 7\n[physics]\nreject_uncarried = 1", "physics.reject_uncarried", "expected true or false, found an integer"),
];

#[test]
fn reject_uncarried_is_off_unless_asked() {
    assert!(!load(EXAMPLE).unwrap().physics.reject_uncarried);
    let on = EXAMPLE.replacen(
        "seed = 7",
        "seed = 7\n[physics]\nreject_uncarried = true",
        1,
    );
    assert!(load(&on).unwrap().physics.reject_uncarried);
}

#[test]
fn every_bad_scene_names_file_and_key() {
    for &(from, to, key, words) in BAD {
        assert!(EXAMPLE.contains(from), "fixture does not contain {from:?}");
        let text = EXAMPLE.replacen(from, to, 1);
        let err = load(&text).expect_err(&format!("{from:?} -> {to:?} should fail"));
        let msg = err.to_string();
        assert!(
            msg.starts_with(&format!("scenes/x.toml: {key}: ")),
            "{from:?} -> {to:?}: {msg}"
        );
        assert!(
            msg.contains(words),
            "{from:?} -> {to:?}: expected {words:?} in {msg}"
        );
    }
}

#[test]
fn syntax_errors_and_unreadable_files() {
    let err = load("name = \"unterminated\n").unwrap_err();
    assert!(matches!(err, SceneError::Syntax { .. }));
    assert!(
        err.to_string()
            .starts_with("scenes/x.toml: not valid TOML: "),
        "{err}"
    );
    assert!(!err.to_string().contains('\n'));
    let err = Scene::load(Path::new("/nonexistent/dir/scene.toml")).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("/nonexistent/dir/scene.toml: cannot read scene file"),
        "{err}"
    );
}

#[test]
fn fixture_scene_loads_from_disk() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/box_scene.toml");
    let s = Scene::load(&path).unwrap();
    assert!(s.object.mesh_path.ends_with("tests/data/box.stl"));
    assert!(s.object.mesh_path.exists());
    assert_eq!(s.robots[1].base.rotation.angle(), std::f64::consts::PI);
}
