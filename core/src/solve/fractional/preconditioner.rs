//! The preconditioner of the fractional fast path: the inverse of the kinetic part
//! `P' = Dᵀ L_vv D` of the Jacobian, applied by FFT.
//!
//! On the interior columns, the rows of `D` that belong to interior nodes form a square
//! triangular Toeplitz matrix `D_a = s·T` (σ = −: `T` lower-triangular with the
//! Grünwald–Letnikov weights `w`, `s = h^{−α}`; σ = +: `D_a = −s Tᵀ`); `D` has one row more, `E`
//! (row `N` for σ = −, row `0` for σ = +, with `L_vv` block `H_e` there). With `V` the block
//! diagonal of the `L_vv` at the interior nodes, the whole `L_vv` part of `J` is
//!
//! `P' = Dᵀ L_vv D = P + Eᵀ H_e E`,  `P = D_aᵀ V D_a`.
//!
//! The inverse of `T` is the lower-triangular Toeplitz matrix `G` of the weights
//! `g_r = Γ(r+α)/(Γ(α) r!)`
//! ([`grunwald_letnikov_inverse`](crate::weights::grunwald_letnikov_inverse)), so
//!
//! `P⁻¹ = s⁻² G V⁻¹ Gᵀ` (σ = −),  `P⁻¹ = s⁻² Gᵀ V⁻¹ G` (σ = +),
//!
//! two triangular Toeplitz products by FFT, and the rank-`d` row is added by Woodbury:
//!
//! `P'⁻¹ = P⁻¹ − U (I + H_e E U)⁻¹ H_e E P⁻¹`,  `U = P⁻¹ Eᵀ`,
//!
//! `O(N d²)` per application once `U` is known. `U` costs `d²` products per Newton step, since
//! `D_a⁻ᵀ Eᵀ` has a closed form: `T G = I` makes it `−(g_{N−1}, …, g_1)` for σ = − and
//! `−(g_1, …, g_{N−1})` for σ = +. Without this term `P⁻¹J` had one outlying eigenvalue
//! `E P⁻¹ Eᵀ ≈ Σ_{r<N} g_r² ∝ N^{2α−1}` (about 350 at `N = 10⁶`, α = 0.7), which CG resolves
//! with extra iterations that grew with `N`. Now `P'` is symmetric positive definite when every
//! `L_vv` is, `P'⁻¹ J = I + P'⁻¹(L_xx + L_xv D + Dᵀ L_vx)`, and since `D_a` grows like `h^{−α}`
//! the remainder is a compact perturbation: the iteration counts stay flat as `N` grows (on the
//! benchmark pendulum the most MINRES iterations of a Newton step are 6, 6, 5 at
//! `N = 200, 2000, 20 000`: unit test `krylov_iterations_stay_flat_as_n_grows`).
//!
//! **One FFT product less per CG iteration.** The preconditioner's middle vector
//! `V⁻¹ D_a⁻ᵀ r` is `D_a` of `P⁻¹ r`, and `D_a U` is known, so the preconditioner yields `D_a z`
//! for its output `z` ([`Preconditioner::apply`]'s image); CG carries it along its recurrence,
//! and a CG iteration costs three FFT products instead of four, with the same iterates.
//!
//! **The kinetic product from its inverse.** Where every `L_vv` block is inverted and the
//! Woodbury term formed, this is `P'⁻¹` exactly, so for `z = P'⁻¹ r` the Jacobian's product is
//! `J z = r + (L_xx z + L_xv D z + Dᵀ L_vx z)`: the product `Dᵀ L_vv D z` is `r`, already at
//! hand ([`KrylovSystem::apply_preconditioned`]). With every `L_xv` zero (all `T(v) − U(x)`,
//! the pendulum among them) a MINRES iteration then costs the preconditioner's two products
//! and no third; otherwise `Dᵀ L_vx z` is the one product left. Rounding: the operator the
//! Krylov solver sees changes by `r − P' z`, the rounding error of the preconditioner's
//! products, of the order of that of computing `P' z` by FFT (unit test
//! `products_from_the_preconditioner_match_the_dense_jacobian`: both agree with the assembled
//! Jacobian to 1e-11 relative). The Newton residual itself is always evaluated in full.
//!
//! [`KrylovSystem::apply_preconditioned`]: crate::solve::krylov::KrylovSystem::apply_preconditioned
//!
//! ## Reference
//!
//! Triangular Toeplitz inverses: D. Bini, *Parallel solution of certain Toeplitz linear
//! systems*, SIAM J. Comput. 13 (1984). Woodbury: G. H. Golub and C. F. Van Loan, *Matrix
//! Computations*, 4th ed., §2.1.4.

