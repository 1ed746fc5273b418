//! The operators and rows of an embedding: which operator gives the velocity, which one the
//! direct scheme applies to the momenta, and which nodes carry each scheme's equations.

use super::{Embedding, EmbeddingKind, Scheme};
use crate::end_correction::Role;
use crate::grid::Grid;
use crate::halves;
use crate::operator::Operator;
use crate::side::Side;
use std::ops::RangeInclusive;

impl Embedding {
    /// The operator `Δ_σ` (or `Δ^α_σ`): the velocity is `V = −σ Δ_σ Q` on the quadrature rows.
    /// Built alone: the solvers take it from [`operators`](Self::operators), and the tests
    /// check that against this.
    #[cfg(test)]
    pub(crate) fn velocity_operator(&self, grid: &Grid) -> Operator {
        self.operator(self.side, grid, Role::Velocity)
    }

    /// The operator `Δ_{−σ}` (or `Δ^α_{−σ}`) that the direct scheme of every embedding but
    /// Gauss-FDEσ applies to `p` (with the momentum role's starting columns for the corrected
    /// Gauss-GLEσ), built alone: the solvers take it from [`operators`](Self::operators), and
    /// the tests check that against this.
    #[cfg(test)]
    pub(crate) fn adjoint_operator(&self, grid: &Grid) -> Operator {
        self.operator(self.side.opposite(), grid, Role::Momentum)
    }

    /// The operator `Δ_σ` (or `Δ^α_σ`) of the velocity `V = −σ Δ_σ Q` and the operator `Δ_{−σ}` (or
    /// `Δ^α_{−σ}`) that the direct scheme of every embedding but Gauss-FDEσ applies to `p`
    /// (with the momentum role's starting columns for the corrected Gauss-GLEσ), the two
    /// holding one copy of their weights (the same numbers on both sides): at `N = 10⁷` a copy
    /// is 80 MB, and a recurrence over them.
    ///
    /// The corrected forms' starting columns of the two are computed at once, on two threads
    /// with the `parallel` feature: at `N = 10⁷` each set takes seconds.
    pub(crate) fn operators(&self, grid: &Grid) -> (Operator, Operator) {
        let velocity = self.plain_operator(self.side, grid);
        let adjoint = velocity.on_side(self.side.opposite());
        halves::both(
            || self.with_columns(velocity, grid, Role::Velocity),
            || self.with_columns(adjoint, grid, Role::Momentum),
        )
    }

    /// Row `k` of the operator `B` that brings the momenta into row `k` of `scheme`'s residual,
    /// `f_k + Σ_m B[k, m] p_m`, as its entries `(m, B[k, m])`: `σ Δ_σ` for the direct
    /// Gauss-FDEσ scheme, `−σ Δ_{−σ}` for the direct scheme of the other three-point embeddings,
    /// `−σ Δ_σᵀ` for every variational scheme. `velocity` and `adjoint` are
    /// the velocity operator and the momenta's operator on the grid
    /// ([`operators`](Self::operators)).
    pub(crate) fn momentum_row(
        &self,
        scheme: Scheme,
        (velocity, adjoint): (&Operator, &Operator),
        k: usize,
    ) -> Vec<(usize, f64)> {
        let sigma = self.side.sign();
        match (scheme, self.kind) {
            (Scheme::Direct, EmbeddingKind::FiniteDifference) => velocity
                .row_entries(k)
                .map(|(m, c)| (m, sigma * c))
                .collect(),
            (Scheme::Direct, _) => adjoint
                .row_entries(k)
                .map(|(m, c)| (m, -sigma * c))
                .collect(),
            (Scheme::Variational, _) => velocity
                .column_entries(k)
                .map(|(m, c)| (m, -sigma * c))
                .collect(),
        }
    }

    /// The operator of `side` in `role`: the classical difference, the Grünwald–Letnikov
    /// operator, or that operator with the starting columns of `role` (the corrected form).
    #[cfg(test)]
    fn operator(&self, side: Side, grid: &Grid, role: Role) -> Operator {
        self.with_columns(self.plain_operator(side, grid), grid, role)
    }

    /// The operator of `side` without starting columns: the classical difference or the
    /// Grünwald–Letnikov operator.
    fn plain_operator(&self, side: Side, grid: &Grid) -> Operator {
        match self.kind {
            // The Caputo form's operators are Grünwald–Letnikov's: its velocity applies them to
            // the shifted curve (the discretisation does), and its direct scheme applies the
            // adjoint to the momenta as Gauss-GLEσ does.
            EmbeddingKind::GrunwaldLetnikov { alpha }
            | EmbeddingKind::Caputo { alpha }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { alpha }
            | EmbeddingKind::CorrectedCaputo { alpha } => {
                Operator::grunwald_letnikov(side, alpha, grid)
                    .expect("α was checked when the embedding was built")
            }
            _ => Operator::finite_difference(side, grid),
        }
    }

