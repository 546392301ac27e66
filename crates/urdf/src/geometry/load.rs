//! Deriving a URDF's collision model, through the cache.
//!
//! [`UrdfGeometry::load`]: gather every `<collision>` element (resolving and reading mesh
//! files), digest the inputs into a key, return the cached model for that key if there is a
//! valid one, else compute it ([`UrdfGeometry::compute_from`]) and cache it.
//!
//! The key is FNV-1a 128 (`src/geometry/hash.rs`) over [`ALGORITHM_VERSION`], the robot name, per
//! link with collision elements its name and per element the `<origin>`, the geometry kind
//! and numbers (box size, radius, length, mesh scale, mesh file extension and **bytes**),
//! every joint (name, type, parent, child, origin, axis, limits, mimic), the sampling
//! options and the arm's base and tool link when [`GeometryOptions::arm`] selects the links
//! of one arm ([`super::select`]: then only those links' elements). Paths are not in it: the
//! same robot in two folders shares one entry. Anything that changes the result changes the
//! key; bump [`ALGORITHM_VERSION`] when the code does.

use std::path::{Path, PathBuf};

use pregrasp_limits::{bytes as bytes_in_words, read_limited, MAX_COLLISION_MESH_BYTES};

use super::cache::{self, Read};
pub use super::element::{element_mesh, element_piece, element_points, Element};
use super::entry_check::check_entry;
use super::hash::Fnv128;
use super::mesh;
use super::select::selected;
use super::self_collision::{classify_pairs, SelfCollisionOptions};
use super::tree::LinkTree;
use super::types::{LinkPieces, UrdfGeometry};
use super::values::check_element;
use crate::chain::origin_isometry;
use crate::error::UrdfError;
use crate::limits::{MAX_COLLISION_ELEMENTS, MAX_COLLISION_LINKS, MAX_TOTAL_MESH_BYTES};
use crate::model::UrdfModel;

/// Version of the derivation; part of the cache key.
pub const ALGORITHM_VERSION: &str = "pregrasp-urdf-geometry/1: one hull per element";

/// Where derived models are cached.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum CacheDir {
    /// [`super::default_cache_dir`] (no caching when the environment names none).
    #[default]
    Default,
    /// This folder.
    At(PathBuf),
    /// No caching.
    Off,
}

/// How to derive a collision model.
#[derive(Clone, Debug, Default)]
pub struct GeometryOptions {
    /// Directories searched for `package://` meshes, before the URDF's own folder and its
    /// `meshes/` subfolder (see [`super::mesh`]).
    pub mesh_dirs: Vec<PathBuf>,
    /// The folder relative mesh paths are relative to; default: the folder of the model's
    /// source file.
    pub urdf_dir: Option<PathBuf>,
    /// The cache.
    pub cache: CacheDir,
    /// Self-collision sampling.
    pub self_collision: SelfCollisionOptions,
    /// `(base link, tool link)`: derive only the links of the arm between them and what hangs
    /// below the tool link ([`super::select`]); `None`: every link of the file.
    pub arm: Option<(String, String)>,
}

/// What the cache did on a load.
#[derive(Clone, Debug, PartialEq)]
pub enum CacheOutcome {
    /// The model was read from this entry.
    Hit(PathBuf),
    /// Computed and written to this entry (there was none).
    Written(PathBuf),
    /// The entry was unusable (the reason); recomputed and rewritten.
    Replaced(PathBuf, String),
    /// Computed, not cached (caching off, no cache folder, or the write failed: why).
    NotCached(String),
}

/// A model and how it was obtained.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The collision model.
    pub geometry: UrdfGeometry,
    /// What the cache did.
    pub cache: CacheOutcome,
}

/// Every `<collision>` element of `model`, link by link in file order, its values checked
/// ([`super::values`]) and its mesh resolved and read: a regular file of at most
/// [`MAX_COLLISION_MESH_BYTES`] (errors: [`UrdfError::BadCollision`],
/// [`UrdfError::MissingMesh`], [`UrdfError::Mesh`]).
pub fn collision_elements(
    model: &UrdfModel,
    opts: &GeometryOptions,
) -> Result<Vec<Element>, UrdfError> {
    elements_of(model, opts, None)
}

/// [`collision_elements`] of the links [`GeometryOptions::arm`] selects: the other links'
/// elements are neither checked nor read.
fn arm_elements(model: &UrdfModel, opts: &GeometryOptions) -> Result<Vec<Element>, UrdfError> {
    let keep = selected(model, opts.arm.as_ref())?;
    elements_of(model, opts, keep.as_ref())
}

