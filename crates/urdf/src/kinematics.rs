//! Forward kinematics of a [`SerialChain`]: the tool pose, every joint and link frame, the
//! geometric Jacobian, and the pose error the inverse kinematics drives to zero.
//!
//! All in the base link frame. With `T_j` the child frame of moving joint `j` (see
//! [`crate::chain`]), the joint's axis in the base frame is `z_j = R_j·axis_j` through the
//! point `p_j` (the translation of `T_j`: a joint's motion leaves its own frame origin in
//! place). The geometric Jacobian maps joint velocities to the tool's twist
//! `(v, ω)` — `v` the velocity of the tool frame origin `p`, `ω` the angular velocity, both
//! in the base frame — column by column:
//!
//! ```text
//! revolute / continuous:  J_j = [ z_j × (p − p_j) ;  z_j ]
//! prismatic:              J_j = [ z_j             ;  0   ]
//! ```
//!
//! A mimic joint `j` with master `i` adds `multiplier · J_j` to column `i` (chain rule).

use nalgebra::{Isometry3, Matrix6xX, UnitQuaternion, Vector3, Vector6};

use crate::chain::{value_of, Drive, SerialChain};

impl SerialChain {
    /// Tool link pose in the base link frame for the chain variables `q`
    /// (`q.len() == dof()`, panics otherwise):
    /// `T(q) = origin_1·M_1(q_1) ··· origin_n·M_n(q_n) · tip_offset`.
    pub fn fk(&self, q: &[f64]) -> Isometry3<f64> {
        self.check_len(q);
        let mut t = Isometry3::identity();
        for j in &self.joints {
            t = t * j.origin * j.motion(value_of(j.drive, q));
        }
        t * self.tip_offset
    }

    /// The child link frame of every moving joint ([`SerialChain::joints`] order) in the base
    /// frame.
    pub fn joint_frames(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        self.check_len(q);
        let mut t = Isometry3::identity();
        self.joints
            .iter()
            .map(|j| {
                t = t * j.origin * j.motion(value_of(j.drive, q));
                t
            })
            .collect()
    }

    /// The frame of every link on the path ([`SerialChain::links`] order: base link first,
    /// tool link last) in the base frame.
    pub fn link_frames(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        let joints = self.joint_frames(q);
        self.links
            .iter()
            .map(|l| match l.after_joint {
                Some(j) => joints[j] * l.offset,
                None => l.offset,
            })
            .collect()
    }

    /// The geometric Jacobian at `q` (6 × dof, rows `v` then `ω`, base frame, for the tool
    /// frame origin; see the module documentation).
    pub fn jacobian(&self, q: &[f64]) -> Matrix6xX<f64> {
        let mut jac = Matrix6xX::zeros(self.dof());
        self.fk_jacobian(q, &mut jac);
        jac
    }

    /// Tool pose and Jacobian in one pass; `jac` must be 6 × dof.
    pub(crate) fn fk_jacobian(&self, q: &[f64], jac: &mut Matrix6xX<f64>) -> Isometry3<f64> {
        self.check_len(q);
        jac.fill(0.0);
        // First pass: each moving joint's axis and point; second: the columns, now that the
        // tool position is known.
        let mut t = Isometry3::identity();
        let mut axes: Vec<(Vector3<f64>, Vector3<f64>)> = Vec::with_capacity(self.joints.len());
        for j in &self.joints {
            t *= j.origin;
            axes.push((t.rotation * j.axis.into_inner(), t.translation.vector));
            t *= j.motion(value_of(j.drive, q));
        }
        let tip = t * self.tip_offset;
        let p = tip.translation.vector;
        for (j, &(z, pj)) in self.joints.iter().zip(&axes) {
            let col = if j.kind.is_rotational() {
                let v = z.cross(&(p - pj));
                Vector6::new(v.x, v.y, v.z, z.x, z.y, z.z)
            } else {
                Vector6::new(z.x, z.y, z.z, 0.0, 0.0, 0.0)
            };
            let (i, scale) = match j.drive {
                Drive::Actuated(i) => (i, 1.0),
                Drive::Mimic {
                    master, multiplier, ..
                } => (master, multiplier),
            };
            let mut c = jac.column_mut(i);
            c += col * scale;
        }
        tip
    }
}

/// The pose error `e = (p* − p, θ·u)` from `current` to `target`, both in the base frame:
/// the position difference (m) and the rotation vector (rad) of `R*·Rᵀ`, the rotation that
/// takes `current`'s orientation to `target`'s, expressed in the base frame. For a small
/// joint step `Δq`, `e(q + Δq) ≈ e(q) − J·Δq` with the geometric Jacobian.
pub fn pose_error(target: &Isometry3<f64>, current: &Isometry3<f64>) -> Vector6<f64> {
    let dp = target.translation.vector - current.translation.vector;
    let w = rotation_vector(&(target.rotation * current.rotation.inverse()));
    Vector6::new(dp.x, dp.y, dp.z, w.x, w.y, w.z)
}

/// The rotation vector `θ·u` of a unit quaternion, `θ ∈ [0, π]`, computed as
/// `2·atan2(|v|, |w|)·v/|v|` (sign chosen so `w ≥ 0`), accurate to a few ulp for tiny angles
/// (unlike `2·acos(w)`, which loses half the digits there).
pub fn rotation_vector(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.vector())
    } else {
        (q.w, q.vector().into_owned())
    };
    let s = v.norm();
    if s == 0.0 {
        return Vector3::zeros();
    }
    v * (2.0 * s.atan2(w) / s)
}

/// Position (m) and rotation (rad) distance between two poses: `(|p_a − p_b|, θ)` with `θ`
/// the angle of `R_a·R_bᵀ`.
pub fn pose_distance(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let e = pose_error(a, b);
    (e.fixed_rows::<3>(0).norm(), e.fixed_rows::<3>(3).norm())
}
