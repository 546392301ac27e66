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

use std::collections::BTreeMap;
use std::path::PathBuf;

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
    println!("cargo:rerun-if-changed=build.rs");
}
