//! A small seeded generator for test inputs.
//!
//! SplitMix64 (Steele, Lea and Flood, *Fast splittable pseudorandom number generators*, OOPSLA
//! 2014): a 64-bit counter hashed by a fixed mixer. It is not for statistics; it is for
//! reproducible test cases: the same seed draws the same cases on every platform, so a failure
//! reproduces from the seed in the test.

use varembed::Vector;

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

    /// A vector with entries uniform in `[−scale, scale)`.
    pub fn vector<const D: usize>(&mut self, scale: f64) -> Vector<D> {
        Vector::<D>::from_fn(|_, _| self.uniform(-scale, scale))
    }

    /// A rough discrete curve `Q_0..=Q_n`: every node drawn by [`Rng::vector`] with
    /// `scale = amplitude`, independently of its neighbours.
    pub fn curve<const D: usize>(&mut self, n: usize, amplitude: f64) -> Vec<Vector<D>> {
        (0..=n).map(|_| self.vector::<D>(amplitude)).collect()
    }

    /// A number from a mix of ordinary and hostile ones, for input that must never make the
    /// library panic: NaN 10 % of the time, an infinity, a signed zero, the smallest normal or
    /// ±1e300 10 %, up to ±5e5 10 %, otherwise up to ±10.
    pub fn wild(&mut self) -> f64 {
        match (self.next_f64() * 10.0) as u32 {
            0 => f64::NAN,
            1 => [
                f64::INFINITY,
                f64::NEG_INFINITY,
                0.0,
                -0.0,
                f64::MIN_POSITIVE,
                1e300,
                -1e300,
            ][(self.next_f64() * 7.0) as usize],
            2 => (self.next_f64() - 0.5) * 1e6,
            _ => (self.next_f64() - 0.5) * 20.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Rng;

    /// The published SplitMix64 outputs for seed 0 (the reference implementation's first
    /// three), so that a change to the mixer cannot go unnoticed: every seeded test case in
    /// the workspace depends on this sequence.
    #[test]
    fn splitmix64_reference_outputs() {
        let mut rng = Rng(0);
        assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(rng.next_u64(), 0x06C4_5D18_8009_454F);
    }

    #[test]
    fn draws_stay_in_their_ranges() {
        let mut rng = Rng(1);
        for _ in 0..10_000 {
            let u = rng.uniform(-2.0, 3.0);
            assert!((-2.0..3.0).contains(&u), "{u}");
            assert!(rng.below(7) < 7);
            assert!(rng.vector::<3>(0.5).iter().all(|x| (-0.5..0.5).contains(x)));
        }
        assert_eq!(rng.curve::<2>(10, 1.0).len(), 11);
    }
}
