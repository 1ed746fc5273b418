//! The formulas of [`NodeRule`] over flat slices, written once for both paths: the
//! const-generic [`NodeValues`](super::NodeValues) (through an adapter of its
//! [`Lagrangian<D>`](crate::Lagrangian)), the run-time-dimension node values and the observer of
//! a run-time-dimension run (through an adapter of its
//! [`DynLagrangian`](crate::DynLagrangian)).
//!
//! Node `k` reads the nodes `Q_j` with `|j − k| ≤ 2` (`k − 1`, `k`, `k + 1` at an interior node;
//! `0, 1, 2` at the first and `N − 2, N − 1, N` at the last), so an observer that holds three
//! consecutive nodes can hand each node its velocity and momentum as soon as the node after it
//! is known.

use super::{NodeFormula, NodeRule, rule};
use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Location, Result};
use crate::grid::Grid;
use crate::options::NewtonOptions;
use crate::side::Side;
use crate::solve::newton::at_round_off;

/// The evaluations of a Lagrangian the node formulas and the second-order start
/// ([`second_order_start`](crate::solve::start::second_order_start)) need, at flat slices of
/// length `d`.
pub(crate) trait NodeModel {
    /// Writes `∂L/∂x` into `f` and `∂L/∂v` into `p` at `(x, v, t)`.
    fn gradient(&mut self, x: &[f64], v: &[f64], t: f64, f: &mut [f64], p: &mut [f64]);
    /// Writes `∂L/∂v` at `(x, v, t)` into `p`.
    fn momentum(&mut self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]);
    /// `L(x, v, t)`.
    fn value(&mut self, x: &[f64], v: &[f64], t: f64) -> f64;
    /// Solves `∂²L/∂v²(x, v, t) z = r`, `z` in place of `r` when regular; returns
    /// `‖∂²L/∂v²‖∞` and whether it is regular (`r` means nothing when it is not).
    fn solve_vv(&mut self, x: &[f64], v: &[f64], t: f64, r: &mut [f64]) -> (f64, bool);
    /// Subtracts `∂²L/∂v∂x (x, v, t) u` from `out`: `out_j −= Σ_i ∂²L/∂x_i∂v_j u_i`.
    fn subtract_vx_product(&mut self, x: &[f64], v: &[f64], t: f64, u: &[f64], out: &mut [f64]);
    /// Whether the Lagrangian depends on `t` (no energy then).
    fn depends_on_time(&self) -> bool;
}

/// The velocity and momentum at any node of a solution of one scheme under one embedding on
/// one grid, with the buffers of their formulas (no allocation per node).
pub(crate) struct NodeEngine {
    pub(crate) rule: NodeRule,
    side: Side,
    grid: Grid,
    /// The buffers of the formulas that evaluate `∂L` at quadrature points or invert `∂L/∂v`
    /// (empty for the others): a point, and `∂L/∂x`, `∂L/∂v` there (`f` is then Newton's
    /// residual).
    x: Vec<f64>,
    f: Vec<f64>,
    pi: Vec<f64>,
}

impl NodeEngine {
    /// The engine of `scheme` under `embedding` on `grid` at dimension `d`; the errors of
    /// [`rule`].
    pub(crate) fn new(embedding: &Embedding, scheme: Scheme, grid: Grid, d: usize) -> Result<Self> {
        let rule = rule(embedding, scheme)?;
        let buffers = match rule.formula {
            NodeFormula::DiscreteLegendre { .. } | NodeFormula::SchemeMomenta => d,
            NodeFormula::CentredVelocity | NodeFormula::VelocityOperator => 0,
        };
        Ok(NodeEngine {
            rule,
            side: embedding.side(),
            grid,
            x: vec![0.0; buffers],
            f: vec![0.0; buffers],
            pi: vec![0.0; buffers],
        })
    }

    /// The time `t_k` of node `k`.
    pub(crate) fn time(&self, k: usize) -> f64 {
        self.grid.t(k)
    }

