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
//! `ĉ` is computed when the matrix is built (and again after a release). All vectors are
//! real, so `L = 2K` real values are transformed as `K` complex ones
//! (`z_j = x_{2j} + i x_{2j+1}`), by one complex FFT
//! of length `K` and an `O(K)` pass that separates the even and odd halves (Sorensen et al.):
//! half the work and half the memory of a complex FFT of length `L`. `K ≥ M` is a product of
//! small primes ([`fft_len`]).
//!
//! **One pass, one plan.** A product is: pack `x` into `z`, FFT, one pass over the frequency
//! pairs `(m, K − m)` that unpacks `x̂`, multiplies by `ĉ` and packs the product's spectrum
//! for the inverse transform, FFT again, unpack. The inverse transform is the forward one of
//! the conjugate (`IFFT(W) = conj(FFT(conj W))/K`, the conjugations folded into the pass and
//! the unpacking), so one complex plan (its twiddle tables: 16 bytes per `K`, 8 where the
//! transform is split into halves, below) serves both
//! directions, where a real-FFT library keeps a forward and an inverse plan, each with its
//! own twiddles (48 bytes per `K` with the real passes' tables, measured: 475 MB of plans at
//! `K = 10⁷`). The pass's own twiddles `e^{−πi m/K}`, `m ≤ K/2`, are each the product of an
//! entry of two tables of about `√K` entries (8 bytes per `K` as one table, read beside the
//! spectra in a stream of its own; the product rounds a few units in the last place, as the
//! FFT's own twiddles do).
//!
//! **Two halves, two cores.** From `K/2 =` [`SPLIT_FROM`] on (with the `parallel` feature),
//! each complex FFT of length `K` is taken as two of length `K/2` (one radix-2 step of
//! decimation in time by hand): `Z_m = E_{m'} ± W^{m'} O_{m'}`, `m' = m mod K/2`,
//! `W = e^{−2πi/K}`, with `E`, `O` the transforms of the even- and odd-indexed entries. The
//! loading writes the entries straight into the two halves, the pass and the reading combine
//! `E` and `O` as they go, so the step costs no sweep over memory of its own, and the two
//! half-length FFTs run on two threads (rayon's `join`): the FFTs are most of a large
//! fractional solve's time. So does the pass between the transforms: a pair `(m, K − m)` is
//! written where the inverse transform reads entries `m` and `K − m`, both in the first half
//! for even `m` and both in the second for odd `m` (`K` is even), so one thread takes the
//! pairs of each parity, with the same arithmetic as one thread taking all. The twiddles
//! `W^j` are those of the pass (`W^j = e^{−πi 2j/K}`), so the step keeps no table of its own,
//! and the half-length plan's tables are half as long.
//! A product in place on a slice ([`TriangularToeplitz::mul_strided_in_place`], the
//! preconditioner's) also loads and reads its entries on two threads, each over one half of
//! them; a product through closures calls them in order, on one.
//! `K` is always even, so that the length does not depend on the choice.
//!
//! ## Reference
//!
//! R. M. Gray, *Toeplitz and circulant matrices: a review*, §4 (circulant embedding).
//! H. V. Sorensen et al., *Real-valued fast Fourier transform algorithms*, IEEE Trans. ASSP 35
//! (1987) (the real transform through a half-length complex one).

mod plan;

use crate::halves::both;
use plan::Plan;
pub use plan::SPLIT_FROM;
use rustfft::num_complex::Complex;
use std::sync::Arc;

/// A lower-triangular Toeplitz matrix of order `M` (and its transpose), applied by FFT.
#[derive(Clone)]
pub struct TriangularToeplitz {
    order: usize,
    /// `FFT(c zero-padded to L) / L`, the `K + 1` non-negative frequencies (the `1/L` of the
    /// inverse FFT folded in).
    spectrum: Vec<Complex<f64>>,
    plan: Arc<Plan>,
}

impl std::fmt::Debug for TriangularToeplitz {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriangularToeplitz")
            .field("order", &self.order)
            .field("fft_len", &self.fft_len())
            .finish()
    }
}

