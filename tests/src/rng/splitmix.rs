//! The SplitMix64 generator alone, without a dependency (Steele, Lea and Flood, *Fast splittable
//! pseudorandom number generators*, OOPSLA 2014): a 64-bit counter hashed by a fixed mixer. One
//! file for the three places that draw test cases from a seed: the test support crate
//! (`rng.rs`, which adds vectors and curves), the build script that writes the macro fuzzer's
//! programs and the macro crate's unit tests, which cannot depend on the support crate (it
//! depends on the library, which depends on the macros: a second build of the whole library
//! for the host).

#![allow(
    dead_code,
    reason = "each file that includes this one uses its own part of it"
)]

/// A SplitMix64 generator; the field is its state, so `Rng(seed)` seeds it.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, from the top 53 bits (every value a multiple of `2⁻⁵³`).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `0..n` (`n > 0`; the modulo bias is below `n/2⁶⁴`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}
