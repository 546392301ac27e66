//! The committed example files: they parse with the real scene loader, say what the
//! generators say, and are byte for byte what `pregrasp example write` produces.

mod common;

use common::{committed_dir, committed_scene, world_axis};
use pregrasp_examples::{all, write_example};
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_robot::UrModel;

#[test]
fn committed_files_equal_freshly_generated_ones() {
    let tmp = tempfile::tempdir().unwrap();
    for example in all() {
        for written in write_example(tmp.path(), &example).unwrap() {
            let relative = written.strip_prefix(tmp.path()).unwrap();
            let committed = committed_dir().join(relative);
            let fresh = std::fs::read(&written).unwrap();
            let old = std::fs::read(&committed).unwrap_or_else(|e| {
                panic!(
                    "{}: {e} (run `pregrasp example write examples`)",
                    committed.display()
                )
            });
            assert!(
                fresh == old,
                "{} differs from the generator's output: run `pregrasp example write examples`",
                committed.display()
            );
        }
    }
}

#[test]
fn every_scene_parses_and_matches_its_design() {
    for example in all() {
        let scene = committed_scene(&example);
        assert!(
            scene.warnings.is_empty(),
            "{}: {:?}",
            example.name,
            scene.warnings
        );
        assert_eq!(scene.robots[0].name, "left");
        assert_eq!(scene.robots[1].name, "right");
        assert!(
            scene.robots[0].base.translation.y > 0.0 && scene.robots[1].base.translation.y < 0.0
        );
        for r in &scene.robots {
            assert_eq!(r.arm.ur, Some(UrModel::Ur5e));
        }
        assert_eq!(scene.object.scale, 1.0);
        assert!(scene.object.mesh_entry == format!("meshes/{}.stl", example.name));
        assert_eq!(scene.support_height, 0.0);
        // The support grasp as written is the design's (to the file's 0.1 mm / 0.01° rounding).
        let g = example.design.grasp_pose(&example.design.support);
        let d = scene.grasps.support.inverse() * g;
        assert!(
            d.translation.vector.norm() < 1e-4 && d.rotation.angle() < 1e-3,
            "{}",
            example.name
        );
        // The part lies flat on the table: its lowest vertex at the support height.
        let low = example
            .mesh
            .vertices
            .iter()
            .map(|v| (scene.object.pose * v).z)
            .fold(f64::INFINITY, f64::min);
        assert!(
            low.abs() < 1e-12,
            "{}: lowest vertex at {low}",
            example.name
        );
    }
}

#[test]
fn committed_meshes_load_watertight_with_the_generated_triangles() {
    for example in all() {
        let scene = committed_scene(&example);
        let loaded = load_mesh(&scene.object.mesh_path, scene.object.scale).unwrap();
        assert!(
            loaded.warnings.is_empty(),
            "{}: {:?}",
            example.name,
            loaded.warnings
        );
        assert_eq!(loaded.mesh.triangles.len(), example.mesh.triangles.len());
        assert_eq!(
            loaded.mesh.vertices.len(),
            example.mesh.vertices.len(),
            "{}: welding",
            example.name
        );
    }
}

/// The layout the paper's method needs: the part within reach of both arms, its axis towards
/// them, the supportive arm's grasps on its own side, each power grasp on its arm's side.
#[test]
fn parts_lie_in_front_of_both_arms_with_grasps_on_their_arms_side() {
    for example in all() {
        let scene = committed_scene(&example);
        let p = scene.initial_object_pose();
        let world: Vec<_> = example.mesh.vertices.iter().map(|v| p * v).collect();
        let cx = world.iter().map(|v| v.x).sum::<f64>() / world.len() as f64;
        assert!((0.4..=0.6).contains(&cx), "{}: centre x {cx}", example.name);
        let (a, u) = world_axis(&example.design, &p);
        assert!(
            u.y.abs() > 0.99 && a.x < cx,
            "{}: axis should run along y between arms and part",
            example.name
        );
        let g1 = p * scene.grasps.power[0];
        let g2 = p * scene.grasps.power[1];
        assert!(
            g1.translation.y > g2.translation.y,
            "{}: G_p1 must be on the left arm's side",
            example.name
        );
        for (robot, g) in scene.robots.iter().zip([g1, g2]) {
            let reach = (g.translation.vector - robot.base.translation.vector)
                .xy()
                .norm();
            assert!(
                reach < 0.8,
                "{}: {} grasp {reach:.3} m away",
                example.name,
                robot.name
            );
        }
    }
}