use super::row_blocks::RowBlocks;
use crate::fft_operator::FftOperator;
use crate::halves;
use crate::lagrangian::{Matrix, Vector};
use crate::linalg::{block, set_block};
use crate::operator::Operator;
use crate::side::Side;
use crate::toeplitz::{TriangularToeplitz, Workspace};
use crate::weights::InverseWeights;

/// `P'⁻¹ = P⁻¹ − U K (E P⁻¹)` for `P' = P + Eᵀ H_e E` (Woodbury), `E` the extra row of `D`
/// (`e_j I` blocks), `H_e` its `L_vv`: `U = P⁻¹ Eᵀ` (blocks `u_j`), `K = (I + H_e E U)⁻¹ H_e`.
/// (`D_a U`, which the images need, is `V⁻¹ D_a⁻ᵀ Eᵀ`: blocks `L_vv⁻¹ ⋅ (D_a⁻ᵀ e)_j`, formed
/// where they are used rather than stored.)
pub(super) struct Correction<const D: usize> {
    u: Vec<Matrix<D>>,
    k: Matrix<D>,
}

/// `P'⁻¹` at one linearisation. Its products run in place in the workspace of the solve's
/// FFT operator and in the caller's vectors: it keeps no vectors of its own but the blocks.
pub(super) struct Preconditioner<'a, const D: usize> {
    /// The number of steps `N`.
    n: usize,
    side: Side,
    /// `h^{−α}`.
    scale: f64,
    /// `G`, the inverse of the lower-triangular GL Toeplitz matrix, order `N − 1`.
    inverse: TriangularToeplitz,
    /// `α`, whose weights `g_r` give `D_a⁻ᵀ e` in closed form ([`extra_solved`](Self::extra_solved)).
    alpha: f64,
    /// The Grünwald–Letnikov weights `w`, whose entries make the row of `D` outside the square
    /// block ([`extra`](Self::extra)).
    weights: &'a [f64],
    /// `L_vv⁻¹` at the interior nodes `1..N−1` (entry `j − 1`): one block while all are equal.
    vv_inverse: RowBlocks<D>,
    /// The extra row's term (module docs), when it can be formed.
    pub(super) correction: Option<Correction<D>>,
    /// Whether every `L_vv` block was inverted at the last [`update`](Self::update) (where
    /// one was not, the preconditioner holds a stand-in for it).
    all_inverted: bool,
    /// `H_e` of the last [`update_correction`](Self::update_correction): when no `L_vv`
    /// changed since (a kinetic term independent of `x`, `v` and `t`, as the pendulum's), the
    /// correction is still right and its `d²` products are not repeated.
    corrected_for: Option<Matrix<D>>,
}

/// The position of the extra row of `D` among the quadrature rows: the last for σ = −
/// (row `N`), the first for σ = + (row 0).
pub(super) fn extra_row(side: Side, n: usize) -> usize {
    match side {
        Side::Backward => n - 1,
        Side::Forward => 0,
    }
}