/// The elements of the links in `keep` (every link when `None`), as [`collision_elements`].
fn elements_of(
    model: &UrdfModel,
    opts: &GeometryOptions,
    keep: Option<&std::collections::BTreeSet<String>>,
) -> Result<Vec<Element>, UrdfError> {
    let urdf_dir: Option<PathBuf> = opts.urdf_dir.clone().or_else(|| {
        let src = Path::new(model.source());
        src.is_file()
            .then(|| src.parent().map(Path::to_path_buf).unwrap_or_default())
    });
    let dirs = mesh::search_dirs(urdf_dir.as_deref(), &opts.mesh_dirs);
    let mut out = Vec::new();
    let kept = |name: &String| keep.is_none_or(|k| k.contains(name));
    let links: Vec<&urdf_rs::Link> = (model.robot().links.iter())
        .filter(|l| kept(&l.name) && !l.collision.is_empty())
        .collect();
    let elements: usize = links.iter().map(|l| l.collision.len()).sum();
    let too_large = |what: String, max: String| UrdfError::TooLarge {
        file: model.source().to_string(),
        what,
        max,
    };
    if links.len() > MAX_COLLISION_LINKS {
        let what = format!("{} links with <collision> elements", links.len());
        return Err(too_large(what, MAX_COLLISION_LINKS.to_string()));
    }
    if elements > MAX_COLLISION_ELEMENTS {
        let what = format!("{elements} <collision> elements");
        return Err(too_large(what, MAX_COLLISION_ELEMENTS.to_string()));
    }
    let mut mesh_bytes = 0u64;
    for link in links {
        for (index, c) in link.collision.iter().enumerate() {
            check_element(model.source(), &link.name, &c.geometry)?;
            let mesh = match &c.geometry {
                urdf_rs::Geometry::Mesh { filename, .. } => {
                    let path = mesh::resolve(filename, urdf_dir.as_deref(), &dirs).map_err(
                        |searched| mesh::missing(model.source(), &link.name, filename, &searched),
                    )?;
                    let bytes = read_limited(&path, MAX_COLLISION_MESH_BYTES).map_err(|e| {
                        UrdfError::Mesh {
                            file: model.source().to_string(),
                            link: link.name.clone(),
                            path: path.display().to_string(),
                            message: e.to_string(),
                        }
                    })?;
                    mesh_bytes += bytes.len() as u64;
                    if mesh_bytes > MAX_TOTAL_MESH_BYTES {
                        let what =
                            format!("collision meshes of over {}", bytes_in_words(mesh_bytes));
                        return Err(too_large(what, bytes_in_words(MAX_TOTAL_MESH_BYTES)));
                    }
                    Some((path, bytes))
                }
                _ => None,
            };
            out.push(Element {
                link: link.name.clone(),
                index,
                origin: origin_isometry(&c.origin),
                geometry: c.geometry.clone(),
                mesh,
            });
        }
    }
    Ok(out)
}

/// The cache key of `elements` and the joints of `model` (see the module documentation).
fn key(model: &UrdfModel, elements: &[Element], all: &GeometryOptions) -> String {
    let opts = &all.self_collision;
    use urdf_rs::Geometry as G;
    let mut h = Fnv128::new();
    h.str(ALGORITHM_VERSION);
    h.str(model.name());
    for e in elements {
        h.str(&e.link);
        h.u64(e.index as u64);
        let (t, r) = (e.origin.translation.vector, e.origin.rotation.coords);
        t.iter().chain(r.iter()).for_each(|v| h.f64(*v));
        match &e.geometry {
            G::Box { size } => {
                h.str("box");
                size.0.iter().for_each(|v| h.f64(*v));
            }
            G::Cylinder { radius, length } | G::Capsule { radius, length } => {
                let cylinder = matches!(e.geometry, G::Cylinder { .. });
                h.str(if cylinder { "cylinder" } else { "capsule" });
                h.f64(*radius);
                h.f64(*length);
            }
            G::Sphere { radius } => {
                h.str("sphere");
                h.f64(*radius);
            }
            G::Mesh { scale, .. } => {
                h.str("mesh");
                scale
                    .map_or([1.0; 3], |s| s.0)
                    .iter()
                    .for_each(|v| h.f64(*v));
                let (path, bytes) = e.mesh.as_ref().expect("mesh read");
                h.str(
                    &path
                        .extension()
                        .unwrap_or_default()
                        .to_string_lossy()
                        .to_lowercase(),
                );
                h.field(bytes);
            }
        }
    }
    for j in &model.robot().joints {
        h.str(&j.name);
        h.str(&format!("{:?}", j.joint_type));
        h.str(&j.parent.link);
        h.str(&j.child.link);
        j.origin
            .xyz
            .0
            .iter()
            .chain(&j.origin.rpy.0)
            .for_each(|v| h.f64(*v));
        j.axis.xyz.0.iter().for_each(|v| h.f64(*v));
        [
            j.limit.lower,
            j.limit.upper,
            j.limit.velocity,
            j.limit.effort,
        ]
        .iter()
        .for_each(|v| h.f64(*v));
        if let Some(m) = &j.mimic {
            h.str(&m.joint);
            h.f64(m.multiplier.unwrap_or(1.0));
            h.f64(m.offset.unwrap_or(0.0));
        }
    }
    h.u64(opts.samples as u64);
    h.u64(opts.seed);
    h.f64(opts.always_fraction);
    if let Some((base, tool)) = &all.arm {
        h.str("arm");
        h.str(base);
        h.str(tool);
    }
    h.hex()
}

