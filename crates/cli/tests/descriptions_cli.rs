//! Robot descriptions and the files they name are input too (issue 46): a description, its
//! meshes, an OBJ's material library, a cache entry, the description a plan names — each is
//! read only as a regular file under its size limit, parsed with bounded depth, its values
//! range-checked with the element named. Every test runs the real binary on the chair example
//! with two FR3 read from a description in a temporary folder, and asserts the contract of
//! `docs/hardening.md`: exit 1 and one `error:` line naming the file and element, or a plan;
//! never a panic, an abort or a hang.

mod common;

use std::path::Path;
use std::process::Command;

use common::described::{fr3_scene, run};
use common::{assert_bad_input, files_in, plan_without_timing, stderr};

/// `pregrasp plan fr3.toml -o p.json` is bad input naming `needle`, and writes no plan.
fn plan_is_bad_input(dir: &Path, needle: &str) {
    let out = run(dir, &["plan", "fr3.toml", "-o", "p.json", "--quiet"]);
    assert_bad_input(&out, needle);
    assert!(!dir.join("p.json").exists(), "a plan was written");
}

/// `text` with `attr` of joint `joint`'s `<limit>` set to `value`.
fn with_limit(text: &str, joint: &str, attr: &str, value: &str) -> String {
    let at = text.find(&format!("<joint name=\"{joint}\"")).unwrap();
    let limit = at + text[at..].find("<limit").unwrap();
    let end = limit + text[limit..].find("/>").unwrap();
    let tag = &text[limit..end];
    let key = format!("{attr}=\"");
    let v0 = tag.find(&key).unwrap() + key.len();
    let v1 = v0 + tag[v0..].find('"').unwrap();
    format!("{}{value}{}", &text[..limit + v0], &text[limit + v1..])
}

/// `text` with a collision element `element` added to link `link`.
fn with_collision(text: &str, link: &str, element: &str) -> String {
    let at = text.find(&format!("<link name=\"{link}\">")).unwrap();
    let end = at + text[at..].find("</link>").unwrap();
    format!(
        "{}<collision><geometry>{element}</geometry></collision>{}",
        &text[..end],
        &text[end..]
    )
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success());
}

/// `text` with 20 000 nested elements after its `<robot>` tag: urdf-rs's reader overflowed the
/// stack on it.
fn nested_20000_deep(text: &str) -> String {
    let deep = format!("{}{}", "<a>".repeat(20_000), "</a>".repeat(20_000));
    text.replacen(
        "<robot name=\"fr3\">",
        &format!("<robot name=\"fr3\">{deep}"),
        1,
    )
}

#[test]
fn a_deeply_nested_description_is_bad_input_not_a_stack_overflow() {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, nested_20000_deep);
    plan_is_bad_input(dir.path(), "is nested more than 64 levels deep");
    let out = run(dir.path(), &["plan", "fr3.toml", "-o", "p.json"]);
    assert!(stderr(&out).contains("robot.urdf"), "{}", stderr(&out));
}

