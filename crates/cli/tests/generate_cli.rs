//! `pregrasp example generate` (issue 48): generated parts written as scene + binary STL,
//! same seed same bytes, and the scenes load and plan with `pregrasp plan`.

mod common;

use std::path::Path;

use common::pregrasp;

fn generate(dir: &Path, args: &[&str]) {
    let mut all = vec!["example", "generate", "."];
    all.extend_from_slice(args);
    let out = pregrasp(dir, &all);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for sub in [dir.to_path_buf(), dir.join("meshes")] {
        for e in std::fs::read_dir(&sub).unwrap() {
            let p = e.unwrap().path();
            if p.is_file() {
                let name = p.strip_prefix(dir).unwrap().display().to_string();
                out.push((name, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn generated_scenes_are_deterministic_and_plan() {
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    generate(a.path(), &["--per-family", "1", "--first-seed", "3"]);
    generate(b.path(), &["--per-family", "1", "--first-seed", "3"]);
    let (fa, fb) = (files(a.path()), files(b.path()));
    assert_eq!(fa.len(), 12, "six scenes and six meshes");
    assert_eq!(fa, fb, "same seed, same bytes");
    let names: Vec<&str> = fa.iter().map(|(n, _)| n.as_str()).collect();
    assert!(names.contains(&"u_frame_3.toml"), "{names:?}");
    assert!(names.contains(&"meshes/u_frame_3.stl"), "{names:?}");
    let mut planned = 0;
    for (name, _) in fa.iter().filter(|(n, _)| n.ends_with(".toml")) {
        let out = pregrasp(a.path(), &["plan", name, "-o", "p.json", "--quiet"]);
        // 0 planned, 2 no plan; never bad input (1): the scene and its mesh load.
        let code = out.status.code();
        assert!(
            code == Some(0) || code == Some(2),
            "{name}: {code:?} {}",
            String::from_utf8_lossy(&out.stderr)
        );
        planned += usize::from(code == Some(0));
    }
    assert!(planned >= 3, "only {planned} of 6 generated parts planned");
}

#[test]
fn one_family_only_and_an_unknown_family_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    generate(dir.path(), &["--per-family", "2", "--family", "ladder"]);
    let names: Vec<String> = files(dir.path()).into_iter().map(|(n, _)| n).collect();
    assert_eq!(
        names,
        [
            "ladder_1.toml",
            "ladder_2.toml",
            "meshes/ladder_1.stl",
            "meshes/ladder_2.stl"
        ]
    );
    let other = tempfile::tempdir().unwrap();
    let out = pregrasp(
        other.path(),
        &["example", "generate", "x", "--family", "sofa"],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown family"));
    assert!(!other.path().join("x").exists(), "nothing written");
}

#[test]
fn hard_families_by_flag_or_by_name() {
    let dir = tempfile::tempdir().unwrap();
    generate(
        dir.path(),
        &["--per-family", "1", "--first-seed", "2", "--hard"],
    );
    let names: Vec<String> = files(dir.path()).into_iter().map(|(n, _)| n).collect();
    assert_eq!(names.len(), 12, "six scenes and six meshes: {names:?}");
    for family in [
        "t_junction",
        "l_corner",
        "hand_hole",
        "parallel_bars",
        "chamfered",
        "thin_rungs",
    ] {
        assert!(names.contains(&format!("{family}_2.toml")), "{names:?}");
    }
    let one = tempfile::tempdir().unwrap();
    generate(
        one.path(),
        &[
            "--per-family",
            "1",
            "--first-seed",
            "2",
            "--family",
            "chamfered",
        ],
    );
    let by_name = files(one.path());
    assert_eq!(by_name.len(), 2);
    assert!(
        files(dir.path()).contains(&by_name[0]),
        "same part, same bytes"
    );
}

#[test]
fn other_arms_in_place_of_the_ur5e() {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots");
    let robots = robots.to_str().unwrap();
    let args = |arm: &'static str| ["--per-family", "1", "--family", "frame", "--arm", arm];
    let (ur5e, ur10e, xarm6) = (
        tempfile::tempdir().unwrap(),
        tempfile::tempdir().unwrap(),
        tempfile::tempdir().unwrap(),
    );
    generate(ur5e.path(), &args("ur5e"));
    generate(ur10e.path(), &args("ur10e"));
    let mut described = args("xarm6").to_vec();
    described.extend(["--robots", robots]);
    generate(xarm6.path(), &described);
    let scene = |dir: &Path| std::fs::read_to_string(dir.join("frame_1.toml")).unwrap();
    let (a, b, c) = (scene(ur5e.path()), scene(ur10e.path()), scene(xarm6.path()));
    assert_eq!(b, a.replace("model = \"ur5e\"", "model = \"ur10e\""));
    assert_ne!(a, b);
    let urdf = Path::new(robots).join("xarm6.urdf").canonicalize().unwrap();
    let key = format!("urdf = {:?}", urdf.display().to_string());
    assert_eq!(c.matches(&key).count(), 2, "{c}");
    assert!(c.contains("base = { xyz = [0.100, -0.350, 0.000] }"), "{c}");
    assert_eq!(
        files(ur5e.path()).last(),
        files(xarm6.path()).last(),
        "the same mesh"
    );
    // The described arm's scene loads and plans (or says why not): never bad input.
    let out = pregrasp(
        xarm6.path(),
        &["plan", "frame_1.toml", "-o", "p.json", "-q"],
    );
    assert!(
        matches!(out.status.code(), Some(0 | 2)),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    for (arm, robots, says) in [
        ("ur7", robots, "unknown arm \"ur7\""),
        ("fr3", "/nonexistent", "/nonexistent/fr3.urdf"),
    ] {
        let other = tempfile::tempdir().unwrap();
        let out = pregrasp(
            other.path(),
            &["example", "generate", "x", "--arm", arm, "--robots", robots],
        );
        assert_eq!(out.status.code(), Some(1), "{arm}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{arm}: {err}");
        assert!(!other.path().join("x").exists(), "{arm}: nothing written");
    }
}
