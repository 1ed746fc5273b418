//! [`FftOperator`]: the operators `Δ^α_±` of [`Operator`] applied by FFT, `O(N log N)` per
//! product and `O(N)` memory instead of the dense loops' `O(N²)` time.
//!
//! Every operator is `h^{−α} Σ_r w_r Q_{k∓r}`. With `T` the lower-triangular Toeplitz matrix of
//! order `N + 1` with first column `w` ([`TriangularToeplitz`]):
//!
//! - `Δ_− Q = h^{−α} (T Q)[1..=N]`, `Δ_−ᵀ W = h^{−α} Tᵀ (0, W_1, …, W_N)`;
//! - `Δ_+ Q = h^{−α} (Tᵀ Q)[0..N]`, `Δ_+ᵀ W = h^{−α} T (W_0, …, W_{N−1}, 0)`.
//!
//! Each of the `D` components is one real product. The spectrum of the weights is computed
//! when the operator is built (and again after [`FftOperator::release_spectrum`]), and the
//! buffers of the products are kept with it. For the Grünwald–Letnikov weights at `α ≥ ½` it
//! is not `w`'s own spectrum but the difference form's, below.
//!
//! # Applying the operator to a curve: the difference form
//!
//! An FFT product is accurate to about `ε log L` times the size of its *input*, while `Δ^α Q`
//! of a smooth curve is `h^α` times smaller than `Q` (the weights sum to about zero). Those
//! rounding errors are not smooth, and the Euler–Lagrange rows amplify them by `h^{−α}` once
//! more: on the pendulum `L = ½v² + cos x` under Gauss-GLE− (α = 0.7) at `N = 10⁵` they made
//! `Problem::residual` wrong by 11 times the residual of the exact solution rounded to doubles
//! (1.7e-8 against 1.5e-9, measured by the integration test `residual_floor.rs`); through the
//! differences, by 0.2 times. So for a curve the product is taken through the curve's
//! differences instead, which are `h` times smaller than its nodes:
//! the generating function of the weights factors as `(1 − z)^α = (1 − z)^{α−1} (1 − z)`, so
//! `T = T' B` with `B` the first difference and `T'` the Toeplitz matrix of the weights of
//! `(1 − z)^{α−1}` ([`grunwald_letnikov_inverse`](crate::weights::grunwald_letnikov_inverse)
//! at `1 − α`), and
//!
//! - `(T Q)_k = g'_k Q_0 + (T' d)_k`, `d_0 = 0`, `d_k = Q_k − Q_{k−1}`;
//! - `(Tᵀ Q)_k = g'_{N−k} Q_N + (T'ᵀ d)_k`, `d_N = 0`, `d_k = Q_k − Q_{k+1}`.
//!
//! The one large entry of `B Q` (the end node) is applied exactly, the differences by FFT
//! ([`FftOperator::apply_by_differences`]). For a rough vector the differences are as large as
//! the nodes and `T'`'s weights sum to about `N^{1−α}`, so the Jacobian products of the Krylov
//! solvers keep the plain form.
//!
//! # One spectrum for both forms
//!
//! The plain form needs no spectrum of its own: `T = T' B` holds for the truncated matrices,
//! and the spectrum of `B`'s column `(1, −1)` is `1 − e^{−πi m/K}`, so a plain product
//! multiplies by `ĝ'_m (1 − e^{−πi m/K})` in the pass between the transforms
//! ([`TriangularToeplitz::mul_loaded_with_difference`]). That spares one spectrum, 16 bytes a
//! node. The factor comes from small tables beside the pass's twiddles, formed so that it
//! keeps its relative accuracy at the low frequencies, where it is as small as `π/K` (one
//! minus the twiddle would not, and a smooth curve's transform is largest there).
//! It rounds like a product with `T'`, whose error grows with `‖g'‖₂`: bounded for `α > ½`
//! (the `g'_r` fall like `r^{−α}`), `√(log N)` at `α = ½`, but `N^{½−α}` below, where a
//! residual's product would err above the floor of double precision for small `α` at large
//! `N`. So the plain spectrum is kept for `α < ½`, and for an operator whose weights are not
//! the Grünwald–Letnikov weights of its `α` (the moduli of the weights, which the residual's
//! term sizes apply).