#[test]
fn a_batch_survives_a_description_that_would_overflow_the_stack() {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, nested_20000_deep);
    let out = run(dir.path(), &["batch", ".", "-o", "out"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let files = files_in(&dir.path().join("out"));
    assert!(
        files.iter().any(|f| f.contains("chair_side.plan.json")),
        "the good scenes' plans are lost: {files:?}"
    );
    let summary = std::fs::read_to_string(dir.path().join("out/summary.csv")).unwrap();
    let row = summary.lines().find(|l| l.contains("fr3.toml")).unwrap();
    assert!(row.contains("nested more than 64 levels"), "{row}");
}

#[test]
fn joint_speeds_of_zero_infinity_or_overflow_are_bad_input_naming_the_joint() {
    for value in ["0", "inf", "1e400", "1e300"] {
        let dir = tempfile::tempdir().unwrap();
        fr3_scene(dir.path(), false, |t| {
            with_limit(t, "fr3_joint2", "velocity", value)
        });
        plan_is_bad_input(
            dir.path(),
            "joint `fr3_joint2` has an invalid <limit>: velocity",
        );
    }
}

#[test]
fn a_jaw_stroke_of_1e10_is_bad_input_not_an_allocation() {
    for (attr, value, needle) in [
        (
            "upper",
            "1e10",
            "joint `fr3_finger_joint1` has an invalid <limit>",
        ),
        (
            "upper",
            "0.6",
            "a jaw travels more than 0 and at most 0.5 m",
        ),
        ("effort", "1e400", "the force a jaw presses with"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        fr3_scene(dir.path(), true, |t| {
            with_limit(t, "fr3_finger_joint1", attr, value)
        });
        plan_is_bad_input(dir.path(), needle);
    }
}

#[test]
fn absurd_collision_sizes_and_scales_are_bad_input_at_once() {
    for (element, needle) in [
        ("<box size=\"1e308 1 1\"/>", "box size 1e308: must be finite"),
        ("<sphere radius=\"-1\"/>", "sphere radius -1"),
        ("<cylinder radius=\"nan\" length=\"1\"/>", "cylinder radius NaN"),
        (
            "<mesh filename=\"package://franka_description/meshes/robot_arms/fr3/collision/link4.stl\" scale=\"0 1 1\"/>",
            "each factor must be finite, not zero",
        ),
        ("<mesh filename=\"\"/>", "<mesh> has an empty filename"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        fr3_scene(dir.path(), false, |t| with_collision(t, "fr3_link4", element));
        plan_is_bad_input(dir.path(), needle);
        let out = run(dir.path(), &["plan", "fr3.toml", "-o", "p.json"]);
        assert!(stderr(&out).contains("link `fr3_link4`"), "{}", stderr(&out));
    }
}

#[test]
fn a_mesh_of_an_unknown_format_is_named_in_words() {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| {
        with_collision(t, "fr3_link4", "<mesh filename=\"part.xyz\"/>")
    });
    std::fs::write(dir.path().join("part.xyz"), "solid x\nendsolid x\n").unwrap();
    plan_is_bad_input(dir.path(), "unsupported mesh format \".xyz\"");
    let out = run(dir.path(), &["plan", "fr3.toml", "-o", "p.json"]);
    assert!(!stderr(&out).contains("{path"), "{}", stderr(&out));
}

#[cfg(unix)]
#[test]
fn descriptions_meshes_and_material_libraries_that_are_fifos_or_devices_are_not_read() {
    // The description itself.
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| t.to_string());
    std::fs::remove_file(dir.path().join("robot.urdf")).unwrap();
    mkfifo(&dir.path().join("robot.urdf"));
    plan_is_bad_input(dir.path(), "not a regular file");
    std::fs::remove_file(dir.path().join("robot.urdf")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("robot.urdf")).unwrap();
    plan_is_bad_input(dir.path(), "not a regular file");

    // A collision mesh.
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| {
        with_collision(t, "fr3_link4", "<mesh filename=\"pipe.stl\"/>")
    });
    mkfifo(&dir.path().join("pipe.stl"));
    plan_is_bad_input(dir.path(), "not a regular file");

    // An OBJ's material library is never opened: the mesh loads.
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| {
        with_collision(
            t,
            "fr3_link4",
            "<mesh filename=\"cube.obj\" scale=\"0.01 0.01 0.01\"/>",
        )
    });
    let cube = "mtllib pipe.mtl\nmtllib zero.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
                f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.path().join("cube.obj"), cube).unwrap();
    mkfifo(&dir.path().join("pipe.mtl"));
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.mtl")).unwrap();
    let out = run(dir.path(), &["plan", "fr3.toml", "-o", "p.json", "--quiet"]);
    assert!(matches!(out.status.code(), Some(0 | 2)), "{}", stderr(&out));
}

