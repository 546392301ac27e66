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

/// [`generated_files`] with both robots' `model` set to `model` (a UR: `"ur10e"`, say), as
/// the other-arm sweeps edit the written scenes.
pub fn generated_files_with_arms(family: Family, seed: u64, model: &str) -> (Scene, Mesh) {
    if model == "fr3" {
        return generated_files_edited(family, seed, fr3_for_ur5e);
    }
    generated_files_edited(family, seed, |text| {
        text.replace("model = \"ur5e\"", &format!("model = \"{model}\""))
    })
}

/// A generated scene's text with a Franka FR3 (`data/robots/fr3.urdf`, elbow joint `fr3_joint3`
/// held at 0, its "ready" posture as the start) for each UR5e, the bases 0.1 m nearer the part
/// (x = 0.1), the 2F-85 kept: the scenes of `plan_replay_generated_seeds_56_60_fr3_2f85`.
pub fn fr3_for_ur5e(text: String) -> String {
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots/fr3.urdf");
    let urdf = urdf.canonicalize().expect("data/robots/fr3.urdf");
    let arm = format!(
        "urdf = {:?}\ntool_link = \"fr3_link8\"\nhold = {{ fr3_joint3 = 0.0 }}",
        urdf.display().to_string()
    );
    let mut out = String::new();
    for line in text.lines() {
        let line = if line.trim() == "model = \"ur5e\"" {
            arm.clone()
        } else if line.starts_with("base = { xyz = [0.000, ") {
            line.replacen("[0.000, ", "[0.100, ", 1)
        } else if line.starts_with("start = ") {
            "start = [0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]".to_string()
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
