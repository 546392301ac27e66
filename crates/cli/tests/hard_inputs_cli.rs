//! What the commands do with hard inputs (issue 33): no panic on a valid scene, inputs over their
//! size limit refused unread, plan files validated by every command that reads them, messages a
//! person can read.

mod common;

use std::path::Path;

use common::{
    assert_bad_input, assert_schema_valid, examples_dir, examples_in, plan_chair_side, pregrasp,
    stderr,
};
use serde_json::Value;

#[test]
fn a_start_in_collision_is_no_plan_with_every_candidate_accounted_for() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let text = std::fs::read_to_string(dir.path().join("chair_side.toml")).unwrap();
    // The right arm's base moved onto the left arm's: the start configurations collide.
    let clash = text.replace(
        "base = { xyz = [0.000, -0.450, 0.000] }",
        "base = { xyz = [0.000, 0.350, 0.000] }",
    );
    assert_ne!(clash, text);
    std::fs::write(dir.path().join("clash.toml"), clash).unwrap();
    let out = pregrasp(
        dir.path(),
        &["plan", "clash.toml", "-o", "p.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let plan: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("p.json")).unwrap()).unwrap();
    assert!(plan["reason"].as_str().unwrap().starts_with("start: "));
    let candidates = plan["candidates"].as_array().unwrap();
    assert!(!candidates.is_empty());
    for c in candidates {
        assert!(c["outcome"]
            .as_str()
            .unwrap()
            .starts_with("rejected: start: "));
    }
    assert_schema_valid(&dir.path().join("p.json"));
}

#[test]
fn robustness_at_the_largest_documented_error_runs_to_its_report() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let out = pregrasp(
        dir.path(),
        &[
            "robustness",
            "chair_side.toml",
            "--samples",
            "2",
            "--pos-mm=500",
            "--json",
            "r.json",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(dir.path().join("r.json").is_file());
}

#[test]
fn replan_of_one_parts_plan_at_another_parts_pose_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let out = pregrasp(
        dir.path(),
        &["plan", "shelf_side.toml", "-o", "shelf.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let chair: Value = {
        let out = pregrasp(
            dir.path(),
            &["plan", "chair_side.toml", "-o", "chair.json", "--quiet"],
        );
        assert_eq!(out.status.code(), Some(0));
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("chair.json")).unwrap())
            .unwrap()
    };
    let p = &chair["object"]["initial_pose"];
    let pose: Vec<String> = p["xyz"]
        .as_array()
        .unwrap()
        .iter()
        .chain(p["quat_xyzw"].as_array().unwrap())
        .map(|v| v.to_string())
        .collect();
    let out = pregrasp(
        dir.path(),
        &[
            "replan",
            "shelf.json",
            "--object-pose",
            &pose.join(" "),
            "-o",
            "re.json",
        ],
    );
    assert!(matches!(out.status.code(), Some(0 | 2)), "{}", stderr(&out));
    assert_schema_valid(&dir.path().join("re.json"));
}

#[test]
fn a_mesh_of_two_far_triangles_is_answered_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let stl = "solid two\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 5 5 0\nvertex 5.1 5 0\nvertex 5 5.1 0\nendloop\nendfacet\nendsolid two\n";
    std::fs::write(dir.path().join("meshes/chair_side.stl"), stl).unwrap();
    let out = pregrasp(
        dir.path(),
        &["plan", "chair_side.toml", "-o", "p.json", "--quiet"],
    );
    assert!(matches!(out.status.code(), Some(0 | 2)), "{}", stderr(&out));
    assert_schema_valid(&dir.path().join("p.json"));
}

#[test]
fn a_microscopic_part_is_bad_input_and_one_row_of_a_batch() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    examples_in(&scenes);
    let text = std::fs::read_to_string(scenes.join("stool_side.toml")).unwrap();
    let tiny = text.replace("scale = 1.0", "scale = 5e-324");
    assert_ne!(tiny, text);
    std::fs::write(scenes.join("tiny.toml"), tiny).unwrap();
    let out = pregrasp(&scenes, &["plan", "tiny.toml", "-o", "p.json"]);
    assert_bad_input(&out, "check object.scale");
    assert!(!scenes.join("p.json").exists());
    // In a batch, that scene is one error row; the others plan.
    let out = pregrasp(dir.path(), &["batch", "scenes", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let rows = summary["scenes"].as_array().unwrap();
    let tiny = rows.iter().find(|r| r["scene"] == "tiny.toml").unwrap();
    assert_eq!(tiny["status"], "error");
    assert_eq!(summary["counts"]["planned"], 3);
}

#[test]
fn input_files_over_their_size_limit_are_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    // Sparse files: 1 GiB on paper, nothing on disk; reading them would allocate it all.
    let huge = std::fs::File::create(dir.path().join("huge.toml")).unwrap();
    huge.set_len(1 << 30).unwrap();
    for args in [
        &["plan", "huge.toml", "-o", "p.json"][..],
        &["robustness", "huge.toml"],
        &["axes", "huge.toml"],
    ] {
        let out = pregrasp(dir.path(), args);
        assert_bad_input(&out, "larger than the 4 MiB");
    }
    let plan = std::fs::File::create(dir.path().join("huge.json")).unwrap();
    plan.set_len(1 << 30).unwrap();
    for args in [
        &["check", "huge.json"][..],
        &["export", "huge.json", "-o", "ex"],
        &["physics", "huge.json"],
    ] {
        let out = pregrasp(dir.path(), args);
        assert_bad_input(&out, "larger than the 256 MiB");
    }
    assert!(!dir.path().join("p.json").exists() && !dir.path().join("ex").exists());
}

/// A change to a plan file's JSON.
type Edit = Box<dyn Fn(&mut Value)>;

