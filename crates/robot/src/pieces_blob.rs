//! The link pieces of each UR model as `build.rs` wrote them: the numbers of
//! `data/ur_pieces_<model>.json` as their bits, read here without parsing text (loading a
//! UR5e scene parsed 37 000 numbers of JSON, 13.8 M instructions; reading their bits costs
//! about 0.1 M). The JSON stays the source: the build converts it, and a test checks that the
//! values are bit for bit those `serde_json` parses from it.

use nalgebra::Point3;

use crate::model::UrModel;

/// One shape's pieces as the file gives them: vertices per piece and the slack.
pub(crate) struct ShapePieces {
    /// Shape name (a key of the file's `shapes`).
    pub name: String,
    /// Vertices of each piece, in the link's DH frame (m).
    pub pieces: Vec<Vec<Point3<f64>>>,
    /// How far the pieces reach outside the shape (m).
    pub slack: f64,
}

/// The converted file of `model` (see `build.rs` for the format).
fn blob(model: UrModel) -> &'static [u8] {
    match model {
        UrModel::Ur3e => include_bytes!(concat!(env!("OUT_DIR"), "/ur_pieces_ur3e.bin")),
        UrModel::Ur5e => include_bytes!(concat!(env!("OUT_DIR"), "/ur_pieces_ur5e.bin")),
        UrModel::Ur10e => include_bytes!(concat!(env!("OUT_DIR"), "/ur_pieces_ur10e.bin")),
        UrModel::Ur16e => include_bytes!(concat!(env!("OUT_DIR"), "/ur_pieces_ur16e.bin")),
        UrModel::Ur5 => include_bytes!(concat!(env!("OUT_DIR"), "/ur_pieces_ur5.bin")),
    }
}

/// A read position in a blob `build.rs` wrote (the pieces here, the finger solids of
/// `crate::fingers`); a short read is a build fault (panics).
pub(crate) struct Reader<'a> {
    pub bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let (head, rest) = self.bytes.split_at(N);
        self.bytes = rest;
        head.try_into().expect("split_at gave N bytes")
    }

    pub fn count(&mut self) -> usize {
        u32::from_le_bytes(self.take()) as usize
    }

    /// A `u32` length, then that many bytes of UTF-8.
    pub fn name(&mut self) -> &'a str {
        let len = self.count();
        let (name, rest) = self.bytes.split_at(len);
        self.bytes = rest;
        std::str::from_utf8(name).expect("build.rs wrote a UTF-8 name")
    }

    pub fn number(&mut self) -> f64 {
        f64::from_bits(u64::from_le_bytes(self.take()))
    }
}

/// The shapes of `model`'s pieces file, in name order.
pub(crate) fn shapes(model: UrModel) -> Vec<ShapePieces> {
    let mut r = Reader { bytes: blob(model) };
    let n = r.count();
    let mut shapes = Vec::with_capacity(n);
    for _ in 0..n {
        let name = r.name().to_string();
        let slack = r.number();
        let pieces = (0..r.count())
            .map(|_| {
                (0..r.count())
                    .map(|_| Point3::new(r.number(), r.number(), r.number()))
                    .collect()
            })
            .collect();
        shapes.push(ShapePieces {
            name,
            pieces,
            slack,
        });
    }
    assert!(r.bytes.is_empty(), "ur_pieces_{model}.bin: bytes left over");
    shapes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize)]
    struct PiecesJson {
        pieces: Vec<Vec<[f64; 3]>>,
        slack: f64,
    }

    #[derive(serde::Deserialize)]
    struct PiecesFileJson {
        shapes: std::collections::BTreeMap<String, PiecesJson>,
    }

    /// The converted pieces are the JSON's, parsed as the crate parsed them before the build
    /// converted them: the same names in the same order, the same bits.
    #[test]
    fn the_blob_holds_the_json_numbers_bit_for_bit() {
        let models = [
            (UrModel::Ur3e, include_str!("../data/ur_pieces_ur3e.json")),
            (UrModel::Ur5e, include_str!("../data/ur_pieces_ur5e.json")),
            (UrModel::Ur10e, include_str!("../data/ur_pieces_ur10e.json")),
            (UrModel::Ur16e, include_str!("../data/ur_pieces_ur16e.json")),
            (UrModel::Ur5, include_str!("../data/ur_pieces_ur5.json")),
        ];
        let bits = |p: &Point3<f64>| p.coords.map(f64::to_bits);
        for (model, text) in models {
            let file: PiecesFileJson = serde_json::from_str(text).unwrap();
            let got = shapes(model);
            assert_eq!(got.len(), file.shapes.len(), "{model}");
            for (s, (name, p)) in got.iter().zip(&file.shapes) {
                assert_eq!(&s.name, name, "{model}");
                assert_eq!(s.slack.to_bits(), p.slack.to_bits(), "{model} {name}");
                assert_eq!(s.pieces.len(), p.pieces.len(), "{model} {name}");
                for (a, b) in s.pieces.iter().zip(&p.pieces) {
                    assert_eq!(a.len(), b.len(), "{model} {name}");
                    for (u, v) in a.iter().zip(b) {
                        assert_eq!(bits(u), bits(&Point3::from(*v)), "{model} {name}");
                    }
                }
            }
        }
    }
}
