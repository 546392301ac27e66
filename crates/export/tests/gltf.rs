//! The glTF export, read back with the `gltf` crate (which validates the document): accessor
//! counts and bounds, one animation on the plan's time line, and node transforms at the plan's
//! time stamps equal to forward kinematics and the part's poses.

// Joint loops index several arrays at once (`for j in 0..6`): clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

mod common;

use pregrasp_io::plan_file::SegmentName;
use std::collections::HashMap;

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use pregrasp_export::{Format, Options};

fn glb() -> Vec<u8> {
    let (file, mesh) = common::chair_side();
    let out =
        common::export_file(file, 0, &[Format::Gltf], &Options::default(), Some(mesh)).unwrap();
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].name, "plan.glb");
    out[0].bytes.clone()
}

fn iso(t: [f32; 3], r: [f32; 4]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(t[0] as f64, t[1] as f64, t[2] as f64),
        UnitQuaternion::from_quaternion(Quaternion::new(
            r[3] as f64,
            r[0] as f64,
            r[1] as f64,
            r[2] as f64,
        )),
    )
}

/// Largest distance between the images of a few points (origin, 0.2 m along each axis) under
/// two poses: a position error that also sees rotation.
fn pose_gap(a: &Isometry3<f64>, b: &Isometry3<f64>) -> f64 {
    [
        Point3::origin(),
        Point3::new(0.2, 0.0, 0.0),
        Point3::new(0.0, 0.2, 0.0),
        Point3::new(0.0, 0.0, 0.2),
    ]
    .iter()
    .map(|p| (a * p - b * p).norm())
    .fold(0.0, f64::max)
}

#[test]
fn glb_parses_validates_and_accessors_are_consistent() {
    let bytes = glb();
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );
    let g = gltf::Gltf::from_slice(&bytes).expect("valid glTF 2.0");
    let blob = g.blob.as_deref().expect("a BIN chunk");
    assert_eq!(g.scenes().count(), 1);
    let names: Vec<String> = g
        .nodes()
        .filter_map(|n| n.name().map(String::from))
        .collect();
    let (file, mesh) = common::chair_side();
    for want in ["world", "table", "part"] {
        assert!(names.iter().any(|n| n == want), "node {want}");
    }
    for r in &file.robots {
        for i in 1..=6 {
            assert!(names.contains(&format!("{}_joint{i}", r.name)));
            assert!(names.contains(&format!("{}_frame{i}", r.name)));
        }
        assert!(names.contains(&format!("{}_gripper_open", r.name)));
    }
    for m in g.meshes() {
        for p in m.primitives() {
            let reader = p.reader(|_| Some(blob));
            let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
            let acc = p.get(&gltf::Semantic::Positions).unwrap();
            assert_eq!(acc.count(), pos.len());
            let (min, max) = (acc.min().unwrap(), acc.max().unwrap());
            for k in 0..3 {
                let lo = pos.iter().map(|v| v[k]).fold(f32::INFINITY, f32::min);
                let hi = pos.iter().map(|v| v[k]).fold(f32::NEG_INFINITY, f32::max);
                assert_eq!(min[k].as_f64().unwrap() as f32, lo);
                assert_eq!(max[k].as_f64().unwrap() as f32, hi);
            }
            let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
            assert_eq!(idx.len() % 3, 0);
            assert!(
                idx.iter().all(|&i| (i as usize) < pos.len()),
                "{:?}",
                m.name()
            );
            if m.name() == Some("part") {
                assert_eq!(pos.len(), mesh.vertices.len());
                assert_eq!(idx.len(), 3 * mesh.triangles.len());
            }
        }
    }
}

#[test]
fn animation_is_on_the_plan_time_line_and_nodes_follow_fk() {
    let (file, _) = common::chair_side();
    nodes_follow_fk(file, &glb());
}

/// Two FR3 (an arm from its robot description, elbow held) in place of the chair's UR5e: the
/// nodes follow its kinematics as they follow the UR's.
#[test]
fn an_arm_from_its_description_is_animated_by_its_own_chain() {
    let (file, bytes) = fr3_chair("");
    nodes_follow_fk(&file, &bytes);
}

/// The same with the Franka Hand the description carries: its jaws are the gripper variants,
/// placed where each segment's `grip_width` says they stop.
#[test]
fn a_jaw_gripper_from_the_description_is_exported() {
    let (file, bytes) = fr3_chair("gripper = \"urdf\"");
    assert!(file
        .robots
        .iter()
        .all(|r| r.gripper.as_deref() == Some("urdf")));
    nodes_follow_fk(&file, &bytes);
}

