//! Algorithm 1 of the paper (§IV): rotation-axis candidates and their maximum rotation angles.
//!
//! The part lies on the support plane `z = s`. At P_init (the object pose raised by the lift),
//! every **feature edge** of its convex hull (an edge where two non-coplanar hull faces meet)
//! whose endpoints are both within Δd_s of the support and which is longer than Δl is a rotation
//! axis. For each axis and each sense of rotation (ccw / cw) θ_max is the largest angle, capped at
//! φ_obj, by which the part turns about the axis before any point goes below the support. The hull
//! is convex, so its vertices are the lowest points; each hull vertex's height is a sinusoid of
//! the angle and θ_max is the first downward crossing of `z = s` over all vertices, computed in
//! closed form ([`pregrasp_geometry::rotation`]). The paper's stepped search would stop at
//! `⌊θ_max / Δφ⌋ Δφ`, reported as `theta_max_stepped`.
//!
//! Candidates are scored S_rot = ω_l · length + ω_m · θ_max and sorted best first.

use std::cmp::Ordering;

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use pregrasp_geometry::rotation::{max_rotation_above, rotation_about_line};
use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_io::plan_file::{CandidateJson, Outcome};
use pregrasp_io::scene::PlannerParams;

/// What follows "not evaluated" in the outcome of a candidate only Algorithm 1 has seen.
const AXES_ONLY: &str = " (axes only)";

/// Heights within this distance (m) of the support count as on it when a rotation starts.
const HEIGHT_TOLERANCE: f64 = 1e-12;

/// Sense of rotation about `axis[1] − axis[0]` (the plan file's vocabulary).
pub use pregrasp_io::plan_terms::RotationDirection as Direction;

/// One (axis, direction) pair of Algorithm 1.
#[derive(Clone, Debug, PartialEq)]
pub struct RotationAxisCandidate {
    /// Rank after sorting, 0 = best score.
    pub id: usize,
    /// World endpoints at P_init, in lexicographic (x, y, z) order.
    pub axis: [Point3<f64>; 2],
    pub direction: Direction,
    /// `|axis[1] − axis[0]|` (m).
    pub length: f64,
    /// θ_max (rad), exact, in `[0, φ_obj]`.
    pub theta_max: f64,
    /// θ_max rounded down to a multiple of Δφ (rad), what the paper's stepped search finds.
    pub theta_max_stepped: f64,
    /// S_rot = ω_l · length + ω_m · θ_max.
    pub score: f64,
}

impl RotationAxisCandidate {
    /// Object pose after rotating P_init by `theta` (rad, ≥ 0) about the axis in this direction.
    pub fn rotated_pose(&self, p_init: &Isometry3<f64>, theta: f64) -> Isometry3<f64> {
        rotation_about_line(&self.axis[0], &self.signed_axis(), theta) * p_init
    }

    /// Unit axis direction in world, signed so positive angle = this candidate's direction.
    pub fn signed_axis(&self) -> Unit<Vector3<f64>> {
        Unit::new_normalize((self.axis[1] - self.axis[0]) * self.direction.sign())
    }

    /// The candidate as the plan model records it (θ_goal unknown yet).
    pub fn to_model(&self) -> pregrasp_model::Candidate {
        pregrasp_model::Candidate {
            id: self.id,
            axis: self.axis,
            direction: self.direction,
            length: self.length,
            theta_max: self.theta_max,
            score: self.score,
            theta_goal: None,
        }
    }

    /// The plan file's candidate entry: `theta_goal` null, outcome "not evaluated (axes only)".
    pub fn to_json(&self) -> CandidateJson {
        let p = |q: &Point3<f64>| [q.x, q.y, q.z];
        CandidateJson {
            id: self.id,
            axis: [p(&self.axis[0]), p(&self.axis[1])],
            direction: self.direction,
            length: self.length,
            theta_max: self.theta_max,
            score: self.score,
            theta_goal: None,
            outcome: Outcome::NotEvaluated(AXES_ONLY.to_string()),
        }
    }
}

/// What Algorithm 1 produced.
#[derive(Clone, Debug)]
pub struct AxesResult {
    /// P_init: the object pose raised by `lift` along world `z`.
    pub p_init: Isometry3<f64>,
    /// The convex hull in the object frame (empty if the mesh has no 2-D or 3-D hull).
    pub hull: ConvexHull,
    /// Best score first.
    pub candidates: Vec<RotationAxisCandidate>,
    /// Remarks, e.g. why the hull is empty.
    pub warnings: Vec<String>,
}

