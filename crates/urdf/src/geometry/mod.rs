//! Collision geometry of a URDF robot from its `<collision>` elements, derived once and
//! cached.
//!
//! * [`mesh`]: `package://`, `file://` and relative mesh names resolved against a search
//!   path; STL, OBJ and COLLADA read with `mesh-loader`; `<mesh scale>` and `<origin>`
//!   applied, so meshes are in the **link frame**; a COLLADA file is first checked by
//!   [`collada`], so that `mesh-loader` only ever reads one it handles safely.
//! * [`pieces`], [`primitives`]: one convex piece per element: the convex hull of a mesh
//!   (every vertex inside, tested to 1e-9 m), or a polytope circumscribing a box, cylinder,
//!   sphere or capsule.
//! * [`self_collision`]: the link pairs to check: all pairs minus adjacent ones and those in
//!   contact always or never over deterministic joint samples, over the whole link tree
//!   ([`tree`]); [`UrdfGeometry::allow`] removes more.
//! * [`select`]: with [`GeometryOptions::arm`], only the links one arm and its gripper use
//!   (a 6-joint arm in a file with 400 other links samples its own pairs only).
//! * [`load`]: [`UrdfGeometry::load`], keyed by a digest of every input and cached on disk
//!   ([`cache`]); [`excess`] measures how far pieces reach outside their geometry.
//!
//! The result, [`UrdfGeometry`], is shaped like `pregrasp-robot`'s `ArmGeometry`: per link a
//! list of convex pieces (vertices in the link frame), and index pairs of links.

pub mod cache;
pub mod collada;
mod element;
mod entry_check;
pub mod excess;
mod hash;
mod lazy;
pub mod load;
pub mod mesh;
pub mod pieces;
pub mod primitives;
pub mod select;
pub mod self_collision;
pub mod tree;
mod types;
pub mod values;

use nalgebra::Isometry3;

pub use cache::default_cache_dir;
pub use excess::{measure_excess, PieceExcess};
pub use lazy::LazyGeometry;
pub use load::{CacheDir, CacheOutcome, GeometryOptions, Loaded, ALGORITHM_VERSION};
pub use self_collision::{PieceShapes, SelfCollisionOptions};
pub use tree::{LinkTree, TreeVariable};
pub use types::{ExcludedPair, Exclusion, LinkPieces, UrdfGeometry};
pub use values::MAX_LINK_EXTENT;

use crate::error::UrdfError;

impl UrdfGeometry {
    /// Stops checking the pair of links `a`, `b` (an allowed-collision entry): moves it from
    /// [`UrdfGeometry::self_collision_pairs`] to the excluded pairs as
    /// [`Exclusion::Allowed`]. Returns whether it was checked before. An unknown link (or one
    /// without pieces) is an error naming it.
    pub fn allow(&mut self, a: &str, b: &str) -> Result<bool, UrdfError> {
        let index = |name: &str| {
            self.index_of(name).ok_or_else(|| UrdfError::UnknownLink {
                file: self.robot.clone(),
                link: name.to_string(),
                context: "named in an allowed-collision pair; links with collision geometry: "
                    .to_string()
                    + &self
                        .links
                        .iter()
                        .map(|l| l.link.as_str())
                        .collect::<Vec<_>>()
                        .join(", "),
            })
        };
        let (i, j) = (index(a)?, index(b)?);
        let pair = (i.min(j), i.max(j));
        let Some(k) = self.self_collision_pairs.iter().position(|&p| p == pair) else {
            return Ok(false);
        };
        self.self_collision_pairs.remove(k);
        let at = self.excluded_pairs.partition_point(|e| (e.a, e.b) < pair);
        self.excluded_pairs.insert(
            at,
            ExcludedPair {
                a: pair.0,
                b: pair.1,
                why: Exclusion::Allowed,
                hits: 0,
                samples: 0,
            },
        );
        Ok(true)
    }

    /// [`UrdfGeometry::allow`] for every pair of a list.
    pub fn allow_all<'a>(
        &mut self,
        pairs: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(), UrdfError> {
        for (a, b) in pairs {
            self.allow(a, b)?;
        }
        Ok(())
    }

    /// The checked pairs ([`UrdfGeometry::self_collision_pairs`]) whose pieces touch or
    /// overlap with the links posed by `pose_of` (link name → pose, all in one frame; pairs
    /// with an unposed link are skipped). Builds the polyhedra on each call: keep a
    /// [`PieceShapes`] to test many poses.
    pub fn colliding_pairs(
        &self,
        pose_of: impl Fn(&str) -> Option<Isometry3<f64>>,
    ) -> Vec<(usize, usize)> {
        let shapes = PieceShapes::new(&self.links);
        let poses: Vec<Option<Isometry3<f64>>> =
            self.links.iter().map(|l| pose_of(&l.link)).collect();
        self.self_collision_pairs
            .iter()
            .copied()
            .filter(|&(a, b)| match (&poses[a], &poses[b]) {
                (Some(pa), Some(pb)) => shapes.intersect(a, pa, b, pb),
                _ => false,
            })
            .collect()
    }
}
