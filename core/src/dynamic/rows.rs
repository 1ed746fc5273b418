//! The residual rows of the classical embeddings on a whole curve of a run-time-dimension
//! model, and the entries of their Jacobian: the const-generic discretisation's rows and
//! Jacobian blocks, entry for entry, on flat slices and with the model's sparse
//! second-derivative blocks. This module holds Gauss-FDEσ and its coherent asymmetric
//! version; the symmetric embeddings (midpoint, trapezoidal), whose rows read interval values,
//! are in [`symmetric`].
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
use crate::interval::Rule;
use crate::operator::Operator;

use super::DynLagrangian;
use super::sparse::{SparseBlock, SparseForceJacobian, SparseHessian};

/// The values at the quadrature nodes of a curve, flat by node index `0..=N` (the node outside
/// `I_σ` holds zeros), and the residual rows, flat (row `i` is the equation of node
/// `rows.start() + i`). For the symmetric embeddings entry `k ≥ 1` of `v`, `p` and `f` holds
/// interval `k`'s velocity, momentum `P_k` and force `F_{w,k}`, `f_left` its `F_{u,k}`, and
/// `f_node` the direct scheme's force at node `k` with the centred velocity (the const-generic
/// `Pointwise`); the other embeddings leave those two empty.
pub(crate) struct CurveValues {
    pub(crate) v: Vec<f64>,
    pub(crate) f: Vec<f64>,
    pub(crate) p: Vec<f64>,
    pub(crate) f_left: Vec<f64>,
    pub(crate) f_node: Vec<f64>,
    pub(crate) r: Vec<f64>,
}

/// A point at which the rows evaluate the model, and so a Hessian they read.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Point {
    /// Quadrature node `k` with its velocity `V_k` (Gauss-FDEσ, asymmetric).
    Node(usize),
    /// The midpoint of interval `k`, `[Q_{k−1}, Q_k]`, with its velocity (midpoint rule).
    Mid(usize),
    /// The left end `Q_{k−1}` of interval `k` with its velocity, at `t_{k−1}` (trapezoidal).
    Left(usize),
    /// The right end `Q_k` of interval `k` with its velocity, at `t_k` (trapezoidal).
    Right(usize),
    /// Node `k` with the centred velocity `(Q_{k+1} − Q_{k−1})/(2h)` (the symmetric
    /// embeddings' direct scheme).
    Centred(usize),
}

