//! The node values of a run-time-dimension solution ([`DynNodeValues`]) and of each node handed
//! to an observer: time, position, velocity, momentum and energy at the nodes, by the formulas
//! of [`NodeRule`] that the const-generic [`NodeValues`](crate::NodeValues) uses — the same
//! code (the engine of the node values), read through an adapter of the [`DynLagrangian`] that
//! solves `∂²L/∂v²` as a band. The exports (CSV, `serde`) are in `nodes/export.rs`.

mod export;

use crate::error::{Error, Result, check_len};
use crate::solve::nodes::NodeRule;

use super::DynLagrangian;
use super::observer::NodeObserver;
use super::problem::DynSolution;

/// A run-time-dimension solution's values at its nodes `t_0, …, t_N`: flat, as
/// [`DynSolution::q`], node `k` at `[k d..(k + 1) d]` of [`q`](Self::q), [`v`](Self::v) and
/// [`p`](Self::p) — one buffer per field for the `N + 1` nodes of a model of any size, read as
/// slices ([`get`](Self::get), [`iter`](Self::iter)).
///
/// Built by [`DynSolution::node_values`], by the formulas and of the order of
/// [`Solution::node_values`](crate::Solution::node_values) ([`NodeRule`]).
///
/// # Example
///
/// ```
/// use varembed::{DynProblem, Grid, Scheme, lagrangian};
///
/// /// `n` uncoupled unit oscillators.
/// #[lagrangian]
/// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
///     let mut l = 0.0;
///     for i in 0..n {
///         l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
///     }
///     l
/// }
///
/// let model = Oscillators { n: 3 };
/// let problem = DynProblem::recommended(&model, Grid::new(0.0, 1.0, 100)?);
/// let nodes = problem.solve_ivp(Scheme::Variational, &[1.0; 3], &[0.0; 3])?.node_values(&model)?;
/// assert_eq!((nodes.len(), nodes.rule.order), (101, 2));
/// // q = cos t: v = −sin t to second order, at every node.
/// for node in nodes.iter() {
///     assert!(node.v.iter().all(|v| (v + node.t.sin()).abs() < 1e-4));
/// }
/// // E = 3 × ½: the midpoint rule's energy error is O(h²).
/// assert!(nodes.energy.unwrap().iter().all(|e| (e - 1.5).abs() < 1e-4));
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct DynNodeValues {
    /// The dimension `d`.
    pub dimension: usize,
    /// `t_k = a + k h` (`t_N = b` exactly).
    pub t: Vec<f64>,
    /// The positions `Q_k`, flat.
    pub q: Vec<f64>,
    /// The velocities, flat.
    pub v: Vec<f64>,
    /// The momenta, flat.
    pub p: Vec<f64>,
    /// The energies `v·∂L/∂v − L` at `(Q_k, v_k, t_k)` for an autonomous Lagrangian (as
    /// [`DynLagrangian::dependence`] declares); `None` otherwise.
    pub energy: Option<Vec<f64>>,
    /// How `v` and `p` were computed, and their order.
    pub rule: NodeRule,
}

/// One node of [`DynNodeValues`]: `(t_k, Q_k, v_k, p_k)` and the energy there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynNodeState<'a> {
    /// `t_k`.
    pub t: f64,
    /// `Q_k`.
    pub q: &'a [f64],
    /// The velocity ([`NodeRule`]).
    pub v: &'a [f64],
    /// The momentum ([`NodeRule`]).
    pub p: &'a [f64],
    /// The energy, for an autonomous Lagrangian.
    pub energy: Option<f64>,
}

impl DynNodeValues {
    /// The number of nodes, `N + 1`.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Always `false`: a solution has at least two nodes.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Node `k`, `None` when `k > N`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// let model = Oscillators { n: 2 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Direct, &[1.0; 2], &[0.0; 2])?.node_values(&model)?;
    /// let node = nodes.get(3).expect("N = 10");
    /// // The direct Gauss-FDE− scheme's velocity at t_3: its backward difference.
    /// let q2 = nodes.get(2).unwrap().q;
    /// assert_eq!(node.v[0], (node.q[0] - q2[0]) / 0.1);
    /// assert_eq!(node.p, node.v); // p = ∂L/∂v = v
    /// assert!(nodes.get(11).is_none());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn get(&self, k: usize) -> Option<DynNodeState<'_>> {
        let d = self.dimension;
        (k < self.len()).then(|| DynNodeState {
            t: self.t[k],
            q: &self.q[k * d..(k + 1) * d],
            v: &self.v[k * d..(k + 1) * d],
            p: &self.p[k * d..(k + 1) * d],
            energy: self.energy.as_ref().map(|e| e[k]),
        })
    }

    /// The nodes in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = DynNodeState<'_>> + '_ {
        (0..self.len()).map(|k| self.get(k).expect("k ≤ N"))
    }
}