    /// Writes `v_k` and `p_k` of node `k` into `v` and `p`, by the rule's formula, from the
    /// nodes `node(j)` it reads (see the module) and, for [`NodeFormula::SchemeMomenta`], the
    /// momentum `carried` the scheme carries at node `k`. Errors as
    /// [`Solution::node_values`](crate::Solution::node_values) at node `k`.
    pub(crate) fn at<'q>(
        &mut self,
        model: &mut impl NodeModel,
        k: usize,
        node: impl Fn(usize) -> &'q [f64],
        carried: Option<&[f64]>,
        (v, p): (&mut [f64], &mut [f64]),
    ) -> Result<()> {
        let (n, h, t) = (self.grid.n(), self.grid.h(), self.grid.t(k));
        let q = node(k);
        // The difference quotient of step j → j + 1.
        let quotient = |j: usize, out: &mut [f64]| {
            let (a, b) = (node(j), node(j + 1));
            for i in 0..out.len() {
                out[i] = (b[i] - a[i]) / h;
            }
        };
        match self.rule.formula {
            NodeFormula::DiscreteLegendre { points } => {
                // p_k^− = −∂L_d(Q_k, Q_{k+1})/∂Q_k = Σ_i w_i [p_i − h (1 − θ_i) f_i] for k < N,
                // p_N^+ = ∂L_d(Q_{N−1}, Q_N)/∂Q_N = Σ_i w_i [p_i + h θ_i f_i].
                // The step's difference quotient, in v: the velocity of the discrete Lagrangian
                // and Newton's guess.
                let j = k.min(n - 1);
                quotient(j, v);
                let (a, b) = (node(j), node(j + 1));
                p.fill(0.0);
                for &(theta, w) in points {
                    for i in 0..q.len() {
                        self.x[i] = a[i] * (1.0 - theta) + b[i] * theta;
                    }
                    // The rectangle rules sit on nodes: take their time exactly (t_N = b).
                    let ti = if theta == 0.0 {
                        self.grid.t(j)
                    } else if theta == 1.0 {
                        self.grid.t(j + 1)
                    } else {
                        self.grid.t(j) + theta * h
                    };
                    model.gradient(&self.x, v, ti, &mut self.f, &mut self.pi);
                    let c = h * if k < n { theta - 1.0 } else { theta };
                    for i in 0..q.len() {
                        p[i] += (self.pi[i] + self.f[i] * c) * w;
                    }
                }
                self.invert_momentum(model, (q, t, &*p), v, k)?;
            }
            NodeFormula::SchemeMomenta => {
                let carried = carried.ok_or(Error::WrongLength {
                    what: "solution momenta",
                    expected: n + 1,
                    found: 0,
                })?;
                p.copy_from_slice(carried);
                quotient(k.min(n - 1), v);
                self.invert_momentum(model, (q, t, &*p), v, k)?;
            }
            NodeFormula::CentredVelocity => {
                match (k, n) {
                    (_, 1) => quotient(0, v),
                    (0, _) => {
                        let (a, b, c) = (node(0), node(1), node(2));
                        for i in 0..v.len() {
                            v[i] = (b[i] * 4.0 - a[i] * 3.0 - c[i]) / (2.0 * h);
                        }
                    }
                    (k, n) if k == n => {
                        let (a, b, c) = (node(n - 2), node(n - 1), node(n));
                        for i in 0..v.len() {
                            v[i] = (c[i] * 3.0 - b[i] * 4.0 + a[i]) / (2.0 * h);
                        }
                    }
                    (k, _) => {
                        let (a, c) = (node(k - 1), node(k + 1));
                        for i in 0..v.len() {
                            v[i] = (c[i] - a[i]) / (2.0 * h);
                        }
                    }
                }
                model.momentum(q, v, t, p);
            }
            NodeFormula::VelocityOperator => {
                match self.side {
                    Side::Backward => quotient(k.max(1) - 1, v),
                    Side::Forward => quotient(k.min(n - 1), v),
                }
                model.momentum(q, v, t, p);
            }
        }
        if v.iter().chain(p.iter()).all(|c| c.is_finite()) {
            Ok(())
        } else {
            Err(Error::NotFinite {
                at: Location::Node(k),
            })
        }
    }

    /// The energy `v·p − L(q, v, t)` at `(q, v, p)` of a node at `t`; `None` when the
    /// Lagrangian depends on `t`.
    pub(crate) fn energy(
        model: &mut impl NodeModel,
        (q, v, p): (&[f64], &[f64], &[f64]),
        t: f64,
    ) -> Option<f64> {
        (!model.depends_on_time())
            .then(|| v.iter().zip(p).map(|(v, p)| v * p).sum::<f64>() - model.value(q, v, t))
    }

    /// [`invert_momentum`] with this engine's buffer.
    fn invert_momentum(
        &mut self,
        model: &mut impl NodeModel,
        (x, t, p): (&[f64], f64, &[f64]),
        v: &mut [f64],
        k: usize,
    ) -> Result<()> {
        invert_momentum(model, (x, t, p), v, &mut self.f, k)
    }
}

/// The velocity `v` with `∂L/∂v(x, v, t) = p`: Newton's method on `∂²L/∂v²` from the guess in
/// `v`, stopping at the default Newton tolerance relative to the terms of the equation,
/// `max(‖p‖∞, ‖∂L/∂v(x, v, t)‖∞)` (no absolute part: `c L` gives the velocity `L` gives), or
/// at round-off (`at_round_off`, with `‖∂²L/∂v²‖∞` and `‖v‖∞`). `r` is a buffer of length
/// `d`; errors at [`Location::Node`] `k`.
pub(crate) fn invert_momentum(
    model: &mut impl NodeModel,
    (x, t, p): (&[f64], f64, &[f64]),
    v: &mut [f64],
    r: &mut [f64],
    k: usize,
) -> Result<()> {
    let options = NewtonOptions::default();
    let at = Location::Node(k);
    let amax = |x: &[f64]| x.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let mut residual = f64::INFINITY;
    for iteration in 0..=options.max_iterations {
        model.momentum(x, v, t, r);
        let pv = amax(r);
        for (r, p) in r.iter_mut().zip(p) {
            *r -= p;
        }
        let previous = residual;
        residual = amax(r);
        if !residual.is_finite() || r.iter().any(|c| !c.is_finite()) {
            return Err(Error::NotFinite { at });
        }
        if residual <= options.tolerance * amax(p).max(pv) {
            return Ok(());
        }
        let (vv_norm, regular) = model.solve_vv(x, v, t, r);
        if at_round_off(residual, previous, vv_norm, amax(v)) {
            return Ok(());
        }
        if !regular {
            return Err(Error::SingularJacobian { at });
        }
        for (v, delta) in v.iter_mut().zip(r.iter()) {
            *v -= delta;
        }
        if iteration == options.max_iterations {
            break;
        }
    }
    Err(Error::NewtonDidNotConverge {
        at,
        iterations: options.max_iterations,
        residual,
    })
}
