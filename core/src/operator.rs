//! The discrete operators `Δ_±` and `Δ^α_±` of the paper, with `apply` and `apply_transpose`.
//!
//! `Δ_− Q_k = (Q_k − Q_{k−1})/h` (`k = 1..=N`), `Δ_+ Q_k = (Q_k − Q_{k+1})/h` (`k = 0..=N−1`),
//! `Δ^α_− Q_k = h^{−α} Σ_{r=0}^{k} α_r Q_{k−r}` (`k = 1..=N`) and
//! `Δ^α_+ Q_k = h^{−α} Σ_{r=0}^{N−k} α_r Q_{k+r}` (`k = 0..=N−1`). All four are one formula,
//! `h^{−α} Σ_r w_r Q_{k ∓ r}`, with `w = (1, −1)` for the classical operators and the
//! Grünwald–Letnikov weights for the fractional ones; the classical operator is stored with two
//! weights so that applying it costs `O(N)`.
//!
//! Values "on the rows" (the result of `apply`, the argument of `apply_transpose`) are stored
//! by position: entry `i` belongs to row `k = i + first_row`.

use crate::end_correction::{Role, columns};
use crate::error::{Error, Result, check_len};
use crate::grid::Grid;
use crate::lagrangian::Vector;
use crate::side::Side;
use crate::weights::grunwald_letnikov;
use std::ops::RangeInclusive;
use std::sync::Arc;

/// `Δ_σ` or `Δ^α_σ` on a grid of `N` steps: an `N × (N + 1)` matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Operator {
    side: Side,
    alpha: f64,
    n: usize,
    scale: f64,
    /// Shared between the two operators of a discretisation where they are equal (the
    /// fractional ones: `N + 1` numbers each).
    weights: Arc<[f64]>,
    /// Columns added next to the node where the sums are cut (the corrected Gauss-GLEσ's
    /// starting weights, `end_correction`): `(node, weights)`, the weight of row `k` at
    /// `weights[distance of k from that node − 1]`, without the factor `h^{−α}`. Empty for
    /// the paper's operators.
    columns: Vec<(usize, Vec<f64>)>,
}

impl Operator {
    /// The classical finite difference `Δ_σ` on `grid`.
    pub fn finite_difference(side: Side, grid: &Grid) -> Self {
        Operator {
            side,
            alpha: 1.0,
            n: grid.n(),
            scale: 1.0 / grid.h(),
            weights: Arc::new([1.0, -1.0]),
            columns: Vec::new(),
        }
    }

