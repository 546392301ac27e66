//! Recognising a Universal Robots arm in a URDF chain, so the analytic solver of
//! `pregrasp-robot` can replace the numerical one.
//!
//! # The test
//!
//! By the product of exponentials, a chain's tool pose is
//! `T(q) = e^{[S_1] q_1} ··· e^{[S_6] q_6} · T(0)`, where `S_i` is joint `i`'s screw (its axis
//! line, direction and point) at `q = 0` in the base frame. Two 6R chains whose screws are
//! related by one rigid transform `A` (`S_i = Ad_A S'_i` for every `i`) therefore satisfy,
//! for every `q`,
//!
//! ```text
//! T_chain(q) = A · T_dh(q) · B,    B = (A · T_dh(0))⁻¹ · T_chain(0).
//! ```
//!
//! [`recognise_ur`] takes the UR model's standard-DH chain (`UrKinematics`: joint `i` turns
//! about `z_{i−1}` of the DH frames at `q = 0`), builds `A` from the first two axes (two
//! non-parallel lines fix a rigid transform: the directions fix the rotation, the closest
//! points of the two lines fix the translation), and accepts the model when all six axes
//! then coincide — same direction, and each DH axis point mapped within the tolerance of the
//! chain's axis line. The joint zero and direction must be the DH ones (the UR ROS
//! descriptions keep them); an offset or reversed joint is not recognised.
//!
//! For the ROS 2 description (`base_link` → `tool0`), `A` is the rotation by π about z
//! (`base_link` → `base`, the controller's Base frame, equivalently the
//! `base_link_inertia` turn) and `B` the identity (`tool0` is DH frame 6); a chain ending at
//! `flange` gets `B` = the `tool0` → `flange` rotation.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use pregrasp_robot::{Joints, UrKinematics, UrModel};

use crate::chain::SerialChain;
use crate::kinematics::pose_distance;

/// Default tolerance of [`recognise_ur`]: 1 µm on axis points, 1 µrad on axis directions
/// (the ROS descriptions round π/2 to 1.570796327 and carry 2e-11 m offsets).
pub const UR_MATCH_TOLERANCE: f64 = 1e-6;

/// A chain recognised as a UR arm: `chain.fk(q) = base · UrKinematics::new(model).fk(q) · tool`
/// for every `q` (up to [`UrMatch::deviation`] per joint axis).
#[derive(Clone, Copy, Debug)]
pub struct UrMatch {
    /// The arm model.
    pub model: UrModel,
    /// The DH base frame (controller Base) in the chain's base link frame.
    pub base: Isometry3<f64>,
    /// The chain's tool link frame in the DH flange frame (tool0).
    pub tool: Isometry3<f64>,
    /// The largest axis mismatch found (m for points, rad for directions).
    pub deviation: f64,
}

impl UrMatch {
    /// The model's analytic kinematics.
    pub fn kinematics(&self) -> UrKinematics {
        UrKinematics::new(self.model)
    }

    /// The chain's tool pose through the analytic FK: `base · fk_dh(q) · tool`.
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        self.base * self.kinematics().fk(q) * self.tool
    }

    /// The DH flange pose for a chain tool pose: `base⁻¹ · target · tool⁻¹`.
    pub fn to_flange(&self, target: &Isometry3<f64>) -> Isometry3<f64> {
        self.base.inverse() * target * self.tool.inverse()
    }

    /// Every analytic solution for a chain tool pose, within the model's joint limits,
    /// sorted by distance to `seed` (`UrKinematics::ik`).
    pub fn ik(&self, target: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        self.kinematics().ik(&self.to_flange(target), seed)
    }

    /// The analytic solution nearest to `seed` (`UrKinematics::ik_nearest`).
    pub fn ik_nearest(&self, target: &Isometry3<f64>, seed: &Joints) -> Option<Joints> {
        self.kinematics().ik_nearest(&self.to_flange(target), seed)
    }
}

/// [`recognise_ur_with_tolerance`] with [`UR_MATCH_TOLERANCE`].
pub fn recognise_ur(chain: &SerialChain) -> Option<UrMatch> {
    recognise_ur_with_tolerance(chain, UR_MATCH_TOLERANCE)
}

