//! Scene texts as the tests vary them, and the committed examples as the CLI reads them.

use std::path::Path;

use pregrasp_examples::arm_in_place::ArmInPlace;
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
/// described arm in place of each UR5e (`"fr3"`, `"xarm6"`), as `pregrasp example generate
/// --arm` writes the other-arm sweeps' scenes ([`ArmInPlace`]).
pub fn generated_files_with_arms(family: Family, seed: u64, model: &str) -> (Scene, Mesh) {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/robots");
    let arm = ArmInPlace::by_name(model, &robots).unwrap();
    generated_files_edited(family, seed, |text| arm.put_in(&text))
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
