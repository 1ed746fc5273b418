//! Triangular Toeplitz matrices applied by FFT in `O(M log M)` time and `O(M)` memory.
//!
//! The lower-triangular Toeplitz matrix of order `M` with first column `c` is
//! `T[k, j] = c_{k−j}` (`k ≥ j`), so `(T x)_k = Σ_{r=0}^{k} c_r x_{k−r}` (a truncated linear
//! convolution) and `(Tᵀ x)_j = Σ_{r=0}^{M−1−j} c_r x_{j+r}` (a truncated correlation).
//! Zero-padding `c` and `x` to a length `L ≥ 2M − 1` turns both into circular products that
//! never wrap around, so with `ĉ = FFT(c)`, `x̂ = FFT(x)`:
//!
//! `T x = IFFT(ĉ · x̂)[0..M]`,  `Tᵀ x = IFFT(conj(ĉ) · x̂)[0..M]` (`c` real).
//!
//! `ĉ` is computed once, when the matrix is built. All vectors are real, so the transforms are
//! real-to-complex and complex-to-real FFTs ([`realfft`]): a length-`L` real transform is one
//! complex FFT of length `L/2` plus an `O(L)` pass, half the work and half the memory of a
//! complex FFT of length `L`. `L` is even, `L = 2K` with `K ≥ M` a product of small primes
//! ([`fft_len`]).
//!
//! ## Reference
//!
//! R. M. Gray, *Toeplitz and circulant matrices: a review*, §4 (circulant embedding).
//! H. V. Sorensen et al., *Real-valued fast Fourier transform algorithms*, IEEE Trans. ASSP 35
//! (1987) (the real transform through a half-length complex one).

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::sync::Arc;

/// A lower-triangular Toeplitz matrix of order `M` (and its transpose), applied by FFT.
#[derive(Clone)]
pub struct TriangularToeplitz {
    order: usize,
    /// `FFT(c zero-padded to L) / L`, the `L/2 + 1` non-negative frequencies (the `1/L` of the
    /// inverse FFT folded in).
    spectrum: Vec<Complex<f64>>,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
}

impl std::fmt::Debug for TriangularToeplitz {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriangularToeplitz")
            .field("order", &self.order)
            .field("fft_len", &self.fft_len())
            .finish()
    }
}

/// The buffers one product needs (`L` reals, `L/2 + 1` complex numbers and the FFTs' scratch);
/// built once and reused, so that a product allocates nothing.
#[derive(Clone, Debug)]
pub struct Workspace {
    real: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Workspace {
    /// Buffers for `matrix` (and for any matrix of the same FFT length).
    pub fn new(matrix: &TriangularToeplitz) -> Self {
        let scratch = matrix
            .forward
            .get_scratch_len()
            .max(matrix.inverse.get_scratch_len());
        Workspace {
            real: vec![0.0; matrix.fft_len()],
            spectrum: vec![Complex::new(0.0, 0.0); matrix.spectrum.len()],
            scratch: vec![Complex::new(0.0, 0.0); scratch],
        }
    }
}

/// The smallest `2^a 3^b 5^c ≥ k ≥ 1` with `c ≤ 2`.
fn smooth(k: usize) -> usize {
    let mut best = k.next_power_of_two();
    for p5 in [1, 5, 25] {
        let mut p35 = p5;
        while p35 < best {
            // The smallest power of two that lifts p35 to at least `k`.
            let mut len = p35;
            while len < k {
                len *= 2;
            }
            best = best.min(len);
            p35 *= 3;
        }
    }
    best
}

/// The FFT length used for order `m`: `L = 2K` with `K` the smallest `2^a 3^b 5^c ≥ m` with
/// `c ≤ 2`, so `L ≥ 2m − 1` and the real transform runs on a complex FFT of length `K`.
///
/// rustfft has fast butterflies for these radices, and such a `K` is within 15% of `m` where a
/// power of two can be almost twice as long. Factors of 5 are capped because at large `K`, where
/// the FFT is bound by memory bandwidth, each radix-5 pass is one more sweep over the buffer:
/// measured on the benchmark machine (real transform of length `2K`), `K = 1 012 500 = 2²3⁴5⁵`
/// takes 12.0 ms, `K = 1 036 800 = 2⁹3⁴5²` 10.3 ms; `K = 10 125 = 3⁴5³` 0.044 ms,
/// `K = 10 240 = 2¹¹5` 0.037 ms.
pub fn fft_len(m: usize) -> usize {
    2 * smooth(m.max(1))
}

impl TriangularToeplitz {
    /// The lower-triangular Toeplitz matrix of order `column.len()` with first column `column`.
    pub fn new(column: &[f64]) -> Self {
        Self::with_fft_len(column, fft_len(column.len()))
    }