/// The buffers one product needs (`K` complex numbers, and the FFT's scratch, which the
/// out-of-place transform keeps at `K` more); built once and reused, so that a product
/// allocates nothing.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// The packed vector `x_{2j} + i x_{2j+1}` (in halves when split, as [`Plan::forward`]
    /// reads them) before a product, the product's packed spectrum before the inverse
    /// transform.
    packed: Vec<Complex<f64>>,
    /// The transform of `packed` (as its halves, [`Plan::entry`]): the input's, then the
    /// product's.
    spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Workspace {
    /// Buffers for `matrix` (and for any matrix of the same FFT length).
    pub fn new(matrix: &TriangularToeplitz) -> Self {
        Self::for_plan(&matrix.plan)
    }

    fn for_plan(plan: &Plan) -> Self {
        let k = plan.len();
        Workspace {
            packed: vec![Complex::new(0.0, 0.0); k],
            spectrum: vec![Complex::new(0.0, 0.0); k],
            scratch: vec![Complex::new(0.0, 0.0); plan.scratch_len()],
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

/// The FFT length used for order `m`: `L = 2K` with `K` the smallest even `2^a 3^b 5^c ≥ m`
/// with `c ≤ 2`, so `L ≥ 2m − 1` and the real transform runs on a complex FFT of length `K`
/// (two of length `K/2`).
///
/// rustfft has fast butterflies for these radices, and such a `K` is within 15% of `m` where a
/// power of two can be almost twice as long. Factors of 5 are capped because at large `K`, where
/// the FFT is bound by memory bandwidth, each radix-5 pass is one more sweep over the buffer:
/// measured on the benchmark machine (real transform of length `2K`), `K = 1 012 500 = 2²3⁴5⁵`
/// takes 12.0 ms, `K = 1 036 800 = 2⁹3⁴5²` 10.3 ms; `K = 10 125 = 3⁴5³` 0.044 ms,
/// `K = 10 240 = 2¹¹5` 0.037 ms.
pub fn fft_len(m: usize) -> usize {
    4 * smooth(m.max(1).div_ceil(2))
}

impl TriangularToeplitz {
    /// The lower-triangular Toeplitz matrix of order `column.len()` with first column `column`.
    pub fn new(column: &[f64]) -> Self {
        Self::with_workspace(column).0
    }

    /// [`new`](Self::new), and the [`Workspace`] its spectrum was computed in, for its
    /// products: a workspace of a long matrix is hundreds of megabytes, which a second one
    /// would fault in and clear again.
    pub fn with_workspace(column: &[f64]) -> (Self, Workspace) {
        Self::with_workspace_from(column.len(), |r| column[r])
    }

    /// [`with_workspace`](Self::with_workspace) of the column of order `order` whose entry
    /// `r` is `column(r)`, asked for once each with `r` increasing (a column computed by a
    /// recurrence as it is read is never kept: at `N = 10⁷` a column is 80 MB).
    pub(crate) fn with_workspace_from(
        order: usize,
        column: impl FnMut(usize) -> f64,
    ) -> (Self, Workspace) {
        let plan = Plan::new(fft_len(order) / 2);
        let mut ws = Workspace::for_plan(&plan);
        let matrix = Self::with_plan((order, column), Arc::new(plan), &mut ws);
        (matrix, ws)
    }

    /// Another matrix of the same FFT length, sharing this one's FFT plan (its twiddle
    /// tables) and [`Workspace`]s; its spectrum is computed in `ws`, one of those.
    ///
    /// # Panics
    ///
    /// If `column` is longer than half the FFT length, or `ws` is of another length (an
    /// internal misuse, never user input).
    pub fn with_same_plans(&self, column: &[f64], ws: &mut Workspace) -> Self {
        self.with_same_plans_from(column.len(), |r| column[r], ws)
    }

    /// [`with_same_plans`](Self::with_same_plans) of the column of order `order` whose entry
    /// `r` is `column(r)`, asked for as [`with_workspace_from`](Self::with_workspace_from)
    /// asks.
    pub(crate) fn with_same_plans_from(
        &self,
        order: usize,
        column: impl FnMut(usize) -> f64,
        ws: &mut Workspace,
    ) -> Self {
        assert!(2 * order <= self.fft_len(), "column too long");
        Self::with_plan((order, column), self.plan.clone(), ws)
    }

    fn with_plan(
        (order, column): (usize, impl FnMut(usize) -> f64),
        plan: Arc<Plan>,
        ws: &mut Workspace,
    ) -> Self {
        let mut matrix = TriangularToeplitz {
            order,
            spectrum: Vec::new(),
            plan,
        };
        matrix.compute_spectrum_from(column, ws);
        matrix
    }

    /// Frees the spectrum (16 bytes per `K`), for a phase of a computation that makes no
    /// product with this matrix; [`compute_spectrum_from`](Self::compute_spectrum_from)
    /// computes it again, one transform.
    pub(crate) fn release_spectrum(&mut self) {
        self.spectrum = Vec::new();
    }

    /// Whether the spectrum is held (not released).
    pub(crate) fn has_spectrum(&self) -> bool {
        !self.spectrum.is_empty()
    }

    /// Computes the spectrum of the first column whose entry `r` is `column(r)`, asked for as
    /// [`with_workspace_from`](Self::with_workspace_from) asks, in `ws`.
    pub(crate) fn compute_spectrum_from(
        &mut self,
        column: impl FnMut(usize) -> f64,
        ws: &mut Workspace,
    ) {
        let k = self.plan.len();
        self.load(ws, column);
        self.transform_forward(ws);
        let inv_len = 1.0 / (2 * k) as f64;
        let mut spectrum = vec![Complex::new(0.0, 0.0); k + 1];
        let (z, plan) = (&ws.spectrum, &self.plan);
        let tw = &plan.twiddles;
        let z0 = plan.entry(z, 0);
        spectrum[0] = Complex::new((z0.re + z0.im) * inv_len, 0.0);
        spectrum[k] = Complex::new((z0.re - z0.im) * inv_len, 0.0);
        plan.for_each_pair(z, |m, zm, zkm| {
            let (xm, xkm) = unpack(zm, zkm, tw.get(m));
            spectrum[m] = xm * inv_len;
            spectrum[k - m] = xkm * inv_len;
        });
        self.spectrum = spectrum;
    }

    /// The order `M`.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The FFT length `L` (of the real transform; the complex one is `L/2`).
    pub fn fft_len(&self) -> usize {
        2 * self.plan.len()
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
        input: impl FnMut(usize) -> f64,
        out: impl FnMut(usize, f64),
    ) {
        self.load(ws, input);
        self.mul_loaded(transpose, ws);
        self.store(ws, out);
    }

    /// Writes the input `x_k = input(k)`, `k = 0..M`, into `ws` (zero-padded), for
    /// [`mul_loaded`](Self::mul_loaded), reading it in increasing `k`. With
    /// [`store`](Self::store) after it, a caller that reads its input from the vector it writes
    /// the output to needs no buffer of its own.
    pub fn load(&self, ws: &mut Workspace, input: impl FnMut(usize) -> f64) {
        self.load_in_order(ws, input, false);
    }

    /// [`load`](Self::load), reading the input in decreasing `k`.
    pub fn load_descending(&self, ws: &mut Workspace, input: impl FnMut(usize) -> f64) {
        self.load_in_order(ws, input, true);
    }

    #[inline(always)]
    fn load_in_order(
        &self,
        ws: &mut Workspace,
        mut input: impl FnMut(usize) -> f64,
        descending: bool,
    ) {
        let m = self.order;
        let mut value = |k: usize| if k < m { input(k) } else { 0.0 };
        // The entries of one complex number (or two), each read once, in the order asked.
        let mut read = |first: usize, len: usize| {
            let mut x = [0.0; 4];
            for i in 0..len {
                let i = if descending { len - 1 - i } else { i };
                x[i] = value(first + i);
            }
            x
        };
        let order = |len: usize| (0..len).map(move |i| if descending { len - 1 - i } else { i });
        if !self.plan.split {
            let packed = &mut ws.packed;
            for j in order(packed.len()) {
                let [re, im, ..] = read(2 * j, 2);
                packed[j] = Complex::new(re, im);
            }
            return;
        }
        let (first, second) = ws.packed.split_at_mut(self.plan.h);
        // z_{2i} = x_{4i} + i x_{4i+1} into the first half, z_{2i+1} into the second.
        for i in order(first.len()) {
            let [a, b, c, d] = read(4 * i, 4);
            first[i] = Complex::new(a, b);
            second[i] = Complex::new(c, d);
        }
    }

    /// `(T B) x` (or its transpose) of the input [`load`](Self::load)ed into `ws`, as
    /// [`mul_loaded`](Self::mul_loaded), for `B` the first difference
    /// (`(B x)_k = x_k − x_{k−1}`, `x_{−1} = 0`): a product with the lower-triangular Toeplitz
    /// matrix whose first column is `c * (1, −1)` cut at the order, from `T`'s spectrum alone
    /// (`ĉ_m (1 − e^{−πi m/K})` is the spectrum of `c * (1, −1)`, whose one entry past the
    /// order lands only on entries past it). One complex multiplication per frequency more in
    /// the pass.
    pub(crate) fn mul_loaded_with_difference(&self, transpose: bool, ws: &mut Workspace) {
        self.mul_loaded_times(transpose, true, ws);
    }

    /// `T x` (or `Tᵀ x`) of the input [`load`](Self::load)ed into `ws`, left in `ws`.
    ///
    /// # Panics
    ///
    /// If `ws` was built for another FFT length (an internal misuse, never user input).
    pub fn mul_loaded(&self, transpose: bool, ws: &mut Workspace) {
        self.mul_loaded_times(transpose, false, ws);
    }

    /// [`mul_loaded`](Self::mul_loaded) of `T`, or of `T B` when `difference`
    /// ([`mul_loaded_with_difference`](Self::mul_loaded_with_difference)).
    fn mul_loaded_times(&self, transpose: bool, difference: bool, ws: &mut Workspace) {
        self.transform_forward(ws);
        let plan = &self.plan;
        let k = plan.len();
        let (z, w, s, tw) = (&ws.spectrum, &mut ws.packed, &self.spectrum, &plan.twiddles);
        let filter = |c: Complex<f64>| if transpose { c.conj() } else { c };
        // The spectrum at m and K − m, times that of B (`1 − t`, formed without cancellation,
        // and `1 + conj t`) where asked.
        let one = Complex::new(1.0, 0.0);
        let spectrum = |m: usize, t: Complex<f64>| {
            let (sm, skm) = (s[m], s[k - m]);
            if difference {
                (filter(sm * tw.gap(m)), filter(skm * (one + t.conj())))
            } else {
                (filter(sm), filter(skm))
            }
        };
        // m = 0 and m = K: x̂_0 and x̂_K are real (a NaN input stays in the real parts).
        let z0 = plan.entry(z, 0);
        let (s0, sk) = spectrum(0, one);
        let y0 = (z0.re + z0.im) * s0.re;
        let yk = (z0.re - z0.im) * sk.re;
        // conj(W_0) for W_0 = (ŷ_0 + ŷ_K) + i(ŷ_0 − ŷ_K).
        w[0] = Complex::new(y0 + yk, -(y0 - yk));
        // The pairs of entries `(m, K − m)`: into `out`, all of `w` when whole, or one half of
        // it when split (entry `j` at `j/2` of the half of its parity, `Plan::forward`), the two
        // halves on two threads: the same arithmetic either way.
        let pass = |parity: Option<usize>, out: &mut [Complex<f64>]| {
            let at = |j: usize| if parity.is_some() { j >> 1 } else { j };
            plan.for_each_pair_of(z, parity, |m, zm, zkm| {
                let t = tw.get(m);
                let (xm, xkm) = unpack(zm, zkm, t);
                let (sm, skm) = spectrum(m, t);
                let (ym, ykm) = (xm * sm, xkm * skm);
                let (wm, wkm) = pack_conjugate(ym, ykm, t);
                out[at(m)] = wm;
                out[at(k - m)] = wkm;
            })
        };
        if plan.split {
            let (even, odd) = w.split_at_mut(plan.h);
            both(|| pass(Some(0), even), || pass(Some(1), odd));
        } else {
            pass(None, w);
        }
        // The inverse transform as the forward one of the conjugate, into `spectrum`.
        self.transform_forward(ws);
    }

    /// Reads the result of [`mul_loaded`](Self::mul_loaded): `out(k, y_k)` for `k = 0..M`, in
    /// increasing `k`.
    pub fn store(&self, ws: &Workspace, out: impl FnMut(usize, f64)) {
        self.store_in_order(ws, out, false);
    }

    /// [`store`](Self::store) in decreasing `k`.
    pub fn store_descending(&self, ws: &Workspace, out: impl FnMut(usize, f64)) {
        self.store_in_order(ws, out, true);
    }

    #[inline(always)]
    fn store_in_order(&self, ws: &Workspace, mut out: impl FnMut(usize, f64), descending: bool) {
        let m = self.order;
        let pairs = m.div_ceil(2);
        for j in 0..pairs {
            let j = if descending { pairs - 1 - j } else { j };
            let (even, odd) = self.result_pair(&ws.spectrum, j);
            if !descending {
                out(2 * j, even);
            }
            if let Some(y) = odd {
                out(2 * j + 1, y);
            }
            if descending {
                out(2 * j, even);
            }
        }
    }

    /// The product's entries `y_{2j}` and, below the order, `y_{2j+1}`, from the packed result
    /// in `spectrum`: it is conj(FFT(conj W)), so `y_{2j} = Re`, `y_{2j+1} = −Im`.
    #[inline(always)]
    fn result_pair(&self, spectrum: &[Complex<f64>], j: usize) -> (f64, Option<f64>) {
        let z = self.plan.entry(spectrum, j);
        (z.re, (2 * j + 1 < self.order).then_some(-z.im))
    }

    /// `T x` (or `Tᵀ x`) in place on the entries `x[k · stride + offset]`, `k = 0..M`, of a
    /// slice that holds `stride` interleaved vectors (the components of a curve in `ℝ^d`).
    /// Where the transform is split, the loading and the reading run on two threads as the
    /// transforms do, each over one half of the entries: the same arithmetic as
    /// [`load`](Self::load) and [`store`](Self::store), so the same product bit for bit.
    ///
    /// # Panics
    ///
    /// If `x` is shorter than `M · stride` or `offset ≥ stride`, or `ws` was built for another
    /// FFT length (internal misuses, never user input).
    pub fn mul_strided_in_place(
        &self,
        transpose: bool,
        ws: &mut Workspace,
        x: &mut [f64],
        (stride, offset): (usize, usize),
    ) {
        let m = self.order;
        assert!(
            offset < stride && x.len() >= m * stride,
            "strided vector too short"
        );
        if !self.plan.split {
            self.load(ws, |k| x[k * stride + offset]);
            self.mul_loaded(transpose, ws);
            self.store(ws, |k, y| x[k * stride + offset] = y);
            return;
        }
        let value = |k: usize| if k < m { x[k * stride + offset] } else { 0.0 };
        let (first, second) = ws.packed.split_at_mut(self.plan.h);
        let half = first.len() / 2;
        let (first_low, first_high) = first.split_at_mut(half);
        let (second_low, second_high) = second.split_at_mut(half);
        // z_{2i} = x_{4i} + i x_{4i+1} into the first half, z_{2i+1} into the second, as
        // `load` writes them, for `i` from `start`.
        let fill = |first: &mut [Complex<f64>], second: &mut [Complex<f64>], start: usize| {
            for (i, (e, o)) in first.iter_mut().zip(second).enumerate() {
                let k = 4 * (start + i);
                *e = Complex::new(value(k), value(k + 1));
                *o = Complex::new(value(k + 2), value(k + 3));
            }
        };
        both(
            || fill(first_low, second_low, 0),
            || fill(first_high, second_high, half),
        );
        self.mul_loaded(transpose, ws);
        // The pairs `j` from `start` into a part of `x` that begins at entry `2 start`.
        let spectrum = &ws.spectrum;
        let read = |part: &mut [f64], start: usize, end: usize| {
            let base = 2 * start * stride;
            for j in start..end {
                let (even, odd) = self.result_pair(spectrum, j);
                part[2 * j * stride + offset - base] = even;
                if let Some(y) = odd {
                    part[(2 * j + 1) * stride + offset - base] = y;
                }
            }
        };
        let pairs = m.div_ceil(2);
        let middle = pairs / 2;
        let (low, high) = x.split_at_mut(2 * middle * stride);
        both(|| read(low, 0, middle), || read(high, middle, pairs));
    }

    /// `packed` → `spectrum` by the forward FFT, left as its halves ([`Plan::forward`];
    /// `packed` is destroyed).
    fn transform_forward(&self, ws: &mut Workspace) {
        self.plan
            .forward(&mut ws.packed, &mut ws.spectrum, &mut ws.scratch);
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

/// The real transform `x̂_m`, `x̂_{K−m}` (`L = 2K`) from the complex one `Z` of the packed
/// `z_j = x_{2j} + i x_{2j+1}`: with `E = (Z_m + conj Z_{K−m})/2`,
/// `O = −i (Z_m − conj Z_{K−m})/2` and `t = e^{−πi m/K}`, `x̂_m = E + t O` and
/// `x̂_{K−m} = conj(E − t O)`.
fn unpack(zm: Complex<f64>, zkm: Complex<f64>, t: Complex<f64>) -> (Complex<f64>, Complex<f64>) {
    let e = (zm + zkm.conj()) * 0.5;
    let d = zm - zkm.conj();
    let o = Complex::new(d.im, -d.re) * 0.5;
    let to = t * o;
    (e + to, (e - to).conj())
}

/// `conj W_m` and `conj W_{K−m}` of the packed spectrum whose inverse transform of length `K`
/// gives `y_{2j} + i y_{2j+1}` (the real inverse transform of `ŷ`): with
/// `A = ŷ_m + conj ŷ_{K−m}`, `B = ŷ_m − conj ŷ_{K−m}`, `W_m = A + i conj(t) B` and
/// `W_{K−m} = conj A + i t conj B`.
fn pack_conjugate(
    ym: Complex<f64>,
    ykm: Complex<f64>,
    t: Complex<f64>,
) -> (Complex<f64>, Complex<f64>) {
    let a = ym + ykm.conj();
    let b = ym - ykm.conj();
    let i = Complex::new(0.0, 1.0);
    let wm = a + i * t.conj() * b;
    let wkm = a.conj() + i * t * b.conj();
    (wm.conj(), wkm.conj())
}

#[cfg(test)]
mod tests;
