//! Arms that are not Universal Robots, read from their descriptions (issue 36): two Franka FR3
//! (elbow joint `fr3_joint3` held at 0, the planner driving the other six) and two UFACTORY
//! xArm6, each with the 2F-85 on its flange, and two FR3 with the Franka Hand their description
//! carries (`gripper = "urdf"`), plan the examples and pass the check; the plan
//! file names the description, the held joint and the six driven joints; the same scene
//! plans to the same bytes; μ_rot stays on one IK branch.

mod common;

use common::scenes::auto_scene;
use pregrasp_examples::arm_in_place::ArmInPlace;
use std::path::{Path, PathBuf};

use pregrasp_geometry::Mesh;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::{PlanFile, PlanStatus, RobotModel, SegmentName};
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::PlanOptions;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An arm to put in place of the examples' UR5e: its `[[robot]]` keys and its start.
struct Arm {
    keys: String,
    start: &'static str,
}

/// A described arm as `pregrasp example generate --arm` puts it in place of a UR5e: its keys
/// and start (Franka's "ready" posture without the held joint for the FR3).
fn described(name: &str) -> Arm {
    match ArmInPlace::by_name(name, &root().join("data/robots")).unwrap() {
        ArmInPlace::Described { keys, start, .. } => Arm { keys, start },
        ArmInPlace::Ur(_) => unreachable!("{name} is described"),
    }
}

fn fr3() -> Arm {
    described("fr3")
}

/// The FR3 with the Franka Hand its description carries (`gripper = "urdf"`).
fn fr3_hand() -> Arm {
    let mut arm = fr3();
    arm.keys.push_str("\ngripper = \"urdf\"");
    arm
}

fn xarm6() -> Arm {
    described("xarm6")
}

