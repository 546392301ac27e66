//! Mesh files: binary and ASCII STL (via `stl_io`) and OBJ (via `tobj`), in; binary STL, out.
//!
//! [`load_mesh`] refuses what cannot be a part (empty or truncated file, something that is not a
//! mesh, no triangles, non-finite coordinates) with a [`MeshError`] naming the file. STL stores
//! every triangle's corners separately; they are welded by exact coordinate equality so the mesh
//! has topology. A mesh that is not a closed 2-manifold still loads, with a warning returned in
//! [`LoadedMesh::warnings`] (the library never prints).

use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

use pregrasp_geometry::{BitsBuildHasher, Mesh, Point};

/// A mesh read from a file, in metres (scale applied), with any warnings about it.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedMesh {
    pub mesh: Mesh,
    /// Human-readable remarks such as `part.stl: mesh is not watertight: 4 open edges`.
    pub warnings: Vec<String>,
}

/// A mesh file that cannot be used. Every message starts with the file name.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{file}: cannot read mesh file: {error}")]
    Read { file: String, error: std::io::Error },
    #[error("{file}: mesh file is empty")]
    Empty { file: String },
    #[error("{file}: not a regular file (a mesh must be a file, not a directory, pipe or device)")]
    NotAFile { file: String },
    #[error("{file}: unsupported mesh format (expected .stl or .obj)")]
    Format { file: String },
    #[error("{file}: not a mesh file: {reason}")]
    NotAMesh { file: String, reason: String },
    #[error("{file}: truncated STL: {reason}")]
    Truncated { file: String, reason: String },
    #[error("{file}: malformed {format}: {reason}")]
    Malformed {
        file: String,
        format: &'static str,
        reason: String,
    },
    #[error("{file}: mesh has no triangles")]
    NoTriangles { file: String },
    /// `index` counts vertices in file order (for STL, `3 × triangle + corner`).
    #[error("{file}: vertex {index} (in file order) has a non-finite coordinate {value:?}")]
    NonFinite {
        file: String,
        index: usize,
        value: [f64; 3],
    },
    /// The part is too small (or scaled to nothing), too large, or flat everywhere.
    #[error("{file}: {reason}")]
    NotAPart { file: String, reason: String },
    #[error("{file}: scale must be a finite number > 0, found {scale}")]
    Scale { file: String, scale: f64 },
    /// A face of an in-memory mesh ([`mesh_from_arrays`]) names a vertex that is not there.
    #[error("{file}: face {face} uses vertex {index}, but there are {vertices} vertices")]
    BadIndex {
        file: String,
        face: usize,
        index: i64,
        vertices: usize,
    },
}

/// Reads the mesh at `path` (format from the extension, `.stl` or `.obj`, any case) and
/// multiplies every coordinate by `scale` (> 0) to get metres.
pub fn load_mesh(path: &Path, scale: f64) -> Result<LoadedMesh, MeshError> {
    let file = path.display().to_string();
    if !(scale.is_finite() && scale > 0.0) {
        return Err(MeshError::Scale { file, scale });
    }
    parse_mesh(&read_mesh_bytes(path)?, path, scale)
}

/// The bytes of the mesh file at `path`, which must be a regular file: a FIFO or device would
/// block the read for ever.
pub fn read_mesh_bytes(path: &Path) -> Result<Vec<u8>, MeshError> {
    let file = path.display().to_string();
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => return Err(MeshError::NotAFile { file }),
        _ => {}
    }
    crate::limits::read_limited(path, crate::limits::MAX_MESH_BYTES)
        .map_err(|error| MeshError::Read { file, error })
}

/// Parses mesh `bytes` read from `path` (format from its extension, as [`load_mesh`]).
pub fn parse_mesh(bytes: &[u8], path: &Path, scale: f64) -> Result<LoadedMesh, MeshError> {
    let file = path.display().to_string();
    if !(scale.is_finite() && scale > 0.0) {
        return Err(MeshError::Scale { file, scale });
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("stl") => parse_stl(bytes, &file, scale),
        Some("obj") => parse_obj(bytes, &file, scale),
        _ => Err(MeshError::Format { file }),
    }
}

