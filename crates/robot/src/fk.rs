//! Forward kinematics of a UR arm: the flange pose and every DH link frame in the base frame.
//!
//! Each DH step `T_i = Rz(θ_i)·Tz(d_i)·Tx(a_i)·Rx(α_i)` is composed as a unit quaternion
//! (from the half angles of θ_i and the fixed α_i ∈ {0, ±π/2}) plus a translation
//! `R_{i−1}·(a_i cos θ_i, a_i sin θ_i, d_i)`, so no rotation matrix is ever converted and
//! nothing is allocated.

use nalgebra::{Isometry3, Matrix3, Quaternion, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::angle::sin_cos;
use crate::model::{DhParams, Joints, UrModel};

/// Kinematics of one arm model (immutable, cheap to copy).
#[derive(Clone, Copy, Debug)]
pub struct UrKinematics {
    model: UrModel,
    pub(crate) dh: DhParams,
    /// Per DH row: (d_i, a_i, α_i as −1, 0 or +1 quarter turns).
    rows: [(f64, f64, i8); 6],
}

impl UrKinematics {
    /// Kinematics of `model` with UR's nominal DH parameters.
    pub fn new(model: UrModel) -> Self {
        let dh = model.dh();
        let rows = [
            (dh.d1, 0.0, 1),
            (0.0, dh.a2, 0),
            (0.0, dh.a3, 0),
            (dh.d4, 0.0, 1),
            (dh.d5, 0.0, -1),
            (dh.d6, 0.0, 0),
        ];
        UrKinematics { model, dh, rows }
    }

    /// The arm model.
    pub fn model(&self) -> UrModel {
        self.model
    }

    /// The DH parameters in use.
    pub fn dh(&self) -> DhParams {
        self.dh
    }

    /// Flange (tool0) pose in the arm base frame.
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        let sc: [(f64, f64); 6] = std::array::from_fn(|i| sin_cos(q[i]));
        let (r, p) = self.fk_sin_cos(&sc);
        let rot = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
        Isometry3::from_parts(Translation3::from(p), rot)
    }

    /// Flange rotation matrix and position from the joints' `(sin q_i, cos q_i)`.
    ///
    /// Each step right-multiplies `Rz(θ_i)` (touching two columns) and `Rx(α_i)` (a column
    /// permutation with one sign for α = ±π/2), and adds `R_{i−1}·(a_i cos θ_i, a_i sin θ_i, d_i)`.
    #[inline]
    pub(crate) fn fk_sin_cos(&self, sc: &[(f64, f64); 6]) -> (Matrix3<f64>, Vector3<f64>) {
        let mut cx = Vector3::x();
        let mut cy = Vector3::y();
        let mut cz = Vector3::z();
        let mut p = Vector3::zeros();
        for (i, &(s, c)) in sc.iter().enumerate() {
            let (d, a, alpha) = self.rows[i];
            let nx = c * cx + s * cy;
            let ny = c * cy - s * cx;
            p += a * nx + d * cz;
            cx = nx;
            match alpha {
                1 => {
                    cy = cz;
                    cz = -ny;
                }
                -1 => {
                    cy = -cz;
                    cz = ny;
                }
                _ => cy = ny,
            }
        }
        (Matrix3::from_columns(&[cx, cy, cz]), p)
    }

    /// DH frames 0..=6 in the base frame: `[0]` = identity (base), `[i]` = T_1···T_i,
    /// `[6]` = flange. Frame i moves with joint i (frame 1 with shoulder_pan, …, frame 6
    /// with wrist_3).
    pub fn fk_frames(&self, q: &Joints) -> [Isometry3<f64>; 7] {
        let mut frames = [Isometry3::identity(); 7];
        let mut rot = UnitQuaternion::identity();
        let mut pos = Vector3::zeros();
        for (i, &qi) in q.iter().enumerate() {
            self.step(i, qi, &mut rot, &mut pos);
            frames[i + 1] = Isometry3::from_parts(Translation3::from(pos), rot);
        }
        frames
    }

    /// Applies DH row `i` with joint angle `theta` to the accumulated frame.
    #[inline(always)]
    fn step(&self, i: usize, theta: f64, rot: &mut UnitQuaternion<f64>, pos: &mut Vector3<f64>) {
        let (d, a, alpha) = self.rows[i];
        let (sh, ch) = sin_cos(0.5 * theta);
        // cos θ and sin θ from the half angles.
        let (c, s) = (ch * ch - sh * sh, 2.0 * sh * ch);
        *pos += *rot * Vector3::new(a * c, a * s, d);
        // qz(θ) ⊗ qx(α) for α = k·π/2, k ∈ {−1, 0, 1}.
        let local = if alpha == 0 {
            Quaternion::new(ch, 0.0, 0.0, sh)
        } else {
            let k = std::f64::consts::FRAC_1_SQRT_2;
            let sg = f64::from(alpha);
            Quaternion::new(ch * k, sg * ch * k, sg * sh * k, sh * k)
        };
        *rot = UnitQuaternion::new_unchecked(rot.as_ref() * local);
    }
}
