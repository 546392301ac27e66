//! A hasher for keys made of the bits of floats and small integers: vertex coordinates to weld,
//! link poses to remember. Such keys have no adversary and are already well spread, so a
//! multiply-rotate step per 64-bit word (as rustc's FxHash) serves where SipHash, the standard
//! library's default, cost a tenth of the work it indexed.
//!
//! The hash decides only where a key is stored, never what a map answers: a program's output
//! does not depend on it.

use std::hash::{BuildHasherDefault, Hasher};

/// The multiply-rotate hasher (see the module documentation).
#[derive(Clone, Copy, Debug, Default)]
pub struct BitsHasher(u64);

/// Builds [`BitsHasher`]s, for `HashMap::with_hasher` / `HashMap::default`.
pub type BitsBuildHasher = BuildHasherDefault<BitsHasher>;

impl Hasher for BitsHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }

    /// Bytes as little-endian 64-bit words, the last one zero-padded.
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    #[inline]
    fn write_u8(&mut self, x: u8) {
        self.write_u64(u64::from(x));
    }

    #[inline]
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }

    #[inline]
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    #[inline]
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::hash::BuildHasher;

    #[test]
    fn bytes_hash_as_their_words() {
        let mut by_bytes = BitsHasher::default();
        by_bytes.write(&[1, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0]);
        let mut by_words = BitsHasher::default();
        by_words.write_u64(1);
        by_words.write_u64(2);
        assert_eq!(by_bytes.finish(), by_words.finish());
    }

    #[test]
    fn a_map_keyed_by_float_bits_finds_every_key() {
        let build = BitsBuildHasher::default();
        let keys: Vec<[u64; 3]> = (0..1000)
            .map(|i| [f64::from(i) * 1e-3, -f64::from(i), 0.5].map(f64::to_bits))
            .collect();
        let mut map = HashMap::with_hasher(build.clone());
        for (i, k) in keys.iter().enumerate() {
            map.insert(*k, i);
        }
        assert_eq!(map.len(), keys.len());
        for (i, k) in keys.iter().enumerate() {
            assert_eq!(map[k], i);
        }
        // Keys that differ in one coordinate's bits hash apart.
        let distinct: std::collections::HashSet<u64> =
            keys.iter().map(|k| build.hash_one(k)).collect();
        assert_eq!(distinct.len(), keys.len());
    }
}