/// A mesh given as arrays (a part straight from perception, or from Python): `vertices` in
/// mesh units (multiplied by `scale` to metres), `faces` as vertex indices. The same checks as
/// a file's: finite coordinates, indices in range, degenerate faces dropped with a warning, a
/// warning for open or non-manifold edges. `name` stands for the file in messages.
pub fn mesh_from_arrays(
    vertices: &[[f64; 3]],
    faces: &[[i64; 3]],
    name: &str,
    scale: f64,
) -> Result<LoadedMesh, MeshError> {
    let file = name.to_string();
    if !(scale.is_finite() && scale > 0.0) {
        return Err(MeshError::Scale { file, scale });
    }
    if let Some((index, v)) = vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !v.iter().all(|c| c.is_finite()))
    {
        return Err(MeshError::NonFinite {
            file,
            index,
            value: *v,
        });
    }
    let n = vertices.len();
    let mut triangles = Vec::with_capacity(faces.len());
    for (face, f) in faces.iter().enumerate() {
        if let Some(&index) = f.iter().find(|&&i| i < 0 || i as u64 >= n as u64) {
            return Err(MeshError::BadIndex {
                file,
                face,
                index,
                vertices: n,
            });
        }
        triangles.push(f.map(|i| i as u32));
    }
    let points = vertices
        .iter()
        .map(|v| Point::new(v[0], v[1], v[2]) * scale)
        .collect();
    let mut loaded = LoadedMesh {
        mesh: Mesh::new(points, triangles),
        warnings: Vec::new(),
    };
    finish(&mut loaded, &file)?;
    Ok(loaded)
}

/// Parses STL bytes (binary or ASCII); `file` names the source in messages.
pub fn parse_stl(bytes: &[u8], file: &str, scale: f64) -> Result<LoadedMesh, MeshError> {
    let file = file.to_string();
    if bytes.is_empty() {
        return Err(MeshError::Empty { file });
    }
    if let Some(kind) = foreign_magic(bytes) {
        return Err(MeshError::NotAMesh {
            file,
            reason: format!("looks like {kind}"),
        });
    }
    // A binary STL is exactly 84 + 50·n bytes, n the little-endian count at byte 80. That test
    // comes first: many exporters start binary headers with "solid" too.
    let binary_len = (bytes.len() >= 84).then(|| {
        84 + 50
            * u64::from(u32::from_le_bytes([
                bytes[80], bytes[81], bytes[82], bytes[83],
            ]))
    });
    let triangles = if binary_len == Some(bytes.len() as u64) {
        read_binary_stl(bytes)
    } else if bytes.starts_with(b"solid") && bytes.is_ascii() {
        read_ascii_stl(bytes, &file)?
    } else {
        return Err(match binary_len {
            None => MeshError::Truncated {
                file,
                reason: format!("{} bytes is shorter than the 84-byte binary STL header", bytes.len()),
            },
            Some(expected) if expected > bytes.len() as u64 && bytes.len() >= 134 => MeshError::Truncated {
                file,
                reason: format!(
                    "header declares {} triangles ({expected} bytes) but the file has {} bytes",
                    (expected - 84) / 50,
                    bytes.len()
                ),
            },
            Some(expected) => MeshError::NotAMesh {
                file,
                reason: format!(
                    "neither ASCII STL (`solid ...`) nor binary STL (header declares {expected} bytes, file has {})",
                    bytes.len()
                ),
            },
        });
    };
    let mut loaded = weld(&triangles, scale, &file)?;
    finish(&mut loaded, &file)?;
    Ok(loaded)
}

/// The ASCII STL reader's message in words for people: its "expected finite f32, got NaN which
/// is Nan" becomes "a vertex coordinate is not a finite number (NaN)".
fn readable_stl_reason(reason: &str) -> String {
    match reason.split_once("expected finite f32, got ") {
        Some((before, rest)) => {
            let value = rest.split(" which is").next().unwrap_or(rest);
            format!("{before}a vertex coordinate is not a finite number ({value})")
        }
        None => reason.to_string(),
    }
}

/// Reads an ASCII STL with `stl_io`, requiring the closing `endsolid`.
fn read_ascii_stl(bytes: &[u8], file: &str) -> Result<Vec<[[f32; 3]; 3]>, MeshError> {
    let malformed = |e: std::io::Error| MeshError::Malformed {
        file: file.to_string(),
        format: "ASCII STL",
        reason: readable_stl_reason(&e.to_string()),
    };
    let truncated = |reason: &str| MeshError::Truncated {
        file: file.to_string(),
        reason: reason.to_string(),
    };
    if !ends_with_endsolid(bytes) {
        return Err(truncated("no closing `endsolid` line"));
    }
    // stl_io wants "solid <name>"; a bare "solid" line is common and just as valid.
    let named: Vec<u8>;
    let bytes = if bytes.starts_with(b"solid\n") || bytes.starts_with(b"solid\r\n") {
        named = [b"solid unnamed".as_slice(), &bytes[5..]].concat();
        &named[..]
    } else {
        bytes
    };
    let mut cursor = Cursor::new(bytes);
    let mut out = Vec::new();
    for t in stl_io::create_stl_reader(&mut cursor).map_err(malformed)? {
        let t = t.map_err(|e| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => truncated("file ends inside a facet"),
            _ => malformed(e),
        })?;
        out.push(t.vertices.map(|v| v.0));
    }
    Ok(out)
}

