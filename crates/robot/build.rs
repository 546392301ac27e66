//! Converts the link pieces (`data/ur_pieces_<model>.json`, about 12 000 vertices per model)
//! into a flat binary file in `OUT_DIR` that `src/pieces_blob.rs` reads back: parsing the JSON
//! was most of what loading a scene cost (13.8 M instructions for the UR5e, against about
//! 0.1 M to read the numbers' bits). The numbers are parsed here by the same `serde_json`
//! (with `float_roundtrip`, as the crate's own dependency) and written as their bits, so the
//! values are the ones parsing the JSON at run time gave; a test compares the two.
//!
//! Format, little-endian: `u32` shape count, then per shape (in name order) `u32` name length,
//! the name's bytes, `u64` bits of `slack`, `u32` piece count, and per piece `u32` vertex
//! count and 3 `u64` bits per vertex.
//!
//! It also bakes the built-in 2F-85's finger solids with their tight boxes
//! (`data/robotiq_2f85_fingers.json`, see `finger_solids`), which `src/fingers.rs` reads back.

use std::collections::BTreeMap;
use std::path::PathBuf;

// The finger links' tight boxes, computed by the crate's own code.
#[allow(dead_code)]
#[path = "src/finger_box.rs"]
mod finger_box;

const MODELS: [&str; 5] = ["ur3e", "ur5e", "ur10e", "ur16e", "ur5"];

fn u32_of(n: usize, what: &str) -> [u8; 4] {
    u32::try_from(n)
        .unwrap_or_else(|_| panic!("{what}: {n} does not fit in u32"))
        .to_le_bytes()
}

fn number(v: &serde_json::Value, what: &str) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("{what}: {v} is not a number"))
}

fn convert(model: &str, text: &str) -> Vec<u8> {
    let file: serde_json::Value =
        serde_json::from_str(text).unwrap_or_else(|e| panic!("ur_pieces_{model}.json: {e}"));
    let shapes: BTreeMap<&String, &serde_json::Value> = file["shapes"]
        .as_object()
        .unwrap_or_else(|| panic!("ur_pieces_{model}.json: no `shapes` object"))
        .iter()
        .collect();
    let mut out = Vec::new();
    out.extend(u32_of(shapes.len(), "shapes"));
    for (name, shape) in shapes {
        let what = format!("ur_pieces_{model}.json: {name}");
        out.extend(u32_of(name.len(), &what));
        out.extend(name.as_bytes());
        out.extend(number(&shape["slack"], &what).to_bits().to_le_bytes());
        let pieces = shape["pieces"]
            .as_array()
            .unwrap_or_else(|| panic!("{what}: no `pieces` array"));
        out.extend(u32_of(pieces.len(), &what));
        for piece in pieces {
            let verts = piece
                .as_array()
                .unwrap_or_else(|| panic!("{what}: a piece is not an array"));
            out.extend(u32_of(verts.len(), &what));
            for v in verts {
                let xyz = v
                    .as_array()
                    .filter(|xyz| xyz.len() == 3)
                    .unwrap_or_else(|| panic!("{what}: a vertex is not 3 numbers"));
                for c in xyz {
                    out.extend(number(c, &what).to_bits().to_le_bytes());
                }
            }
        }
    }
    out
}

/// The built-in 2F-85's finger solids (`data/robotiq_2f85_fingers.json`), both fingers in
/// shape order (`SIDES` of `src/fingers.rs`: the `−x` finger, then the `+x` one), each link's
/// pieces mirrored to its side and its tight box (`finger_box::tighter_box` of the pieces'
/// box): what `FingerSolids::robotiq_2f85` built at run time (34 % of loading a scene: the
/// JSON, 2.7 M instructions, and ten tight boxes at 179 angles each, 6.0 M).
///
/// Format, little-endian: `u32` link count, then per link `u32` name length, the name's bytes,
/// 7 `u64` bits (box centre, half extents, angle), `u32` piece count, and per piece `u32`
/// vertex count and 3 `u64` bits per vertex.
fn finger_solids(text: &str) -> Vec<u8> {
    const SIDES: [f64; 2] = [-1.0, 1.0];
    let what = "robotiq_2f85_fingers.json";
    let file: serde_json::Value =
        serde_json::from_str(text).unwrap_or_else(|e| panic!("{what}: {e}"));
    let links = file["links"]
        .as_array()
        .unwrap_or_else(|| panic!("{what}: no `links` array"));
    let mut out = Vec::new();
    out.extend(u32_of(SIDES.len() * links.len(), what));
    for side in SIDES {
        for link in links {
            let alias = link["alias"]
                .as_str()
                .unwrap_or_else(|| panic!("{what}: a link without `alias`"));
            let name = alias.split_whitespace().next().unwrap_or("finger");
            let pieces: Vec<Vec<[f64; 3]>> =
                link["pieces"]
                    .as_array()
                    .unwrap_or_else(|| panic!("{what}: {name}: no `pieces` array"))
                    .iter()
                    .map(|piece| {
                        piece
                            .as_array()
                            .unwrap_or_else(|| panic!("{what}: {name}: a piece is not an array"))
                            .iter()
                            .map(|v| {
                                let xyz = v.as_array().filter(|xyz| xyz.len() == 3).unwrap_or_else(
                                    || panic!("{what}: {name}: a vertex is not 3 numbers"),
                                );
                                let c = |i: usize| number(&xyz[i], what);
                                [side * c(0), c(1), c(2)]
                            })
                            .collect()
                    })
                    .collect();
            let all: Vec<[f64; 3]> = pieces.iter().flatten().copied().collect();
            let (center, half, angle) = finger_box::tighter_box(finger_box::aabb(&all), &all);
            out.extend(u32_of(name.len(), what));
            out.extend(name.as_bytes());
            for c in center.into_iter().chain(half).chain([angle]) {
                out.extend(c.to_bits().to_le_bytes());
            }
            out.extend(u32_of(pieces.len(), what));
            for piece in &pieces {
                out.extend(u32_of(piece.len(), what));
                for c in piece.iter().flatten() {
                    out.extend(c.to_bits().to_le_bytes());
                }
            }
        }
    }
    out
}

fn main() {
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    for model in MODELS {
        let src = format!("data/ur_pieces_{model}.json");
        println!("cargo:rerun-if-changed={src}");
        let text = std::fs::read_to_string(&src).unwrap_or_else(|e| panic!("{src}: {e}"));
        let blob = convert(model, &text);
        let dst = out_dir.join(format!("ur_pieces_{model}.bin"));
        std::fs::write(&dst, blob).unwrap_or_else(|e| panic!("{}: {e}", dst.display()));
    }
    let src = "data/robotiq_2f85_fingers.json";
    println!("cargo:rerun-if-changed={src}");
    println!("cargo:rerun-if-changed=src/finger_box.rs");
    let text = std::fs::read_to_string(src).unwrap_or_else(|e| panic!("{src}: {e}"));
    let dst = out_dir.join("robotiq_2f85_fingers.bin");
    std::fs::write(&dst, finger_solids(&text)).unwrap_or_else(|e| panic!("{}: {e}", dst.display()));
    println!("cargo:rerun-if-changed=build.rs");
}
