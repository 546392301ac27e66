//! Collision geometry of the arm links, in the DH frames they move with.
//!
//! Source: `data/ur_links.json` and `data/ur_pieces_<model>.json`, fitted by
//! `tools/geometry/derive.py` and `derive_pieces.py` to the visual meshes of Universal Robots'
//! ROS 2 description (UR3e, UR5e, UR10e, UR16e and the CB3 UR5, each from its own meshes;
//! provenance and per-link numbers in `data/PROVENANCE.md`). Every link is a few [`Cylinder`]s,
//! flat-ended or with rounded rims where the housings are rounded: coaxial stacks on the joint
//! axes for the housings, the base and the flange, and cylinders from joint axis to joint axis
//! for the tubes, so no round cap sticks out along an axis. Each cylinder carries its
//! [`ConvexPieces`]: convex polytopes hugging the part of the link it was fitted to (the
//! shoulder's tilted cap, the tube junctions), which decide contact where the cylinder is
//! close (the two-tier test is in `pregrasp_collision::tight`). Every mesh vertex lies inside
//! its link's shapes and inside its pieces (tested); neither carries a margin — the clearance
//! the arms keep is a planner setting (`[planner] link_clearance`).
//!
//! DH frames at q = 0 (UR5e, base coordinates): frames 1–3 have x = X, y = Z, z = −Y;
//! frame 4 has x = X, y = −Y, z = −Z; frames 5 and 6 have x = X, y = Z, z = −Y. The link
//! carried by joint i is expressed in DH frame i (shoulder 1, upper arm 2, forearm 3,
//! wrist_1 4, wrist_2 5, wrist_3 6); the base is in frame 0.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use crate::model::UrModel;

/// A capsule: the points within `radius` of the segment `a`–`b` (a sphere when `a == b`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// First segment end, in the owning frame (m).
    pub a: Point3<f64>,
    /// Second segment end, in the owning frame (m).
    pub b: Point3<f64>,
    /// Radius (m).
    pub radius: f64,
}

impl Capsule {
    /// Distance from `p` to the capsule's segment (m).
    pub fn segment_distance(&self, p: &Point3<f64>) -> f64 {
        let ab = self.b - self.a;
        let len2 = ab.norm_squared();
        let t = if len2 > 0.0 {
            ((p - self.a).dot(&ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (self.a + t * ab)).norm()
    }

    /// True when `p` lies inside (or on) the capsule.
    pub fn contains(&self, p: &Point3<f64>) -> bool {
        self.segment_distance(p) <= self.radius
    }
}

/// A solid circular cylinder with flat ends and, optionally, rounded rims: end-face centres
/// `a`, `b` and radius `radius` span its envelope (the points within `radius` of the segment
/// `a`–`b` whose projection onto the line `ab` falls between `a` and `b`), and a `border`
/// `e > 0` rounds both rims with radius `e`. With the unit axis `u`, the solid is the
/// Minkowski sum of the cylinder with end-face centres `a + e·u`, `b − e·u` and radius
/// `radius − e` with a ball of radius `e` (parry's `RoundCylinder`). `border = 0` is the sharp
/// cylinder; `0 ≤ border ≤ min(radius, |b − a| / 2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    /// Centre of the first end face, in the owning frame (m).
    pub a: Point3<f64>,
    /// Centre of the second end face, in the owning frame (m).
    pub b: Point3<f64>,
    /// Radius (m).
    pub radius: f64,
    /// Radius of the rounded rims (m), 0 for sharp rims.
    pub border: f64,
}

impl Cylinder {
    /// A cylinder with sharp rims.
    pub fn sharp(a: Point3<f64>, b: Point3<f64>, radius: f64) -> Cylinder {
        Cylinder {
            a,
            b,
            radius,
            border: 0.0,
        }
    }

    /// The inner cylinder `(a + e·u, b − e·u, radius − e)` whose Minkowski sum with a ball of
    /// radius `e = border` is this solid.
    pub fn inset(&self) -> (Point3<f64>, Point3<f64>, f64) {
        let ab = self.b - self.a;
        let len = ab.norm();
        if self.border == 0.0 || len == 0.0 {
            return (self.a, self.b, self.radius);
        }
        let step = ab * (self.border / len);
        (self.a + step, self.b - step, self.radius - self.border)
    }

    /// How far `p` lies outside the solid (m; 0 inside or on it): the distance to the inset
    /// core less the border.
    pub fn outside_distance(&self, p: &Point3<f64>) -> f64 {
        let (a, b, r) = self.inset();
        (point_cylinder_distance(p, &a, &b, r) - self.border).max(0.0)
    }