/// Reads the triangles of a binary STL whose size was already checked. (Done here rather than
/// by `stl_io`, whose format probe takes a binary file whose header starts with "solid " for
/// ASCII.)
/// Each 50-byte record: normal (3 × f32, ignored), 3 corners (9 × f32), attribute (u16).
fn read_binary_stl(bytes: &[u8]) -> Vec<[[f32; 3]; 3]> {
    bytes[84..]
        .chunks_exact(50)
        .map(|rec| {
            let f = |o: usize| f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]);
            [0, 1, 2].map(|c| [0, 1, 2].map(|k| f(12 + 12 * c + 4 * k)))
        })
        .collect()
}

fn ends_with_endsolid(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(bytes);
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|l| l.trim_start().starts_with("endsolid"))
}

/// Recognises common non-mesh files by their first bytes.
fn foreign_magic(bytes: &[u8]) -> Option<&'static str> {
    const MAGICS: [(&[u8], &str); 7] = [
        (b"\x89PNG\r\n\x1a\n", "a PNG image"),
        (b"\xff\xd8\xff", "a JPEG image"),
        (b"GIF8", "a GIF image"),
        (b"%PDF", "a PDF document"),
        (b"PK\x03\x04", "a ZIP archive"),
        (b"\x7fELF", "an executable"),
        (b"\x1f\x8b", "a gzip archive"),
    ];
    MAGICS
        .iter()
        .find(|(m, _)| bytes.starts_with(m))
        .map(|(_, k)| *k)
}

/// Welds triangle-soup corners that are exactly equal (`-0.0` equals `0.0`) into shared
/// vertices, in first-seen order, and scales them. Fails on a non-finite coordinate.
fn weld(tris: &[[[f32; 3]; 3]], scale: f64, file: &str) -> Result<LoadedMesh, MeshError> {
    let mut index: HashMap<[u32; 3], u32, BitsBuildHasher> =
        HashMap::with_capacity_and_hasher(tris.len(), Default::default());
    let mut vertices = Vec::with_capacity(tris.len() / 2 + 3);
    let mut triangles = Vec::with_capacity(tris.len());
    for (ti, t) in tris.iter().enumerate() {
        let mut tri = [0u32; 3];
        for (k, (slot, v)) in tri.iter_mut().zip(t).enumerate() {
            if !v.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFinite {
                    file: file.to_string(),
                    index: 3 * ti + k,
                    value: v.map(f64::from),
                });
            }
            let key = v.map(|c| if c == 0.0 { 0u32 } else { c.to_bits() });
            let next = vertices.len() as u32;
            *slot = *index.entry(key).or_insert_with(|| {
                vertices
                    .push(Point::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])) * scale);
                next
            });
        }
        triangles.push(tri);
    }
    Ok(LoadedMesh {
        mesh: Mesh::new(vertices, triangles),
        warnings: Vec::new(),
    })
}

