//! The residual rows of the Gauss-FDEσ embeddings (and their coherent asymmetric version) on a
//! whole curve of a run-time-dimension model, and the entries of their Jacobian: the
//! const-generic discretisation's rows and Jacobian blocks, entry for entry, on flat slices and
//! with the model's sparse second-derivative blocks.
//!
//! A curve is stored flat, node `k` at `q[k d..(k + 1) d]`. With `V = D Q`, `D = −σ Δ_σ`, and
//! `f = ∂L/∂x`, `p = ∂L/∂v` at the quadrature nodes `(Q_k, V_k, t_k)`, every row is
//! `r_k = f_k + Σ_m B[k, m] p_m` with `B = σ Δ_σ` (direct Gauss-FDEσ), `−σ Δ_{−σ}` (direct
//! asymmetric) or `Dᵀ` (variational); its Jacobian with respect to the interior nodes is
//! `∂r_k/∂Q_j = δ_kj L_xx + L_xv D[k, j] + Σ_m B[k, m] (δ_mj L_vx + L_vv D[m, j])`
//! ([schemes](crate::guide::schemes)).

use crate::discretisation::relative;
use crate::embedding::{Embedding, EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result};
use crate::grid::Grid;
use crate::operator::Operator;

use super::DynLagrangian;
use super::sparse::{SparseBlock, SparseHessian};

/// The values at the quadrature nodes of a curve, flat by node index `0..=N` (the node outside
/// `I_σ` holds zeros), and the residual rows, flat (row `i` is the equation of node
/// `rows.start() + i`).
pub(crate) struct CurveValues {
    pub(crate) v: Vec<f64>,
    pub(crate) f: Vec<f64>,
    pub(crate) p: Vec<f64>,
    pub(crate) r: Vec<f64>,
}

impl CurveValues {
    /// Zeroed values for `N + 1` nodes of dimension `d`.
    pub(crate) fn zeros(n: usize, d: usize) -> Self {
        let nodes = (n + 1) * d;
        CurveValues {
            v: vec![0.0; nodes],
            f: vec![0.0; nodes],
            p: vec![0.0; nodes],
            r: vec![0.0; n.saturating_sub(1) * d],
        }
    }
}

/// A block of the Jacobian entries: which second-derivative block, at which node, transposed
/// or not.
#[derive(Clone, Copy)]
enum Part {
    Xx,
    Xv,
    Vx,
    Vv,
}

/// A run-time-dimension model on a grid under a Gauss-FDEσ or asymmetric embedding.
pub(crate) struct DynRows<'a, L: ?Sized> {
    pub(crate) lagrangian: &'a L,
    pub(crate) grid: Grid,
    pub(crate) embedding: Embedding,
    pub(crate) scheme: Scheme,
    pub(crate) d: usize,
    /// `Δ_σ`.
    velocity: Operator,
    /// `Δ_{−σ}`.
    adjoint: Operator,
}

impl<'a, L: DynLagrangian + ?Sized> DynRows<'a, L> {
    /// The rows of `scheme`; [`Error::Unsupported`] for any embedding but Gauss-FDEσ and the
    /// asymmetric one.
    pub(crate) fn new(
        lagrangian: &'a L,
        grid: Grid,
        embedding: Embedding,
        scheme: Scheme,
    ) -> Result<Self> {
        if !matches!(
            embedding.kind(),
            EmbeddingKind::FiniteDifference | EmbeddingKind::Asymmetric
        ) {
            return Err(Error::Unsupported {
                operation: "a boundary value problem of a run-time-dimension model",
                embedding: embedding.to_string(),
            });
        }
        Ok(DynRows {
            lagrangian,
            grid,
            embedding,
            scheme,
            d: lagrangian.dimension(),
            velocity: embedding.velocity_operator(&grid),
            adjoint: embedding.adjoint_operator(&grid),
        })
    }

    /// `σ`.
    fn sigma(&self) -> f64 {
        self.embedding.side().sign()
    }

    /// The quadrature nodes `I_σ`.
    pub(crate) fn quadrature_rows(&self) -> std::ops::RangeInclusive<usize> {
        self.embedding.quadrature_rows(self.grid.n())
    }

