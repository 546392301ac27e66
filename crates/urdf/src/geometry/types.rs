//! The collision model derived from a URDF: convex pieces per link, in the link frame, and
//! the link pairs checked for self-collision (the shape `pregrasp-robot`'s `ArmGeometry`
//! takes: pieces per link plus index pairs).

use nalgebra::{Isometry3, Point3};
use serde::{Deserialize, Serialize};

/// The collision geometry of one link: convex polytopes, each given by its vertices in the
/// **link frame** (m); the polytope is their convex hull. The union of the pieces contains
/// every `<collision>` element of the link (mesh vertices, primitive solids), with its
/// `<origin>` and `<mesh scale>` applied.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinkPieces {
    /// The URDF link name.
    pub link: String,
    /// Vertices of each piece in the link frame (m).
    pub pieces: Vec<Vec<Point3<f64>>>,
    /// For each piece, the index of the `<collision>` element of the link it was made from
    /// (file order; one piece per element in this version).
    pub elements: Vec<usize>,
}

impl LinkPieces {
    /// The pieces' vertices carried by `at` (from the link frame into the frame `at` maps to).
    pub fn placed(&self, at: &Isometry3<f64>) -> Vec<Vec<Point3<f64>>> {
        self.pieces
            .iter()
            .map(|p| p.iter().map(|v| at * v).collect())
            .collect()
    }
}

/// Why a pair of links is not checked for self-collision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Exclusion {
    /// Joined by a joint (through fixed joints and geometry-less links).
    Adjacent,
    /// In contact in (at least the configured fraction of) every sampled configuration.
    Always,
    /// In contact in no sampled configuration.
    Never,
    /// Named in an allowed-collision list.
    Allowed,
}

/// A pair of links left out of the self-collision check, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExcludedPair {
    /// Indices into [`UrdfGeometry::links`], `a < b`.
    pub a: usize,
    /// See `a`.
    pub b: usize,
    /// The reason.
    pub why: Exclusion,
    /// Sampled configurations in which the pair was in contact, of `samples`
    /// (0 of 0 for adjacent and allowed pairs).
    pub hits: usize,
    /// Sampled configurations tested.
    pub samples: usize,
}

/// The collision model of a URDF: pieces per link and the self-collision pairs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UrdfGeometry {
    /// The robot name of the URDF.
    pub robot: String,
    /// Every link that has `<collision>` elements, URDF file order.
    pub links: Vec<LinkPieces>,
    /// Pairs `(i, j)`, `i < j`, of indices into `links` that must not touch, ascending.
    pub self_collision_pairs: Vec<(usize, usize)>,
    /// The other pairs of `links`, with the reason each is not checked, ascending.
    pub excluded_pairs: Vec<ExcludedPair>,
    /// Hex digest of everything the model was derived from (the cache key).
    pub key: String,
}

impl UrdfGeometry {
    /// Index into [`UrdfGeometry::links`] of the link called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.link == name)
    }

    /// The names of a pair of link indices.
    pub fn pair_names(&self, (a, b): (usize, usize)) -> (&str, &str) {
        (&self.links[a].link, &self.links[b].link)
    }
}
