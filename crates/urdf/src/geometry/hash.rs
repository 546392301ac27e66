//! FNV-1a, 128-bit: the digest keying the geometry cache.
//!
//! `h ← offset basis; for each byte b: h ← (h ⊕ b) · prime (mod 2¹²⁸)` with the offset basis
//! `0x6c62272e07bb014262b821756295c58d` and the prime `2⁸⁸ + 2⁸ + 0x3b`
//! (Fowler, Noll & Vo; IETF draft-eastlake-fnv). Not a cryptographic hash: the cache only
//! needs different inputs to give different keys with overwhelming probability, and the
//! stored entry repeats the key, so a stale entry is never taken for a current one.
//! Variable-length fields are length-prefixed, so concatenations cannot alias.

/// FNV-1a 128-bit state.
#[derive(Clone, Debug)]
pub(crate) struct Fnv128(u128);

const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
const PRIME: u128 = (1 << 88) + (1 << 8) + 0x3b;

impl Fnv128 {
    pub(crate) fn new() -> Self {
        Fnv128(OFFSET)
    }

    /// Feeds raw bytes.
    pub(crate) fn bytes(&mut self, data: &[u8]) {
        let mut h = self.0;
        for &b in data {
            h = (h ^ b as u128).wrapping_mul(PRIME);
        }
        self.0 = h;
    }

    /// Feeds a length-prefixed byte string.
    pub(crate) fn field(&mut self, data: &[u8]) {
        self.u64(data.len() as u64);
        self.bytes(data);
    }

    /// Feeds a length-prefixed string.
    pub(crate) fn str(&mut self, s: &str) {
        self.field(s.as_bytes());
    }

    pub(crate) fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }

    /// Feeds the bits of `v` (so −0 and 0 differ, as they do in the file).
    pub(crate) fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }

    /// The digest as 32 lowercase hex digits.
    pub(crate) fn hex(&self) -> String {
        format!("{:032x}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::Fnv128;

    #[test]
    fn known_vectors() {
        // Published FNV-1a 128 test vectors.
        let h = |s: &str| {
            let mut f = Fnv128::new();
            f.bytes(s.as_bytes());
            f.hex()
        };
        assert_eq!(h(""), "6c62272e07bb014262b821756295c58d");
        assert_eq!(h("a"), "d228cb696f1a8caf78912b704e4a8964");
    }
}