use crate::error::{Result, check_len};
use crate::lagrangian::Vector;
use crate::operator::Operator;
use crate::side::Side;
use crate::toeplitz::{TriangularToeplitz, Workspace};
use crate::weights::{InverseWeights, are_grunwald_letnikov};

/// `Δ_σ` or `Δ^α_σ` (an `N × (N + 1)` matrix) with products by FFT.
#[derive(Clone, Debug)]
pub struct FftOperator {
    side: Side,
    n: usize,
    scale: f64,
    alpha: f64,
    toeplitz: Forms,
    ws: Workspace,
}

/// The Toeplitz matrices of an [`FftOperator`]'s two forms (module docs).
#[derive(Clone, Debug)]
enum Forms {
    /// `T'` alone, whose spectrum serves both forms (`T = T' B`).
    Differences(TriangularToeplitz),
    /// `T`, and `T'`, built on the first
    /// [`apply_by_differences`](FftOperator::apply_by_differences); its first column `g'` is
    /// not kept.
    Plain(TriangularToeplitz, Option<TriangularToeplitz>),
}

impl FftOperator {
    /// The FFT form of `op` (its weights transformed once): of its Toeplitz part only. A
    /// corrected operator's starting columns are not in it; its users (the fast solver, the
    /// discretisation's evaluations) add them beside its products.
    pub fn new(op: &Operator) -> Self {
        Self::with_forms(op, true)
    }

    /// [`new`](Self::new), with one spectrum for both forms only where `share` allows it.
    fn with_forms(op: &Operator, share: bool) -> Self {
        let n = op.rows().count();
        let (alpha, weights) = (op.alpha(), op.weights());
        let (toeplitz, ws) = if share && alpha >= 0.5 && are_grunwald_letnikov(weights, alpha) {
            let mut g = InverseWeights::new(1.0 - alpha);
            let (t, ws) = TriangularToeplitz::with_workspace_from(n + 1, |r| g.at(r));
            (Forms::Differences(t), ws)
        } else {
            let column = |r: usize| weights.get(r).copied().unwrap_or(0.0);
            let (t, ws) = TriangularToeplitz::with_workspace_from(n + 1, column);
            (Forms::Plain(t, None), ws)
        };
        FftOperator {
            side: op.side(),
            n,
            scale: op.scale(),
            alpha,
            toeplitz,
            ws,
        }
    }

    /// Whether the plain products are taken through `T'`'s spectrum (module docs).
    #[cfg(test)]
    fn shares_one_spectrum(&self) -> bool {
        matches!(self.toeplitz, Forms::Differences(_))
    }

    /// A matrix of the operator's FFT length: the one whose plans the others share.
    fn any(&self) -> &TriangularToeplitz {
        match &self.toeplitz {
            Forms::Differences(t) | Forms::Plain(t, _) => t,
        }
    }

    /// Frees the spectrum that serves both forms, for a phase that makes no product (16 bytes
    /// a node); the next product computes it again, one transform. An operator with a plain
    /// spectrum of its own keeps both (its weights are not kept to compute them from).
    pub(crate) fn release_spectrum(&mut self) {
        if let Forms::Differences(t) = &mut self.toeplitz {
            t.release_spectrum();
        }
    }

    /// Computes `T'`'s spectrum again where it was released.
    fn differences_spectrum(&mut self) {
        if let Forms::Differences(t) = &mut self.toeplitz
            && !t.has_spectrum()
        {
            let mut g = InverseWeights::new(1.0 - self.alpha);
            t.compute_spectrum_from(|r| g.at(r), &mut self.ws);
        }
    }

