//! The global system of the symmetric embeddings (midpoint, trapezoidal): residual rows,
//! action, energy and Jacobian, from the interval values of the interval module.
//!
//! With `P_k`, `F_{u,k}`, `F_{w,k}` the momentum and forces of the interval `[t_{k−1}, t_k]`
//! and `f_k` the force at node `k` with the centred velocity `(Q_{k+1} − Q_{k−1})/(2h)`, the rows
//! `k = 1..=N−1` are ([schemes](crate::guide::schemes))
//!
//! ```text
//! variational:  ½ (F_{w,k} + F_{u,k+1}) − (P_{k+1} − P_k)/h     = (1/h) ∂S_h/∂Q_k
//! direct:       f_k                     − (P_{k+1} − P_k)/h
//! ```
//!
//! These are computed here from the interval values, by code separate from the step kernels
//! that solve the same equations one node at a time: the initial value problem's nodes zero
//! these rows (a test checks it), which ties the two together.

use super::{Discretisation, Pointwise};
use crate::embedding::{EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result};
use crate::interval::{Interval, IntervalJacobian, Rule, node_force, node_force_jacobian};
use crate::lagrangian::{Lagrangian, Matrix, Vector};

impl<L: Lagrangian<D> + ?Sized, const D: usize> Discretisation<'_, L, D> {
    /// The discrete Lagrangian of the embedding.
    fn rule(&self) -> Rule {
        match self.embedding.kind() {
            EmbeddingKind::Midpoint => Rule::Midpoint,
            _ => Rule::Trapezoidal,
        }
    }

    /// The interval `[t_{k−1}, t_k]` of `Q`, `k = 1..=N`.
    fn interval(&self, q: &[Vector<D>], k: usize) -> Interval<D> {
        Interval {
            u: q[k - 1],
            w: q[k],
            t_u: self.grid.t(k - 1),
            t_w: self.grid.t(k),
            h: self.grid.h(),
        }
    }

    /// The direct schemes' force at node `k` of `Q`, with its derivatives `[f_x, f_v]`.
    fn node_force(&self, q: &[Vector<D>], k: usize) -> (Vector<D>, [Matrix<D>; 2]) {
        let t = self.grid.t(k);
        node_force(
            self.lagrangian,
            &q[k - 1],
            &q[k],
            &q[k + 1],
            t,
            self.grid.h(),
        )
    }

    /// The interval values and the node forces of `Q` (see [`Pointwise`]).
    pub(super) fn symmetric_pointwise(&self, q: &[Vector<D>]) -> Result<Pointwise<D>> {
        self.check_curve(q)?;
        let (n, rule) = (self.grid.n(), self.rule());
        let zeros = vec![Vector::<D>::zeros(); n + 1];
        let mut pw = Pointwise {
            v: zeros.clone(),
            f: zeros.clone(),
            p: zeros.clone(),
            f_left: zeros.clone(),
            f_node: zeros,
        };
        let finite = |x: &Vector<D>| x.iter().all(|c| c.is_finite());
        for k in 1..=n {
            let interval = self.interval(q, k);
            let g = interval.gradient(self.lagrangian, rule);
            if ![g.momentum, g.force_left, g.force_right].iter().all(finite) {
                return Err(Error::NotFinite {
                    at: Location::Node(k),
                });
            }
            pw.v[k] = interval.velocity();
            pw.p[k] = g.momentum;
            pw.f[k] = g.force_right;
            pw.f_left[k] = g.force_left;
        }
        for k in 1..n {
            let (f, _) = self.node_force(q, k);
            if !finite(&f) {
                return Err(Error::NotFinite {
                    at: Location::Node(k),
                });
            }
            pw.f_node[k] = f;
        }
        Ok(pw)
    }

    /// The rows `1..=N−1` of `scheme` (module docs).
    pub(super) fn symmetric_residual(&self, scheme: Scheme, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        let inv_h = 1.0 / self.grid.h();
        self.rows(scheme)
            .map(|k| {
                let force = match scheme {
                    Scheme::Variational => (pw.f[k] + pw.f_left[k + 1]) * 0.5,
                    Scheme::Direct => pw.f_node[k],
                };
                force - (pw.p[k + 1] - pw.p[k]) * inv_h
            })
            .collect()
    }

    /// `S_h(Q) = Σ_k L_d(Q_{k−1}, Q_k)`.
    pub(super) fn symmetric_action(&self, q: &[Vector<D>]) -> Result<f64> {
        self.check_curve(q)?;
        let rule = self.rule();
        let mut s = 0.0;
        for k in 1..=self.grid.n() {
            let value = self
                .interval(q, k)
                .discrete_lagrangian(self.lagrangian, rule);
            if !value.is_finite() {
                return Err(Error::NotFinite {
                    at: Location::Node(k),
                });
            }
            s += value;
        }
        Ok(s)
    }

    /// The energy of each interval, `k = 1..=N` (at its midpoint, or the mean of its ends).
    pub(super) fn symmetric_energy(&self, q: &[Vector<D>]) -> Result<Vec<f64>> {
        self.check_curve(q)?;
        let rule = self.rule();
        Ok((1..=self.grid.n())
            .map(|k| self.interval(q, k).energy(self.lagrangian, rule))
            .collect())
    }

    /// The Jacobian of [`symmetric_residual`](Self::symmetric_residual) with respect to
    /// `Q_1..Q_{N−1}`, block by block (as `assemble_jacobian`): row `k` couples `Q_{k−1}`,
    /// `Q_k`, `Q_{k+1}` through the intervals `k` (`[Q_{k−1}, Q_k]`) and `k + 1`.
    pub(super) fn assemble_symmetric_jacobian(
        &self,
        scheme: Scheme,
        q: &[Vector<D>],
        mut add: impl FnMut(usize, usize, &Matrix<D>),
    ) {
        let (n, h, rule) = (self.grid.n(), self.grid.h(), self.rule());
        let inv_h = 1.0 / h;
        let jacobians: Vec<IntervalJacobian<D>> = (1..=n)
            .map(|k| {
                self.interval(q, k)
                    .gradient_and_jacobian(self.lagrangian, rule)
                    .1
            })
            .collect();
        // Interval k is entry k − 1.
        let interval = |k: usize| &jacobians[k - 1];
        for (i, k) in self.rows(scheme).enumerate() {
            let (before, after) = (interval(k), interval(k + 1));
            // ∂/∂Q_{k−1}, ∂/∂Q_k, ∂/∂Q_{k+1} of −(P_{k+1} − P_k)/h.
            let mut blocks = [
                before.momentum[0] * inv_h,
                (before.momentum[1] - after.momentum[0]) * inv_h,
                -after.momentum[1] * inv_h,
            ];
            match scheme {
                Scheme::Variational => {
                    blocks[0] += before.force_right[0] * 0.5;
                    blocks[1] += (before.force_right[1] + after.force_left[0]) * 0.5;
                    blocks[2] += after.force_left[1] * 0.5;
                }
                Scheme::Direct => {
                    let (_, derivatives) = self.node_force(q, k);
                    for (block, df) in blocks.iter_mut().zip(node_force_jacobian(&derivatives, h)) {
                        *block += df;
                    }
                }
            }
            for (j, block) in (k - 1..=k + 1).zip(&blocks) {
                if (1..n).contains(&j) {
                    add(i, j - 1, block);
                }
            }
        }
    }
}