/// The UR model whose standard-DH joint axes match the chain's, with the fixed base and tool
/// transforms (see the module documentation); `None` unless the chain has exactly six
/// revolute or continuous joints, none of them mimic, matching one model within `tol`.
pub fn recognise_ur_with_tolerance(chain: &SerialChain, tol: f64) -> Option<UrMatch> {
    if chain.dof() != 6
        || chain.joints().len() != 6
        || chain.joints().iter().any(|j| !j.kind.is_rotational())
    {
        return None;
    }
    let zero = [0.0; 6];
    let axes: Vec<Line> = chain
        .joints()
        .iter()
        .zip(chain.joint_frames(&zero))
        .map(|(j, f)| Line {
            point: f.translation.vector.into(),
            dir: f.rotation * j.axis,
        })
        .collect();
    let t_chain = chain.fk(&zero);
    UrModel::ALL.into_iter().find_map(|model| {
        let kin = UrKinematics::new(model);
        let frames = kin.fk_frames(&zero);
        let dh: Vec<Line> = frames[..6]
            .iter()
            .map(|f| Line {
                point: f.translation.vector.into(),
                dir: Unit::new_normalize(f.rotation * Vector3::z()),
            })
            .collect();
        let base = rigid_from_two_lines(&dh[0], &dh[1], &axes[0], &axes[1])?;
        let mut deviation: f64 = 0.0;
        for (d, c) in dh.iter().zip(&axes) {
            let dir = base.rotation * d.dir;
            let p = base * d.point;
            deviation = deviation
                .max((dir.into_inner() - c.dir.into_inner()).norm())
                .max((p - c.point).cross(&c.dir).norm());
        }
        if deviation > tol {
            return None;
        }
        let tool = (base * frames[6]).inverse() * t_chain;
        Some(UrMatch {
            model,
            base,
            tool,
            deviation,
        })
    })
}

/// A joint axis line.
struct Line {
    point: Point3<f64>,
    dir: Unit<Vector3<f64>>,
}

/// The rigid transform mapping lines `a1`, `a2` onto `b1`, `b2` (directions included), if
/// the angles between them agree (within 1e-6) and the lines are not parallel: the rotation
/// maps the frames `(u1, n, u1 × n)`, `n = u1 × u2 / |u1 × u2|`; the translation maps the
/// point of `a1` closest to `a2` onto the point of `b1` closest to `b2`. (The distances
/// between the lines are compared by the caller's check of every axis.)
fn rigid_from_two_lines(a1: &Line, a2: &Line, b1: &Line, b2: &Line) -> Option<Isometry3<f64>> {
    let frame = |u: &Unit<Vector3<f64>>, v: &Unit<Vector3<f64>>| {
        let n = u.cross(v);
        (n.norm() > 1e-6).then(|| {
            let n = n.normalize();
            nalgebra::Matrix3::from_columns(&[u.into_inner(), n, u.cross(&n)])
        })
    };
    if (a1.dir.dot(&a2.dir) - b1.dir.dot(&b2.dir)).abs() > 1e-6 {
        return None;
    }
    let fa = frame(&a1.dir, &a2.dir)?;
    let fb = frame(&b1.dir, &b2.dir)?;
    let rot = UnitQuaternion::from_matrix(&(fb * fa.transpose()));
    let ca = closest_on_first(a1, a2);
    let cb = closest_on_first(b1, b2);
    let t = cb.coords - rot * ca.coords;
    Some(Isometry3::from_parts(Translation3::from(t), rot))
}

/// The point of line `l` closest to the (non-parallel) line `m`.
fn closest_on_first(l: &Line, m: &Line) -> Point3<f64> {
    // Minimise |l.p + s·u − m.p − t·v|²: s = (b·e − c·d)/(a·c − b²) with unit u, v
    // (a = c = 1), b = u·v, d = u·w, e = v·w, w = l.p − m.p.
    let (u, v) = (l.dir.into_inner(), m.dir.into_inner());
    let w = l.point - m.point;
    let (b, d, e) = (u.dot(&v), u.dot(&w), v.dot(&w));
    let s = (b * e - d) / (1.0 - b * b);
    l.point + u * s
}

/// Largest `(position m, rotation rad)` difference between the chain's FK and the matched
/// analytic FK over the given joint vectors (a check for tests and diagnostics).
pub fn ur_fk_deviation(chain: &SerialChain, m: &UrMatch, qs: &[Joints]) -> (f64, f64) {
    qs.iter().fold((0.0, 0.0), |(p, r), q| {
        let (dp, dr) = pose_distance(&chain.fk(q), &m.fk(q));
        (f64::max(p, dp), f64::max(r, dr))
    })
}