#[cfg(unix)]
#[test]
fn descriptions_and_meshes_over_their_size_limit_are_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| t.to_string());
    let urdf = std::fs::OpenOptions::new()
        .append(true)
        .open(dir.path().join("robot.urdf"))
        .unwrap();
    urdf.set_len(17 << 20).unwrap(); // sparse: nothing is written
    plan_is_bad_input(dir.path(), "larger than the 16 MiB");

    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| {
        with_collision(t, "fr3_link4", "<mesh filename=\"huge.stl\"/>")
    });
    let mesh = std::fs::File::create(dir.path().join("huge.stl")).unwrap();
    mesh.set_len(129 << 20).unwrap();
    plan_is_bad_input(dir.path(), "larger than the 128 MiB");
}

#[cfg(unix)]
#[test]
fn a_cache_entry_that_is_a_fifo_or_wrong_is_derived_again() {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| t.to_string());
    let out = run(
        dir.path(),
        &["plan", "fr3.toml", "-o", "cold.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let cold = plan_without_timing(&dir.path().join("cold.json"));
    let entries = dir.path().join("cache/urdf-geometry");
    let entry = files_in(&entries)
        .into_iter()
        .find(|f| f.ends_with(".json"))
        .map(|f| entries.join(f))
        .expect("a cache entry");
    let good = std::fs::read_to_string(&entry).unwrap();
    let mut value: serde_json::Value = serde_json::from_str(&good).unwrap();
    // Every piece cut to one point; then every link's pieces emptied.
    let cut = |v: &mut serde_json::Value, f: &dyn Fn(&mut serde_json::Value)| {
        for link in v["geometry"]["links"].as_array_mut().unwrap() {
            for piece in link["pieces"].as_array_mut().unwrap() {
                f(piece);
            }
        }
    };
    cut(&mut value, &|p| {
        let first = p[0].clone();
        *p = serde_json::json!([first]);
    });
    let to_a_point = value.to_string();
    let mut emptied: serde_json::Value = serde_json::from_str(&good).unwrap();
    for link in emptied["geometry"]["links"].as_array_mut().unwrap() {
        link["pieces"] = serde_json::json!([]);
        link["elements"] = serde_json::json!([]);
    }
    for (what, planted) in [("to a point", to_a_point), ("emptied", emptied.to_string())] {
        std::fs::write(&entry, planted).unwrap();
        let out = run(
            dir.path(),
            &["plan", "fr3.toml", "-o", "warm.json", "--quiet"],
        );
        assert_eq!(out.status.code(), Some(0), "{what}: {}", stderr(&out));
        let warm = plan_without_timing(&dir.path().join("warm.json"));
        assert!(
            warm == cold,
            "pieces {what}: the plan differs from a cold cache's"
        );
        assert_eq!(
            std::fs::read_to_string(&entry).unwrap(),
            good,
            "{what}: not rewritten"
        );
    }
    std::fs::remove_file(&entry).unwrap();
    mkfifo(&entry);
    let out = run(
        dir.path(),
        &["plan", "fr3.toml", "-o", "warm.json", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(plan_without_timing(&dir.path().join("warm.json")) == cold);
}

#[cfg(unix)]
#[test]
fn a_plan_whose_description_became_a_fifo_is_refused_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    fr3_scene(dir.path(), false, |t| t.to_string());
    let out = run(dir.path(), &["plan", "fr3.toml", "-o", "p.json", "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    std::fs::remove_file(dir.path().join("robot.urdf")).unwrap();
    mkfifo(&dir.path().join("robot.urdf"));
    // `check` reports the plan invalid (rule 0: its robots cannot be loaded), exit 2.
    let out = run(dir.path(), &["check", "p.json"]);
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out));
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(
        said.contains("robot.urdf: cannot read the file: not a regular file"),
        "{said}"
    );
    // `physics` needs the arms: bad input.
    let out = run(dir.path(), &["physics", "p.json"]);
    assert_bad_input(&out, "not a regular file");
}