    /// The nodes `k` of the equations; row `i` is node `rows().start() + i`.
    pub(crate) fn rows(&self) -> std::ops::RangeInclusive<usize> {
        self.embedding.scheme_rows(self.scheme, self.grid.n())
    }

    /// `V_k = −σ (Δ_σ Q)_k` into `v` (length `d`).
    pub(crate) fn velocity_at(&self, q: &[f64], k: usize, v: &mut [f64]) {
        let d = self.d;
        v.fill(0.0);
        for (j, c) in self.velocity.row_entries(k) {
            for (v, q) in v.iter_mut().zip(&q[j * d..(j + 1) * d]) {
                *v += q * c;
            }
        }
        let sign = -self.sigma();
        v.iter_mut().for_each(|v| *v *= sign);
    }

    /// `V`, `f`, `p` at the quadrature nodes of `q` and the residual rows, into `values`.
    /// [`Error::NotFinite`] at the first node whose force or momentum is not finite.
    pub(crate) fn evaluate(&self, q: &[f64], values: &mut CurveValues) -> Result<()> {
        let d = self.d;
        for k in self.quadrature_rows() {
            let at = k * d..(k + 1) * d;
            self.velocity_at(q, k, &mut values.v[at.clone()]);
            let (x, v, t) = (&q[at.clone()], &values.v[at.clone()], self.grid.t(k));
            self.lagrangian.force(x, v, t, &mut values.f[at.clone()]);
            self.lagrangian.momentum(x, v, t, &mut values.p[at.clone()]);
            let finite = values.f[at.clone()].iter().all(|c| c.is_finite())
                && values.p[at].iter().all(|c| c.is_finite());
            if !finite {
                return Err(Error::NotFinite {
                    at: Location::Node(k),
                });
            }
        }
        self.residual(values);
        Ok(())
    }

    /// The scale of the rows at `values`, as the const-generic discretisation's `row_scale`:
    /// the largest force a row reads plus `h^{−α}` times the largest momentum. The force at the
    /// end node outside the rows plays no part.
    pub(crate) fn scale(&self, values: &CurveValues) -> f64 {
        let d = self.d;
        let largest = |x: &[f64]| x.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let forces = self
            .rows()
            .fold(0.0f64, |m, k| m.max(largest(&values.f[k * d..(k + 1) * d])));
        let h_alpha = self.grid.h().powf(-self.embedding.alpha());
        forces + h_alpha * largest(&values.p)
    }

    /// The residual relative to the size of each row's terms, as the const-generic
    /// discretisation's `relative_residual`: `max_k |r_k|∞ / s_k`, `s_k = |f_k|∞ +
    /// Σ_m |B[k, m]| |p_m|∞`, at `values` (already evaluated).
    pub(crate) fn relative_residual(&self, values: &CurveValues) -> f64 {
        let d = self.d;
        let largest = |x: &[f64]| x.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let operators = (&self.velocity, &self.adjoint);
        self.rows()
            .enumerate()
            .map(|(i, k)| {
                let momenta: f64 = self
                    .embedding
                    .momentum_row(self.scheme, operators, k)
                    .into_iter()
                    .map(|(m, c)| c.abs() * largest(&values.p[m * d..(m + 1) * d]))
                    .sum();
                let size = largest(&values.f[k * d..(k + 1) * d]) + momenta;
                relative(largest(&values.r[i * d..(i + 1) * d]), size)
            })
            .fold(0.0, f64::max)
    }

    /// The residual rows from `f` and `p`, as the const-generic discretisation sums them.
    fn residual(&self, values: &mut CurveValues) {
        let d = self.d;
        let CurveValues { f, p, r, .. } = values;
        let mut acc = vec![0.0; d];
        for (i, k) in self.rows().enumerate() {
            acc.fill(0.0);
            // B p: the momenta's entries of row k (signs included; ±1 is exact, so this sums
            // what the const-generic discretisation sums).
            let operators = (&self.velocity, &self.adjoint);
            for (m, c) in self.embedding.momentum_row(self.scheme, operators, k) {
                for (acc, p) in acc.iter_mut().zip(&p[m * d..(m + 1) * d]) {
                    *acc += p * c;
                }
            }
            let row = &mut r[i * d..(i + 1) * d];
            for ((r, f), acc) in row.iter_mut().zip(&f[k * d..(k + 1) * d]).zip(&acc) {
                *r = f + acc;
            }
        }
    }

