//! The finger pieces MuJoCo collides for the Menagerie 2F-85 (hulls of its meshes, pad boxes;
//! `data/gripper_truth/menagerie_2f85_collision.json`, written by `tools/gripper_truth/hulls.py`).
//! Shared by this crate's closing test and the collision crate's (`#[path]`-included there).

use nalgebra::Point3;
use pregrasp_robot::FINGER_LINKS;
use serde_json::Value;

/// The file's JSON.
fn collision_json() -> Value {
    let path = format!(
        "{}/../robot/data/gripper_truth/menagerie_2f85_collision.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Per link ([`FINGER_LINKS`] order), its pieces as point sets in the link frame of the `+x`
/// finger, `x` multiplied by `sign` (−1: the mirror finger).
pub fn collision_pieces(sign: f64) -> Vec<Vec<Vec<Point3<f64>>>> {
    let json = collision_json();
    FINGER_LINKS
        .iter()
        .map(|name| {
            json["links"][name]
                .as_array()
                .unwrap()
                .iter()
                .map(|piece| {
                    piece
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|p| {
                            let c = |k: usize| p[k].as_f64().unwrap();
                            Point3::new(sign * c(0), c(1), c(2))
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}
