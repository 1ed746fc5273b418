//! The FFT plan of the Toeplitz products: one complex transform of length `K`, or, from
//! [`SPLIT_FROM`] on, two of length `K/2` on two threads, combined by one radix-2 step as the
//! entries are written and read (the parent module's docs, "Two halves, two cores").

use crate::halves::both;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// The complex FFT of length `K` (whole), or of length `K/2` for the two halves of one of
/// length `K` (split, from [`SPLIT_FROM`] on), and the twiddles `e^{−πi m/K}`, `m = 0..=K/2`,
/// of the pass between real and half-length complex transforms.
pub(super) struct Plan {
    fft: Arc<dyn Fft<f64>>,
    /// Whether `fft` is the half-length transform of the two halves.
    pub(super) split: bool,
    /// `K/2`.
    pub(super) h: usize,
    pub(super) twiddles: Twiddles,
}

/// The half length `K/2` from which each transform is taken as two halves on two threads
/// (with the `parallel` feature; one thread has no use for the halves). Below it the halves
/// gained nothing measurable (at `K/2 = 51 200`, the fractional solves at `N = 10⁵`: probes
/// equal either way, one criterion run up to a tenth slower with them), at `K/2 ≈ 1.5·10⁵`
/// the two ran even, at `K/2 ≈ 5·10⁵` the halves were clearly faster (BENCHMARKS.md).
pub const SPLIT_FROM: usize = 1 << 17;

/// The twiddles `e^{−πi m/K}`, `m = 0..=K/2`, of the pass between the real and the complex
/// transforms, each the product of an entry of two tables of about `√K` entries:
/// `e^{−πi (aS + b)/K} = e^{−πi aS/K} e^{−πi b/K}`, `S` a power of two. A table of all of them
/// is 8 bytes a node, and the pass reads it in a stream of its own beside the spectra; the
/// product rounds once more (a few units in the last place, as an FFT's own twiddles).
pub(super) struct Twiddles {
    /// `e^{−πi aS/K}`, `a = 0..=K/(2S)`.
    coarse: Vec<Complex<f64>>,
    /// `e^{−πi b/K}`, `b = 0..S`.
    fine: Vec<Complex<f64>>,
    /// `1 − e^{−πi aS/K}` and `1 − e^{−πi b/K}` ([`gap`](Self::gap)).
    coarse_gap: Vec<Complex<f64>>,
    fine_gap: Vec<Complex<f64>>,
    /// `log₂ S`.
    shift: u32,
}

impl Twiddles {
    fn new(k: usize) -> Self {
        let last = k / 2;
        let shift = (last + 1).isqrt().next_power_of_two().trailing_zeros();
        let step = -std::f64::consts::PI / k as f64;
        let theta = |m: usize| -step * m as f64;
        let at = |m: usize| Complex::from_polar(1.0, step * m as f64);
        // 1 − e^{−iθ} = 2 sin(θ/2) (sin(θ/2) + i cos(θ/2)), with no cancellation for small θ.
        let gap = |m: usize| {
            let (sin, cos) = (0.5 * theta(m)).sin_cos();
            Complex::new(sin, cos) * (2.0 * sin)
        };
        let coarse_m = || (0..=last >> shift).map(|a| a << shift);
        Twiddles {
            coarse: coarse_m().map(at).collect(),
            fine: (0..1usize << shift).map(at).collect(),
            coarse_gap: coarse_m().map(gap).collect(),
            fine_gap: (0..1usize << shift).map(gap).collect(),
            shift,
        }
    }

    /// `e^{−πi m/K}`, `m ≤ K/2`.
    #[inline(always)]
    pub(super) fn get(&self, m: usize) -> Complex<f64> {
        self.coarse[m >> self.shift] * self.fine[m & ((1 << self.shift) - 1)]
    }

    /// `1 − e^{−πi m/K}`, `m ≤ K/2`, to a few units in the last place of its own size. One
    /// minus [`get`](Self::get) would lose the relative accuracy where the value is small, at
    /// low `m` (an absolute error of `ε` on a value of about `πm/K`), and these are the
    /// frequencies where a smooth vector's transform is largest. Formed as
    /// `(1 − c) + c (1 − f)` from the two tables' entries `c`, `f` and their gaps.
    #[inline(always)]
    pub(super) fn gap(&self, m: usize) -> Complex<f64> {
        let (a, b) = (m >> self.shift, m & ((1 << self.shift) - 1));
        self.coarse_gap[a] + self.coarse[a] * self.fine_gap[b]
    }
}

impl Plan {
    pub(super) fn new(k: usize) -> Self {
        let split = cfg!(feature = "parallel") && k / 2 >= SPLIT_FROM;
        let len = if split { k / 2 } else { k };
        let fft = FftPlanner::<f64>::new().plan_fft_forward(len);
        let twiddles = Twiddles::new(k);
        Plan {
            fft,
            split,
            h: k / 2,
            twiddles,
        }
    }

