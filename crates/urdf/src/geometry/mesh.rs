//! Finding and reading the mesh files a URDF's `<collision>` elements name.
//!
//! # Resolution
//!
//! * `package://PKG/REST`: for each directory `d` of the search path in order, `d/PKG/REST`
//!   (`d` holds package folders, as `data/robots/meshes` does) or, when `d`'s own name is
//!   `PKG`, `d/REST` (`d` is the package folder); the first file that exists.
//! * `file:///abs/path` and absolute paths: as written. `file://rel/path` and relative paths:
//!   relative to the directory of the URDF file.
//!
//! The search path is the caller's directories followed by the URDF's directory and its
//! `meshes/` subdirectory ([`search_dirs`]). A mesh found nowhere is one error naming the
//! URDF, the link, the filename and the directories searched.
//!
//! # Loading
//!
//! `mesh-loader` reads STL (binary and ASCII), Wavefront OBJ and COLLADA (units applied);
//! every mesh of the file is merged into one triangle soup. `f32` coordinates become `f64`,
//! then `<mesh scale="sx sy sz">` scales each axis and the `<collision><origin>` places the
//! element in the link frame: `p_link = origin · diag(s) · p_file`.

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Point3};

use super::collada;
use crate::error::UrdfError;

/// A triangle mesh in the link frame (m).
#[derive(Clone, Debug, Default)]
pub struct LinkMesh {
    /// Vertices in the link frame (scale and origin applied).
    pub vertices: Vec<Point3<f64>>,
    /// Triangles, indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// The directories `package://` URIs are looked up in: `extra` in order, then the URDF's
/// directory and its `meshes/` subdirectory.
pub fn search_dirs(urdf_dir: Option<&Path>, extra: &[PathBuf]) -> Vec<PathBuf> {
    let mut dirs = extra.to_vec();
    if let Some(d) = urdf_dir {
        dirs.push(d.to_path_buf());
        dirs.push(d.join("meshes"));
    }
    dirs
}

/// The file `filename` (as written in the URDF) names, or `None` and the directories looked
/// in (see the module documentation for the rules).
pub fn resolve(
    filename: &str,
    urdf_dir: Option<&Path>,
    dirs: &[PathBuf],
) -> Result<PathBuf, Vec<PathBuf>> {
    let relative = |p: &str| -> Result<PathBuf, Vec<PathBuf>> {
        let path = Path::new(p);
        let full = match urdf_dir {
            Some(d) if path.is_relative() => d.join(path),
            _ => path.to_path_buf(),
        };
        if present(&full) {
            Ok(full)
        } else {
            Err(vec![full
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default()])
        }
    };
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, rest) = rest.split_once('/').unwrap_or((rest, ""));
        for d in dirs {
            let inside = d.join(pkg).join(rest);
            if present(&inside) {
                return Ok(inside);
            }
            if d.file_name().is_some_and(|n| n == pkg) && present(&d.join(rest)) {
                return Ok(d.join(rest));
            }
        }
        return Err(dirs.to_vec());
    }
    match filename.strip_prefix("file://") {
        Some(p) => relative(p),
        None => relative(filename),
    }
}

/// Whether `path` names something that is not a folder. A FIFO or device counts, so that
/// reading it ([`pregrasp_limits::read_limited`]) refuses it in words instead of "not found".
fn present(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_dir())
}

/// The error for a mesh found nowhere.
pub(crate) fn missing(file: &str, link: &str, filename: &str, searched: &[PathBuf]) -> UrdfError {
    UrdfError::MissingMesh {
        file: file.to_string(),
        link: link.to_string(),
        filename: filename.to_string(),
        searched: searched.iter().map(|d| d.display().to_string()).collect(),
    }
}

/// The mesh formats read, by lower-case file extension.
pub const MESH_EXTENSIONS: [&str; 3] = ["stl", "obj", "dae"];

/// Parses mesh file bytes (`path` gives the format by its extension) into the link frame:
/// `origin · diag(scale) · p`. An extension other than [`MESH_EXTENSIONS`] is refused; an OBJ's
/// material library (`mtllib`) is not read at all.
///
/// Any input gives a mesh or an error, never a panic: a COLLADA file (as `mesh-loader` detects
/// one, [`collada::is_collada`]) is first checked by [`collada::validate`], whose
/// [`std::io::ErrorKind::InvalidData`] error names the element at fault.
pub fn parse(
    bytes: &[u8],
    path: &Path,
    scale: [f64; 3],
    origin: &Isometry3<f64>,
) -> std::io::Result<LinkMesh> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if !MESH_EXTENSIONS.contains(&ext.as_str()) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::Unsupported,
            format!(
                "unsupported mesh format {:?} (STL, OBJ and COLLADA are read: .stl, .obj, .dae)",
                if ext.is_empty() {
                    "no extension".to_string()
                } else {
                    format!(".{ext}")
                }
            ),
        ));
    }
    // Collision geometry has no colours: an OBJ's `mtllib` is never opened (it may name a
    // FIFO, a device or a huge file), the loader is handed an empty library instead.
    let no_materials = |_: &Path| Ok(Vec::new());
    if collada::is_collada(path, bytes) {
        collada::validate(bytes)?;
    }
    let scene =
        mesh_loader::Loader::default().load_from_slice_with_reader(bytes, path, no_materials)?;
    let mut out = LinkMesh::default();
    for m in scene.meshes {
        let base = u32::try_from(out.vertices.len())
            .ok()
            .filter(|b| b.checked_add(m.vertices.len() as u32).is_some())
            .ok_or_else(|| {
                std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    "more than 2^32 vertices in one mesh file",
                )
            })?;
        out.vertices.extend(m.vertices.iter().map(|v| {
            let p = Point3::new(
                v[0] as f64 * scale[0],
                v[1] as f64 * scale[1],
                v[2] as f64 * scale[2],
            );
            origin * p
        }));
        out.triangles.extend(
            m.faces
                .iter()
                .map(|f| [f[0] + base, f[1] + base, f[2] + base]),
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn package_uri_against_both_kinds_of_directory() {
        let tmp = tempfile::tempdir().unwrap();
        let pkg = tmp.path().join("share").join("my_pkg");
        std::fs::create_dir_all(pkg.join("meshes")).unwrap();
        std::fs::write(pkg.join("meshes/a.stl"), b"solid").unwrap();
        let uri = "package://my_pkg/meshes/a.stl";
        let holder = vec![tmp.path().join("nowhere"), tmp.path().join("share")];
        assert_eq!(resolve(uri, None, &holder), Ok(pkg.join("meshes/a.stl")));
        assert_eq!(
            resolve(uri, None, std::slice::from_ref(&pkg)),
            Ok(pkg.join("meshes/a.stl"))
        );
        let other = vec![tmp.path().to_path_buf()];
        assert_eq!(resolve(uri, None, &other), Err(other.clone()));
        // Relative and file:// names are relative to the URDF's directory.
        let rel = resolve("meshes/a.stl", Some(&pkg), &[]);
        assert_eq!(rel, Ok(pkg.join("meshes/a.stl")));
        assert_eq!(resolve("file://meshes/a.stl", Some(&pkg), &[]), rel);
        let abs = format!("file://{}", pkg.join("meshes/a.stl").display());
        assert_eq!(resolve(&abs, None, &[]), Ok(pkg.join("meshes/a.stl")));
    }
}