    /// The plain product of `T` (or `Tᵀ`), through closures as [`TriangularToeplitz::mul_with`].
    fn mul_with(
        &mut self,
        transpose: bool,
        input: impl FnMut(usize) -> f64,
        out: impl FnMut(usize, f64),
    ) {
        self.differences_spectrum();
        match &self.toeplitz {
            Forms::Differences(t) => {
                t.load(&mut self.ws, input);
                t.mul_loaded_with_difference(transpose, &mut self.ws);
                t.store(&self.ws, out);
            }
            Forms::Plain(t, _) => t.mul_with(transpose, &mut self.ws, input, out),
        }
    }

    /// The number of steps `N`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The Toeplitz matrix of order `order` whose first column has entry `r` = `column(r)`
    /// (asked for with `r` increasing, so a column computed as it is read is never kept),
    /// sharing this operator's plans and workspace ([`TriangularToeplitz::with_same_plans`]).
    pub(crate) fn with_same_plans_from(
        &mut self,
        order: usize,
        column: impl FnMut(usize) -> f64,
    ) -> TriangularToeplitz {
        let (toeplitz, ws) = match &self.toeplitz {
            Forms::Differences(t) | Forms::Plain(t, _) => (t, &mut self.ws),
        };
        toeplitz.with_same_plans_from(order, column, ws)
    }

    /// The buffers of the products, to share with other matrices of the same FFT length.
    pub(crate) fn workspace_mut(&mut self) -> &mut Workspace {
        &mut self.ws
    }

    /// The FFT length (at least `2N + 2`).
    pub fn fft_len(&self) -> usize {
        self.any().fft_len()
    }

    /// One component of `Δ Q`: `out(i, (Δ Q)_i)` for the rows `i = 0..N` (entry `i` is row
    /// `i + first_row`, as [`Operator::apply`]), with node `k`'s value `input(k)`, `k = 0..=N`.
    /// The vectors of a product live in the caller's closures, so a solver needs no buffers of
    /// its own for them.
    pub(crate) fn apply_with(
        &mut self,
        input: impl FnMut(usize) -> f64,
        mut out: impl FnMut(usize, f64),
    ) {
        let (transpose, shift) = match self.side {
            Side::Backward => (false, 1),
            Side::Forward => (true, 0),
        };
        let (n, s) = (self.n, self.scale);
        self.mul_with(transpose, input, |k, y| {
            if k >= shift && k - shift < n {
                out(k - shift, y * s);
            }
        });
    }

    /// One component of `Δᵀ W`: `out(k, (Δᵀ W)_k)` for the nodes `k = 0..=N`, with row `i`'s
    /// value `input(i)`, `i = 0..N`.
    pub(crate) fn apply_transpose_with(
        &mut self,
        mut input: impl FnMut(usize) -> f64,
        mut out: impl FnMut(usize, f64),
    ) {
        let (transpose, shift) = match self.side {
            Side::Backward => (true, 1),
            Side::Forward => (false, 0),
        };
        let (n, s) = (self.n, self.scale);
        self.mul_with(
            transpose,
            |k| {
                if k >= shift && k - shift < n {
                    input(k - shift)
                } else {
                    0.0
                }
            },
            |k, y| out(k, y * s),
        );
    }

    /// `Δ Q` into `out`: `q` has `N + 1` nodes, `out` `N` values (entry `i` is row
    /// `i + first_row`, as [`Operator::apply`]).
    pub fn apply_inplace<const D: usize>(
        &mut self,
        q: &[Vector<D>],
        out: &mut [Vector<D>],
    ) -> Result<()> {
        check_len("curve", self.n + 1, q.len())?;
        check_len("values on the rows", self.n, out.len())?;
        for c in 0..D {
            self.apply_with(|k| q[k][c], |i, y| out[i][c] = y);
        }
        Ok(())
    }

    /// `Δ Q` into `out` like [`apply_inplace`](Self::apply_inplace), taken through the
    /// differences of the nodes (module docs): for a smooth curve the rounding error is that of
    /// its differences, about `h` times that of [`apply_inplace`](Self::apply_inplace). Costs
    /// the same per product; the first call builds `T'` (one more FFT; its spectrum is kept).
    pub fn apply_by_differences_inplace<const D: usize>(
        &mut self,
        q: &[Vector<D>],
        out: &mut [Vector<D>],
    ) -> Result<()> {
        check_len("curve", self.n + 1, q.len())?;
        check_len("values on the rows", self.n, out.len())?;
        for c in 0..D {
            self.apply_by_differences_with(|k| q[k][c], |i, y| out[i][c] = y);
        }
        Ok(())
    }

