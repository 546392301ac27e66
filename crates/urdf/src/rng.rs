//! A small deterministic random generator for IK restarts: SplitMix64.
//!
//! State update `s ← s + 0x9E37_79B9_7F4A_7C15` (2⁶⁴/φ, the golden-ratio increment), output
//! `z = s; z = (z ⊕ (z ≫ 30))·0xBF58_4768_1CE4_E5B9; z = (z ⊕ (z ≫ 27))·0x94D0_49BB_1331_11EB;
//! z ⊕ (z ≫ 31)` (Steele, Lea & Flood, "Fast splittable pseudorandom number generators",
//! OOPSLA 2014; the mixing constants are Stafford's "Mix13"). Every IK call starts a fresh
//! generator from [`crate::IkOptions::rng_seed`], so the same input gives the same output, bit
//! for bit, on every run and thread.

/// SplitMix64 state.
#[derive(Clone, Debug)]
pub(crate) struct SplitMix64(u64);

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_4768_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`: the top 53 bits scaled by 2⁻⁵³.
    pub(crate) fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}
