//! The supported Universal Robots arms: standard DH parameters, joint limits, speed and
//! acceleration limits (`docs/hardware-facts.md`).
//!
//! Convention: standard DH, `T_i = Rz(θ_i)·Tz(d_i)·Tx(a_i)·Rx(α_i)` with
//! α = (π/2, 0, 0, π/2, −π/2, 0), a1 = a4 = a5 = a6 = 0, d2 = d3 = 0, expressed in the
//! controller's *Base* frame; frame 6 is the flange (tool0), z out of the flange.
//! Lengths in metres, angles in radians.

use std::f64::consts::{PI, TAU};

/// A joint vector (rad), ordered as [`JOINT_NAMES`].
pub type Joints = [f64; 6];

/// Joint names, base to flange (the UR ROS names).
pub const JOINT_NAMES: [&str; 6] = [
    "shoulder_pan",
    "shoulder_lift",
    "elbow",
    "wrist_1",
    "wrist_2",
    "wrist_3",
];

/// Conservative joint acceleration limit (rad/s²) used for every joint of every model.
///
/// The datasheets give none; this is URScript's `movej` default `a = 1.4 rad/s²`, which
/// every UR arm executes with any rated payload.
pub const DEFAULT_JOINT_ACCEL: f64 = 1.4;

/// A supported arm model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UrModel {
    /// UR3e.
    Ur3e,
    /// UR5e.
    Ur5e,
    /// UR10e.
    Ur10e,
    /// UR16e.
    Ur16e,
    /// UR5 (CB3 generation).
    Ur5,
}

/// The non-zero standard DH lengths of a UR arm (m). The remaining ones (a1, a4, a5, a6,
/// d2, d3) are zero and α is fixed, see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DhParams {
    /// Base to shoulder height.
    pub d1: f64,
    /// Upper-arm length (negative: the arm stretches along base −x at q = 0).
    pub a2: f64,
    /// Forearm length (negative).
    pub a3: f64,
    /// Shoulder-to-wrist lateral offset.
    pub d4: f64,
    /// Wrist 1 to wrist 2 offset.
    pub d5: f64,
    /// Wrist 2 to flange offset.
    pub d6: f64,
}

impl DhParams {
    /// `(d, a, α)` of DH row `i` (0-based), including the zero entries.
    pub fn row(&self, i: usize) -> (f64, f64, f64) {
        match i {
            0 => (self.d1, 0.0, PI / 2.0),
            1 => (0.0, self.a2, 0.0),
            2 => (0.0, self.a3, 0.0),
            3 => (self.d4, 0.0, PI / 2.0),
            4 => (self.d5, 0.0, -PI / 2.0),
            5 => (self.d6, 0.0, 0.0),
            _ => panic!("DH row index {i} out of range 0..6"),
        }
    }
}

/// Error for an unknown model name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown robot model `{0}` (expected one of: ur3e, ur5e, ur10e, ur16e, ur5)")]
pub struct UnknownModel(pub String);

impl std::str::FromStr for UrModel {
    type Err = UnknownModel;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        UrModel::from_name(s).ok_or_else(|| UnknownModel(s.to_string()))
    }
}

impl std::fmt::Display for UrModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl UrModel {
    /// Every supported model.
    pub const ALL: [UrModel; 5] = [
        UrModel::Ur3e,
        UrModel::Ur5e,
        UrModel::Ur10e,
        UrModel::Ur16e,
        UrModel::Ur5,
    ];

    /// Parses a lower-case model name: "ur3e", "ur5e", "ur10e", "ur16e", "ur5"
    /// (ASCII case-insensitive).
    pub fn from_name(name: &str) -> Option<UrModel> {
        UrModel::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(name.trim()))
    }

    /// The lower-case model name.
    pub fn name(self) -> &'static str {
        match self {
            UrModel::Ur3e => "ur3e",
            UrModel::Ur5e => "ur5e",
            UrModel::Ur10e => "ur10e",
            UrModel::Ur16e => "ur16e",
            UrModel::Ur5 => "ur5",
        }
    }

    /// UR's nominal standard DH lengths (m).
    pub fn dh(self) -> DhParams {
        let (d1, a2, a3, d4, d5, d6) = match self {
            UrModel::Ur3e => (0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921),
            UrModel::Ur5e => (0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
            UrModel::Ur10e => (0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
            UrModel::Ur16e => (0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655),
            UrModel::Ur5 => (0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823),
        };
        DhParams {
            d1,
            a2,
            a3,
            d4,
            d5,
            d6,
        }
    }

    /// Position limits `(lower, upper)` (rad): ±2π on every joint except the elbow, which is
    /// kept within ±π (as the UR ROS descriptions do: beyond it the forearm meets the upper
    /// arm).
    pub fn joint_limits(self) -> [(f64, f64); 6] {
        let full = (-TAU, TAU);
        [full, full, (-PI, PI), full, full, full]
    }

    /// Datasheet joint speed limits (rad/s).
    pub fn max_joint_speed(self) -> Joints {
        let d180 = PI;
        let d120 = 2.0 * PI / 3.0;
        let d360 = TAU;
        match self {
            UrModel::Ur3e => [d180, d180, d180, d360, d360, d360],
            UrModel::Ur5e | UrModel::Ur5 => [d180; 6],
            UrModel::Ur10e | UrModel::Ur16e => [d120, d120, d180, d180, d180, d180],
        }
    }

    /// Joint acceleration limits (rad/s²): [`DEFAULT_JOINT_ACCEL`] on every joint (a
    /// conservative choice, the datasheets give none).
    pub fn max_joint_accel(self) -> Joints {
        [DEFAULT_JOINT_ACCEL; 6]
    }

    /// Nominal reach (m) from the datasheet table.
    pub fn reach(self) -> f64 {
        match self {
            UrModel::Ur3e => 0.50,
            UrModel::Ur5e | UrModel::Ur5 => 0.85,
            UrModel::Ur10e => 1.30,
            UrModel::Ur16e => 0.90,
        }
    }
}