    /// The same, padded to at least a given FFT length (so that several matrices can share a
    /// [`Workspace`]); the length used is [`fft_len`] of `max(len/2, column.len())`.
    pub fn with_fft_len(column: &[f64], len: usize) -> Self {
        let len = fft_len(column.len().max(len.div_ceil(2)));
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(len);
        let inverse = planner.plan_fft_inverse(len);
        Self::with_plans(column, forward, inverse)
    }

    /// Another matrix of the same FFT length, sharing this one's FFT plans (their twiddle
    /// tables) and [`Workspace`]s.
    ///
    /// # Panics
    ///
    /// If `column` is longer than half the FFT length (an internal misuse, never user input).
    pub fn with_same_plans(&self, column: &[f64]) -> Self {
        assert!(2 * column.len() <= self.fft_len(), "column too long");
        Self::with_plans(column, self.forward.clone(), self.inverse.clone())
    }

    fn with_plans(
        column: &[f64],
        forward: Arc<dyn RealToComplex<f64>>,
        inverse: Arc<dyn ComplexToReal<f64>>,
    ) -> Self {
        let len = forward.len();
        let inv_len = 1.0 / len as f64;
        let mut padded = vec![0.0; len];
        for (p, &c) in padded.iter_mut().zip(column) {
            *p = c * inv_len;
        }
        let mut spectrum = forward.make_output_vec();
        let mut scratch = forward.make_scratch_vec();
        forward
            .process_with_scratch(&mut padded, &mut spectrum, &mut scratch)
            .expect("buffers made by the plan");
        TriangularToeplitz {
            order: column.len(),
            spectrum,
            forward,
            inverse,
        }
    }

    /// The order `M`.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The FFT length `L`.
    pub fn fft_len(&self) -> usize {
        self.forward.len()
    }

    /// The general product: `out(k, (T x)_k)` (or `Tᵀ x` when `transpose`) for `k = 0..M`,
    /// where the input is `x_k = input(k)` for `k = 0..M`.
    ///
    /// # Panics
    ///
    /// If `ws` was built for another FFT length (an internal misuse, never user input).
    pub fn mul_with(
        &self,
        transpose: bool,
        ws: &mut Workspace,
        mut input: impl FnMut(usize) -> f64,
        mut out: impl FnMut(usize, f64),
    ) {
        let (head, tail) = ws.real.split_at_mut(self.order);
        for (k, b) in head.iter_mut().enumerate() {
            *b = input(k);
        }
        // The real transform uses its input as scratch: the padding is written every time.
        tail.fill(0.0);
        self.forward
            .process_with_scratch(&mut ws.real, &mut ws.spectrum, &mut ws.scratch)
            .expect("workspace built for this FFT length");
        if transpose {
            for (b, s) in ws.spectrum.iter_mut().zip(&self.spectrum) {
                *b *= s.conj();
            }
        } else {
            for (b, s) in ws.spectrum.iter_mut().zip(&self.spectrum) {
                *b *= s;
            }
        }
        // The zero and Nyquist frequencies of a real vector's product are real; a non-finite input
        // could leave a NaN there, which the inverse transform rejects (the NaN still propagates
        // through the real parts).
        let last = ws.spectrum.len() - 1;
        ws.spectrum[0].im = 0.0;
        ws.spectrum[last].im = 0.0;
        self.inverse
            .process_with_scratch(&mut ws.spectrum, &mut ws.real, &mut ws.scratch)
            .expect("workspace built for this FFT length");
        for (k, b) in ws.real[..self.order].iter().enumerate() {
            out(k, *b);
        }
    }