impl Point {
    /// A number that differs between the points a few consecutive rows read: the Hessian
    /// cache's slot is this modulo its size.
    fn key(self) -> usize {
        match self {
            Point::Node(k) => k,
            Point::Mid(k) | Point::Left(k) => 3 * k,
            Point::Right(k) => 3 * k + 1,
            Point::Centred(k) => 3 * k + 2,
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
    /// The discrete Lagrangian of a symmetric embedding; `None` for the others.
    pub(crate) rule: Option<Rule>,
}

impl<'a, L: DynLagrangian + ?Sized> DynRows<'a, L> {
    /// The rows of `scheme`; [`Error::Unsupported`] for the fractional and the one-step
    /// (Gauss–Legendre) embeddings.
    pub(crate) fn new(
        lagrangian: &'a L,
        grid: Grid,
        embedding: Embedding,
        scheme: Scheme,
    ) -> Result<Self> {
        let rule = match embedding.kind() {
            EmbeddingKind::FiniteDifference | EmbeddingKind::Asymmetric => None,
            EmbeddingKind::Midpoint => Some(Rule::Midpoint),
            EmbeddingKind::Trapezoidal => Some(Rule::Trapezoidal),
            _ => {
                return Err(Error::Unsupported {
                    operation: "a boundary value problem of a run-time-dimension model",
                    embedding: embedding.to_string(),
                });
            }
        };
        let (velocity, adjoint) = embedding.operators(&grid);
        Ok(DynRows {
            rule,
            lagrangian,
            grid,
            embedding,
            scheme,
            d: lagrangian.dimension(),
            velocity,
            adjoint,
        })
    }

    /// Zeroed values for this curve's `N + 1` nodes (with the symmetric embeddings' interval
    /// forces only where they are read).
    pub(crate) fn zero_values(&self) -> CurveValues {
        let (n, d) = (self.grid.n(), self.d);
        let nodes = (n + 1) * d;
        let symmetric = if self.rule.is_some() { nodes } else { 0 };
        CurveValues {
            v: vec![0.0; nodes],
            f: vec![0.0; nodes],
            p: vec![0.0; nodes],
            f_left: vec![0.0; symmetric],
            f_node: vec![0.0; symmetric],
            r: vec![0.0; n.saturating_sub(1) * d],
        }
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
        if let Some(rule) = self.rule {
            return self.evaluate_symmetric(rule, q, values);
        }
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

    /// The energy the comparison reports, at `values` (already evaluated): `E_k = V_k·p_k − L`
    /// at the quadrature nodes, or each interval's energy for the symmetric embeddings.
    pub(crate) fn energies(&self, q: &[f64], values: &CurveValues) -> Vec<f64> {
        if let Some(rule) = self.rule {
            return self.symmetric_energies(rule, q, values);
        }
        let d = self.d;
        self.quadrature_rows()
            .map(|k| {
                let at = k * d..(k + 1) * d;
                let (x, v) = (&q[at.clone()], &values.v[at]);
                self.lagrangian.energy(x, v, self.grid.t(k))
            })
            .collect()
    }

    /// The scale of the rows at `values`, as the const-generic discretisation's `row_scale`:
    /// the largest force a row reads plus `h^{−α}` times the largest momentum. The force at the
    /// end node outside the rows plays no part.
    pub(crate) fn scale(&self, values: &CurveValues) -> f64 {
        let d = self.d;
        let forces = if self.rule.is_some() {
            self.symmetric_forces(values)
        } else {
            self.rows()
                .fold(0.0f64, |m, k| m.max(largest(&values.f[k * d..(k + 1) * d])))
        };
        let h_alpha = self.grid.h().powf(-self.embedding.alpha());
        forces + h_alpha * largest(&values.p)
    }

    /// The residual relative to the size of each row's terms, as the const-generic
    /// discretisation's `relative_residual`: `max_k |r_k|∞ / s_k`, `s_k = |f_k|∞ +
    /// Σ_m |B[k, m]| |p_m|∞`, at `values` (already evaluated).
    pub(crate) fn relative_residual(&self, values: &CurveValues) -> f64 {
        if self.rule.is_some() {
            return self.symmetric_relative_residual(values);
        }
        let d = self.d;
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

    /// The block contributions to row `k` of the Jacobian: `(point m, part, block column j,
    /// coefficient)` for `∂r_k/∂Q_j += coefficient · part(m)`, interior `j` only.
    fn contributions(&self, k: usize) -> Vec<(Point, Part, usize, f64)> {
        if let Some(rule) = self.rule {
            return self.symmetric_contributions(rule, k);
        }
        let (n, sigma) = (self.grid.n(), self.sigma());
        let unknown = |j: usize| (1..n).contains(&j);
        let d_row = |m: usize| {
            self.velocity
                .row_entries(m)
                .map(move |(j, c)| (j, -sigma * c))
        };
        let mut out = Vec::new();
        let node = Point::Node(k);
        if unknown(k) {
            out.push((node, Part::Xx, k, 1.0));
        }
        for (j, c) in d_row(k) {
            if unknown(j) {
                out.push((node, Part::Xv, j, c));
            }
        }
        let operators = (&self.velocity, &self.adjoint);
        for (m, b) in self.embedding.momentum_row(self.scheme, operators, k) {
            if unknown(m) {
                out.push((Point::Node(m), Part::Vx, m, b));
            }
            for (j, c) in d_row(m) {
                if unknown(j) {
                    out.push((Point::Node(m), Part::Vv, j, b * c));
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
            let (h, force) = hessians.at(self, q, values, m);
            // The force's derivatives ∂f/∂x, ∂f/∂v are L_xx, L_xv and a generalised force's
            // blocks; the momentum's are L's alone.
            let (block, extra, transposed): (&SparseBlock, Option<&SparseBlock>, bool) = match part
            {
                Part::Xx => (&h.xx, force.map(|f| &f.x), false),
                Part::Xv => (&h.xv, force.map(|f| &f.v), false),
                Part::Vx => (&h.xv, None, true),
                Part::Vv => (&h.vv, None, false),
            };
            let (row0, col0) = (i * d, (j - 1) * d);
            for &(a, b, value) in block.entries() {
                let (a, b) = if transposed { (b, a) } else { (a, b) };
                add(row0 + a, col0 + b, value * coefficient);
            }
            for &(a, b, value) in extra.map_or(&[][..], |e| e.entries()) {
                add(row0 + a, col0 + b, value * coefficient);
            }
        }
    }
}

/// The largest modulus in `x`.
fn largest(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, c| m.max(c.abs()))
}

/// How many Hessians the cache holds: the rows are visited in order and each reads at most five
/// points of consecutive [`Point::key`]s (the trapezoidal rule's direct row: both ends of its
/// two intervals and the centred node), so eight slots hold every Hessian a row needs and the
/// ones the next row shares with it.
const SLOTS: usize = 8;

/// The Hessians (and a generalised force's Jacobians) at the last few points read, `O(d)`
/// memory however long the curve.
pub(crate) struct HessianCache {
    slots: Vec<(Option<Point>, SparseHessian, SparseForceJacobian)>,
    /// The position and velocity of the point being evaluated.
    x: Vec<f64>,
    v: Vec<f64>,
}

impl HessianCache {
    /// Empty slots for dimension `d`.
    pub(crate) fn new(d: usize) -> Self {
        HessianCache {
            slots: (0..SLOTS)
                .map(|_| (None, SparseHessian::new(d), SparseForceJacobian::new(d)))
                .collect(),
            x: vec![0.0; d],
            v: vec![0.0; d],
        }
    }

    /// The Hessian at `point` of `q` (with the velocities in `values`), and a generalised
    /// force's Jacobian there when the model is forced.
    fn at<L: DynLagrangian + ?Sized>(
        &mut self,
        rows: &DynRows<'_, L>,
        q: &[f64],
        values: &CurveValues,
        point: Point,
    ) -> (&SparseHessian, Option<&SparseForceJacobian>) {
        let forced = rows.lagrangian.is_forced();
        let slot = &mut self.slots[point.key() % SLOTS];
        if slot.0 != Some(point) {
            let t = rows.point(q, values, point, (&mut self.x, &mut self.v));
            slot.1.clear();
            rows.lagrangian.hessian(&self.x, &self.v, t, &mut slot.1);
            if forced {
                slot.2.clear();
                rows.lagrangian
                    .force_jacobian(&self.x, &self.v, t, &mut slot.2);
            }
            slot.0 = Some(point);
        }
        (&slot.1, forced.then_some(&slot.2))
    }

    /// Forgets every Hessian (the curve has changed).
    pub(crate) fn invalidate(&mut self) {
        self.slots.iter_mut().for_each(|s| s.0 = None);
    }
}

mod symmetric;

#[cfg(test)]
mod tests;