/// The chair planned with two FR3 (`extra`: more `[[robot]]` keys), and its glTF export.
fn fr3_chair(extra: &str) -> (pregrasp_io::plan_file::PlanFile, Vec<u8>) {
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let urdf = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots/fr3.urdf");
    let arm = format!(
        "urdf = {:?}\ntool_link = \"fr3_link8\"\nhold = {{ fr3_joint3 = 0.0 }}\n{extra}",
        urdf.display().to_string()
    );
    let own_gripper = !extra.is_empty();
    let mut text = String::new();
    for line in ex.scene_toml.lines() {
        match line {
            l if l.trim() == "model = \"ur5e\"" => text.push_str(&arm),
            l if l.starts_with("start = ") => {
                text.push_str("start = [0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]")
            }
            // The description's gripper comes with its own tool points.
            l if own_gripper
                && ["gripper =", "precision_point_z", "power_point_z"]
                    .iter()
                    .any(|k| l.trim().starts_with(k)) => {}
            l => text.push_str(l),
        }
        text.push('\n');
    }
    let scene = pregrasp_io::scene::Scene::from_str(
        &text,
        std::path::Path::new("examples/chair_side.toml"),
    )
    .unwrap();
    let options = pregrasp_planner::pipeline::PlanOptions::default();
    let file = pregrasp_planner::pipeline::plan(&scene, &ex.mesh, &options, &|_| {}, &|| {})
        .unwrap()
        .file;
    assert!(!file.plans.is_empty(), "{:?}", file.reason);
    let out = common::export_file(
        &file,
        0,
        &[Format::Gltf],
        &Options::default(),
        Some(&ex.mesh),
    )
    .unwrap();
    let bytes = out[0].bytes.clone();
    (file, bytes)
}