/// A plan file with one field changed.
fn edited_plan(dir: &Path, edit: impl FnOnce(&mut Value)) {
    let path = dir.join("plan.json");
    let mut plan: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edit(&mut plan);
    std::fs::write(dir.join("bad.json"), serde_json::to_string(&plan).unwrap()).unwrap();
}

#[test]
fn every_command_that_reads_a_plan_refuses_one_check_calls_malformed() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    plan_chair_side(dir.path());
    let edits: [(&str, Edit); 5] = [
        (
            "is not a joint angle",
            Box::new(|p| p["plans"][0]["segments"][1]["points"][0]["q"][0] = 100.0.into()),
        ),
        (
            "out of range",
            Box::new(|p| p["plans"][0]["segments"][0]["points"][1]["t"] = 2e44.into()),
        ),
        (
            "is not one of ur3e",
            Box::new(|p| p["robots"][0]["model"] = "UR5E".into()),
        ),
        (
            "always ends at the support grasp",
            Box::new(|p| p["plans"][0]["segments"][1]["grasp"] = "power".into()),
        ),
        (
            "norm overflows",
            Box::new(|p| {
                p["object"]["initial_pose"]["quat_xyzw"] = serde_json::json!([1e300, 1e300, 0, 0])
            }),
        ),
    ];
    for (needle, edit) in edits {
        edited_plan(dir.path(), edit);
        for args in [
            &["check", "bad.json"][..],
            &["export", "bad.json", "-o", "ex"],
            &["physics", "bad.json"],
            &["view", "bad.json", "-o", "v.html"],
            &[
                "replan",
                "bad.json",
                "--scene",
                "chair_side.toml",
                "--object-pose",
                "0.6881 0.4466 0 0 0 -0.9989 0.0471",
                "-o",
                "re.json",
            ],
        ] {
            let out = pregrasp(dir.path(), args);
            assert_bad_input(&out, needle);
        }
        assert!(!dir.path().join("ex").exists());
        assert!(!dir.path().join("v.html").exists());
        assert!(!dir.path().join("re.json").exists());
    }
}

#[test]
fn replan_writes_only_schema_outcomes_and_normalises_huge_quaternions() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    plan_chair_side(dir.path());
    // The chair's pose with its quaternion scaled by 1e300: the same rotation.
    let out = pregrasp(
        dir.path(),
        &[
            "replan",
            "plan.json",
            "--scene",
            "chair_side.toml",
            "--object-pose",
            "0.6881 0.4466 0.001 0 0 -0.9989e300 0.0471e300",
            "-o",
            "re.json",
        ],
    );
    assert!(matches!(out.status.code(), Some(0 | 2)), "{}", stderr(&out));
    assert_schema_valid(&dir.path().join("re.json"));
    let re: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("re.json")).unwrap())
            .unwrap();
    let q: Vec<f64> = re["object"]["initial_pose"]["quat_xyzw"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((norm - 1.0).abs() < 1e-9, "{q:?}");
}

#[test]
fn physics_refuses_an_absurd_mass_and_names_the_scene_once() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    plan_chair_side(dir.path());
    let out = pregrasp(dir.path(), &["physics", "plan.json", "--mass", "1e308"]);
    assert_bad_input(&out, "--mass: must be in (0, 10000] kg, found 1e308");
    // A bad [physics] value in the scene the plan names: the file is named once.
    let scene = examples_dir().join("chair_side.toml");
    let text = std::fs::read_to_string(scene).unwrap();
    std::fs::write(
        dir.path().join("bad_scene.toml"),
        format!("{text}\n[physics]\nmu_pad = -1\n"),
    )
    .unwrap();
    edited_plan(dir.path(), |p| p["scene"]["file"] = "bad_scene.toml".into());
    let out = pregrasp(dir.path(), &["physics", "bad.json"]);
    assert_bad_input(&out, "physics.mu_pad");
    assert_eq!(
        stderr(&out).matches("bad_scene.toml").count(),
        1,
        "{}",
        stderr(&out)
    );
}

#[test]
fn huge_numbers_in_messages_are_written_in_scientific_notation() {
    let dir = tempfile::tempdir().unwrap();
    examples_in(dir.path());
    let text = std::fs::read_to_string(dir.path().join("chair_side.toml")).unwrap();
    std::fs::write(
        dir.path().join("heavy.toml"),
        text.replace("mass = 1.53", "mass = 1e308"),
    )
    .unwrap();
    let out = pregrasp(dir.path(), &["plan", "heavy.toml", "-o", "p.json"]);
    assert_bad_input(&out, "found 1e308");
    let err = stderr(&out);
    let longest_digits = err
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest_digits < 20, "{err}");
}

#[test]
fn view_refuses_a_speed_the_page_does_not_offer() {
    let dir = tempfile::tempdir().unwrap();
    for speed in ["3", "0.3", "16"] {
        let out = pregrasp(
            dir.path(),
            &["view", "missing.json", "-o", "v.html", "--speed", speed],
        );
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(64), "{err}");
        assert!(err.contains("choose 0.25, 0.5, 1, 2, 4 or 8"), "{err}");
    }
}

#[test]
fn no_committed_fixture_holds_a_machine_path() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut stack = vec![
        root.join("fuzz/seeds"),
        root.join("examples"),
        root.join("tests"),
    ];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if let Ok(text) = std::fs::read_to_string(&p) {
                // A quoted absolute path into a machine's own folders.
                for dir in ["tmp", "root", "home", "work"] {
                    let prefix = format!("\"/{dir}/");
                    assert!(!text.contains(&prefix), "{} holds {prefix}…", p.display());
                }
            }
        }
    }
}
