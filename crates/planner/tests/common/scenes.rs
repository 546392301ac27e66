//! Scene texts as the tests vary them, and the committed examples as the CLI reads them.

use std::path::Path;

use pregrasp_examples::generated::generated_scene;
use pregrasp_examples::parts::families::generate;
use pregrasp_examples::Family;
use pregrasp_geometry::Mesh;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::scene::Scene;

/// The committed scene `examples/<name>.toml` and its mesh, as `pregrasp plan` run from the
/// repository's root reads them (paths in a plan file relative to it).
pub fn example_files(name: &str) -> (Scene, Mesh) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene_path = format!("examples/{name}.toml");
    let text = std::fs::read_to_string(root.join(&scene_path)).unwrap();
    let scene = Scene::from_str(&text, Path::new(&scene_path)).unwrap();
    let mesh = load_mesh(&root.join(&scene.object.mesh_path), scene.object.scale)
        .unwrap()
        .mesh;
    (scene, mesh)
}

/// [`generated_files`] with both robots' `model` set to `model` (a UR: `"ur10e"`, say), or a
/// described arm in place of each UR5e ([`described_arm`]), as the other-arm sweeps edit the
/// written scenes.
pub fn generated_files_with_arms(family: Family, seed: u64, model: &str) -> (Scene, Mesh) {
    if let Some(arm) = described_arm(model) {
        return generated_files_edited(family, seed, |text| in_place_of_ur5e(&text, &arm));
    }
    generated_files_edited(family, seed, |text| {
        text.replace("model = \"ur5e\"", &format!("model = \"{model}\""))
    })
}

/// An arm from `data/robots/` put in place of a generated scene's UR5e: its keys, its start and
/// where its bases stand (`[x, ±y, 0]`).
pub struct DescribedArm {
    keys: String,
    start: &'static str,
    base: [&'static str; 2],
}

/// The described arms of the other-arm sweeps of generated parts, the 2F-85 kept on each:
/// `"fr3"`, the Franka FR3 (elbow joint `fr3_joint3` held at 0, its "ready" posture, the bases
/// 0.1 m nearer the part), and `"xarm6"`, the UFACTORY xArm6 (the bases also 0.1 m nearer the
/// middle, for its 0.7 m reach), as `crates/planner/tests/non_ur_arms.rs` places them.
pub fn described_arm(model: &str) -> Option<DescribedArm> {
    let urdf = |file: &str| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/robots")
            .join(file);
        format!(
            "{:?}",
            path.canonicalize().expect(file).display().to_string()
        )
    };
    match model {
        "fr3" => Some(DescribedArm {
            keys: format!(
                "urdf = {}\ntool_link = \"fr3_link8\"\nhold = {{ fr3_joint3 = 0.0 }}",
                urdf("fr3.urdf")
            ),
            start: "[0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]",
            base: ["0.100", "0.450"],
        }),
        "xarm6" => Some(DescribedArm {
            keys: format!("urdf = {}", urdf("xarm6.urdf")),
            start: "[0.0, -0.5, -0.8, 0.0, 1.3, 0.0]",
            base: ["0.100", "0.350"],
        }),
        _ => None,
    }
}

/// A generated scene's text with `arm` for each UR5e (which stand at `[0, ±0.45, 0]`).
pub fn in_place_of_ur5e(text: &str, arm: &DescribedArm) -> String {
    let [x, y] = arm.base;
    let mut out = String::new();
    for line in text.lines() {
        let line = if line.trim() == "model = \"ur5e\"" {
            arm.keys.clone()
        } else if line == "base = { xyz = [0.000, 0.450, 0.000] }" {
            format!("base = {{ xyz = [{x}, {y}, 0.000] }}")
        } else if line == "base = { xyz = [0.000, -0.450, 0.000] }" {
            format!("base = {{ xyz = [{x}, -{y}, 0.000] }}")
        } else if line.starts_with("start = ") {
            format!("start = {}", arm.start)
        } else {
            line.to_string()
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// The generated part of `family` and `seed` (`pregrasp example generate`): its scene, read as
/// `generated/<stem>.toml`, and its mesh.
pub fn generated_files(family: Family, seed: u64) -> (Scene, Mesh) {
    generated_files_edited(family, seed, |text| text)
}

/// [`generated_files`] with the scene's text passed through `edit` before it is read.
fn generated_files_edited(
    family: Family,
    seed: u64,
    edit: impl FnOnce(String) -> String,
) -> (Scene, Mesh) {
    let g = generated_scene(&generate(family, seed));
    let path = format!("generated/{}.toml", g.stem);
    let text = edit(g.scene_toml);
    (Scene::from_str(&text, Path::new(&path)).unwrap(), g.mesh)
}

/// The scene text with its `[grasps]` table replaced by `mode = "auto"` and `extra` lines.
pub fn auto_scene(text: &str, extra: &str) -> String {
    let start = text.find("[grasps]").expect("a [grasps] table");
    let end = text[start + 1..]
        .find("\n[")
        .map_or(text.len(), |k| start + 1 + k);
    format!(
        "{}[grasps]\nmode = \"auto\"\n{extra}{}",
        &text[..start],
        &text[end..]
    )
}