/// The text of example `name` with `arm` for each UR5e, the arms' bases at `x` (and y = ±`y`)
/// in the world, and the example's path.
fn scene_text(name: &str, arm: &Arm, x: f64, y: f64) -> (PathBuf, String) {
    let scene_path = root().join(format!("examples/{name}.toml"));
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let mut out = String::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if line.trim() == "model = \"ur5e\"" {
            let base = lines.next().unwrap();
            let side = if base.contains("-0.450") { -y } else { y };
            lines.next().expect("the start line");
            out.push_str(&format!(
                "{}\nbase = {{ xyz = [{x}, {side}, 0.0] }}\nstart = {}\n",
                arm.keys, arm.start
            ));
        } else if arm.keys.contains("gripper =")
            && ["gripper =", "precision_point_z", "power_point_z"]
                .iter()
                .any(|k| line.trim().starts_with(k))
        {
            // The arm brings its own gripper, and its tool points with it.
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    (scene_path, out)
}

/// Example `name` with `arm` for each UR5e, the arms' bases at `x` (and y = ±`y`) in the
/// world, planned: (scene path, scene, plan file, mesh).
fn plan_with(name: &str, arm: &Arm, x: f64, y: f64) -> (PathBuf, Scene, PlanFile, Mesh) {
    let (scene_path, out) = scene_text(name, arm, x, y);
    let scene = Scene::from_str(&out, &scene_path).unwrap();
    let mesh = load_mesh(&scene.object.mesh_path, scene.object.scale)
        .unwrap()
        .mesh;
    let options = PlanOptions::default();
    let file = pregrasp_planner::plan_scene(&scene, &mesh, &options, &|_| {}, &|| {})
        .unwrap()
        .file;
    (scene_path, scene, file, mesh)
}

/// The plan file describes the arms as they were given, and every plan passes the check.
fn planned_and_valid(name: &str, file: &PlanFile, mesh: &Mesh, joints: &[&str; 6]) {
    assert_eq!(
        file.status,
        PlanStatus::Planned,
        "{name}: {:?}",
        file.reason
    );
    assert!(!file.plans.is_empty());
    for r in &file.robots {
        assert_eq!(r.model, RobotModel::Described);
        assert_eq!(r.joint_names, joints.map(str::to_string));
        assert!(r.urdf.is_some());
    }
    let check = pregrasp_planner::check::check_plan(file, mesh);
    assert!(check.is_valid(), "{name}: {:?}", check.rules);
}

/// The check finds the descriptions from the plan file's scene, as `pregrasp check` does with
/// a file (here one said to be in the temporary folder), and passes the plan.
fn valid_as_read_from_a_file(name: &str, file: &PlanFile, mesh: &Mesh) {
    let path = std::env::temp_dir().join(format!("pregrasp-{name}.json"));
    let check = pregrasp_planner::check::check_plan_at(file, Some(&path), mesh);
    assert!(check.is_valid(), "{name}: {:?}", check.rules);
}

/// Along μ_rot the supportive arm stays on one branch: no joint moves more than 0.1 rad
/// between two points (the part turns by Δφ = 1° between them; a branch switch moves some
/// joint by far more).
fn rotation_on_one_branch(name: &str, file: &PlanFile) {
    for plan in &file.plans {
        let rot = plan
            .segments
            .iter()
            .find(|s| s.name == SegmentName::Rot)
            .unwrap();
        for w in rot.points.windows(2) {
            let step = (0..6)
                .map(|j| (w[1].q[j] - w[0].q[j]).abs())
                .fold(0.0, f64::max);
            assert!(step < 0.1, "{name}: μ_rot joint step {step} rad");
        }
    }
}

const FR3_JOINTS: [&str; 6] = [
    "fr3_joint1",
    "fr3_joint2",
    "fr3_joint4",
    "fr3_joint5",
    "fr3_joint6",
    "fr3_joint7",
];

#[test]
fn two_fr3_plan_the_three_examples_and_pass_the_check() {
    // The chair where the UR5e stand; the shelf and the stool, nearer the base, 10 cm closer.
    for (name, x) in [
        ("chair_side", 0.0),
        ("shelf_side", 0.1),
        ("stool_side", 0.1),
    ] {
        let (_, _, file, mesh) = plan_with(name, &fr3(), x, 0.45);
        planned_and_valid(name, &file, &mesh, &FR3_JOINTS);
        rotation_on_one_branch(name, &file);
        let urdf = file.robots[0].urdf.as_ref().unwrap();
        assert_eq!(urdf.tool_link, "fr3_link8");
        assert_eq!(urdf.held.get("fr3_joint3"), Some(&0.0));
        valid_as_read_from_a_file(name, &file, &mesh);
    }
}

#[test]
fn two_fr3_with_the_franka_hand_plan_the_three_examples_and_pass_the_check() {
    // Where the UR5e stand, the stool's arms 10 cm nearer the part.
    for (name, x) in [
        ("chair_side", 0.0),
        ("shelf_side", 0.0),
        ("stool_side", 0.1),
    ] {
        let (_, _, file, mesh) = plan_with(name, &fr3_hand(), x, 0.45);
        planned_and_valid(name, &file, &mesh, &FR3_JOINTS);
        rotation_on_one_branch(name, &file);
        for r in &file.robots {
            assert_eq!(r.gripper.as_deref(), Some("urdf"));
            // The tool points carry the hand's turn: x is the jaws' closing axis.
            let q = r.precision_point.quat_xyzw;
            let angle = 2.0 * q[2].atan2(q[3]);
            assert!(
                (angle - std::f64::consts::FRAC_PI_4).abs() < 1e-12,
                "{angle}"
            );
        }
        // Every closing is the jaws': a width, no 2F-85 finger joints. The pinch holds within
        // the hand's 100 N (its description's jaw effort), not the 2F-85's 235 N.
        for plan in &file.plans {
            let physics = plan.physics.as_ref().expect("the part's mass is known");
            let force = physics.grip_force_recommended.expect("the rotation holds");
            assert!(force <= 100.0, "{name}: {force} N");
            for seg in plan.segments.iter().filter(|s| s.grip_width.is_some()) {
                assert!(seg.fingers.is_none(), "{name}: {}", seg.name);
                let w = seg.grip_width.unwrap();
                assert!(w > 0.0 && w < 0.08, "{name}: {} closes at {w} m", seg.name);
            }
        }
        valid_as_read_from_a_file(name, &file, &mesh);
    }
}

#[test]
fn two_xarm6_plan_the_stool() {
    let (_, _, file, mesh) = plan_with("stool_side", &xarm6(), 0.1, 0.35);
    let joints = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6"];
    planned_and_valid("stool_side", &file, &mesh, &joints);
    rotation_on_one_branch("stool_side", &file);
}

/// An allowed-collision list travels with the plan: the file records it and `check` loads the
/// arm with it.
#[test]
fn allowed_pairs_are_planned_with_and_checked_with() {
    let mut arm = fr3();
    arm.keys
        .push_str("\nallow_collisions = [[\"fr3_link1\", \"fr3_link6\"]]");
    let (_, _, file, mesh) = plan_with("chair_side", &arm, 0.0, 0.45);
    planned_and_valid("chair_side", &file, &mesh, &FR3_JOINTS);
    let urdf = file.robots[0].urdf.as_ref().unwrap();
    assert_eq!(
        urdf.allow_collisions,
        [["fr3_link1".to_string(), "fr3_link6".to_string()]]
    );
}

#[test]
fn an_fr3_scene_plans_to_the_same_bytes_twice() {
    let (_, _, a, _) = plan_with("chair_side", &fr3(), 0.0, 0.45);
    let (_, _, b, _) = plan_with("chair_side", &fr3(), 0.0, 0.45);
    let bytes = |f: &PlanFile| {
        let mut f = f.clone();
        f.timing_ms.clear();
        f.to_json()
    };
    assert_eq!(bytes(&a), bytes(&b));
}

#[test]
fn a_seven_joint_arm_needs_a_held_joint_and_a_ur_none() {
    let scene_path = root().join("examples/chair_side.toml");
    let text = std::fs::read_to_string(&scene_path).unwrap();
    // The scene's error with the first arm's `model` line replaced by `keys`.
    let error_with = |keys: String| {
        let text = text.replacen("model = \"ur5e\"", &keys, 1);
        Scene::from_str(&text, &scene_path).unwrap_err().to_string()
    };
    let fr3 = format!(
        "urdf = {:?}\ntool_link = \"fr3_link8\"",
        root().join("data/robots/fr3.urdf").display().to_string()
    );
    let err = error_with(fr3.clone());
    assert!(err.contains("robot[0].urdf"), "{err}");
    assert!(
        err.contains("7 actuated joints") && err.contains("hold one joint"),
        "{err}"
    );
    let err = error_with(format!("{fr3}\nhold = {{ fr3_joint9 = 0.0 }}"));
    assert!(
        err.contains("robot[0].hold") && err.contains("fr3_joint9"),
        "{err}"
    );
    let err = error_with(format!(
        "{fr3}\nhold = {{ fr3_joint3 = 0.0 }}\nallow_collisions = [[\"fr3_link1\", \"fr3_wing\"]]"
    ));
    assert!(
        err.contains("robot[0].allow_collisions") && err.contains("fr3_wing"),
        "{err}"
    );
    let ur5e = root().join("data/robots/ur5e.urdf");
    let err = error_with(format!(
        "urdf = {:?}\nhold = {{ shoulder_pan_joint = 0.0 }}",
        ur5e.display().to_string()
    ));
    assert!(
        err.contains("robot[0].hold") && err.contains("nothing to hold"),
        "{err}"
    );
}

#[test]
fn a_urdf_gripper_needs_a_description_with_jaws() {
    let scene_path = root().join("examples/chair_side.toml");
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let error_with = |from: &str, to: String| {
        let text = text.replacen(from, &to, 1);
        Scene::from_str(&text, &scene_path).unwrap_err().to_string()
    };
    // A built-in arm has no description to take the gripper from.
    let err = error_with(
        "gripper = \"robotiq_2f85\"",
        "gripper = \"urdf\"".to_string(),
    );
    assert!(
        err.contains("robot[0].gripper") && err.contains("give `urdf`"),
        "{err}"
    );
    // The UR5e's description ends at tool0: no jaws below it.
    let ur5e = root().join("data/robots/ur5e.urdf");
    let keys = format!("urdf = {:?}", ur5e.display().to_string());
    let described = text.replacen("model = \"ur5e\"", &keys, 1);
    let err = Scene::from_str(
        &described.replacen("gripper = \"robotiq_2f85\"", "gripper = \"urdf\"", 1),
        &scene_path,
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("robot[0].gripper") && err.contains("0 prismatic joints"),
        "{err}"
    );
}

/// Issue 49: the grasp search works for a jaw gripper too, with its own stroke, jaws and
/// open-hand test. Two FR3 with the Franka Hand plan the examples with `mode = "auto"`, every
/// plan passes the check (rule 2 included: no open jaw or palm inside the part), and the
/// search chose its own grasps.
#[test]
fn two_fr3_with_the_franka_hand_plan_the_examples_from_auto_grasps() {
    for (name, x) in [
        ("chair_side", 0.0),
        ("shelf_side", 0.0),
        ("stool_side", 0.1),
    ] {
        let (path, text) = scene_text(name, &fr3_hand(), x, 0.45);
        let auto = auto_scene(&text, "");
        let scene = Scene::from_str(&auto, &path).unwrap();
        let mesh = load_mesh(&scene.object.mesh_path, scene.object.scale)
            .unwrap()
            .mesh;
        let file =
            pregrasp_planner::plan_scene(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
                .unwrap()
                .file;
        planned_and_valid(name, &file, &mesh, &FR3_JOINTS);
        let search = file.grasps.auto.as_ref().expect("the search is reported");
        assert!(
            search.sites > 0 && search.chosen.is_some(),
            "{name}: {search:?}"
        );
        // Every bar the jaws close on fits their 80 mm stroke.
        assert!(
            search.widths.iter().all(|&w| w > 0.0 && w < 0.08),
            "{name}: {search:?}"
        );
        for plan in &file.plans {
            for seg in plan.segments.iter().filter(|s| s.grip_width.is_some()) {
                assert!(seg.fingers.is_none(), "{name}: {}", seg.name);
            }
        }
    }
}