impl<'a, const D: usize> Preconditioner<'a, D> {
    /// For `velocity = Δ^α_σ` on `N ≥ 2` steps; `fft` is its FFT form, whose plans `G` shares
    /// (order `N + 1 ≥ N − 1`), so that both use one workspace and one set of twiddle tables.
    pub(super) fn new(velocity: &'a Operator, fft: &mut FftOperator) -> Self {
        let n = fft.n();
        // g_0..g_{N−2}, the first column of G (order N − 1).
        let side = velocity.side();
        let mut g = InverseWeights::new(velocity.alpha());
        let inverse = fft.with_same_plans_from(n - 1, |r| g.at(r));
        Preconditioner {
            n,
            side,
            scale: velocity.scale(),
            inverse,
            alpha: velocity.alpha(),
            weights: velocity.weights(),
            vv_inverse: RowBlocks::uniform(Matrix::<D>::identity(), n - 1),
            correction: None,
            all_inverted: true,
            corrected_for: None,
        }
    }

    /// `(D_a⁻ᵀ e)_p` in closed form (module docs), `−g_{N−1−p}` (σ = −) or `−g_{p+1}` (σ = +),
    /// for `p` in [`walk`](Self::walk)'s order, which asks for the weights `g_r` with `r`
    /// increasing: they are computed as they are read rather than kept (8 bytes a node).
    fn extra_solved(&self) -> impl FnMut(usize) -> f64 {
        let (n, side) = (self.n, self.side);
        let mut g = InverseWeights::new(self.alpha);
        move |p| match side {
            Side::Backward => -g.at(n - 1 - p),
            Side::Forward => -g.at(p + 1),
        }
    }

    /// `0..N−1`, decreasing for σ = − and increasing for σ = +: the order in which
    /// [`extra_solved`](Self::extra_solved) is read.
    fn walk(&self) -> impl Iterator<Item = usize> {
        let (m, backward) = (self.n - 1, self.side == Side::Backward);
        (0..m).map(move |i| if backward { m - 1 - i } else { i })
    }

    /// Entry `p = j − 1` of the row of `D` outside the square block `D_a`, on the interior
    /// columns: `e_j = h^{−α} w_{N−j}` for σ = − (row `N`), `e_j = −h^{−α} w_j` for σ = + (row 0).
    pub(super) fn extra(&self, p: usize) -> f64 {
        match self.side {
            Side::Backward => self.scale * self.weights[self.n - 1 - p],
            Side::Forward => -self.scale * self.weights[p + 1],
        }
    }

    /// The blocks at a new linearisation: `vv`, the `L_vv` blocks on the quadrature rows, the
    /// first of which is node `first_row`.
    pub(super) fn update(&mut self, vv: &RowBlocks<D>, first_row: usize, ws: &mut Workspace) {
        // Where an L_vv block cannot be inverted the preconditioner keeps the identity there:
        // it only has to be good, and the Krylov solver reports what it cannot solve.
        let mut changed = false;
        self.all_inverted = true;
        for j in 1..self.n {
            let vv = vv.get(j - first_row);
            let inv = vv.try_inverse().filter(|m| m.iter().all(|c| c.is_finite()));
            self.all_inverted &= inv.is_some();
            let size = vv.amax();
            let inv = inv.unwrap_or_else(|| {
                if size > 0.0 {
                    Matrix::<D>::identity() / size
                } else {
                    Matrix::<D>::identity()
                }
            });
            changed |= inv != *self.vv_inverse.get(j - 1);
            self.vv_inverse.set(j - 1, inv);
        }
        let h_e = *vv.get(extra_row(self.side, self.n));
        if changed || self.corrected_for != Some(h_e) {
            self.update_correction(&h_e, ws);
            self.corrected_for = Some(h_e);
        }
    }

