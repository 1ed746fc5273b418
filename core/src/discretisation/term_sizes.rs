//! The size of the terms each row of a scheme sums, and the residual measured row by row against
//! it: what the comparison reports as the other scheme's residual.
//!
//! Every row is `r_k = F_k + Σ_m B[k, m] p_m`, a force plus momenta weighted by the scheme's
//! operator. Its terms have the size `s_k = |F_k|∞ + Σ_m |B[k, m]| |p_m|∞`, the row's own scale:
//! `|r_k|∞ / s_k` is what is left of the equation relative to what it balances. A max-norm of
//! the rows instead grows with the Lagrangian wherever `L` does along the run (the
//! Caldirola–Kanai oscillator `e^{γt}(½v² − ½ω²x²)`: its rows at `t` carry the factor `e^{γt}`,
//! so over `[0, 200]` the plain max-norm was 1.09e4 where over `[0, 20]` it was 1.7e-4), and it
//! changes with the scale of `L`; the relative one does neither.

use super::{Discretisation, Pointwise};
use crate::embedding::{EmbeddingKind, Scheme};
use crate::error::Result;
use crate::fft_operator::FftOperator;
use crate::lagrangian::{Lagrangian, Vector};

impl<L: Lagrangian<D> + ?Sized, const D: usize> Discretisation<'_, L, D> {
    /// `s_k` of the module docs for each row of `scheme` (in the order of
    /// [`rows`](Self::rows)).
    pub(crate) fn term_sizes(&self, scheme: Scheme, pw: &Pointwise<D>) -> Vec<f64> {
        let rows = self.rows(scheme);
        if self.embedding.is_symmetric() {
            let inv_h = 1.0 / self.grid.h();
            return rows
                .map(|k| {
                    let force = match scheme {
                        Scheme::Variational => 0.5 * (pw.f[k].amax() + pw.f_left[k + 1].amax()),
                        Scheme::Direct => pw.f_node[k].amax(),
                    };
                    force + (pw.p[k].amax() + pw.p[k + 1].amax()) * inv_h
                })
                .collect();
        }
        let size = |p: &Vector<D>| Vector::<1>::new(p.amax());
        // Σ_m |B[k, m]| |p_m|: the operator with its weights' moduli applied to the moduli, by
        // FFT where the residual itself is (the products are of nonnegative values, so the
        // transform's rounding is small against them).
        let fft = self.by_fft();
        let weighted: Vec<f64> = match (scheme, self.embedding.kind()) {
            (Scheme::Direct, kind) => {
                let op = match kind {
                    EmbeddingKind::FiniteDifference => self.velocity.absolute(),
                    _ => self.adjoint.absolute(),
                };
                let sizes: Vec<Vector<1>> = pw.p.iter().map(size).collect();
                let products = if fft {
                    FftOperator::new(&op).apply(&sizes).map(|mut products| {
                        op.add_end_columns(&sizes, &mut products);
                        products
                    })
                } else {
                    op.apply(&sizes)
                }
                .expect("p has one value per node");
                let first = op.first_row();
                rows.map(|k| products[k - first][0]).collect()
            }
            (Scheme::Variational, _) => {
                let op = self.velocity.absolute();
                let sizes: Vec<Vector<1>> = self
                    .embedding
                    .quadrature_rows(self.grid.n())
                    .map(|k| size(&pw.p[k]))
                    .collect();
                let products = if fft {
                    FftOperator::new(&op)
                        .apply_transpose(&sizes)
                        .map(|mut products| {
                            op.add_end_columns_transpose(&sizes, &mut products);
                            products
                        })
                } else {
                    op.apply_transpose(&sizes)
                }
                .expect("p has one value per quadrature row");
                rows.map(|j| products[j][0]).collect()
            }
        };
        self.rows(scheme)
            .zip(weighted)
            .map(|(k, w)| pw.f[k].amax() + w)
            .collect()
    }

    /// `max_k |r_k|∞ / s_k` over the rows of `scheme` at `Q`: the residual relative to the size
    /// of the terms of each row (0 on a row whose terms all vanish, as the row then does).
    pub(crate) fn relative_residual(&self, scheme: Scheme, q: &[Vector<D>]) -> Result<f64> {
        let pw = self.pointwise(q)?;
        let residual = self.residual_from(scheme, &pw);
        let sizes = self.term_sizes(scheme, &pw);
        Ok(residual
            .iter()
            .zip(sizes)
            .fold(0.0, |m, (r, s)| m.max(relative(r.amax(), s))))
    }
}

/// `r / s`, 0 when both vanish (a row whose terms are all zero is satisfied).
pub(crate) fn relative(r: f64, s: f64) -> f64 {
    if r == 0.0 { 0.0 } else { r / s }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::embedding::Embedding;
    use crate::grid::Grid;
    use crate::options::FFT_OPERATOR_THRESHOLD;
    use crate::side::Side;
    use crate::test_models::Mixed;

    /// The term sizes of every non-symmetric embedding and both schemes equal the sums
    /// `|F_k| + Σ_m |B[k, m]| |p_m|` over the entries of each row that the embedding lists
    /// (`momentum_row`, summed one by one), by the loops and by FFT.
    #[test]
    fn term_sizes_are_the_rows_entries_summed_in_modulus() {
        let n = FFT_OPERATOR_THRESHOLD + 9;
        let grid = Grid::new(0.0, 2.0, n).unwrap();
        let q: Vec<Vector<2>> = (0..=n)
            .map(|k| {
                let t = grid.t(k);
                Vector::<2>::new((3.0 * t).sin() + 0.2, (2.0 * t).cos() * t)
            })
            .collect();
        let embeddings = [Side::Backward, Side::Forward]
            .into_iter()
            .flat_map(|side| {
                [
                    Embedding::finite_difference(side),
                    Embedding::asymmetric(side),
                    Embedding::grunwald_letnikov(side, 0.6).unwrap(),
                    Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap(),
                ]
            });
        for embedding in embeddings {
            for fft_threshold in [FFT_OPERATOR_THRESHOLD, usize::MAX] {
                let mut disc = Discretisation::new(&Mixed, grid, embedding);
                disc.fft_threshold = fft_threshold;
                let pw = disc.pointwise(&q).unwrap();
                let operators = (
                    &embedding.velocity_operator(&grid),
                    &embedding.adjoint_operator(&grid),
                );
                for scheme in [Scheme::Direct, Scheme::Variational] {
                    let sizes = disc.term_sizes(scheme, &pw);
                    for (k, size) in disc.rows(scheme).zip(sizes) {
                        let oracle = pw.f[k].amax()
                            + embedding
                                .momentum_row(scheme, operators, k)
                                .into_iter()
                                .map(|(m, c)| c.abs() * pw.p[m].amax())
                                .sum::<f64>();
                        assert!(
                            (size - oracle).abs() <= 1e-12 * oracle,
                            "{embedding} {scheme:?} row {k}: {size} vs {oracle}"
                        );
                    }
                }
            }
        }
    }
}