    /// `plain` with the starting columns of `role` where the embedding is corrected.
    fn with_columns(&self, plain: Operator, grid: &Grid, role: Role) -> Operator {
        match self.kind {
            // Starting columns need two nodes besides the one where the sums are cut.
            EmbeddingKind::CorrectedGrunwaldLetnikov { .. }
            | EmbeddingKind::CorrectedCaputo { .. }
                if grid.n() >= 2 =>
            {
                plain.with_end_columns(role)
            }
            _ => plain,
        }
    }

    /// The Gauss σ-quadrature rows `I_σ`: `1..=N` for σ = −, `0..=N−1` for σ = +.
    ///
    /// ```
    /// use varembed::{Embedding, EmbeddingKind, Side};
    /// assert_eq!(Embedding::finite_difference(Side::Backward).quadrature_rows(4), 1..=4);
    /// assert_eq!(Embedding::finite_difference(Side::Forward).quadrature_rows(4), 0..=3);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn quadrature_rows(&self, n: usize) -> RangeInclusive<usize> {
        match self.side {
            Side::Backward => 1..=n,
            Side::Forward => 0..=n - 1,
        }
    }

    /// The rows of the direct scheme (the table in [schemes](crate::guide::schemes)):
    /// Gauss-FDE− `2..=N`, Gauss-FDE+ `0..=N−2`, the coherent embeddings `1..=N−1`. Always
    /// `N − 1` rows (empty when `N = 1`).
    ///
    /// ```
    /// use varembed::{Embedding, Side};
    /// assert_eq!(Embedding::finite_difference(Side::Forward).direct_rows(4), 0..=2);
    /// assert_eq!(Embedding::asymmetric(Side::Forward).direct_rows(4), 1..=3);
    /// assert!(Embedding::asymmetric(Side::Forward).direct_rows(1).is_empty());
    /// ```
    #[allow(clippy::reversed_empty_ranges)] // an empty range is the right answer for N = 1
    pub fn direct_rows(&self, n: usize) -> RangeInclusive<usize> {
        match (self.kind, self.side) {
            (EmbeddingKind::FiniteDifference, Side::Backward) => 2..=n,
            (EmbeddingKind::FiniteDifference, Side::Forward) if n >= 2 => 0..=n - 2,
            (EmbeddingKind::FiniteDifference, Side::Forward) => 1..=0,
            _ => variational_rows(n),
        }
    }

    /// The nodes `k` of the equations of `scheme` on a grid of `n` steps: the direct rows
    /// above, or the interior nodes `1..=N−1` for the variational scheme.
    pub(crate) fn scheme_rows(&self, scheme: Scheme, n: usize) -> RangeInclusive<usize> {
        match scheme {
            Scheme::Direct => self.direct_rows(n),
            Scheme::Variational => variational_rows(n),
        }
    }
}

/// The rows of the variational scheme, `1..=N−1` (the interior nodes).
#[allow(clippy::reversed_empty_ranges)]
pub(crate) fn variational_rows(n: usize) -> RangeInclusive<usize> {
    if n >= 2 { 1..=n - 1 } else { 1..=0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two operators built together are those built one at a time (the momentum role's
    /// starting columns on the adjoint), and hold one copy of the weights.
    #[test]
    fn operators_built_together_share_their_weights() {
        let embeddings = |side| {
            [
                Embedding::finite_difference(side),
                Embedding::asymmetric(side),
                Embedding::grunwald_letnikov(side, 0.7).unwrap(),
                Embedding::caputo(side, 0.4).unwrap(),
                Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap(),
                Embedding::corrected_caputo(side, 0.8).unwrap(),
                Embedding::midpoint(),
            ]
        };
        for n in [1, 2, 9] {
            let grid = Grid::new(0.0, 1.0, n).unwrap();
            for side in [Side::Backward, Side::Forward] {
                for embedding in embeddings(side) {
                    let (velocity, adjoint) = embedding.operators(&grid);
                    assert_eq!(velocity, embedding.velocity_operator(&grid), "{embedding}");
                    assert_eq!(adjoint, embedding.adjoint_operator(&grid), "{embedding}");
                    let (v, a) = (velocity.weights(), adjoint.weights());
                    assert!(std::ptr::eq(v, a), "{embedding}: two copies");
                }
            }
        }
    }
}
