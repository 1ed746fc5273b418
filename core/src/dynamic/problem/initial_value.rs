//! [`DynProblem`]'s initial value problems: each method hands the problem's parts to the
//! run-time engine's run ([`DynIvp`]), storing every node, every `s`-th node, or none (an
//! observer).

use super::{DynProblem, DynSolution};
use crate::dynamic::DynLagrangian;
use crate::dynamic::ivp::{DynIvp, DynRun, SecondNode};
use crate::dynamic::observer::DynNode;
use crate::embedding::Scheme;
use crate::error::{Error, Result};
use crate::memory::reserve;
use crate::solve::start::Start;

impl<'l> DynProblem<'l, dyn DynLagrangian + 'l> {
    /// The run-time engine's run of this problem (its model erased, see
    /// [`erased`](DynProblem::erased)).
    fn ivp(&self) -> DynIvp<'l, dyn DynLagrangian + 'l> {
        DynIvp {
            lagrangian: self.lagrangian,
            grid: self.grid,
            embedding: self.embedding,
            newton: self.newton,
            blow_up_guard: self.blow_up_guard,
            resolution_check: self.resolution_check,
        }
    }

    /// The run from `q0` with `v0` or a given `Q_1`, storing the nodes `Q_k` with `k` a
    /// multiple of `stride` (not 0) and the last.
    fn store_every(
        &self,
        scheme: Scheme,
        (q0, v0): (&[f64], &[f64]),
        second: SecondNode<'_>,
        stride: usize,
    ) -> Result<DynSolution> {
        let n = self.grid.n();
        let stored = n / stride + 2;
        let mut indices = reserve(stored, "the indices of the stored nodes")?;
        let mut q = reserve(
            stored.saturating_mul(q0.len()),
            "the stored nodes of the run",
        )?;
        // The positions only (and the momenta a Gauss–Legendre run carries): the node values
        // are computed from the stored nodes, if asked.
        let mut momenta = Vec::new();
        let run = self.ivp().run(scheme, (q0, v0), (second, false), |node| {
            if node.index % stride == 0 || node.index == n {
                indices.push(node.index);
                q.extend_from_slice(node.q);
                momenta.extend_from_slice(node.p);
            }
        })?;
        Ok(DynSolution {
            warnings: run.warnings.clone(),
            run,
            dimension: q0.len(),
            indices,
            q,
            momenta,
        })
    }
}

impl<'l, L: DynLagrangian + ?Sized> DynProblem<'l, L> {
    /// The run of `scheme` from `q(a) = q0`, `q̇(a) = v0` (from the problem's start), storing
    /// every node: `O(N d)` memory. See [`solve_ivp_every`](Self::solve_ivp_every) and
    /// [`run_ivp`](Self::run_ivp) for long runs.
    pub fn solve_ivp(&self, scheme: Scheme, q0: &[f64], v0: &[f64]) -> Result<DynSolution> {
        self.solve_ivp_every(scheme, q0, v0, 1)
    }

