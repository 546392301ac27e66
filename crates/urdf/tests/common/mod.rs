//! Shared test helpers: the robots of `data/robots/` (inside the repository) and random
//! joint vectors from a fixed-seed generator.
#![allow(dead_code)]

use nalgebra::Isometry3;
use pregrasp_urdf::{SerialChain, UrdfModel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Path of a file of `data/robots/`.
pub fn data(name: &str) -> String {
    format!("{}/../../data/robots/{name}", env!("CARGO_MANIFEST_DIR"))
}

pub fn model(name: &str) -> UrdfModel {
    UrdfModel::from_file(data(name)).unwrap()
}

/// Franka FR3, `fr3_link0` → `fr3_link8` (the flange), 7 joints.
pub fn fr3() -> SerialChain {
    model("fr3.urdf").chain("fr3_link0", "fr3_link8").unwrap()
}

/// UFACTORY xArm6, `link_base` → `link_eef`, 6 joints.
pub fn xarm6() -> SerialChain {
    model("xarm6.urdf").chain("link_base", "link_eef").unwrap()
}

/// UR5e, `base_link` → `tool0`.
pub fn ur5e() -> SerialChain {
    model("ur5e.urdf").chain("base_link", "tool0").unwrap()
}

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// Uniform within the limits, `margin` inside each bound (infinite ranges: [−π, π]).
pub fn random_q(chain: &SerialChain, rng: &mut ChaCha8Rng, margin: f64) -> Vec<f64> {
    chain
        .limits()
        .iter()
        .map(|l| {
            let lo = if l.lower.is_finite() {
                l.lower
            } else {
                -std::f64::consts::PI
            };
            let hi = if l.upper.is_finite() {
                l.upper
            } else {
                std::f64::consts::PI
            };
            rng.random_range(lo + margin..hi - margin)
        })
        .collect()
}

/// `(position m, rotation rad)` distance.
pub fn dist(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    pregrasp_urdf::pose_distance(a, b)
}

/// Median of a sample.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