    /// [`Correction`] at the current linearisation: `U = P⁻¹Eᵀ = D_a⁻¹ V⁻¹ (D_a⁻ᵀ Eᵀ)`, with
    /// `D_a⁻ᵀ Eᵀ` in closed form, so `d²` FFT products, each in place in the workspace.
    fn update_correction(&mut self, h_e: &Matrix<D>, ws: &mut Workspace) {
        let m = self.n - 1;
        let mut u = match self.correction.take() {
            Some(old) => old.u,
            None => vec![Matrix::<D>::zeros(); m],
        };
        let g_transposed = self.side == Side::Forward;
        let factor = -self.side.sign() / self.scale;
        for c in 0..D {
            for a in 0..D {
                let (vv_inverse, mut extra_solved) = (&self.vv_inverse, self.extra_solved());
                let input = |j| vv_inverse.get(j)[(a, c)] * extra_solved(j);
                match self.side {
                    Side::Backward => self.inverse.load_descending(ws, input),
                    Side::Forward => self.inverse.load(ws, input),
                }
                self.inverse.mul_loaded(g_transposed, ws);
                self.inverse.store(ws, |j, x| u[j][(a, c)] = x * factor);
            }
        }
        let mut eu = Matrix::<D>::zeros();
        for (p, uj) in u.iter().enumerate() {
            eu += uj * self.extra(p);
        }
        let k = (Matrix::<D>::identity() + h_e * eu)
            .try_inverse()
            .map(|inv| inv * h_e)
            .filter(|k| k.iter().all(|c| c.is_finite()));
        self.correction = k.map(|k| Correction { u, k });
    }

    /// Whether this is the exact inverse of the kinetic part `P'` at the last update: every
    /// `L_vv` block inverted and the extra row's term formed.
    pub(super) fn is_exact(&self) -> bool {
        self.all_inverted && self.correction.is_some()
    }

    /// `x ↦ Gᵀ x` (transpose) or `G x` in place on `x`, one real product per component.
    fn mul_inverse_in_place(&self, transpose: bool, x: &mut [f64], ws: &mut Workspace) {
        for a in 0..D {
            self.inverse.mul_strided_in_place(transpose, ws, x, (D, a));
        }
    }

    /// `z = P'⁻¹ r`, and `D_a z` into `image` if asked. With `D_a = −σ s A` (`A = T` for σ = −,
    /// `Tᵀ` for σ = +) and `A⁻¹ = G` or `Gᵀ`: `middle = s⁻² V⁻¹ A⁻ᵀ r`, `z = A⁻¹ middle`, and
    /// `D_a z = −σ s · middle`; then the Woodbury term. The middle vector lives in `z`.
    pub(super) fn apply(
        &self,
        r: &[f64],
        z: &mut [f64],
        mut image: Option<&mut [f64]>,
        ws: &mut Workspace,
    ) {
        let m = self.n - 1;
        let first_transposed = self.side == Side::Backward;
        z.copy_from_slice(r);
        self.mul_inverse_in_place(first_transposed, z, ws);
        let s2 = 1.0 / (self.scale * self.scale);
        let vv_inverse = &self.vv_inverse;
        halves::each((m, D), &mut z[..], |first, z| {
            for j in 0..z.len() / D {
                let middle = vv_inverse.get(first + j) * block::<D>(z, j) * s2;
                set_block(z, j, &middle);
            }
        });
        if let Some(image) = image.as_deref_mut() {
            let factor = -self.side.sign() * self.scale;
            halves::each((m, D), (&mut image[..], &z[..]), |_, (image, z)| {
                for (i, x) in image.iter_mut().zip(z) {
                    *i = x * factor;
                }
            });
        }
        self.mul_inverse_in_place(!first_transposed, z, ws);
        if let Some(corr) = &self.correction {
            let ez = halves::sum((m, D), &z[..], |first, z| {
                let mut ez = Vector::<D>::zeros();
                for p in 0..z.len() / D {
                    ez += block::<D>(z, p) * self.extra(first + p);
                }
                ez
            });
            let c = corr.k * ez;
            halves::each((m, D), &mut z[..], |first, z| {
                for j in 0..z.len() / D {
                    set_block(z, j, &(block::<D>(z, j) - corr.u[first + j] * c));
                }
            });
            if let Some(image) = image {
                let mut extra_solved = self.extra_solved();
                for j in self.walk() {
                    let du = self.vv_inverse.get(j) * extra_solved(j);
                    let v = block::<D>(image, j) - du * c;
                    set_block(image, j, &v);
                }
            }
        }
    }
}