    /// The run of [`solve_ivp`](Self::solve_ivp) from `start`, whatever
    /// [`with_start`](Self::with_start) set: the same call as
    /// [`Problem::solve_ivp_with`](crate::Problem::solve_ivp_with).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, Start, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     (0..n).map(|i| 0.5 * (v[i] * v[i] - x[i] * x[i])).sum()
    /// }
    ///
    /// let model = Oscillators { n: 2 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_ivp_with(Scheme::Variational, &[1.0; 2], &[0.0; 2], Start::SecondOrder)?;
    /// // Q_1 = q0 + h v0 + ½h² q̈(0) with q̈ = −q; the problem's own start is the Legendre one.
    /// assert!((run.node(1)[0] - 0.995).abs() < 1e-12);
    /// assert_eq!(problem.solve_ivp(Scheme::Variational, &[1.0; 2], &[0.0; 2])?.node(1)[0], 1.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_with(
        &self,
        scheme: Scheme,
        q0: &[f64],
        v0: &[f64],
        start: Start,
    ) -> Result<DynSolution> {
        let problem = DynProblem { start, ..*self };
        problem.solve_ivp(scheme, q0, v0)
    }

    /// The run of the recurrence of `scheme` from given first nodes `Q_0 = q0`, `Q_1 = q1`,
    /// storing every node: the same call as
    /// [`Problem::solve_ivp_from_nodes`](crate::Problem::solve_ivp_from_nodes), with the same
    /// checks and errors: the first nodes finite (a bad coordinate named, `q1[5] = NaN`), and
    /// the domain and `∂²L/∂v²` at `Q_1` with the velocity `(Q_1 − Q_0)/h`, at step 1. The
    /// stability verdict and, with the resolution check, the warning are taken at `q0` with
    /// that velocity at `a`; a `q1` of the wrong length is an error naming `q1`. [`Error::Unsupported`] under
    /// Gauss–Legendre, a one-step map of `(q, p)` that runs from `q(a)`, `q̇(a)`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     (0..n).map(|i| 0.5 * (v[i] * v[i] - x[i] * x[i])).sum()
    /// }
    ///
    /// let model = Oscillators { n: 2 };
    /// let problem = DynProblem::new(&model, Grid::new(0.0, 1.0, 100)?, Embedding::midpoint());
    /// let h = 0.01f64;
    /// let run = problem.solve_ivp_from_nodes(Scheme::Variational, &[1.0; 2], &[h.cos(); 2])?;
    /// assert_eq!(run.node(1)[0], h.cos());
    /// assert!((run.node(100)[0] - 1f64.cos()).abs() < 1e-4);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_from_nodes(
        &self,
        scheme: Scheme,
        q0: &[f64],
        q1: &[f64],
    ) -> Result<DynSolution> {
        self.erased()
            .store_every(scheme, (q0, &[]), SecondNode::Given(q1), 1)
    }

    /// The run of [`solve_ivp`](Self::solve_ivp) storing only the nodes `Q_k` with `k` a
    /// multiple of `stride`, and the last: `O((N / stride + 1) d)` memory.
    /// [`Error::InvalidGrid`] for a stride of 0.
    pub fn solve_ivp_every(
        &self,
        scheme: Scheme,
        q0: &[f64],
        v0: &[f64],
        stride: usize,
    ) -> Result<DynSolution> {
        if stride == 0 {
            return Err(Error::InvalidGrid {
                a: self.grid.a(),
                b: self.grid.b(),
                n: self.grid.n(),
                reason: "a stride of 0 nodes between stored nodes",
            });
        }
        self.erased()
            .store_every(scheme, (q0, v0), SecondNode::Start(self.start), stride)
    }

    /// The run of [`solve_ivp`](Self::solve_ivp) storing nothing: each node `Q_0, …, Q_N` is
    /// handed to `observe` in order with the node before it, its velocity and momentum left
    /// empty (but the momentum a Gauss–Legendre run carries) and its energy `None`
    /// ([`run_ivp_with_values`](Self::run_ivp_with_values) computes them, at the cost of the
    /// model's evaluations at every node). Node `k` is handed once
    /// `Q_{k+1}` is computed, the last at the end of the run ([`DynNode`]). Beyond what `observe`
    /// keeps, the run needs `O(d b)` memory for a step Jacobian of half-bandwidth `b`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, lagrangian};
    ///
    /// #[lagrangian]
    /// fn springs(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     (0..n).map(|i| 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i]).sum()
    /// }
    ///
    /// let model = Springs { n: 8 };
    /// let problem = DynProblem::new(&model, Grid::new(0.0, 1.0, 100)?, Embedding::midpoint());
    /// let mut furthest = 0.0f64;
    /// let run = problem.run_ivp(Scheme::Variational, &[1.0; 8], &[0.0; 8], |node| {
    ///     furthest = furthest.max(node.q[0].abs());
    ///     assert!(node.v.is_empty() && node.energy.is_none());
    /// })?;
    /// assert_eq!((furthest, run.last.len()), (1.0, 8));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn run_ivp(
        &self,
        scheme: Scheme,
        q0: &[f64],
        v0: &[f64],
        observe: impl FnMut(DynNode<'_>),
    ) -> Result<DynRun> {
        self.erased().ivp().run(
            scheme,
            (q0, v0),
            (SecondNode::Start(self.start), false),
            observe,
        )
    }

    /// The run of [`run_ivp`](Self::run_ivp) with the node values: each node `Q_0, …, Q_N` is
    /// handed to `observe` in order, with the node before it and its velocity, momentum and
    /// energy — those of [`DynSolution::node_values`], bit for bit, at the same order. Node `k`
    /// is handed once `Q_{k+1}` is computed (the formulas read it), the last at the end of the
    /// run ([`DynNode`]). Beyond what `observe` keeps, the run needs `O(d b)` memory for a step
    /// Jacobian of half-bandwidth `b`, and allocates nothing per node for the values. A node
    /// whose values cannot be computed stops the run with the error
    /// [`DynSolution::node_values`] gives there.
    ///
    /// # Example
    ///
    /// The energy at each node, as a long run would record it without storing the nodes:
    ///
    /// ```
    /// # use varembed::{DynLagrangian, SparseHessian};
    /// # struct Oscillators { n: usize }
    /// # impl DynLagrangian for Oscillators {
    /// #     fn dimension(&self) -> usize { self.n }
    /// #     fn value(&self, x: &[f64], v: &[f64], _t: f64) -> f64 {
    /// #         x.iter().zip(v).map(|(x, v)| 0.5 * (v * v - x * x)).sum()
    /// #     }
    /// #     fn force(&self, x: &[f64], _v: &[f64], _t: f64, f: &mut [f64]) {
    /// #         for (f, x) in f.iter_mut().zip(x) { *f = -x; }
    /// #     }
    /// #     fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
    /// #         p.copy_from_slice(v);
    /// #     }
    /// #     fn hessian(&self, _x: &[f64], _v: &[f64], _t: f64, out: &mut SparseHessian) {
    /// #         for i in 0..self.n { out.xx.add(i, i, -1.0); out.vv.add(i, i, 1.0); }
    /// #     }
    /// #     fn dependence(&self) -> varembed::Dependence {
    /// #         varembed::Dependence { x: true, v: true, t: false }
    /// #     }
    /// # }
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side};
    /// let model = Oscillators { n: 64 };
    /// let grid = Grid::new(0.0, 10.0, 1000)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let mut energies = Vec::new();
    /// problem.run_ivp_with_values(Scheme::Variational, &vec![1.0; 64], &vec![0.0; 64], |node| {
    ///     // The discrete Legendre transform p_k^− = (Q_{k+1} − Q_k)/h + O(h) for ½v² − ½x².
    ///     assert_eq!(node.p, node.v);
    ///     energies.push(node.energy.expect("the model declares no time dependence"));
    /// })?;
    /// let e0 = 32.0; // 64 oscillators at rest at x = 1: ½ x² each
    /// assert_eq!(energies.len(), 1001);
    /// assert!(energies.iter().all(|e| (e - e0).abs() < 0.01 * e0));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn run_ivp_with_values(
        &self,
        scheme: Scheme,
        q0: &[f64],
        v0: &[f64],
        observe: impl FnMut(DynNode<'_>),
    ) -> Result<DynRun> {
        self.erased().ivp().run(
            scheme,
            (q0, v0),
            (SecondNode::Start(self.start), true),
            observe,
        )
    }
}