    /// `T x` (or `Tᵀ x`) into `y`. A slice `x` shorter than `M` is padded with zeros, a longer `y`
    /// is left alone past `M` (and a shorter one cut).
    pub fn mul(&self, transpose: bool, ws: &mut Workspace, x: &[f64], y: &mut [f64]) {
        self.mul_with(
            transpose,
            ws,
            |k| x.get(k).copied().unwrap_or(0.0),
            |k, v| {
                if let Some(t) = y.get_mut(k) {
                    *t = v;
                }
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense(c: &[f64], x: &[f64], transpose: bool) -> Vec<f64> {
        let m = c.len();
        (0..m)
            .map(|k| {
                (0..m)
                    .map(|j| {
                        let (row, col) = if transpose { (j, k) } else { (k, j) };
                        if row >= col { c[row - col] * x[j] } else { 0.0 }
                    })
                    .sum()
            })
            .collect()
    }

    #[test]
    fn small_products_are_the_matrix_products() {
        let t = TriangularToeplitz::new(&[1.0, -1.0, 0.5]);
        let mut ws = Workspace::new(&t);
        let (mut ta, mut tta) = (vec![0.0; 3], vec![0.0; 3]);
        t.mul(false, &mut ws, &[1.0, 2.0, 3.0], &mut ta);
        t.mul(true, &mut ws, &[1.0, 2.0, 3.0], &mut tta);
        // T = [[1, 0, 0], [−1, 1, 0], [0.5, −1, 1]]
        for (x, y) in ta.iter().zip([1.0, 1.0, 1.5]) {
            assert!((x - y).abs() < 1e-14);
        }
        for (x, y) in tta.iter().zip([0.5, -1.0, 3.0]) {
            assert!((x - y).abs() < 1e-14);
        }
    }

    #[test]
    fn products_match_the_dense_matrix() {
        for m in [1usize, 2, 3, 5, 16, 17, 100, 257] {
            let c: Vec<f64> = (0..m).map(|r| ((r * 7 + 3) as f64).sin()).collect();
            let a: Vec<f64> = (0..m).map(|r| ((r * 5 + 1) as f64).cos()).collect();
            let b: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64)).collect();
            let t = TriangularToeplitz::new(&c);
            assert!(t.fft_len() >= 2 * m - 1);
            let mut ws = Workspace::new(&t);
            for transpose in [false, true] {
                let (mut ta, mut tb) = (vec![0.0; m], vec![0.0; m]);
                t.mul(transpose, &mut ws, &a, &mut ta);
                t.mul(transpose, &mut ws, &b, &mut tb);
                for (got, want) in [
                    (ta, dense(&c, &a, transpose)),
                    (tb, dense(&c, &b, transpose)),
                ] {
                    let scale = want.iter().fold(1e-300f64, |s, x| s.max(x.abs()));
                    for (g, w) in got.iter().zip(&want) {
                        assert!((g - w).abs() <= 1e-13 * scale, "m = {m}: {g} vs {w}");
                    }
                }
            }
        }
    }

    /// A matrix sharing another's plans (and workspace) multiplies like one built alone.
    #[test]
    fn shared_plans_give_the_same_products() {
        let m = 40;
        let c: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64)).collect();
        let x: Vec<f64> = (0..m).map(|r| ((r * 3) as f64).sin()).collect();
        let host = TriangularToeplitz::new(&vec![1.0; m + 7]);
        let shared = host.with_same_plans(&c);
        assert_eq!(shared.fft_len(), host.fft_len());
        let alone = TriangularToeplitz::new(&c);
        let mut ws = Workspace::new(&host);
        let mut ws_alone = Workspace::new(&alone);
        for transpose in [false, true] {
            let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
            shared.mul(transpose, &mut ws, &x, &mut a);
            alone.mul(transpose, &mut ws_alone, &x, &mut b);
            let want = dense(&c, &x, transpose);
            for ((a, b), w) in a.iter().zip(&b).zip(&want) {
                assert!(
                    (a - w).abs() < 1e-13 && (b - w).abs() < 1e-13,
                    "{a} {b} {w}"
                );
            }
        }
    }

    #[test]
    fn fft_lengths_are_long_enough_smooth_and_tight() {
        for m in 1..2000 {
            let l = fft_len(m);
            assert!(l >= 2 * m - 1 && l.is_multiple_of(2));
            let mut odd = l >> l.trailing_zeros();
            for p in [3, 5] {
                while odd.is_multiple_of(p) {
                    odd /= p;
                }
            }
            assert_eq!(odd, 1, "{l}");
            assert!(!(l / 2).is_multiple_of(125), "{l} has 5³");
            assert!(
                l <= 2 * m - 1 + (2 * m - 1) / 8 + 8,
                "{m}: {l} is not tight"
            );
        }
    }
}