impl UrdfGeometry {
    /// The collision model of `model`: from the cache when a valid entry for its inputs
    /// exists, else computed and cached (see the module documentation). Cache problems are
    /// never errors; errors are missing or unreadable meshes and bad joints.
    pub fn load(model: &UrdfModel, opts: &GeometryOptions) -> Result<Loaded, UrdfError> {
        let elements = arm_elements(model, opts)?;
        let key = key(model, &elements, opts);
        let dir = match &opts.cache {
            CacheDir::Default => cache::default_cache_dir(),
            CacheDir::At(d) => Some(d.clone()),
            CacheDir::Off => None,
        };
        let Some(dir) = dir else {
            let geometry = Self::compute_from(model, &elements, key, opts)?;
            let why = if opts.cache == CacheDir::Off {
                "caching off"
            } else {
                "no cache folder"
            };
            return Ok(Loaded {
                geometry,
                cache: CacheOutcome::NotCached(why.to_string()),
            });
        };
        let path = cache::entry_path(&dir, model.name(), &key);
        let bad = match cache::read(&path, ALGORITHM_VERSION, &key) {
            Read::Hit(geometry) => match check_entry(model, &elements, &geometry) {
                Ok(()) => {
                    return Ok(Loaded {
                        geometry,
                        cache: CacheOutcome::Hit(path),
                    })
                }
                Err(why) => Some(why),
            },
            Read::Absent => None,
            Read::Bad(why) => Some(why),
        };
        let geometry = Self::compute_from(model, &elements, key, opts)?;
        let cache = match (cache::write(&path, ALGORITHM_VERSION, &geometry), bad) {
            (Err(why), _) => CacheOutcome::NotCached(why),
            (Ok(()), None) => CacheOutcome::Written(path),
            (Ok(()), Some(why)) => CacheOutcome::Replaced(path, why),
        };
        Ok(Loaded { geometry, cache })
    }

    /// [`UrdfGeometry::load`] without the cache.
    pub fn compute(model: &UrdfModel, opts: &GeometryOptions) -> Result<UrdfGeometry, UrdfError> {
        let elements = arm_elements(model, opts)?;
        let key = key(model, &elements, opts);
        Self::compute_from(model, &elements, key, opts)
    }

    /// The model of already gathered elements: one piece per element, grouped by link (file
    /// order), then the self-collision pairs ([`super::self_collision`]).
    pub fn compute_from(
        model: &UrdfModel,
        elements: &[Element],
        key: String,
        opts: &GeometryOptions,
    ) -> Result<UrdfGeometry, UrdfError> {
        let mut links: Vec<LinkPieces> = Vec::new();
        for e in elements {
            let piece = element_piece(model, e)?;
            match links.last_mut() {
                Some(l) if l.link == e.link => {
                    l.pieces.push(piece);
                    l.elements.push(e.index);
                }
                _ => links.push(LinkPieces {
                    link: e.link.clone(),
                    pieces: vec![piece],
                    elements: vec![e.index],
                }),
            }
        }
        let tree = LinkTree::new(model)?;
        let (self_collision_pairs, excluded_pairs) =
            classify_pairs(&tree, &links, &opts.self_collision);
        Ok(UrdfGeometry {
            robot: model.name().to_string(),
            links,
            self_collision_pairs,
            excluded_pairs,
            key,
        })
    }
}
