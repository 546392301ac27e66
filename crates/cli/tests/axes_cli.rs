//! `pregrasp axes` run as a real process: the table and JSON outputs on a flat box, and every
//! bad scene or mesh refused with its message and exit code 1, without a panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(name)
}

fn pregrasp(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pregrasp"))
        .args(args)
        .output()
        .expect("runs pregrasp")
}

/// A temp dir holding `scene.toml` (the fixture scene with `edit` applied) and the mesh
/// fixture `mesh` copied as `part.<ext>`.
fn scene_with(mesh: &str, edit: impl Fn(String) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let ext = Path::new(mesh)
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("stl");
    let part = format!("part.{ext}");
    std::fs::copy(data(mesh), dir.path().join(&part)).unwrap();
    let text = std::fs::read_to_string(data("box_scene.toml"))
        .unwrap()
        .replace("box.stl", &part);
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, edit(text)).unwrap();
    (dir, path)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn table_lists_the_four_bottom_edges_both_ways() {
    let out = pregrasp(&["axes", data("box_scene.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| {
            let mut words = l.split_whitespace();
            words.next().is_some_and(|w| w.parse::<usize>().is_ok())
                && words.next().is_some_and(|w| w.starts_with('('))
        })
        .collect();
    assert_eq!(rows.len(), 8, "{text}");
    assert_eq!(rows.iter().filter(|r| r.contains(" ccw ")).count(), 4);
    assert_eq!(
        rows.iter().filter(|r| r.contains("90.0000")).count(),
        4,
        "{text}"
    );
    assert!(text.contains("8 candidate(s)"));
}

#[test]
fn json_is_the_plan_formats_candidates_array() {
    let out = pregrasp(&["axes", "--json", data("box_scene.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let arr = v.as_array().unwrap();
    assert_eq!(arr.len(), 8);
    for (i, c) in arr.iter().enumerate() {
        let keys: Vec<&str> = c.as_object().unwrap().keys().map(String::as_str).collect();
        let mut expected = [
            "id",
            "axis",
            "direction",
            "length",
            "theta_max",
            "score",
            "theta_goal",
            "outcome",
        ];
        let mut keys_sorted = keys.clone();
        keys_sorted.sort_unstable();
        expected.sort_unstable();
        assert_eq!(keys_sorted, expected);
        assert_eq!(c["id"], i);
        assert!(c["theta_goal"].is_null());
        assert_eq!(c["outcome"], "not evaluated (axes only)");
        for end in c["axis"].as_array().unwrap() {
            assert!((end[2].as_f64().unwrap() - 0.001).abs() < 1e-9);
        }
    }
    assert!((arr[0]["theta_max"].as_f64().unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert!((arr[0]["length"].as_f64().unwrap() - 0.6).abs() < 1e-6);
    let last = arr[7]["theta_max"].as_f64().unwrap();
    assert!((last - (0.001f64 / 0.6).asin()).abs() < 1e-6, "{last}");
}

#[test]
fn other_mesh_formats_work_too() {
    for mesh in ["box_ascii.stl", "box.obj", "box_solid_header.stl"] {
        let (_dir, scene) = scene_with(mesh, |t| t);
        let out = pregrasp(&["axes", "--json", scene.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(0), "{mesh}: {}", stderr(&out));
    }
    // A mesh with holes still works, with a warning.
    let (_dir, scene) = scene_with("open_box.stl", |t| t);
    let out = pregrasp(&["axes", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("warning:") && stderr(&out).contains("not watertight"));
}

#[test]
fn bad_meshes_fail_naming_scene_key_and_file() {
    let cases = [
        ("empty.stl", "mesh file is empty"),
        ("truncated.stl", "truncated STL"),
        ("truncated_ascii.stl", "truncated STL"),
        ("not_a_mesh.stl", "not a mesh file: looks like a PNG image"),
        ("zero_triangles.stl", "mesh has no triangles"),
        ("nan.stl", "non-finite coordinate"),
        ("inf_ascii.stl", "finite"),
        ("not_a_mesh.obj", "mesh has no triangles"),
    ];
    for (mesh, words) in cases {
        let (_dir, scene) = scene_with(mesh, |t| t);
        let out = pregrasp(&["axes", scene.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{mesh}: {err}");
        assert!(err.starts_with("error: "), "{mesh}: {err}");
        assert!(
            err.contains("scene.toml: object.mesh: ") && err.contains("part."),
            "{mesh}: {err}"
        );
        assert!(err.contains(words), "{mesh}: expected {words:?} in {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn bad_scenes_fail_naming_file_and_key() {
    let cases: [(&str, &str, &str); 9] = [
        (
            "model = \"ur5e\"\nbase = { xyz = [0.0, -0.45",
            "model = \"ur7\"\nbase = { xyz = [0.0, -0.45",
            "robot[1].model: unknown robot model \"ur7\" (expected one of ur3e, ur5e, ur10e, ur16e, ur5)",
        ),
        ("scale = 1.0", "scale = -2.0", "object.scale: must be > 0"),
        ("mesh = \"part.stl\"", "mesh = \"missing.stl\"", "object.mesh: "),
        ("[support]\nheight = 0.0", "", "support: missing key"),
        ("height = 0.0", "height = nan", "support.height: number must be finite"),
        ("quat_xyzw = [0, 0, 1, 0]", "quat_xyzw = [0, 0, 0, 0]", "robot[1].base.quat_xyzw: zero quaternion"),
        ("[[robot]]\nname = \"right\"", "[[Robot]]\nname = \"right\"", "robot: expected exactly two [[robot]] tables, found 1"),
        ("max_angle_deg = 90.0", "max_angle_deg = 0", "planner.max_angle_deg: must be > 0"),
        ("name = \"flat box\"", "name = \"flat box", "not valid TOML"),
    ];
    for (from, to, words) in cases {
        let (_dir, scene) = scene_with("box.stl", |t| {
            assert!(t.contains(from), "fixture lacks {from:?}");
            t.replacen(from, to, 1)
        });
        let out = pregrasp(&["axes", scene.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{to}: {err}");
        assert!(
            err.starts_with(&format!("error: {}: ", scene.display())),
            "{err}"
        );
        assert!(err.contains(words), "expected {words:?} in {err}");
        assert_eq!(err.lines().count(), 1, "one message: {err}");
    }
    let out = pregrasp(&["axes", "/nonexistent/scene.toml"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("/nonexistent/scene.toml: cannot read scene file"));
}

#[test]
fn no_candidates_exits_2() {
    // Raised 5 cm above the support: no edge within Δd_s.
    let (_dir, scene) = scene_with("box.stl", |t| {
        t.replace("xyz = [0.5, -0.3, 0.0]", "xyz = [0.5, -0.3, 0.05]")
    });
    let out = pregrasp(&["axes", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("no rotation-axis candidates"));
}

#[test]
fn help_explains_every_option() {
    let out = pregrasp(&["axes", "--help"]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    for words in ["SCENE", "--json", "candidates", "Exit status", "θ_max"] {
        assert!(text.contains(words), "{words:?} missing from:\n{text}");
    }
}
