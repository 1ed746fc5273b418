//! What a run-time-dimension run hands its observer: each node with its velocity, momentum
//! and energy ([`DynNode`]), computed by the engine of the node formulas through an adapter of
//! the [`DynLagrangian`] (`∂²L/∂v²` solved as a band) — also what
//! [`DynSolution::node_values`](crate::DynSolution::node_values) reads.

use crate::embedding::{Embedding, Scheme};
use crate::error::Result;
use crate::grid::Grid;
use crate::solve::nodes::engine::{NodeEngine, NodeModel};

use super::DynLagrangian;
use super::band::BandSystem;
use super::sparse::SparseHessian;

/// A node handed to the observer of a run: `Q_k` at `t_k` with the node before it (`Q_0` itself
/// for `k = 0`), and the velocity, momentum and energy at the node by the formulas, and of the
/// order, of [`DynSolution::node_values`](crate::DynSolution::node_values) — bit for
/// bit the values it gives on the stored run ([`NodeRule`](crate::NodeRule)).
///
/// Those formulas read the node after `Q_k` (the centred velocity, the discrete Legendre
/// transform `p_k^−` of step `k → k + 1`), so node `k` is handed once `Q_{k+1}` is computed,
/// node 0 with node 1 once `Q_2` is, and the last node `Q_N` at the end of the run, by its
/// one-sided formula. A run that fails at step `k` has handed the nodes before `Q_{k−1}`.
#[derive(Clone, Copy, Debug)]
pub struct DynNode<'a> {
    /// Its index `k`.
    pub index: usize,
    /// Its time `t_k`.
    pub t: f64,
    /// `Q_k`.
    pub q: &'a [f64],
    /// `Q_{k−1}` (`Q_0` when `k = 0`).
    pub previous: &'a [f64],
    /// The velocity `v_k` ([`NodeRule`](crate::NodeRule)) from
    /// [`DynProblem::run_ivp_with_values`](crate::DynProblem::run_ivp_with_values); empty from
    /// [`DynProblem::run_ivp`](crate::DynProblem::run_ivp), which computes no node values.
    pub v: &'a [f64],
    /// The momentum `p_k` ([`NodeRule`](crate::NodeRule)), as `v`: empty from `run_ivp`, but
    /// for a Gauss–Legendre run, which carries its momenta from node to node and hands them
    /// from both.
    pub p: &'a [f64],
    /// The energy `v_k·p_k − L(Q_k, v_k, t_k)` for an autonomous Lagrangian from
    /// `run_ivp_with_values`; `None` otherwise, and always from `run_ivp`.
    pub energy: Option<f64>,
}

/// The node values of a run-time-dimension model at any node: the engine of the node formulas
/// and the model's adapter, with the buffers `v`, `p` of the node handed to an observer.
pub(crate) struct NodeObserver<'l, L: ?Sized> {
    engine: NodeEngine,
    model: DynNodeModel<'l, L>,
    v: Vec<f64>,
    p: Vec<f64>,
}

impl<'l, L: DynLagrangian + ?Sized> NodeObserver<'l, L> {
    /// The node values of `scheme` under `embedding` on `grid` at dimension `d`;
    /// [`Error::Unsupported`](crate::Error::Unsupported) for the fractional embeddings. The Gauss–Legendre integrators'
    /// momenta are the ones the scheme carries, handed to [`at`](Self::at) and
    /// [`hand`](Self::hand).
    pub(crate) fn new(
        lagrangian: &'l L,
        (embedding, scheme, grid): (&Embedding, Scheme, Grid),
        d: usize,
    ) -> Result<Self> {
        let engine = NodeEngine::new(embedding, scheme, grid, d)?;
        Ok(NodeObserver {
            engine,
            model: DynNodeModel::new(lagrangian, d),
            v: vec![0.0; d],
            p: vec![0.0; d],
        })
    }

    /// The rule of the node formulas.
    pub(crate) fn rule(&self) -> crate::NodeRule {
        self.engine.rule
    }

    /// With `∂²L/∂v²` factorised at `(x, v, t)` when the model declares it constant, and the
    /// Hessian's buffers then freed: what a run does before its steps allocate theirs.
    pub(crate) fn primed(mut self, x: &[f64], v: &[f64], t: f64) -> Self {
        if self.model.constant {
            // `p` serves as the right-hand side; the node values overwrite it.
            self.model.solve_vv(x, v, t, &mut self.p);
        }
        self
    }

    /// Writes `v_k`, `p_k` into `v`, `p` and returns the energy at node `k`, from consecutive
    /// nodes flat in `nodes.1`, the first of them node `nodes.0`, and the momentum `carried`
    /// at node `k` of a scheme that carries one (Gauss–Legendre).
    pub(crate) fn at(
        &mut self,
        k: usize,
        (first, nodes): (usize, &[f64]),
        carried: Option<&[f64]>,
        (v, p): (&mut [f64], &mut [f64]),
    ) -> Result<Option<f64>> {
        let d = v.len();
        let node = |j: usize| &nodes[(j - first) * d..(j - first + 1) * d];
        self.engine
            .at(&mut self.model, k, node, carried, (&mut *v, &mut *p))?;
        let t = self.engine.time(k);
        Ok(NodeEngine::energy(&mut self.model, (node(k), v, p), t))
    }

