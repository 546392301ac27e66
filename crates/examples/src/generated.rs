//! Generated parts ([`crate::parts::families`]) as scene files for users and for sweeps
//! (`pregrasp example generate`): each part's scene `<stem>.toml` and its binary STL
//! `meshes/<stem>.stl`, laid out as the examples and with the family's hand-placed grasps.
//!
//! ```
//! use pregrasp_examples::generated::{generated_scene, select};
//! let parts = select(1, 2, Some("ladder")).unwrap();
//! assert_eq!(parts.len(), 2);
//! let scene = generated_scene(&parts[0]);
//! assert_eq!(scene.stem, "ladder_1");
//! assert!(scene.scene_toml.contains("mesh = \"meshes/ladder_1.stl\""));
//! ```

use std::path::{Path, PathBuf};

use crate::parts::families::{generate, Family, GeneratedPart, FAMILIES};
use crate::parts::hard::HARD_FAMILIES;
use crate::scene::{scene_toml, SceneLayout};
use crate::{mesh_relative_path, Mesh, WriteError};

/// One generated part ready to write: its file stem, the scene text and the mesh.
#[derive(Clone, Debug)]
pub struct GeneratedScene {
    /// File stem `<family>_<seed>`, e.g. `"u_frame_3"`.
    pub stem: String,
    /// The part's one-line description ([`GeneratedPart::label`]), the scene's `name`.
    pub title: String,
    pub mesh: Mesh,
    /// The scene file text; refers to `meshes/<stem>.stl` with scale 1.0.
    pub scene_toml: String,
}

impl Family {
    /// The family called `name` (its [`Family::name`], e.g. `"u_frame"` or the hard family
    /// `"t_junction"`).
    pub fn from_name(name: &str) -> Option<Family> {
        FAMILIES
            .iter()
            .chain(&HARD_FAMILIES)
            .copied()
            .find(|f| f.name() == name)
    }
}

/// The file stem of a generated part: `<family>_<seed>`.
pub fn stem(part: &GeneratedPart) -> String {
    format!("{}_{}", part.family.name(), part.seed)
}

/// `per_family` parts (seeds `first_seed`, `first_seed + 1`, …) of every family of
/// [`FAMILIES`], or of the family called `family` only (a family of [`FAMILIES`] or of
/// [`HARD_FAMILIES`]). `Err` names the unknown family and lists the known ones.
pub fn select(
    first_seed: u64,
    per_family: usize,
    family: Option<&str>,
) -> Result<Vec<GeneratedPart>, String> {
    select_from(&FAMILIES, first_seed, per_family, family)
}

/// [`select`] among `families` when no `family` is named (e.g. [`HARD_FAMILIES`] for
/// `pregrasp example generate --hard`); a named family may be any.
pub fn select_from(
    families: &[Family],
    first_seed: u64,
    per_family: usize,
    family: Option<&str>,
) -> Result<Vec<GeneratedPart>, String> {
    let families: Vec<Family> = match family {
        None => families.to_vec(),
        Some(name) => vec![Family::from_name(name).ok_or_else(|| {
            let known: Vec<&str> = FAMILIES
                .iter()
                .chain(&HARD_FAMILIES)
                .map(|f| f.name())
                .collect();
            format!(
                "unknown family \"{name}\" (expected one of {})",
                known.join(", ")
            )
        })?],
    };
    let parts: Vec<GeneratedPart> = families
        .iter()
        .flat_map(|&f| (0..per_family as u64).map(move |k| generate(f, first_seed + k)))
        .collect();
    // A drawn design whose rings do not make a solid is the generator's bug: one error naming
    // the part rather than a panic while the files are made.
    for part in &parts {
        let d = &part.design;
        if let Err(e) = crate::try_extrude(&d.outline, &d.holes, d.thickness) {
            return Err(format!(
                "{}: the drawn part is not a solid ({e}); a bug of the generator, please report \
                 the family and seed (other seeds work)",
                part.label()
            ));
        }
    }
    Ok(parts)
}

/// The scene and mesh of a generated part (the examples' layout, the family's hand-placed
/// grasps). Deterministic: same part, same bytes.
pub fn generated_scene(part: &GeneratedPart) -> GeneratedScene {
    let stem = stem(part);
    let title = part.label();
    let text = scene_toml(
        &stem,
        &title,
        &mesh_relative_path(&stem),
        &part.design,
        &SceneLayout::default(),
    );
    // The first line names where the file is from: a generated part, not a built-in example.
    let body = text.split_once('\n').map_or("", |(_, rest)| rest);
    let scene_toml = format!(
        "# {stem}.toml, {title}: generated part of pregrasp (`pregrasp example generate`, \
         family {}, seed {}).\n{body}",
        part.family.name(),
        part.seed
    );
    GeneratedScene {
        stem,
        title,
        mesh: part.design.mesh(),
        scene_toml,
    }
}

/// Writes every scene of `scenes` into `dir` (created if missing): `dir/<stem>.toml` and the
/// binary STL `dir/meshes/<stem>.stl`, all files or none. Returns the paths written, each
/// part's scene before its mesh.
pub fn write_generated(dir: &Path, scenes: &[GeneratedScene]) -> Result<Vec<PathBuf>, WriteError> {
    let mut out = pregrasp_io::output::Outputs::new();
    let mut paths = Vec::new();
    for s in scenes {
        let scene_path = dir.join(format!("{}.toml", s.stem));
        let mesh_path = dir.join(mesh_relative_path(&s.stem));
        let mesh = out.declare_creating_dirs(&mesh_path)?;
        let scene = out.declare_creating_dirs(&scene_path)?;
        out.write(mesh, &pregrasp_io::mesh_io::stl_bytes(&s.mesh))?;
        out.write(scene, s.scene_toml.as_bytes())?;
        paths.extend([scene_path, mesh_path]);
    }
    out.commit()?;
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_bytes_and_every_family_by_name() {
        for f in FAMILIES.into_iter().chain(HARD_FAMILIES) {
            assert_eq!(Family::from_name(f.name()), Some(f));
        }
        assert!(select(1, 1, Some("sofa"))
            .unwrap_err()
            .contains("thin_rungs"));
        let hard = select_from(&HARD_FAMILIES, 2, 2, None).unwrap();
        assert_eq!(hard.len(), 12);
        assert_eq!(select(2, 2, Some("l_corner")).unwrap()[..], hard[2..4]);
        assert!(select(1, 1, Some("sofa")).unwrap_err().contains("u_frame"));
        let a = select(4, 2, None).unwrap();
        assert_eq!(a.len(), 12);
        for part in a.iter().chain(&hard) {
            let (x, y) = (generated_scene(part), generated_scene(part));
            assert_eq!(x.scene_toml, y.scene_toml);
            assert_eq!(
                pregrasp_io::mesh_io::stl_bytes(&x.mesh),
                pregrasp_io::mesh_io::stl_bytes(&y.mesh)
            );
            assert!(x.scene_toml.starts_with(&format!("# {}.toml", x.stem)));
        }
    }
}