impl DynSolution {
    /// Time, position, velocity, momentum and (for an autonomous Lagrangian) energy at every
    /// node `t_k`, `k = 0..=N`, by the formulas, and of the order, of
    /// [`Solution::node_values`](crate::Solution::node_values) for the same embedding and
    /// scheme ([`NodeRule`]: the discrete Legendre transforms of the variational schemes, the
    /// velocity operator of the direct Gauss-FDEσ schemes, the centred velocity of the direct
    /// symmetric ones). `lagrangian` must be the one the solution was computed with; where the
    /// velocity solves `∂L/∂v(Q_k, v_k, t_k) = p_k`, Newton's method solves `∂²L/∂v²` as a band
    /// (factorised once when the model declares it constant,
    /// [`DynLagrangian::hessian_dependence`]).
    ///
    /// The same values reach the observer of [`DynProblem::run_ivp_with_values`](crate::DynProblem::run_ivp_with_values)
    /// node by node, bit for bit, without storing the run.
    ///
    /// Errors: [`Error::NodesNotStored`] for a solution of
    /// [`solve_ivp_every`](crate::DynProblem::solve_ivp_every) that does not store every node
    /// (solve with [`solve_ivp`](crate::DynProblem::solve_ivp), or observe the run);
    /// [`Error::Unsupported`] for an embedding the run-time path does not solve;
    /// [`Error::WrongLength`] when the nodes are not `(N + 1) d` numbers; and the errors of
    /// [`Solution::node_values`](crate::Solution::node_values) at a node.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Error, Grid, Scheme, lagrangian};
    ///
    /// /// A ring of `n` pendula, each coupled to its neighbours.
    /// #[lagrangian]
    /// fn ring(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     (0..n)
    ///         .map(|i| 0.5 * v[i] * v[i] + x[i].cos() - 0.5 * (x[(i + 1) % n] - x[i]).powi(2))
    ///         .sum()
    /// }
    ///
    /// let ring = Ring { n: 32 };
    /// let q0: Vec<f64> = (0..32).map(|i| (i as f64 * 0.2).sin()).collect();
    /// let drift = |steps: usize| -> varembed::Result<f64> {
    ///     let problem = DynProblem::new(&ring, Grid::new(0.0, 4.0, steps)?, Embedding::midpoint());
    ///     let nodes = problem.solve_ivp(Scheme::Variational, &q0, &[0.0; 32])?.node_values(&ring)?;
    ///     let energy = nodes.energy.expect("autonomous");
    ///     Ok(energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max))
    /// };
    /// // Second order: halving the step divides the energy's drift by about 4.
    /// let ratio = drift(200)? / drift(400)?;
    /// assert!((ratio - 4.0).abs() < 0.3, "{ratio}");
    ///
    /// // A run that keeps every 10th node has no neighbours to differentiate.
    /// let problem = DynProblem::new(&ring, Grid::new(0.0, 4.0, 200)?, Embedding::midpoint());
    /// let thinned = problem.solve_ivp_every(Scheme::Variational, &q0, &[0.0; 32], 10)?;
    /// assert!(matches!(thinned.node_values(&ring), Err(Error::NodesNotStored { stored: 21, nodes: 201, .. })));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn node_values<L: DynLagrangian + ?Sized>(&self, lagrangian: &L) -> Result<DynNodeValues> {
        self.values_of(&lagrangian)
    }

    /// [`node_values`](Self::node_values), compiled once for every model.
    fn values_of(&self, lagrangian: &dyn DynLagrangian) -> Result<DynNodeValues> {
        let run = &self.run;
        let (n, d) = (run.grid.n(), self.dimension);
        let every =
            self.indices.len() == n + 1 && self.indices.iter().enumerate().all(|(j, &k)| j == k);
        if !every {
            return Err(Error::NodesNotStored {
                operation: "DynSolution::node_values",
                stored: self.indices.len(),
                nodes: n + 1,
            });
        }
        check_len("solution nodes", (n + 1).saturating_mul(d), self.q.len())?;
        if !self.momenta.is_empty() {
            check_len(
                "solution momenta",
                (n + 1).saturating_mul(d),
                self.momenta.len(),
            )?;
        }
        let mut values = NodeObserver::new(lagrangian, (&run.embedding, run.scheme, run.grid), d)?;
        let (mut v, mut p) = (vec![0.0; (n + 1) * d], vec![0.0; (n + 1) * d]);
        let mut energy = Vec::with_capacity(n + 1);
        for k in 0..=n {
            let nodes = (0, self.q.as_slice());
            let carried = self.momenta.get(k * d..(k + 1) * d);
            let (vk, pk) = (&mut v[k * d..(k + 1) * d], &mut p[k * d..(k + 1) * d]);
            energy.push(values.at(k, nodes, carried, (vk, pk))?);
        }
        Ok(DynNodeValues {
            dimension: d,
            t: run.grid.nodes(),
            q: self.q.clone(),
            v,
            p,
            energy: energy.into_iter().collect(),
            rule: values.rule(),
        })
    }
}