    /// Hands node `k` to `observe`, with its velocity, momentum and energy, from the window of
    /// consecutive nodes `window`, the first of them node `first` (every node the formulas
    /// read at `k`, and `Q_{k−1}`) and the momentum `carried` at node `k` (as [`at`](Self::at)).
    pub(crate) fn hand(
        &mut self,
        k: usize,
        (first, window): (usize, &[&[f64]]),
        carried: Option<&[f64]>,
        observe: &mut impl FnMut(DynNode<'_>),
    ) -> Result<()> {
        let node = |j: usize| window[j - first];
        let t = self.engine.time(k);
        let (v, p) = (&mut self.v, &mut self.p);
        self.engine
            .at(&mut self.model, k, node, carried, (&mut *v, &mut *p))?;
        let energy = NodeEngine::energy(&mut self.model, (node(k), v, p), t);
        observe(DynNode {
            index: k,
            t,
            q: node(k),
            previous: node(k.max(1) - 1),
            v,
            p,
            energy,
        });
        Ok(())
    }
}

/// A [`DynLagrangian`] read by the node formulas: `∂²L/∂v²` assembled from the model's sparse
/// block and solved as a band, planned at its first solve (again when an entry falls outside
/// the band), and factorised once when the model declares it constant.
pub(crate) struct DynNodeModel<'l, L: ?Sized> {
    lagrangian: &'l L,
    hessian: SparseHessian,
    system: Option<BandSystem>,
    /// `∂²L/∂v²` depends on nothing ([`DynLagrangian::hessian_dependence`]).
    constant: bool,
    /// Its norm and regularity, once factorised, when constant.
    factorised: Option<(f64, bool)>,
}

impl<'l, L: DynLagrangian + ?Sized> DynNodeModel<'l, L> {
    /// `lagrangian` at dimension `d`, nothing planned or factorised yet.
    pub(crate) fn new(lagrangian: &'l L, d: usize) -> Self {
        let vv = lagrangian.hessian_dependence().vv;
        DynNodeModel {
            lagrangian,
            hessian: SparseHessian::new(d),
            system: None,
            constant: !(vv.x || vv.v || vv.t),
            factorised: None,
        }
    }
}

impl<L: DynLagrangian + ?Sized> NodeModel for DynNodeModel<'_, L> {
    fn gradient(&mut self, x: &[f64], v: &[f64], t: f64, f: &mut [f64], p: &mut [f64]) {
        self.lagrangian.force(x, v, t, f);
        self.lagrangian.momentum(x, v, t, p);
    }
    fn momentum(&mut self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        self.lagrangian.momentum(x, v, t, p);
    }
    fn value(&mut self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.lagrangian.value(x, v, t)
    }
    fn solve_vv(&mut self, x: &[f64], v: &[f64], t: f64, r: &mut [f64]) -> (f64, bool) {
        if let (Some((norm, regular)), Some(system)) = (self.factorised, &mut self.system) {
            if regular {
                system.solve_in_place(r);
            }
            return (norm, regular);
        }
        self.hessian.clear();
        self.lagrangian.hessian(x, v, t, &mut self.hessian);
        let vv = &self.hessian.vv;
        let system = loop {
            let system = self.system.get_or_insert_with(|| {
                BandSystem::plan(x.len(), self.lagrangian.hessian_bandwidth(), &[vv])
            });
            system.clear();
            if vv
                .entries()
                .iter()
                .all(|&(i, j, value)| system.add(i, j, value).is_ok())
            {
                break system;
            }
            // An entry outside the planned band: plan again from this pattern, which fits.
            self.system = None;
        };
        let (norms, regular) = system.factorize_measured();
        if regular {
            system.solve_in_place(r);
        }
        if self.constant {
            self.factorised = Some((norms.inf, regular));
            // Never read again.
            self.hessian = SparseHessian::new(0);
        }
        (norms.inf, regular)
    }
    fn subtract_vx_product(&mut self, x: &[f64], v: &[f64], t: f64, u: &[f64], out: &mut [f64]) {
        // A constant `∂²L/∂v²`, once factorised, has freed the Hessian's buffers.
        if self.hessian.xv.dimension() != x.len() {
            self.hessian = SparseHessian::new(x.len());
        }
        self.hessian.clear();
        self.lagrangian.hessian(x, v, t, &mut self.hessian);
        for &(i, j, value) in self.hessian.xv.entries() {
            out[j] -= value * u[i];
        }
    }
    fn depends_on_time(&self) -> bool {
        self.lagrangian.dependence().t
    }
}
