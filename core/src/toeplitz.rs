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
//! `ĉ` is computed once, when the matrix is built. Because `c` is real, two real vectors `a`,
//! `b` are multiplied at once by packing them into `a + i b`: the real and imaginary parts of
//! the product are `T a` and `T b`.
//!
//! # Example
//!
//! ```
//! use varembed::toeplitz::{TriangularToeplitz, Workspace};
//! let t = TriangularToeplitz::new(&[1.0, -1.0, 0.5]);
//! let mut ws = Workspace::new(&t);
//! let (mut ta, mut tb) = (vec![0.0; 3], vec![0.0; 3]);
//! t.mul_pair(false, &mut ws, &[1.0, 2.0, 3.0], Some(&[0.0, 1.0, 0.0]), &mut ta, Some(&mut tb));
//! // T = [[1, 0, 0], [−1, 1, 0], [0.5, −1, 1]]
//! for (x, y) in ta.iter().zip([1.0, 1.0, 1.5]) { assert!((x - y).abs() < 1e-14); }
//! for (x, y) in tb.iter().zip([0.0, 1.0, -1.0]) { assert!((x - y).abs() < 1e-14); }
//! ```
//!
//! ## Reference
//!
//! R. M. Gray, *Toeplitz and circulant matrices: a review*, §4 (circulant embedding).

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// A lower-triangular Toeplitz matrix of order `M` (and its transpose), applied by FFT.
#[derive(Clone)]
pub struct TriangularToeplitz {
    order: usize,
    /// `FFT(c zero-padded to L) / L` (the `1/L` of the inverse FFT folded in).
    spectrum: Vec<Complex<f64>>,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for TriangularToeplitz {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriangularToeplitz")
            .field("order", &self.order)
            .field("fft_len", &self.spectrum.len())
            .finish()
    }
}

/// The buffers one product needs (`2L` complex numbers plus the FFT's scratch); built once and
/// reused, so that a product allocates nothing.
#[derive(Clone, Debug)]
pub struct Workspace {
    buffer: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Workspace {
    /// Buffers large enough for `matrix` (and for any matrix of the same FFT length).
    pub fn new(matrix: &TriangularToeplitz) -> Self {
        let scratch = matrix
            .forward
            .get_inplace_scratch_len()
            .max(matrix.inverse.get_inplace_scratch_len());
        Workspace {
            buffer: vec![Complex::new(0.0, 0.0); matrix.fft_len()],
            scratch: vec![Complex::new(0.0, 0.0); scratch],
        }
    }
}

/// The FFT length used for order `m`: the smallest 5-smooth number (`2^a 3^b 5^c`) that is at
/// least `2m − 1`. rustfft has fast butterflies for these radices, and a 5-smooth length is
/// within a few percent of `2m − 1` where a power of two can be almost twice as long.
pub fn fft_len(m: usize) -> usize {
    let need = (2 * m).saturating_sub(1).max(1);
    let mut best = need.next_power_of_two();
    let mut p5 = 1;
    while p5 < best {
        let mut p35 = p5;
        while p35 < best {
            // The smallest power of two that lifts p35 to at least `need`.
            let mut len = p35;
            while len < need {
                len *= 2;
            }
            best = best.min(len);
            p35 *= 3;
        }
        p5 *= 5;
    }
    best
}

impl TriangularToeplitz {
    /// The lower-triangular Toeplitz matrix of order `column.len()` with first column `column`.
    pub fn new(column: &[f64]) -> Self {
        Self::with_fft_len(column, fft_len(column.len()))
    }

    /// The same, padded to a given FFT length `len ≥ 2·column.len() − 1` (so that several
    /// matrices can share a [`Workspace`]); a shorter `len` is raised to [`fft_len`].
    pub fn with_fft_len(column: &[f64], len: usize) -> Self {
        let order = column.len();
        let len = len.max(fft_len(order));
        let mut planner = FftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(len);
        let inverse = planner.plan_fft_inverse(len);
        let mut spectrum = vec![Complex::new(0.0, 0.0); len];
        let inv_len = 1.0 / len as f64;
        for (s, &c) in spectrum.iter_mut().zip(column) {
            *s = Complex::new(c * inv_len, 0.0);
        }
        let mut scratch = vec![Complex::new(0.0, 0.0); forward.get_inplace_scratch_len()];
        forward.process_with_scratch(&mut spectrum, &mut scratch);
        TriangularToeplitz {
            order,
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
        self.spectrum.len()
    }

    /// The general product: `out(k, (T x)_k)` (or `Tᵀ x` when `transpose`) for `k = 0..M`,
    /// where the input is `x_k = input(k)` for `k = 0..M`, two real vectors packed as
    /// `re + i im`.
    ///
    /// # Panics
    ///
    /// If `ws` was built for a shorter FFT length (an internal misuse, never user input).
    pub fn mul_with(
        &self,
        transpose: bool,
        ws: &mut Workspace,
        mut input: impl FnMut(usize) -> Complex<f64>,
        mut out: impl FnMut(usize, Complex<f64>),
    ) {
        let len = self.fft_len();
        let buffer = &mut ws.buffer[..len];
        for (k, b) in buffer.iter_mut().enumerate() {
            *b = if k < self.order {
                input(k)
            } else {
                Complex::new(0.0, 0.0)
            };
        }
        self.forward.process_with_scratch(buffer, &mut ws.scratch);
        if transpose {
            for (b, s) in buffer.iter_mut().zip(&self.spectrum) {
                *b *= s.conj();
            }
        } else {
            for (b, s) in buffer.iter_mut().zip(&self.spectrum) {
                *b *= s;
            }
        }
        self.inverse.process_with_scratch(buffer, &mut ws.scratch);
        for (k, b) in buffer[..self.order].iter().enumerate() {
            out(k, *b);
        }
    }

    /// `T a` (or `Tᵀ a`) into `ta`, and the same for `b` into `tb` when both are given, in one
    /// complex FFT pair. Slices shorter than `M` are padded with zeros (inputs) or cut (outputs).
    pub fn mul_pair(
        &self,
        transpose: bool,
        ws: &mut Workspace,
        a: &[f64],
        b: Option<&[f64]>,
        ta: &mut [f64],
        mut tb: Option<&mut [f64]>,
    ) {
        let get = |x: &[f64], k: usize| x.get(k).copied().unwrap_or(0.0);
        self.mul_with(
            transpose,
            ws,
            |k| Complex::new(get(a, k), b.map_or(0.0, |b| get(b, k))),
            |k, y| {
                if let Some(t) = ta.get_mut(k) {
                    *t = y.re;
                }
                if let Some(t) = tb.as_deref_mut().and_then(|tb| tb.get_mut(k)) {
                    *t = y.im;
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
                t.mul_pair(transpose, &mut ws, &a, Some(&b), &mut ta, Some(&mut tb));
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

    #[test]
    fn fft_lengths_are_long_enough_smooth_and_tight() {
        for m in 1..2000 {
            let l = fft_len(m);
            assert!(l >= 2 * m - 1);
            let mut odd = l >> l.trailing_zeros();
            for p in [3, 5] {
                while odd.is_multiple_of(p) {
                    odd /= p;
                }
            }
            assert_eq!(odd, 1, "{l}");
            assert!(
                l <= 2 * m - 1 + (2 * m - 1) / 8 + 8,
                "{m}: {l} is not tight"
            );
        }
    }
}
