//! Built-in example parts of pregrasp — the paper's side parts of a chair, a shelf and a
//! stool (§VII) — as parametric triangle meshes with ready-to-plan scene files.
//!
//! Each part is a planar outline with holes (its bars merged in 2-D by construction)
//! extruded by its thickness ([`extrude()`]); the meshes are closed and outward oriented. Object
//! frame: the part lies in its `x-y` plane, `z = 0` is its bottom face and `z = thickness` its
//! top; metres. Each scene places the part flat on the table in front of two UR5e arms with
//! its intended rotation axis (the longest bottom hull edge, which Algorithm 1 ranks first)
//! towards the arms, and defines the grasps G_p1, G_p2 (power) and G_s (support) on its bars.
//!
//! ```
//! let chair = pregrasp_examples::by_name("chair_side").unwrap();
//! assert!(chair.scene_toml.contains("mesh = \"meshes/chair_side.stl\""));
//! // Closed and outward oriented: every directed edge once, its reverse once.
//! pregrasp_examples::mesh_check::check_closed_oriented(&chair.mesh).unwrap();
//! assert!(pregrasp_examples::mesh_check::signed_volume(&chair.mesh) > 0.0);
//! ```

use std::path::{Path, PathBuf};

pub mod arm_in_place;
pub mod design;
pub mod extrude;
pub mod generated;
pub mod mesh_check;
pub mod parts;
pub mod scene;
pub mod triangulate;

pub use design::{GraspSite, PartDesign, GRIPPER_STROKE};
pub use extrude::{extrude, try_extrude, ExtrudeError};
pub use parts::bench_end::BenchEndParams;
pub use parts::chair::{chair_side, ChairSideParams};
pub use parts::families::{Family, GeneratedPart, FAMILIES};
pub use parts::hard::HARD_FAMILIES;
pub use parts::ladder::LadderParams;
pub use parts::shelf::{shelf_side, ShelfSideParams};
pub use parts::stool::{stool_side, StoolSideParams};
pub use pregrasp_geometry::Mesh;
pub use scene::SceneLayout;

/// One built-in example: a part mesh and the scene that uses it.
#[derive(Clone, Debug)]
pub struct Example {
    /// File stem, e.g. `"chair_side"`: the scene is `<name>.toml`, the mesh `meshes/<name>.stl`.
    pub name: &'static str,
    /// Human title, e.g. `"chair side frame"`.
    pub title: &'static str,
    /// The part (object frame, metres).
    pub mesh: Mesh,
    /// The scene file text; refers to `meshes/<name>.stl` with scale 1.0.
    pub scene_toml: String,
    /// The outline, grasps and intended axis the scene was built from.
    pub design: PartDesign,
}

/// The names of the built-in examples, in [`all`] order.
pub const NAMES: [&str; 3] = ["chair_side", "shelf_side", "stool_side"];

/// Path of an example's mesh relative to its scene file.
pub fn mesh_relative_path(name: &str) -> String {
    format!("meshes/{name}.stl")
}

fn build(
    name: &'static str,
    title: &'static str,
    design: PartDesign,
    layout: SceneLayout,
) -> Example {
    let scene_toml = scene::scene_toml(name, title, &mesh_relative_path(name), &design, &layout);
    Example {
        name,
        title,
        mesh: design.mesh(),
        scene_toml,
        design,
    }
}

/// Every built-in example, built from the default parameters.
pub fn all() -> Vec<Example> {
    NAMES.iter().filter_map(|n| by_name(n)).collect()
}

/// The built-in example called `name` (one of [`NAMES`]).
pub fn by_name(name: &str) -> Option<Example> {
    let design = match name {
        "chair_side" => ChairSideParams::default().design(),
        "shelf_side" => ShelfSideParams::default().design(),
        "stool_side" => StoolSideParams::default().design(),
        _ => return None,
    };
    with_design(name, design)
}

/// An example of the family `name` (one of [`NAMES`]) built from another `design` of that
/// family (other stock, other bar widths), laid out and titled as the built-in one.
pub fn with_design(name: &str, design: PartDesign) -> Option<Example> {
    match name {
        "chair_side" => Some(build(
            "chair_side",
            "chair side frame",
            design,
            SceneLayout::default(),
        )),
        // The panel's end grasp lies near its end: keep it clear of the left arm's base.
        "shelf_side" => Some(build(
            "shelf_side",
            "shelf side panel",
            design,
            SceneLayout {
                axis_x: 0.32,
                centre_y: -0.05,
                ..SceneLayout::default()
            },
        )),
        "stool_side" => Some(build(
            "stool_side",
            "stool side",
            design,
            SceneLayout::default(),
        )),
        _ => None,
    }
}

/// A generated part ([`parts::families`]) as an example: its family's name, the examples'
/// layout, its hand-placed grasps.
pub fn generated_example(part: &GeneratedPart) -> Example {
    let name = part.family.name();
    build(name, name, part.design.clone(), SceneLayout::default())
}

/// Errors of [`write_example`].
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error(transparent)]
    Output(#[from] pregrasp_io::output::OutputError),
}

/// Writes `example` into `dir` (created if missing): `dir/<name>.toml` and the binary STL
/// `dir/meshes/<name>.stl`, both or neither. Returns the two paths written, scene first.
pub fn write_example(dir: &Path, example: &Example) -> Result<[PathBuf; 2], WriteError> {
    let mesh_path = dir.join(mesh_relative_path(example.name));
    let scene_path = dir.join(format!("{}.toml", example.name));
    let mut out = pregrasp_io::output::Outputs::new();
    let mesh = out.declare_creating_dirs(&mesh_path)?;
    let scene = out.declare_creating_dirs(&scene_path)?;
    out.write(mesh, &pregrasp_io::mesh_io::stl_bytes(&example.mesh))?;
    out.write(scene, example.scene_toml.as_bytes())?;
    out.commit()?;
    Ok([scene_path, mesh_path])
}
