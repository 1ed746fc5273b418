//! The kinetic part of a fractional scheme's Jacobian, `K[k, j] = Σ_m B[k, m] L_vv(m) D[m, j]`,
//! by matrix products.
//!
//! Entry by entry it is a sum over `m` for each of the `N²` blocks: `O(N³ d²)` steps of block
//! arithmetic, which took 84 % of a dense fractional solve at `N = 800` (the LU the rest).
//! Written as `(B ⊗ I_d) G` with `G[m, j] = L_vv(m) D[m, j]`, it is, for each component `a`
//! of the rows, one matrix product `K_a = B G_a` (`G_a` the rows `a` of `G`'s blocks): the
//! same flops at the speed of a blocked GEMM (nalgebra's, through `matrixmultiply`), over only
//! the rows `m` where `G`'s columns are not zero (`D` is triangular with a few starting
//! columns: about half of them). The unknown columns go in panels, so that `D`'s columns,
//! `G_a` and `K_a` take `O(N · panel)` memory; `B` is kept whole, `N²` numbers: as much
//! again as the Jacobian's `(N d)²` for `d = 1`, freed before the factorisation.

use super::Discretisation;
use crate::embedding::Scheme;
use crate::lagrangian::{Lagrangian, Matrix};
use nalgebra::DMatrix;

/// Unknown nodes per panel of columns: wide enough for the GEMM to run at speed, narrow
/// enough that a panel's two matrices stay small beside the Jacobian.
pub(super) const PANEL: usize = 128;

impl<L: Lagrangian<D> + ?Sized, const D: usize> Discretisation<'_, L, D> {
    /// Hands `add(i, j − 1, K[rows[i], j])` for every row `i` of `scheme` and unknown node
    /// `j = 1..N−1`, with `vv[m]` the `L_vv` of quadrature node `m` (`None` off `I_σ`, where
    /// `B` does not reach).
    pub(super) fn add_kinetic_term(
        &self,
        scheme: Scheme,
        vv: &[Option<Matrix<D>>],
        add: &mut impl FnMut(usize, usize, &Matrix<D>),
    ) {
        let n = self.grid.n();
        let sigma = self.embedding.side().sign();
        let rows = self.rows(scheme);
        let operators = (&self.velocity, &self.adjoint);
        let mut b = DMatrix::<f64>::zeros(rows.clone().count(), n + 1);
        for (i, k) in rows.enumerate() {
            for (m, c) in self.embedding.momentum_row(scheme, operators, k) {
                debug_assert!(vv[m].is_some(), "B only reaches nodes of I_σ");
                b[(i, m)] += c;
            }
        }
        let panel = self.kinetic_panel.max(1);
        let mut block = Matrix::<D>::zeros();
        for start in (0..n - 1).step_by(panel) {
            let width = panel.min(n - 1 - start);
            // D[m, j] = −σ Δ_σ[m, j] on this panel's unknown columns (j = start + 1 + c), on the
            // rows B reads, read by columns: O(N) per column.
            let mut d = DMatrix::<f64>::zeros(n + 1, width);
            for c in 0..width {
                for (m, entry) in self.velocity.column_entries(start + 1 + c) {
                    if vv[m].is_some() {
                        d[(m, c)] -= sigma * entry;
                    }
                }
            }
            let reads = |m: &usize| (0..width).any(|c| d[(*m, c)] != 0.0);
            let (Some(lo), Some(last)) = ((0..=n).find(reads), (0..=n).rfind(reads)) else {
                continue;
            };
            let products: Vec<DMatrix<f64>> = (0..D)
                .map(|a| {
                    let g = DMatrix::from_fn(last + 1 - lo, width * D, |r, c| {
                        let m = lo + r;
                        vv[m].map_or(0.0, |vv| vv[(a, c % D)] * d[(m, c / D)])
                    });
                    b.columns(lo, last + 1 - lo) * g
                })
                .collect();
            for i in 0..b.nrows() {
                for jl in 0..width {
                    for (a, product) in products.iter().enumerate() {
                        for c in 0..D {
                            block[(a, c)] = product[(i, jl * D + c)];
                        }
                    }
                    add(i, start + jl, &block);
                }
            }
        }
    }
}
