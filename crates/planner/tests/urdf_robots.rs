//! Arms read from a robot description (`[[robot]] urdf = …`, issue 36): the UR5e of the
//! Universal Robots ROS 2 description (`data/robots/ur5e.urdf`) plans the examples as the
//! built-in UR5e does (other arms: `non_ur_arms.rs`).

use std::path::{Path, PathBuf};

use pregrasp_geometry::Mesh;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::PlanOptions;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The example scene with each `model = "ur5e"` line replaced by the ROS 2 description's UR5e.
/// The scene's `base` then places the description's root link, which is the controller's
/// Base turned by π about z: the same arm stands at `rotation`, a half turn about z
/// (`quat_xyzw = [0, 0, 1, 0]` exactly, or `rpy_deg = [0, 0, 180]` give or take 1e-16).
fn with_urdf_arms(text: &str, rotation: &str) -> String {
    let urdf = root().join("data/robots/ur5e.urdf");
    let mut out = String::new();
    for line in text.lines() {
        if line.trim() == "model = \"ur5e\"" {
            out.push_str(&format!("urdf = {:?}\n", urdf.display().to_string()));
        } else if let Some(xyz) = line
            .strip_prefix("base = { xyz = ")
            .and_then(|rest| rest.strip_suffix(" }"))
        {
            out.push_str(&format!("base = {{ xyz = {xyz}, {rotation} }}\n"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// Example `name` with the built-in arms and with the described ones placed by `rotation`,
/// both planned: (built-in scene, described scene, built-in plan, described plan, mesh).
fn plan_both(name: &str, rotation: &str) -> (Scene, Scene, PlanFile, PlanFile, Mesh) {
    let scene_path = root().join(format!("examples/{name}.toml"));
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let built_in = Scene::from_str(&text, &scene_path).unwrap();
    let described = Scene::from_str(&with_urdf_arms(&text, rotation), &scene_path).unwrap();
    let mesh = load_mesh(&built_in.object.mesh_path, built_in.object.scale)
        .unwrap()
        .mesh;
    let options = PlanOptions::default();
    let plan =
        |s: &Scene| pregrasp_planner::plan_scene(s, &mesh, &options, &|_| {}, &|| {}).unwrap();
    let (a, b) = (plan(&built_in).file, plan(&described).file);
    (built_in, described, a, b, mesh)
}

#[test]
fn the_ros2_ur5e_plans_the_examples_as_the_built_in_one() {
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let (built_in, described, a, b, mesh) = plan_both(name, "quat_xyzw = [0, 0, 1, 0]");
        for (a, b) in built_in.robots.iter().zip(&described.robots) {
            assert_eq!(a.arm, b.arm);
            let urdf = b.urdf.as_ref().expect("the arm names its description");
            // The description's root (`world`, fixed to `base_link`) and its flange frame.
            assert_eq!(
                (urdf.base_link.as_str(), urdf.tool_link.as_str()),
                ("world", "tool0")
            );
            // The DH Base lands where the built-in arm's is, up to the turn's round-off.
            let d = a.base.inverse() * b.base;
            assert!(
                d.translation.vector.norm() < 1e-12 && d.rotation.angle() < 1e-12,
                "{d}"
            );
        }
        assert_eq!(a.status, b.status, "{name}");
        // Bit for bit: the description's arm is the built-in arm.
        let plans = |f: &PlanFile| serde_json::to_string(&f.plans).unwrap();
        assert_eq!(plans(&a), plans(&b), "{name}");
        assert_eq!(a.candidates, b.candidates, "{name}");
        // The file says which description each arm came from, and names its joints.
        let robot = &b.robots[0];
        assert_eq!(robot.urdf.as_ref().unwrap().tool_link, "tool0");
        assert_eq!(robot.joint_names[0], "shoulder_pan_joint");
        let check = pregrasp_planner::check::check_plan(&b, &mesh);
        assert!(check.is_valid(), "{name}: {:?}", check.rules);
    }
}

#[test]
fn a_model_that_contradicts_the_description_is_refused() {
    let scene_path = root().join("examples/chair_side.toml");
    let ur5e = root().join("data/robots/ur5e.urdf");
    let text = std::fs::read_to_string(&scene_path).unwrap().replacen(
        "model = \"ur5e\"",
        &format!("model = \"ur10e\"\nurdf = {:?}", ur5e.display().to_string()),
        1,
    );
    let err = Scene::from_str(&text, &scene_path).unwrap_err().to_string();
    assert!(
        err.contains("robot[0].model") && err.contains("is a ur5e"),
        "{err}"
    );
}

/// The same arm placed by `rpy_deg = [0, 0, 180]` (a half turn give or take 1e-16) plans too,
/// and its plans pass the check; the motions may differ from the built-in arm's where a
/// random search meets the round-off, the poses not.
#[test]
fn the_ros2_ur5e_placed_by_rpy_plans_and_passes_the_check() {
    let (_, _, a, b, mesh) = plan_both("chair_side", "rpy_deg = [0, 0, 180]");
    assert_eq!(a.plans.len(), b.plans.len());
    for (pa, pb) in a.plans.iter().zip(&b.plans) {
        assert_eq!(pa.candidate, pb.candidate);
        let d = pa.object_goal_pose.to_isometry().inverse() * pb.object_goal_pose.to_isometry();
        assert!(d.translation.vector.norm() < 1e-9 && d.rotation.angle() < 1e-9);
    }
    let check = pregrasp_planner::check::check_plan(&b, &mesh);
    assert!(check.is_valid(), "{:?}", check.rules);
}

/// Branch continuity along μ_rot: the numerical solver of `pregrasp-urdf`, tracking each
/// golden plan's μ_rot tool poses with the ROS 2 description's UR5e from the plan's first
/// configuration, stays on the plan's own branch — every point within 1e-6 rad of the planned
/// joints, which the analytic solver chose.
#[test]
fn the_numerical_solver_follows_every_golden_rotation_on_its_branch() {
    let arm =
        pregrasp_urdf::UrdfArm::load(&root().join("data/robots/ur5e.urdf"), None, None).unwrap();
    let ur = arm.ur.expect("the UR5e is recognised");
    let mut followed = 0;
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/golden/{name}.json"));
        let file = PlanFile::from_json_str(&std::fs::read_to_string(&path).unwrap(), name).unwrap();
        for plan in &file.plans {
            let rot = plan
                .segments
                .iter()
                .find(|s| s.name == pregrasp_io::plan_file::SegmentName::Rot)
                .unwrap();
            let mut q = rot.points[0].q.to_vec();
            for point in &rot.points[1..] {
                // The description's tool pose where the plan puts the arm: base · fk_dh · tool.
                let target = ur.fk(&point.q);
                q = arm
                    .chain
                    .ik_nearest(&target, &q)
                    .unwrap_or_else(|| panic!("{name}: lost the rotation at t = {}", point.t));
                let off = (0..6)
                    .map(|j| (q[j] - point.q[j]).abs())
                    .fold(0.0, f64::max);
                assert!(
                    off < 1e-6,
                    "{name}: {off} rad off the planned branch at t = {}",
                    point.t
                );
            }
            followed += 1;
        }
    }
    // chair 1, shelf 2, stool 1 (the chair's and the stool's second hang from the pinch)
    assert!(followed >= 4, "{followed} rotations followed");
}