    /// True when `p` lies inside (or on) the solid, within `tol`.
    pub fn contains(&self, p: &Point3<f64>, tol: f64) -> bool {
        if self.a == self.b {
            return false;
        }
        self.outside_distance(p) <= tol
    }
}

/// Distance from point `p` to the solid flat-ended cylinder with end-face centres `a`, `b` and
/// radius `r` (`0` inside): the axial and radial excesses combined.
#[inline]
pub fn point_cylinder_distance(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>, r: f64) -> f64 {
    let ab = b - a;
    let len = ab.norm();
    let c = nalgebra::center(a, b);
    let v = p - c;
    if len == 0.0 {
        return (v.norm() - r).max(0.0);
    }
    let u = ab / len;
    let t = v.dot(&u);
    let radial = (v - u * t).norm();
    let dz = (t.abs() - 0.5 * len).max(0.0);
    let dr = (radial - r).max(0.0);
    (dz * dz + dr * dr).sqrt()
}

/// A collision primitive in the frame of the link that carries it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// A capsule (a sphere when both ends coincide).
    Capsule(Capsule),
    /// A cylinder, flat-ended or with rounded rims (joint housings, tubes, the base).
    Cylinder(Cylinder),
    /// A box with its centre and axes at `pose` in the owning frame.
    Cuboid {
        /// Pose of the box centre in the owning frame.
        pose: Isometry3<f64>,
        /// Half side lengths (m).
        half_extents: Vector3<f64>,
    },
}

impl Primitive {
    /// An axis-aligned box spanning `[lo, hi]` in the owning frame.
    pub fn aabb(lo: Vector3<f64>, hi: Vector3<f64>) -> Primitive {
        let c = 0.5 * (lo + hi);
        Primitive::Cuboid {
            pose: Isometry3::from_parts(Translation3::from(c), UnitQuaternion::identity()),
            half_extents: 0.5 * (hi - lo),
        }
    }

    /// Largest distance from the owning frame's origin to a point of the primitive (m).
    pub fn max_origin_distance(&self) -> f64 {
        match self {
            Primitive::Capsule(c) => c.a.coords.norm().max(c.b.coords.norm()) + c.radius,
            Primitive::Cylinder(c) => c.a.coords.norm().max(c.b.coords.norm()) + c.radius,
            Primitive::Cuboid { pose, half_extents } => {
                pose.translation.vector.norm() + half_extents.norm()
            }
        }
    }
}

/// One named collision shape attached to a DH frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkShape {
    /// Shape name, e.g. "upper_arm_tube" or "gripper_body".
    pub name: &'static str,
    /// Index into [`crate::UrKinematics::fk_frames`] (0 = base … 6 = flange/wrist_3).
    pub frame: usize,
    /// The shape, in that frame.
    pub primitive: Primitive,
    /// The link's surface inside this shape as convex pieces, where fitted: the exact tier of
    /// the collision model (`None`: the primitive is the exact shape, as for the gripper).
    pub pieces: Option<&'static ConvexPieces>,
}

/// The exact tier of a link shape: convex polytopes that hold the part of the link's surface
/// the shape was fitted to (every visual-mesh vertex and 0.6 mm surface sample is in their
/// union), each within `slack` of the shape. The shape, grown by `slack`, is then a bound of
/// the pieces: a test that finds the shape clear by `margin + slack` has found the pieces
/// clear by `margin`, and only shapes closer than that are tested on the pieces.
/// Fitted by `tools/geometry/ur_pieces.py`.
#[derive(Debug, PartialEq)]
pub struct ConvexPieces {
    /// Vertices of each piece in the owning frame (m); the piece is their convex hull.
    pub pieces: Vec<Vec<Point3<f64>>>,
    /// How far any piece reaches outside the primitive (m, ≥ 0).
    pub slack: f64,
}

impl ConvexPieces {
    /// `pieces` (vertices in their owning frame) kept for the life of the process, with the box
    /// about the frame's axes that holds them (slack 0); `None` when they have no vertex. Shapes
    /// hold `&'static` pieces: a description's links and parts are made this way, once each.
    pub fn leak_boxed(pieces: Vec<Vec<Point3<f64>>>) -> Option<(&'static ConvexPieces, Primitive)> {
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = Vector3::repeat(f64::NEG_INFINITY);
        for v in pieces.iter().flatten() {
            lo = lo.inf(&v.coords);
            hi = hi.sup(&v.coords);
        }
        if !lo.iter().all(|c| c.is_finite()) {
            return None;
        }
        let pieces = Box::leak(Box::new(ConvexPieces { pieces, slack: 0.0 }));
        Some((pieces, Primitive::aabb(lo, hi)))
    }
}