    /// The block contributions to row `k` of the Jacobian: `(node m, part, block column j,
    /// coefficient)` for `∂r_k/∂Q_j += coefficient · part(m)`, interior `j` only.
    fn contributions(&self, k: usize) -> Vec<(usize, Part, usize, f64)> {
        let (n, sigma) = (self.grid.n(), self.sigma());
        let unknown = |j: usize| (1..n).contains(&j);
        let d_row = |m: usize| {
            self.velocity
                .row_entries(m)
                .map(move |(j, c)| (j, -sigma * c))
        };
        let mut out = Vec::new();
        if unknown(k) {
            out.push((k, Part::Xx, k, 1.0));
        }
        for (j, c) in d_row(k) {
            if unknown(j) {
                out.push((k, Part::Xv, j, c));
            }
        }
        let operators = (&self.velocity, &self.adjoint);
        for (m, b) in self.embedding.momentum_row(self.scheme, operators, k) {
            if unknown(m) {
                out.push((m, Part::Vx, m, b));
            }
            for (j, c) in d_row(m) {
                if unknown(j) {
                    out.push((m, Part::Vv, j, b * c));
                }
            }
        }
        out
    }

    /// Calls `add(row, col, value)` for every entry of the Jacobian block row `i` (the
    /// equation of node `rows().start() + i`), global indices over the unknowns
    /// `Q_1..Q_{N−1}` (node `j`, component `b` is unknown `(j − 1) d + b`); an entry may come
    /// in several parts. `hessians` holds the Hessians at the quadrature nodes the row reads.
    pub(crate) fn jacobian_row(
        &self,
        i: usize,
        hessians: &mut HessianCache,
        q: &[f64],
        values: &CurveValues,
        mut add: impl FnMut(usize, usize, f64),
    ) {
        let d = self.d;
        let k = self.rows().start() + i;
        for (m, part, j, coefficient) in self.contributions(k) {
            let h = hessians.at(self, q, values, m);
            let (block, transposed): (&SparseBlock, bool) = match part {
                Part::Xx => (&h.xx, false),
                Part::Xv => (&h.xv, false),
                Part::Vx => (&h.xv, true),
                Part::Vv => (&h.vv, false),
            };
            let (row0, col0) = (i * d, (j - 1) * d);
            for &(a, b, value) in block.entries() {
                let (a, b) = if transposed { (b, a) } else { (a, b) };
                add(row0 + a, col0 + b, value * coefficient);
            }
        }
    }
}

/// The Hessians at the last few quadrature nodes read: the rows are visited in order and each
/// reads the nodes `k − 1 ..= k + 1`, so four slots hold every Hessian a row needs, `O(d)`
/// memory however long the curve.
pub(crate) struct HessianCache {
    slots: Vec<(Option<usize>, SparseHessian)>,
}

impl HessianCache {
    /// Empty slots for dimension `d`.
    pub(crate) fn new(d: usize) -> Self {
        HessianCache {
            slots: (0..4).map(|_| (None, SparseHessian::new(d))).collect(),
        }
    }

    /// The Hessian at quadrature node `m` of `q` (with its velocity from `values`).
    fn at<L: DynLagrangian + ?Sized>(
        &mut self,
        rows: &DynRows<'_, L>,
        q: &[f64],
        values: &CurveValues,
        m: usize,
    ) -> &SparseHessian {
        let slot = &mut self.slots[m % 4];
        if slot.0 != Some(m) {
            let d = rows.d;
            let at = m * d..(m + 1) * d;
            slot.1.clear();
            rows.lagrangian
                .hessian(&q[at.clone()], &values.v[at], rows.grid.t(m), &mut slot.1);
            slot.0 = Some(m);
        }
        &slot.1
    }

    /// Forgets every Hessian (the curve has changed).
    pub(crate) fn invalidate(&mut self) {
        self.slots.iter_mut().for_each(|s| s.0 = None);
    }
}