    /// One component of `Δ Q` through the differences of the nodes, `input(k)` being node
    /// `k`'s value, as [`apply_with`](Self::apply_with).
    pub(crate) fn apply_by_differences_with(
        &mut self,
        input: impl Fn(usize) -> f64,
        mut out: impl FnMut(usize, f64),
    ) {
        self.differences_spectrum();
        let (n, s, beta) = (self.n, self.scale, 1.0 - self.alpha);
        let t = match &mut self.toeplitz {
            Forms::Differences(t) => t,
            Forms::Plain(toeplitz, differences) => differences.get_or_insert_with(|| {
                let mut weights = InverseWeights::new(beta);
                toeplitz.with_same_plans_from(n + 1, |r| weights.at(r), &mut self.ws)
            }),
        };
        // g'_r for r = 0, 1, 2, … in turn (`InverseWeights`), as the products are read: a row
        // reads g'_r once, and the rows are read in the order that walks r upwards, so the
        // N + 1 weights are not kept.
        let mut weights = InverseWeights::new(beta);
        let mut g = move |r| weights.at(r);
        match self.side {
            // Rows 1..=N of T Q, read with k (= r) increasing.
            Side::Backward => {
                let first = input(0);
                t.load(&mut self.ws, |k| {
                    if k == 0 { 0.0 } else { input(k) - input(k - 1) }
                });
                t.mul_loaded(false, &mut self.ws);
                t.store(&self.ws, |k, y| {
                    if k >= 1 {
                        out(k - 1, (y + g(k) * first) * s);
                    }
                })
            }
            // Rows 0..N of Tᵀ Q, read with k decreasing (r = N − k increasing).
            Side::Forward => {
                let last = input(n);
                t.load(&mut self.ws, |k| {
                    if k == n { 0.0 } else { input(k) - input(k + 1) }
                });
                t.mul_loaded(true, &mut self.ws);
                t.store_descending(&self.ws, |k, y| {
                    if k < n {
                        out(k, (y + g(n - k) * last) * s);
                    }
                })
            }
        }
    }

    /// `Δᵀ W` into `out`: `w` has `N` values on the rows, `out` `N + 1` nodes.
    pub fn apply_transpose_inplace<const D: usize>(
        &mut self,
        w: &[Vector<D>],
        out: &mut [Vector<D>],
    ) -> Result<()> {
        check_len("values on the rows", self.n, w.len())?;
        check_len("curve", self.n + 1, out.len())?;
        for c in 0..D {
            self.apply_transpose_with(|i| w[i][c], |k, y| out[k][c] = y);
        }
        Ok(())
    }

    /// `Δ Q` (allocating), the fast twin of [`Operator::apply`].
    pub fn apply<const D: usize>(&mut self, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        let mut out = vec![Vector::<D>::zeros(); self.n];
        self.apply_inplace(q, &mut out)?;
        Ok(out)
    }

    /// `Δ Q` through the differences of the nodes (allocating): see
    /// [`apply_by_differences_inplace`](Self::apply_by_differences_inplace).
    pub fn apply_by_differences<const D: usize>(
        &mut self,
        q: &[Vector<D>],
    ) -> Result<Vec<Vector<D>>> {
        let mut out = vec![Vector::<D>::zeros(); self.n];
        self.apply_by_differences_inplace(q, &mut out)?;
        Ok(out)
    }