/// Most shapes (arm links + gripper parts) one arm may have: the collision crate poses an
/// arm in a fixed-size buffer, one bit per shape in a `u64`.
pub const MAX_ARM_SHAPES: usize = 34;

/// Most shapes a gripper may have (housing boxes and finger links).
pub const MAX_GRIPPER_SHAPES: usize = 16;

/// Most link shapes an arm from a robot description is given: what leaves room for the
/// largest gripper. A description with more links has those that move with one frame merged
/// (`pregrasp_urdf::describe_arm`).
pub const MAX_LINK_SHAPES: usize = MAX_ARM_SHAPES - MAX_GRIPPER_SHAPES;

/// Collision model of an arm: shapes that contain its links, and the pairs checked.
#[derive(Clone, Debug)]
pub struct ArmGeometry {
    /// Link shapes; `frame` indexes `fk_frames`.
    pub links: Vec<LinkShape>,
    /// Pairs `(i, j)`, `i < j`, of indices into `links` that must not touch.
    pub self_collision_pairs: Vec<(usize, usize)>,
}

impl ArmGeometry {
    /// Index of the shape called `name`, if any.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }
}

/// Link shapes of `model` (fitted to its description meshes) and the shape pairs checked for
/// self-collision.
///
/// Self-collision pairs: every pair of shapes on links two or more joints apart, except
/// pairs whose distance no joint motion can change or that the mechanism keeps apart:
/// wrist_1 vs wrist_3 (wrist_3 is a solid of revolution about z5, which only turns about
/// z4 at a fixed offset from wrist_1) and the base vs the upper arm's shoulder housing (a
/// solid of revolution about the shoulder-lift axis, at a fixed height above the base).
pub fn arm_geometry(model: UrModel) -> ArmGeometry {
    let mut links = fitted_links(model)
        .unwrap_or_else(|| panic!("ur_links.json has no shapes for {model}"))
        .clone();
    let pieces = model_pieces(model);
    for l in &mut links {
        l.pieces = pieces.get(l.name);
    }
    with_self_collision_pairs(links)
}

/// The exact pieces of `model`'s link shapes by shape name (`data/ur_pieces_<model>.json`, as
/// `build.rs` converted it: [`crate::pieces_blob`]), read the first time the model is used: a
/// scene with UR5e arms never reads the others.
fn model_pieces(model: UrModel) -> &'static std::collections::BTreeMap<&'static str, ConvexPieces> {
    type Pieces = std::collections::BTreeMap<&'static str, ConvexPieces>;
    static MODELS: [std::sync::OnceLock<Pieces>; 5] = [const { std::sync::OnceLock::new() }; 5];
    let slot = match model {
        UrModel::Ur3e => 0,
        UrModel::Ur5e => 1,
        UrModel::Ur10e => 2,
        UrModel::Ur16e => 3,
        UrModel::Ur5 => 4,
    };
    MODELS[slot].get_or_init(|| {
        let names = fitted_links(model).expect("every model has shapes");
        crate::pieces_blob::shapes(model)
            .into_iter()
            .map(|p| {
                let name = &p.name;
                let shape = names
                    .iter()
                    .find(|l| l.name == name)
                    .unwrap_or_else(|| panic!("ur_pieces_{model}.json: no shape {name:?}"));
                assert!(
                    p.slack >= 0.0 && p.slack < 0.005 && p.pieces.iter().all(|v| v.len() >= 4),
                    "ur_pieces_{model}.json: {name}: slack {} outside [0, 5 mm) or a piece of < 4 vertices",
                    p.slack
                );
                (
                    shape.name,
                    ConvexPieces {
                        pieces: p.pieces,
                        slack: p.slack,
                    },
                )
            })
            .collect()
    })
}

#[derive(serde::Deserialize)]
struct FittedShapeJson {
    name: String,
    kind: String,
    a: [f64; 3],
    b: [f64; 3],
    radius: f64,
    /// Rounded-rim radius of a cylinder (m); absent or 0: sharp rims.
    #[serde(default)]
    border: f64,
}

#[derive(serde::Deserialize)]
struct FittedLinkJson {
    name: String,
    frame: usize,
    shapes: Vec<FittedShapeJson>,
    #[serde(default)]
    excess_mm: Option<f64>,
    #[serde(default)]
    pieces_excess_mm: Option<f64>,
}

#[derive(serde::Deserialize)]
struct FittedModelJson {
    links: Vec<FittedLinkJson>,
}

#[derive(serde::Deserialize)]
struct FittedFileJson {
    models: std::collections::BTreeMap<String, FittedModelJson>,
}