    /// The scratch length of [`forward`](Self::forward): one per half-length transform, since
    /// the two run at once.
    pub(super) fn scratch_len(&self) -> usize {
        let one = self.fft.get_outofplace_scratch_len();
        if self.split { 2 * one } else { one }
    }

    /// `K`, the length of the complex transform.
    pub(super) fn len(&self) -> usize {
        2 * self.h
    }

    /// `W^j = e^{−2πi j/K}` for `j < K/2`, from the pass's twiddles `e^{−πi m/K}`, `m ≤ K/2`:
    /// `W^j = t_{2j}` for `j ≤ K/4`, and `W^j = −conj(W^{K/2−j})` past it.
    #[inline]
    pub(super) fn w(&self, j: usize) -> Complex<f64> {
        if 2 * j <= self.h {
            self.twiddles.get(2 * j)
        } else {
            -self.twiddles.get(2 * (self.h - j)).conj()
        }
    }

    /// The forward FFT of length `K` of `input` (entry `j` at `j` when whole; when split, at
    /// `j/2` of the first half for even `j`, of the second for odd `j`) into
    /// `output`, whole or, when split, as the two half-length transforms `E`, `O` in its
    /// halves ([`entry`](Self::entry) reads either); `input` is destroyed.
    pub(super) fn forward(
        &self,
        input: &mut [Complex<f64>],
        output: &mut [Complex<f64>],
        scratch: &mut [Complex<f64>],
    ) {
        if !self.split {
            self.fft
                .process_outofplace_with_scratch(input, output, scratch);
            return;
        }
        let h = self.h;
        let (input_e, input_o) = input.split_at_mut(h);
        let (output_e, output_o) = output.split_at_mut(h);
        let (scratch_e, scratch_o) = scratch.split_at_mut(scratch.len() / 2);
        let even = || {
            self.fft
                .process_outofplace_with_scratch(input_e, output_e, scratch_e)
        };
        let odd = || {
            self.fft
                .process_outofplace_with_scratch(input_o, output_o, scratch_o)
        };
        both(even, odd);
    }

    /// Entry `m < K` of the length-`K` transform in `z` (its halves `E`, `O` when split).
    #[inline]
    pub(super) fn entry(&self, z: &[Complex<f64>], m: usize) -> Complex<f64> {
        if !self.split {
            return z[m];
        }
        let h = self.h;
        let j = if m < h { m } else { m - h };
        let t = self.w(j) * z[h + j];
        if m < h { z[j] + t } else { z[j] - t }
    }

    /// `pair(m, Z_m, Z_{K−m})` for `m = 1..=K/2`, in some order, of the length-`K` transform
    /// in `z`. When split, the entries `m`, `K/2 + m`, `K/2 − m`, `K − m` come from `E` and `O`
    /// at `m` and `K/2 − m` with one twiddle (`W^{K/2−m} = −conj W^m`), so each quadruple is
    /// read once.
    #[inline]
    pub(super) fn for_each_pair(
        &self,
        z: &[Complex<f64>],
        pair: impl FnMut(usize, Complex<f64>, Complex<f64>),
    ) {
        self.for_each_pair_of(z, None, pair);
    }

    /// [`for_each_pair`](Self::for_each_pair) for the `m` of one parity only (all when
    /// `None`): `m` and `K − m` have the same parity, so the pairs of one parity are the ones
    /// whose entries [`forward`](Self::forward)'s input holds in one half, and the two parities can be
    /// written by two threads.
    #[inline]
    pub(super) fn for_each_pair_of(
        &self,
        z: &[Complex<f64>],
        parity: Option<usize>,
        mut pair: impl FnMut(usize, Complex<f64>, Complex<f64>),
    ) {
        let keeps = |m: usize| parity.is_none_or(|p| m & 1 == p);
        let h = self.h;
        if !self.split {
            for m in (1..=h).filter(|&m| keeps(m)) {
                pair(m, z[m], z[2 * h - m]);
            }
            return;
        }
        let (e, o) = z.split_at(h);
        for m in 1..h.div_ceil(2) {
            let (first, second) = (keeps(m), keeps(h - m));
            if !first && !second {
                continue;
            }
            let w = self.twiddles.get(2 * m);
            let (t, t_mirror) = (w * o[m], -(w.conj() * o[h - m]));
            // (m, K − m) and (K/2 − m, K/2 + m).
            if first {
                pair(m, e[m] + t, e[h - m] - t_mirror);
            }
            if second {
                pair(h - m, e[h - m] + t_mirror, e[m] - t);
            }
        }
        if h.is_multiple_of(2) && keeps(h / 2) {
            let m = h / 2;
            pair(m, self.entry(z, m), self.entry(z, 2 * h - m));
        }
        if keeps(h) {
            pair(h, self.entry(z, h), self.entry(z, h));
        }
    }
}