/// Common checks after parsing: drops degenerate index triangles, refuses an empty mesh and
/// warns about open or non-manifold edges.
fn finish(loaded: &mut LoadedMesh, file: &str) -> Result<(), MeshError> {
    let mesh = &mut loaded.mesh;
    let before = mesh.triangles.len();
    mesh.triangles
        .retain(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    let dropped = before - mesh.triangles.len();
    if mesh.triangles.is_empty() {
        return Err(MeshError::NoTriangles {
            file: file.to_string(),
        });
    }
    if dropped > 0 {
        loaded.warnings.push(format!(
            "{file}: dropped {dropped} degenerate triangle(s) with repeated vertices"
        ));
    }
    part_size(mesh).map_err(|reason| MeshError::NotAPart {
        file: file.to_string(),
        reason,
    })?;
    let (open, non_manifold) = edge_defects(&mesh.triangles);
    if open > 0 || non_manifold > 0 {
        loaded.warnings.push(format!(
            "{file}: mesh is not watertight: {open} open edge(s), {non_manifold} edge(s) shared by more than two triangles"
        ));
    }
    Ok(())
}

/// Smallest part (m): the bounding box's diagonal, after scale.
pub const MIN_PART_SIZE: f64 = 1e-3;
/// Largest part (m): the bounding box's diagonal, after scale.
pub const MAX_PART_SIZE: f64 = 100.0;

/// Refuses a mesh that cannot be a part on a table: smaller than [`MIN_PART_SIZE`] across
/// (a scale in the wrong unit, or one that rounds every coordinate to zero), larger than
/// [`MAX_PART_SIZE`], or without a triangle of any area.
fn part_size(mesh: &Mesh) -> Result<(), String> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for t in &mesh.triangles {
        for &i in t {
            let p = mesh.vertices[i as usize];
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    if diagonal.is_nan() || diagonal < MIN_PART_SIZE {
        return Err(format!(
            "the part is {:.3e} m across after scale, less than {} mm: check object.scale (mesh              units to metres)",
            diagonal,
            MIN_PART_SIZE * 1e3
        ));
    }
    if diagonal > MAX_PART_SIZE {
        return Err(format!(
            "the part is {diagonal:.1} m across after scale, more than {MAX_PART_SIZE} m: check              object.scale (mesh units to metres)"
        ));
    }
    // Area relative to the part's size: a mesh whose triangles are all slivers is no surface.
    let area: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum();
    if area.is_nan() || area <= 1e-12 * diagonal * diagonal {
        return Err("no triangle of the mesh has an area: it is flat lines or points".into());
    }
    Ok(())
}

/// Counts undirected edges used by one triangle (open) and by more than two (non-manifold).
fn edge_defects(triangles: &[[u32; 3]]) -> (usize, usize) {
    let mut edges: Vec<u64> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (u64::from(a.min(b)) << 32) | u64::from(a.max(b)))
        .collect();
    edges.sort_unstable();
    let (mut open, mut non_manifold) = (0, 0);
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        match j - i {
            1 => open += 1,
            2 => {}
            _ => non_manifold += 1,
        }
        i = j;
    }
    (open, non_manifold)
}

/// Parses OBJ text (faces triangulated, groups merged); `file` names the source in messages.
pub fn parse_obj(bytes: &[u8], file: &str, scale: f64) -> Result<LoadedMesh, MeshError> {
    let file_s = file.to_string();
    if bytes.is_empty() {
        return Err(MeshError::Empty { file: file_s });
    }
    if let Some(kind) = foreign_magic(bytes) {
        return Err(MeshError::NotAMesh {
            file: file_s,
            reason: format!("looks like {kind}"),
        });
    }
    if std::str::from_utf8(bytes).is_err() {
        return Err(MeshError::NotAMesh {
            file: file_s,
            reason: "OBJ must be text, found binary data".into(),
        });
    }
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| MeshError::Malformed {
        file: file_s.clone(),
        format: "OBJ",
        reason: e.to_string(),
    })?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in &models {
        let m = &model.mesh;
        let offset = vertices.len() as u32;
        for p in m.positions.chunks_exact(3) {
            let v = [p[0], p[1], p[2]].map(f64::from);
            if !v.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFinite {
                    file: file_s,
                    index: vertices.len(),
                    value: v,
                });
            }
            vertices.push(Point::new(v[0], v[1], v[2]) * scale);
        }
        for t in m.indices.chunks_exact(3) {
            triangles.push([t[0] + offset, t[1] + offset, t[2] + offset]);
        }
    }
    let mut loaded = LoadedMesh {
        mesh: Mesh::new(vertices, triangles),
        warnings: Vec::new(),
    };
    finish(&mut loaded, file)?;
    Ok(loaded)
}

/// The binary STL of `mesh` (single precision, as the format stores it; normals from the
/// right-hand rule on each triangle).
pub fn stl_bytes(mesh: &Mesh) -> Vec<u8> {
    let tris: Vec<stl_io::Triangle> = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            let n = (b - a).cross(&(c - a));
            let n = if n.norm() > 0.0 { n.normalize() } else { n };
            let v = |p: Point| stl_io::Vertex::new([p.x as f32, p.y as f32, p.z as f32]);
            stl_io::Triangle {
                normal: stl_io::Normal::new([n.x as f32, n.y as f32, n.z as f32]),
                vertices: [v(a), v(b), v(c)],
            }
        })
        .collect();
    let mut out = Vec::with_capacity(84 + 50 * tris.len());
    stl_io::write_stl(&mut out, tris.iter()).expect("writing to memory cannot fail");
    out
}

/// Writes `mesh` to `path` as binary STL, atomically ([`crate::output::write_one`]).
pub fn write_stl(path: &Path, mesh: &Mesh) -> Result<(), crate::output::OutputError> {
    crate::output::write_one(path, &stl_bytes(mesh))
}