    /// `Δᵀ W` (allocating), the fast twin of [`Operator::apply_transpose`].
    pub fn apply_transpose<const D: usize>(&mut self, w: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        let mut out = vec![Vector::<D>::zeros(); self.n + 1];
        self.apply_transpose_inplace(w, &mut out)?;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;

    /// `max |a − b| / max |a|`.
    fn gap(a: &[Vector<1>], b: &[Vector<1>]) -> f64 {
        let size = a.iter().fold(0.0f64, |m, x| m.max(x.amax()));
        let gap = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).amax()));
        gap / size
    }

    /// A curve of `n + 1` nodes and values on `n` rows, `curve(k)` and `rows(i)`.
    fn vectors(
        n: usize,
        curve: impl Fn(usize) -> f64,
        rows: impl Fn(usize) -> f64,
    ) -> (Vec<Vector<1>>, Vec<Vector<1>>) {
        let q = (0..=n).map(|k| Vector::<1>::new(curve(k))).collect();
        let w = (0..n).map(|i| Vector::<1>::new(rows(i))).collect();
        (q, w)
    }

    /// The plain products through the difference form's spectrum round as those through a
    /// spectrum of their own, on smooth vectors at a length where the spectrum of the first
    /// difference, `1 − e^{−πi m/K}`, is as small as `π/K` at the lowest frequencies. Formed
    /// as one minus the twiddle, it lost its relative accuracy there, and `Δ Q` at α = ½ erred
    /// by 3.8e-14 of its size, where it errs by 1.5e-15 (3.7e-15 the largest of the four).
    #[test]
    fn one_spectrum_rounds_as_two_on_long_smooth_vectors() {
        let n = 200_000;
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let (q, w) = vectors(n, |k| grid.t(k).sin() + 0.3, |i| grid.t(i).cos());
        for (side, alpha) in [(Side::Backward, 0.5), (Side::Forward, 0.6)] {
            let op = Operator::grunwald_letnikov(side, alpha, &grid).unwrap();
            let (mut shared, mut plain) =
                (FftOperator::new(&op), FftOperator::with_forms(&op, false));
            assert!(shared.shares_one_spectrum() && !plain.shares_one_spectrum());
            let (a, b) = (shared.apply(&q).unwrap(), plain.apply(&q).unwrap());
            assert!(gap(&b, &a) < 1e-14, "{side:?} Δ: {:e}", gap(&b, &a));
            let (a, b) = (
                shared.apply_transpose(&w).unwrap(),
                plain.apply_transpose(&w).unwrap(),
            );
            assert!(gap(&b, &a) < 1e-14, "{side:?} Δᵀ: {:e}", gap(&b, &a));
        }
    }

    /// Every product equals the dense loops', whether the plain form has a spectrum of its own
    /// (`α < ½`, weights that are not Grünwald–Letnikov's) or is taken through `T'`'s (both
    /// sides, `Δ` and `Δᵀ`, the plain and the difference forms).
    #[test]
    fn products_equal_the_dense_loops() {
        let n = 300;
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let (q, w) = vectors(n, |k| (k as f64).sin() + 0.3, |i| (3.0 * i as f64).cos());
        for side in [Side::Backward, Side::Forward] {
            let paper = |alpha| Operator::grunwald_letnikov(side, alpha, &grid).unwrap();
            let cases = [
                (paper(0.3), false),
                (paper(0.5), true),
                (paper(0.7), true),
                (paper(1.0), true),
                (Operator::finite_difference(side, &grid), true),
                (paper(0.7).absolute(), false),
            ];
            for (k, (op, shared)) in cases.into_iter().enumerate() {
                let what = format!("{side:?} α = {}, shared {shared}", op.alpha());
                let mut fast = FftOperator::new(&op);
                assert_eq!(fast.shares_one_spectrum(), shared, "{what}");
                let dense = op.apply(&q).unwrap();
                assert!(gap(&dense, &fast.apply(&q).unwrap()) < 1e-13, "{what}");
                // The difference form is of Grünwald–Letnikov weights only.
                if k < 5 {
                    let by_differences = fast.apply_by_differences(&q).unwrap();
                    assert!(gap(&dense, &by_differences) < 1e-13, "{what}");
                }
                let dense = op.apply_transpose(&w).unwrap();
                let product = fast.apply_transpose(&w).unwrap();
                assert!(gap(&dense, &product) < 1e-13, "{what}");
            }
        }
    }
}