/// The animation runs on the plan's time line; every arm frame node is at `base · fk_frames`,
/// the part at its plan pose, one gripper variant shown at a time.
fn nodes_follow_fk(file: &pregrasp_io::plan_file::PlanFile, bytes: &[u8]) {
    let g = gltf::Gltf::from_slice(bytes).unwrap();
    let blob = g.blob.as_deref().unwrap();
    let arms = file.arm_descriptions(None).unwrap();
    assert_eq!(g.animations().count(), 1);
    let anim = g.animations().next().unwrap();
    // Node index -> (translation, rotation, scale) keys.
    let mut times: Option<Vec<f32>> = None;
    let mut rot: HashMap<usize, Vec<[f32; 4]>> = HashMap::new();
    let mut tr: HashMap<usize, Vec<[f32; 3]>> = HashMap::new();
    let mut sc: HashMap<usize, Vec<[f32; 3]>> = HashMap::new();
    for ch in anim.channels() {
        let reader = ch.reader(|_| Some(blob));
        let input: Vec<f32> = reader.read_inputs().unwrap().collect();
        if let Some(t) = &times {
            assert_eq!(t, &input, "one time line for every channel");
        }
        let node = ch.target().node().index();
        use gltf::animation::util::ReadOutputs;
        match reader.read_outputs().unwrap() {
            ReadOutputs::Rotations(r) => {
                assert_eq!(
                    ch.sampler().interpolation(),
                    gltf::animation::Interpolation::Linear
                );
                rot.insert(node, r.into_f32().collect());
            }
            ReadOutputs::Translations(t) => {
                assert_eq!(
                    ch.sampler().interpolation(),
                    gltf::animation::Interpolation::Linear
                );
                tr.insert(node, t.collect());
            }
            ReadOutputs::Scales(s) => {
                sc.insert(node, s.collect());
            }
            ReadOutputs::MorphTargetWeights(_) => panic!("no morph targets"),
        }
        times = Some(input);
    }
    let times = times.unwrap();
    assert!(
        times.windows(2).all(|w| w[1] > w[0]),
        "key times strictly increase"
    );
    let points = common::plan_points(file, 0);
    assert_eq!(times[0], 0.0);
    assert!((times.last().unwrap() - points.last().unwrap().0 as f32).abs() < 1e-5);
    // Every plan point time is a key.
    let key_of = |t: f64| -> usize {
        let i = times
            .iter()
            .position(|k| (*k as f64 - t).abs() < 2e-6)
            .unwrap_or_else(|| panic!("no key at plan time {t}"));
        i
    };
    for (t, _, _) in &points {
        key_of(*t);
    }
    for v in rot.values() {
        assert_eq!(v.len(), times.len());
    }

    // Node transforms at key k: static TRS, overridden by the channels.
    let nodes: Vec<gltf::Node> = g.nodes().collect();
    let mut parent = vec![None; nodes.len()];
    for n in &nodes {
        for c in n.children() {
            parent[c.index()] = Some(n.index());
        }
    }
    let by_name = |name: &str| {
        nodes
            .iter()
            .find(|n| n.name() == Some(name))
            .unwrap()
            .index()
    };
    let world = by_name("world");
    let local = |i: usize, k: usize| -> Isometry3<f64> {
        let (t, r, _) = nodes[i].transform().decomposed();
        let t = tr.get(&i).map_or(t, |v| v[k]);
        let r = rot.get(&i).map_or(r, |v| v[k]);
        iso(t, r)
    };
    // Pose of node i in the plan's world (below the y-up `world` node).
    let pose = |i: usize, k: usize| -> Isometry3<f64> {
        let mut m = Isometry3::identity();
        let mut n = Some(i);
        while let Some(j) = n {
            if j == world {
                break;
            }
            m = local(j, k) * m;
            n = parent[j];
        }
        m
    };
    let mut worst: f64 = 0.0;
    for (r, arm) in file.robots.iter().zip(&arms) {
        let kin = &arm.kin;
        let base = r.base.to_isometry();
        let frames: Vec<usize> = (1..=6)
            .map(|i| by_name(&format!("{}_frame{i}", r.name)))
            .collect();
        for (t, _, _) in &points {
            let k = key_of(*t);
            let q = common::plan_q(file, 0, &r.name, *t);
            let fk = kin.fk_frames(&q);
            for i in 0..6 {
                let gap = pose_gap(&pose(frames[i], k), &(base * fk[i + 1]));
                worst = worst.max(gap);
                assert!(
                    gap < 1e-6,
                    "{} frame {} at t = {t}: {gap:.3e} m",
                    r.name,
                    i + 1
                );
            }
        }
    }
    // The part follows `rot`: at each rot point the node pose is the point's object_pose.
    let part = by_name("part");
    let plan = &file.plans[0];
    let mut t0 = 0.0;
    for seg in &plan.segments {
        for p in &seg.points {
            let k = key_of(t0 + p.t);
            let want = match &p.object_pose {
                Some(pose) => pose.to_isometry(),
                None if seg.name == SegmentName::Sup1 => file.object.initial_pose.to_isometry(),
                None => plan.object_goal_pose.to_isometry(),
            };
            let gap = pose_gap(&pose(part, k), &want);
            assert!(gap < 1e-6, "part at {} {}: {gap:.3e}", seg.name, p.t);
        }
        t0 += seg.points.last().unwrap().t;
    }
    // Grippers: at every key exactly one variant of each arm's gripper is shown, the open
    // one at the start, a closed one at the end of each reach/regrasp.
    for r in &file.robots {
        let variants: Vec<usize> = nodes
            .iter()
            .filter(|n| {
                n.name()
                    .is_some_and(|s| s.starts_with(&format!("{}_gripper_", r.name)))
            })
            .map(|n| n.index())
            .collect();
        assert!(variants.len() >= 2);
        for k in 0..times.len() {
            let shown: Vec<usize> = variants
                .iter()
                .copied()
                .filter(|v| sc[v][k] == [1.0; 3])
                .collect();
            assert_eq!(shown.len(), 1, "{} at key {k}", r.name);
            assert!(variants
                .iter()
                .all(|v| sc[v][k] == [1.0; 3] || sc[v][k] == [0.0; 3]));
        }
        assert_eq!(
            nodes[variants[0]].name().unwrap(),
            format!("{}_gripper_open", r.name)
        );
        assert_eq!(sc[&variants[0]][0], [1.0; 3]);
    }
    // The world node turns z-up into y-up.
    let (_, wr, _) = nodes[world].transform().decomposed();
    let w = iso([0.0; 3], wr);
    assert!((w * Vector3::z() - Vector3::y()).norm() < 1e-6);
    eprintln!("largest FK gap {worst:.3e} m");
}

#[test]
fn glb_is_deterministic() {
    assert_eq!(glb(), glb());
}