/// One link of a fitted model: its shapes and the largest outward excess the fit measured over
/// the link's mesh (see `data/PROVENANCE.md`; the mesh vertices the shapes must contain are
/// test data, `data/ur_link_vertices.json`).
#[derive(Clone, Debug)]
pub struct FittedLink {
    /// Link name: base, shoulder, upper_arm, forearm, wrist_1, wrist_2, wrist_3.
    pub name: String,
    /// DH frame the link moves with.
    pub frame: usize,
    /// Indices into [`arm_geometry`]'s `links` of this link's shapes.
    pub shapes: Vec<usize>,
    /// Largest outward excess of the shapes over the mesh (mm), as measured by the fit.
    pub excess_mm: Option<f64>,
    /// Largest outward excess of the shapes' exact pieces ([`ConvexPieces`]) over the mesh
    /// (mm), measured the same way: what decides contact.
    pub pieces_excess_mm: Option<f64>,
}

struct FittedModel {
    shapes: Vec<LinkShape>,
    links: Vec<FittedLink>,
}

/// The link shapes fitted to the description meshes (`data/ur_links.json`, made by
/// `tools/geometry/derive.py`), per model; parsed once.
fn fitted_models() -> &'static std::collections::BTreeMap<String, FittedModel> {
    static MODELS: std::sync::OnceLock<std::collections::BTreeMap<String, FittedModel>> =
        std::sync::OnceLock::new();
    MODELS.get_or_init(|| {
        let file: FittedFileJson = serde_json::from_str(include_str!("../data/ur_links.json"))
            .expect("built-in ur_links.json is valid");
        file.models
            .into_iter()
            .map(|(name, m)| {
                let mut shapes = Vec::new();
                let mut links = Vec::new();
                for l in m.links {
                    let mut indices = Vec::new();
                    for s in l.shapes {
                        let (a, b) = (Point3::from(s.a), Point3::from(s.b));
                        let primitive = match s.kind.as_str() {
                            "cylinder" => {
                                let length = (b - a).norm();
                                assert!(
                                    s.border >= 0.0
                                        && s.border <= s.radius
                                        && 2.0 * s.border < length,
                                    "ur_links.json: {name} {}: border {} outside [0, min(radius, length / 2))",
                                    s.name,
                                    s.border
                                );
                                Primitive::Cylinder(Cylinder {
                                    a,
                                    b,
                                    radius: s.radius,
                                    border: s.border,
                                })
                            }
                            "capsule" => Primitive::Capsule(Capsule {
                                a,
                                b,
                                radius: s.radius,
                            }),
                            other => panic!("ur_links.json: unknown shape kind {other:?}"),
                        };
                        indices.push(shapes.len());
                        shapes.push(LinkShape {
                            name: Box::leak(s.name.into_boxed_str()),
                            frame: l.frame,
                            primitive,
                            pieces: None,
                        });
                    }
                    links.push(FittedLink {
                        name: l.name,
                        frame: l.frame,
                        shapes: indices,
                        excess_mm: l.excess_mm,
                        pieces_excess_mm: l.pieces_excess_mm,
                    });
                }
                (name, FittedModel { shapes, links })
            })
            .collect()
    })
}

fn fitted_links(model: UrModel) -> Option<&'static Vec<LinkShape>> {
    fitted_models().get(model.name()).map(|m| &m.shapes)
}

/// The fitted links of `model`, or `None` for a model whose shapes are the parametric envelope
/// (no mesh fitted).
pub fn fitted_links_of(model: UrModel) -> Option<&'static [FittedLink]> {
    fitted_models()
        .get(model.name())
        .map(|m| m.links.as_slice())
}

/// Adds the self-collision pairs (see [`arm_geometry`]).
fn with_self_collision_pairs(links: Vec<LinkShape>) -> ArmGeometry {
    let excluded = |a: &LinkShape, b: &LinkShape| {
        let frames = (a.frame.min(b.frame), a.frame.max(b.frame));
        frames == (4, 6)
            || (a.frame == 0 && b.name == "upper_arm_shoulder")
            || (b.frame == 0 && a.name == "upper_arm_shoulder")
    };
    let mut self_collision_pairs = Vec::new();
    for i in 0..links.len() {
        for j in i + 1..links.len() {
            if links[i].frame.abs_diff(links[j].frame) >= 2 && !excluded(&links[i], &links[j]) {
                self_collision_pairs.push((i, j));
            }
        }
    }
    ArmGeometry {
        links,
        self_collision_pairs,
    }
}

/// Shape groups of an arm: its link shapes by DH frame 0..=6, then (index 7) the gripper.
pub const SHAPE_GROUPS: usize = 8;