    /// The Grünwald–Letnikov operator `Δ^α_σ` on `grid` (`0 < α ≤ 1`).
    pub fn grunwald_letnikov(side: Side, alpha: f64, grid: &Grid) -> Result<Self> {
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(Error::AlphaOutOfRange { alpha });
        }
        Ok(Operator {
            side,
            alpha,
            n: grid.n(),
            scale: grid.h().powf(-alpha),
            weights: grunwald_letnikov(alpha, grid.n() + 1).into(),
            columns: Vec::new(),
        })
    }

    /// The same operator with the two starting columns of `role` (see `end_correction`); on a
    /// grid of at least two steps.
    pub(crate) fn with_end_columns(mut self, role: Role) -> Self {
        let n = self.n;
        assert!(n >= 2, "starting columns need two nodes besides the end");
        let node = |distance: usize| match self.side {
            Side::Backward => distance,
            Side::Forward => n - distance,
        };
        let [first, second] = role.distances().map(node);
        // The operator's own weights: those the columns correct (only a Grünwald–Letnikov
        // operator is ever corrected).
        debug_assert!(crate::weights::are_grunwald_letnikov(
            &self.weights,
            self.alpha
        ));
        let [a, b] = columns(role, self.alpha, &self.weights);
        self.columns = vec![(first, a), (second, b)];
        self
    }

    /// Whether the operator carries starting columns (the corrected Gauss-GLEσ's).
    pub(crate) fn has_end_columns(&self) -> bool {
        !self.columns.is_empty()
    }

    /// The nodes of the starting columns, in the order
    /// [`column_entries_in_row`](Self::column_entries_in_row) lists their entries.
    pub(crate) fn end_column_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        self.columns.iter().map(|(node, _)| *node)
    }

    /// Adds the starting columns' part of `Δ Q` to `out` (`N` values on the rows): what a
    /// product of the Toeplitz part alone (by FFT) leaves out.
    pub(crate) fn add_end_columns<const D: usize>(&self, q: &[Vector<D>], out: &mut [Vector<D>]) {
        for (i, k) in self.rows().enumerate() {
            for (node, c) in self.column_entries_in_row(k) {
                out[i] += q[node] * c;
            }
        }
    }

    /// Adds the starting columns' part of `Δᵀ W` to `out` (`N + 1` nodes), as
    /// [`add_end_columns`](Self::add_end_columns) for the transpose.
    pub(crate) fn add_end_columns_transpose<const D: usize>(
        &self,
        w: &[Vector<D>],
        out: &mut [Vector<D>],
    ) {
        for (i, k) in self.rows().enumerate() {
            for (node, c) in self.column_entries_in_row(k) {
                out[node] += w[i] * c;
            }
        }
    }

    /// Row `k`'s distance from the node where the sums are cut.
    fn distance(&self, k: usize) -> usize {
        match self.side {
            Side::Backward => k,
            Side::Forward => self.n - k,
        }
    }

    /// The starting columns' entries `(node, M[k, node])` in row `k` (`k ≤ N`); none in a
    /// row at distance 0, which no corrected operator has among its rows.
    pub(crate) fn column_entries_in_row(
        &self,
        k: usize,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        let distance = if k > self.n { 0 } else { self.distance(k) };
        self.columns
            .iter()
            .filter(move |_| distance >= 1)
            .map(move |(node, weights)| (*node, self.scale * weights[distance - 1]))
    }

    /// Which side σ.
    pub fn side(&self) -> Side {
        self.side
    }
    /// The order α (1 for the classical operators).
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// The factor `h^{−α}`.
    pub fn scale(&self) -> f64 {
        self.scale
    }
    /// The weights `w_r` (`1, −1` for the classical operators).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The operator of the same weights, `α` and grid on `side`, holding the same copy of the
    /// weights, without starting columns.
    pub(crate) fn on_side(&self, side: Side) -> Operator {
        Operator {
            side,
            alpha: self.alpha,
            n: self.n,
            scale: self.scale,
            weights: Arc::clone(&self.weights),
            columns: Vec::new(),
        }
    }

    /// The rows `k` on which the operator is defined: `1..=N` for σ = −, `0..=N−1` for σ = +.
    pub fn rows(&self) -> RangeInclusive<usize> {
        match self.side {
            Side::Backward => 1..=self.n,
            Side::Forward => 0..=self.n - 1,
        }
    }
    /// The first row (`1` for σ = −, `0` for σ = +).
    pub fn first_row(&self) -> usize {
        *self.rows().start()
    }

    /// Nonzero entries `(j, M[k, j])` of row `k` (a node index in `0..=N`, not necessarily one
    /// of [`rows`](Self::rows): the sum is cut at the grid's ends; empty when `k > N`). A
    /// corrected operator lists its starting columns' entries after the plain ones (a node
    /// may then appear twice: the entries add).
    pub fn row_entries(&self, k: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let reach = match self.side {
            Side::Backward => k,
            Side::Forward => self.n.saturating_sub(k),
        };
        let len = if k > self.n {
            0
        } else {
            self.weights.len().min(reach + 1)
        };
        let plain = self.weights[..len].iter().enumerate().map(move |(r, w)| {
            let j = match self.side {
                Side::Backward => k - r,
                Side::Forward => k + r,
            };
            (j, self.scale * w)
        });
        plain.chain(self.column_entries_in_row(k))
    }

    /// Nonzero entries `(k, M[k, j])` of column `j` (`j` in `0..=N`), over the rows `k` of
    /// [`rows`](Self::rows): what `apply_transpose` sums. A starting column's entries follow
    /// the plain ones (a row may then appear twice: the entries add).
    pub fn column_entries(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let rows = self.rows();
        let (first, last) = (*rows.start(), *rows.end());
        let len = self.weights.len();
        let (lo, hi) = match self.side {
            // M[k, j] = s w_{k−j} for k ≥ j.
            Side::Backward => (j.max(first), (j + len - 1).min(last)),
            // M[k, j] = s w_{j−k} for k ≤ j.
            Side::Forward => ((j + 1).saturating_sub(len).max(first), j.min(last)),
        };
        let plain = (lo..=hi).map(move |k| {
            let r = k.abs_diff(j);
            (k, self.scale * self.weights[r])
        });
        let corrections = self
            .columns
            .iter()
            .filter(move |(node, _)| *node == j)
            .flat_map(move |(_, weights)| {
                self.rows()
                    .filter(|&k| self.distance(k) >= 1)
                    .map(move |k| (k, self.scale * weights[self.distance(k) - 1]))
            });
        plain.chain(corrections)
    }

    /// The same operator with every weight replaced by its modulus: its product with the
    /// moduli of a curve's values bounds the size of every term a row sums.
    pub(crate) fn absolute(&self) -> Operator {
        Operator {
            weights: self.weights.iter().map(|w| w.abs()).collect(),
            columns: self
                .columns
                .iter()
                .map(|(node, c)| (*node, c.iter().map(|w| w.abs()).collect()))
                .collect(),
            ..self.clone()
        }
    }

    /// `(Δ Q)_k` for one row `k` (the same cut-off as [`row_entries`](Self::row_entries));
    /// `q` holds the `N + 1` nodes.
    pub(crate) fn apply_row<const D: usize>(&self, q: &[Vector<D>], k: usize) -> Vector<D> {
        let mut acc = Vector::<D>::zeros();
        for (j, c) in self.row_entries(k) {
            acc += q[j] * c;
        }
        acc
    }

    /// `Δ Q`: `q` has `N + 1` nodes, the result `N` values (entry `i` is row `i + first_row`).
    pub fn apply<const D: usize>(&self, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        check_len("curve", self.n + 1, q.len())?;
        Ok(self.rows().map(|k| self.apply_row(q, k)).collect())
    }

    /// `Δᵀ W`: `w` has `N` values on the rows, the result `N + 1` nodes.
    pub fn apply_transpose<const D: usize>(&self, w: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        check_len("values on the rows", self.n, w.len())?;
        let mut out = vec![Vector::<D>::zeros(); self.n + 1];
        for (i, k) in self.rows().enumerate() {
            for (j, c) in self.row_entries(k) {
                out[j] += w[i] * c;
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense<const D: usize>(op: &Operator, n: usize) -> Vec<Vec<f64>> {
        let mut m = vec![vec![0.0; n + 1]; n];
        for (i, k) in op.rows().enumerate() {
            for (j, c) in op.row_entries(k) {
                m[i][j] += c;
            }
        }
        m
    }

    #[test]
    fn classical_operators_are_the_paper_differences() {
        let q: Vec<Vector<1>> = [1.0, 4.0, 9.0, 16.0]
            .iter()
            .map(|&x| Vector::<1>::new(x))
            .collect();
        let grid = Grid::new(0.0, 1.5, 3).unwrap(); // h = 0.5
        let minus = Operator::finite_difference(Side::Backward, &grid)
            .apply(&q)
            .unwrap();
        let plus = Operator::finite_difference(Side::Forward, &grid)
            .apply(&q)
            .unwrap();
        assert_eq!(
            minus.iter().map(|v| v[0]).collect::<Vec<_>>(),
            vec![6.0, 10.0, 14.0]
        );
        assert_eq!(
            plus.iter().map(|v| v[0]).collect::<Vec<_>>(),
            vec![-6.0, -10.0, -14.0]
        );
    }

    #[test]
    fn fractional_at_alpha_one_is_classical_and_transpose_is_adjoint() {
        let n = 7;
        let grid = Grid::new(0.0, 2.1, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let gl = Operator::grunwald_letnikov(side, 1.0, &grid).unwrap();
            let fd = Operator::finite_difference(side, &grid);
            assert_eq!(dense::<1>(&gl, n), dense::<1>(&fd, n));
            let op = Operator::grunwald_letnikov(side, 0.4, &grid).unwrap();
            assert_eq!(op.row_entries(n + 1).count(), 0);
            let q: Vec<Vector<2>> = (0..=n)
                .map(|k| Vector::<2>::new(k as f64, (k * k) as f64 - 3.0))
                .collect();
            let w: Vec<Vector<2>> = (0..n)
                .map(|i| Vector::<2>::new((i as f64).sin(), 1.0 / (1.0 + i as f64)))
                .collect();
            // <Δq, w> = <q, Δᵀw>
            let lhs: f64 = op
                .apply(&q)
                .unwrap()
                .iter()
                .zip(&w)
                .map(|(a, b)| a.dot(b))
                .sum();
            let rhs: f64 = q
                .iter()
                .zip(op.apply_transpose(&w).unwrap())
                .map(|(a, b)| a.dot(&b))
                .sum();
            assert!(
                (lhs - rhs).abs() <= 1e-12 * lhs.abs().max(1.0),
                "{lhs} vs {rhs}"
            );
        }
    }

    /// A corrected operator's rows and columns list the same matrix, which is the plain
    /// operator plus the two starting columns at the nodes next to where its sums are cut
    /// (σ = + the mirror image of σ = −), with `h^{−α}` on every entry.
    #[test]
    fn end_columns_add_two_columns_seen_alike_by_rows_and_columns() {
        let n = 9;
        let grid = Grid::new(0.0, 0.9, n).unwrap();
        let alpha = 0.55;
        for role in [Role::Velocity, Role::Momentum] {
            let weights = columns(role, alpha, &grunwald_letnikov(alpha, n + 1));
            for side in [Side::Backward, Side::Forward] {
                let plain = Operator::grunwald_letnikov(side, alpha, &grid).unwrap();
                let corrected = plain.clone().with_end_columns(role);
                assert!(corrected.has_end_columns() && !plain.has_end_columns());
                let (p, c) = (dense::<1>(&plain, n), dense::<1>(&corrected, n));
                let mut from_columns = vec![vec![0.0; n + 1]; n];
                let first = corrected.first_row();
                for j in 0..=n {
                    for (k, value) in corrected.column_entries(j) {
                        from_columns[k - first][j] += value;
                    }
                }
                for (i, k) in corrected.rows().enumerate() {
                    let distance = match side {
                        Side::Backward => k,
                        Side::Forward => n - k,
                    };
                    for j in 0..=n {
                        let d = match side {
                            Side::Backward => j,
                            Side::Forward => n - j,
                        };
                        let slot = role.distances().iter().position(|&x| x == d);
                        let added = slot.map_or(0.0, |s| plain.scale() * weights[s][distance - 1]);
                        assert!(
                            (c[i][j] - p[i][j] - added).abs() < 1e-13,
                            "{role:?} {side:?}"
                        );
                        assert!((from_columns[i][j] - c[i][j]).abs() < 1e-13);
                    }
                }
            }
        }
    }

    #[test]
    fn wrong_lengths_and_alpha_are_errors() {
        let grid = Grid::new(0.0, 0.3, 3).unwrap();
        let op = Operator::finite_difference(Side::Backward, &grid);
        assert!(matches!(
            op.apply(&[Vector::<1>::zeros(); 3]),
            Err(Error::WrongLength {
                expected: 4,
                found: 3,
                ..
            })
        ));
        assert!(matches!(
            op.apply_transpose(&[Vector::<1>::zeros(); 4]),
            Err(Error::WrongLength { .. })
        ));
        for alpha in [0.0, -0.5, 1.5, f64::NAN] {
            assert!(matches!(
                Operator::grunwald_letnikov(Side::Forward, alpha, &grid),
                Err(Error::AlphaOutOfRange { .. })
            ));
        }
    }
}