/// P_init: `object_pose` raised by `lift` (m) along world `z`.
pub fn initial_pose(object_pose: &Isometry3<f64>, lift: f64) -> Isometry3<f64> {
    let mut p = *object_pose;
    p.translation.vector.z += lift;
    p
}

/// Algorithm 1: rotation-axis candidates of `mesh` (object frame) placed at `object_pose`
/// (before the lift) on the support `z = support_height`, with `params` (Δd_s, Δl, Δφ, φ_obj,
/// ω_l, ω_m, lift).
pub fn rotation_axis_candidates(
    mesh: &Mesh,
    object_pose: &Isometry3<f64>,
    support_height: f64,
    params: &PlannerParams,
) -> AxesResult {
    rotation_axis_candidates_with_hull(mesh, None, object_pose, support_height, params)
}

/// [`rotation_axis_candidates`] with the hull of `mesh` given when the caller has it
/// (object frame; [`PartKnowledge::hull`](crate::context::PartKnowledge::hull)): computed
/// otherwise.
pub fn rotation_axis_candidates_with_hull(
    mesh: &Mesh,
    hull: Option<&ConvexHull>,
    object_pose: &Isometry3<f64>,
    support_height: f64,
    params: &PlannerParams,
) -> AxesResult {
    let p_init = initial_pose(object_pose, params.lift);
    let hull = match hull.map_or_else(|| ConvexHull::of_mesh(mesh), |h| Ok(h.clone())) {
        Ok(h) => h,
        Err(e) => {
            return AxesResult {
                p_init,
                hull: empty_hull(),
                candidates: Vec::new(),
                warnings: vec![format!("no rotation axes: {e}")],
            }
        }
    };
    let candidates = candidates_of_hull(&hull, &p_init, support_height, params);
    AxesResult {
        p_init,
        hull,
        candidates,
        warnings: Vec::new(),
    }
}

/// Algorithm 1 on an already computed hull (object frame) at P_init (lift included).
pub fn candidates_of_hull(
    hull: &ConvexHull,
    p_init: &Isometry3<f64>,
    support_height: f64,
    params: &PlannerParams,
) -> Vec<RotationAxisCandidate> {
    let world: Vec<Point3<f64>> = hull.vertices.iter().map(|v| p_init * v).collect();
    let near_support = |p: &Point3<f64>| (p.z - support_height).abs() <= params.support_distance;
    let tol = HEIGHT_TOLERANCE.max(1e-3 * hull.tolerance);
    let mut out = Vec::new();
    for &[i, j] in &hull.feature_edges {
        let (a, b) = (world[i], world[j]);
        let length = (b - a).norm();
        if !(near_support(&a) && near_support(&b)) || length <= params.min_axis_length {
            continue;
        }
        let axis = if lex_cmp(&a, &b) == Ordering::Greater {
            [b, a]
        } else {
            [a, b]
        };
        for direction in [Direction::Ccw, Direction::Cw] {
            let u = Unit::new_normalize((axis[1] - axis[0]) * direction.sign());
            let theta_max =
                max_rotation_above(&world, &axis[0], &u, support_height, params.max_angle, tol);
            let steps = (theta_max / params.step + 1e-9).floor();
            let theta_max_stepped = (steps * params.step).min(theta_max);
            let score = params.weight_length * length + params.weight_angle * theta_max;
            out.push(RotationAxisCandidate {
                id: 0,
                axis,
                direction,
                length,
                theta_max,
                theta_max_stepped,
                score,
            });
        }
    }
    out.sort_by(|x, y| {
        y.score
            .total_cmp(&x.score)
            .then_with(|| lex_cmp(&x.axis[0], &y.axis[0]))
            .then_with(|| lex_cmp(&x.axis[1], &y.axis[1]))
            .then_with(|| x.direction.cmp(&y.direction))
    });
    for (k, c) in out.iter_mut().enumerate() {
        c.id = k;
    }
    out
}

fn lex_cmp(a: &Point3<f64>, b: &Point3<f64>) -> Ordering {
    a.x.total_cmp(&b.x)
        .then(a.y.total_cmp(&b.y))
        .then(a.z.total_cmp(&b.z))
}

fn empty_hull() -> ConvexHull {
    ConvexHull {
        vertices: Vec::new(),
        triangles: Vec::new(),
        faces: Vec::new(),
        feature_edges: Vec::new(),
        edge_faces: Vec::new(),
        tolerance: 0.0,
    }
}
