//! A solution's values at its nodes `t_k`, `k = 0..=N`: time, position, velocity, momentum and
//! (for an autonomous Lagrangian) energy, each aligned with the node — never with a quadrature
//! row — and their export as CSV or, with the `serde` feature, through `serde`.
//!
//! How the velocity and momentum at a node are obtained depends on the scheme: a variational
//! scheme has the discrete Legendre transforms of its discrete Lagrangian, a direct scheme only
//! its velocity operator. [`NodeRule`] names the formula and its order; [`rule`] is the one
//! place that decides it for an embedding and a scheme (one match arm per embedding family).
//! The exports (CSV, `serde`) are in `nodes/export.rs`.

pub(crate) mod engine;
pub(crate) mod export;

use crate::embedding::{Embedding, EmbeddingKind, Scheme};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::solve_small;
use crate::side::Side;
use engine::{NodeEngine, NodeModel};
use std::fmt;

/// How a solution's velocities and momenta at the nodes are computed, and their order.
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
///
/// #[lagrangian]
/// fn oscillator(x: f64, v: f64) -> f64 {
///     0.5 * v * v - 0.5 * x * x
/// }
///
/// let grid = Grid::new(0.0, 1.0, 10)?;
/// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
/// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
/// assert!(matches!(nodes.rule.formula, varembed::NodeFormula::DiscreteLegendre { .. }));
/// assert_eq!(nodes.rule.order, 1);
/// assert_eq!(nodes.rule.to_string(), "discrete Legendre transforms, order 1");
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeRule {
    /// The formula.
    pub formula: NodeFormula,
    /// The order `r` of the velocities and momenta at every node, end nodes included: on a
    /// smooth solution, and positions of order at least `r`, `|v_k − q̇(t_k)| = O(h^r)` and
    /// `|p_k − ∂L/∂v(q, q̇, t)(t_k)| = O(h^r)`.
    pub order: u32,
}

/// Which formula gives the velocities and momenta at the nodes.
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
///
/// #[lagrangian]
/// fn oscillator(x: f64, v: f64) -> f64 {
///     0.5 * v * v - 0.5 * x * x
/// }
///
/// let grid = Grid::new(0.0, 1.0, 10)?;
/// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
/// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
/// let direct = problem.solve_ivp(Scheme::Direct, 1.0, 0.0)?.node_values(&Oscillator)?;
/// assert_eq!(direct.rule.formula, varembed::NodeFormula::VelocityOperator);
/// // The direct scheme's velocity at t_1 is its backward difference (Q_1 − Q_0)/h.
/// assert_eq!(direct.v[1][0], (direct.q[1][0] - direct.q[0][0]) / 0.1);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum NodeFormula {
    /// The discrete Legendre transforms of a variational scheme. Its action is a sum of
    /// discrete Lagrangians `L_d(Q_k, Q_{k+1}) = h Σ_i w_i L(x_i, V, t_k + θ_i h)` with
    /// `V = (Q_{k+1} − Q_k)/h` and `x_i = (1 − θ_i) Q_k + θ_i Q_{k+1}`; the momenta are
    /// `p_k^− = −∂L_d(Q_k, Q_{k+1})/∂Q_k` at `k = 0..=N−1` and
    /// `p_N^+ = ∂L_d(Q_{N−1}, Q_N)/∂Q_N` at the last node (at an interior node the scheme's
    /// equation is `p_k^+ = p_k^−`, so either side gives the same momentum up to the solver's
    /// tolerance). The velocity `v_k` solves `∂L/∂v(Q_k, v_k, t_k) = p_k` (Newton's method on
    /// `∂²L/∂v²`, from the neighbouring difference quotient).
    ///
    /// <!-- tex: L_d(Q_k, Q_{k+1}) = h \sum_i w_i \, L\big((1 - \theta_i) Q_k + \theta_i Q_{k+1}, \tfrac{Q_{k+1} - Q_k}{h}, t_k + \theta_i h\big), \qquad p_k^- = -\frac{\partial L_d}{\partial Q_k}, \quad p_{k+1}^+ = \frac{\partial L_d}{\partial Q_{k+1}} -->
    /// <math display="block"><mrow><msub><mi>L</mi><mi>d</mi></msub><mo stretchy="false">&#x00028;</mo><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0002C;</mo><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mn>1</mn></mrow></msub><mo stretchy="false">&#x00029;</mo><mo>&#x0003D;</mo><mi>h</mi><munder><mo>&#x02211;</mo><mi>i</mi></munder><msub><mi>w</mi><mi>i</mi></msub><mspace width="0.167em" /><mi>L</mi><mo minsize="1.2em" maxsize="1.2em">(</mo><mo stretchy="false">&#x00028;</mo><mn>1</mn><mo>&#x02212;</mo><msub><mi>&#x003B8;</mi><mi>i</mi></msub><mo stretchy="false">&#x00029;</mo><msub><mi>Q</mi><mi>k</mi></msub><mo>&#x0002B;</mo><msub><mi>&#x003B8;</mi><mi>i</mi></msub><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mn>1</mn></mrow></msub><mo>&#x0002C;</mo><mstyle displaystyle="false" scriptlevel="0"><mfrac><mrow><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mn>1</mn></mrow></msub><mo>&#x02212;</mo><msub><mi>Q</mi><mi>k</mi></msub></mrow><mrow><mi>h</mi></mrow></mfrac></mstyle><mo>&#x0002C;</mo><msub><mi>t</mi><mi>k</mi></msub><mo>&#x0002B;</mo><msub><mi>&#x003B8;</mi><mi>i</mi></msub><mi>h</mi><mo minsize="1.2em" maxsize="1.2em">)</mo><mo>&#x0002C;</mo><mspace width="2em" /><msubsup><mi>p</mi><mi>k</mi><mo>&#x02212;</mo></msubsup><mo>&#x0003D;</mo><mo>&#x02212;</mo><mfrac><mrow><mo>&#x02202;</mo><msub><mi>L</mi><mi>d</mi></msub></mrow><mrow><mo>&#x02202;</mo><msub><mi>Q</mi><mi>k</mi></msub></mrow></mfrac><mo>&#x0002C;</mo><mspace width="1em" /><msubsup><mi>p</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mn>1</mn></mrow><mo>&#x0002B;</mo></msubsup><mo>&#x0003D;</mo><mfrac><mrow><mo>&#x02202;</mo><msub><mi>L</mi><mi>d</mi></msub></mrow><mrow><mo>&#x02202;</mo><msub><mi>Q</mi><mrow><mi>k</mi><mo>&#x0002B;</mo><mn>1</mn></mrow></msub></mrow></mfrac></mrow></math>
    DiscreteLegendre {
        /// The points `(θ_i, w_i)` of the discrete Lagrangian's quadrature.
        points: &'static [(f64, f64)],
    },
    /// The momenta `p_k` a one-step integrator carries as its state (the Gauss–Legendre
    /// integrators: `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})`, both of order `2s`); the velocity `v_k`
    /// solves `∂L/∂v(Q_k, v_k, t_k) = p_k`, as for the discrete Legendre transforms.
    SchemeMomenta,
    /// The centred velocity of the direct schemes of the symmetric embeddings (midpoint,
    /// trapezoidal), the one their force is evaluated with: `v_k = (Q_{k+1} − Q_{k−1})/(2h)` at
    /// the interior nodes and the second-order one-sided differences
    /// `(−3Q_0 + 4Q_1 − Q_2)/(2h)`, `(3Q_N − 4Q_{N−1} + Q_{N−2})/(2h)` at the ends (for `N = 1`,
    /// the one difference quotient); `p_k = ∂L/∂v(Q_k, v_k, t_k)`.
    CentredVelocity,
    /// The direct scheme's own velocity operator: `v_k = V_k = −σ Δ_σ Q_k` on the rows `I_σ`
    /// and, at the one node outside them (`k = 0` for σ = −, `k = N` for σ = +), the same
    /// difference quotient as its neighbour row (`(Q_1 − Q_0)/h`, resp. `(Q_N − Q_{N−1})/h`);
    /// `p_k = ∂L/∂v(Q_k, v_k, t_k)`.
    VelocityOperator,
}

impl fmt::Display for NodeRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let formula = match self.formula {
            NodeFormula::DiscreteLegendre { .. } => "discrete Legendre transforms",
            NodeFormula::SchemeMomenta => "the scheme's own momenta",
            NodeFormula::CentredVelocity => "the centred velocity",
            NodeFormula::VelocityOperator => "the scheme's velocity operator",
        };
        write!(f, "{formula}, order {}", self.order)
    }
}

/// The rectangle rule at the step's right end, `L_d = h L(Q_{k+1}, V, t_{k+1})` (σ = −).
const RIGHT_END: &[(f64, f64)] = &[(1.0, 1.0)];
/// The rectangle rule at the step's left end, `L_d = h L(Q_k, V, t_k)` (σ = +).
const LEFT_END: &[(f64, f64)] = &[(0.0, 1.0)];
/// The midpoint rule, `L_d = h L((Q_k + Q_{k+1})/2, V, t_k + h/2)`.
const MIDPOINT: &[(f64, f64)] = &[(0.5, 1.0)];
/// The trapezoidal rule, `L_d = h/2 [L(Q_k, V, t_k) + L(Q_{k+1}, V, t_{k+1})]`.
const TRAPEZOIDAL: &[(f64, f64)] = &[(0.0, 0.5), (1.0, 0.5)];

/// How the velocities and momenta at the nodes of a solution of `scheme` under `embedding` are
/// computed. Errors with [`Error::Unsupported`] for Gauss-GLEσ: the fractional velocity at the
/// node outside `I_σ` is the Riemann–Liouville derivative at an end of the interval, which has
/// no finite limit, and a fractional action has no two-point discrete Lagrangian.
pub(crate) fn rule(embedding: &Embedding, scheme: Scheme) -> Result<NodeRule> {
    let unsupported = || Error::Unsupported {
        operation: "Solution::node_values",
        embedding: embedding.to_string(),
    };
    match (embedding.kind(), scheme) {
        // Both Gauss-FDEσ embeddings have the action h Σ_{I_σ} L(Q_k, V_k, t_k): a rectangle
        // rule on each step, first order (for L = ½v² − U, p_k^− = (Q_{k+1} − Q_k)/h).
        (EmbeddingKind::FiniteDifference | EmbeddingKind::Asymmetric, Scheme::Variational) => {
            let points = match embedding.side() {
                Side::Backward => RIGHT_END,
                Side::Forward => LEFT_END,
            };
            Ok(NodeRule {
                formula: NodeFormula::DiscreteLegendre { points },
                order: 1,
            })
        }
        // One-sided differences: first order at every node.
        (EmbeddingKind::FiniteDifference | EmbeddingKind::Asymmetric, Scheme::Direct) => {
            Ok(NodeRule {
                formula: NodeFormula::VelocityOperator,
                order: 1,
            })
        }
        // Symmetric discrete Lagrangians: their Legendre transforms are second order.
        (EmbeddingKind::Midpoint, Scheme::Variational) => Ok(NodeRule {
            formula: NodeFormula::DiscreteLegendre { points: MIDPOINT },
            order: 2,
        }),
        (EmbeddingKind::Trapezoidal, Scheme::Variational) => Ok(NodeRule {
            formula: NodeFormula::DiscreteLegendre {
                points: TRAPEZOIDAL,
            },
            order: 2,
        }),
        (EmbeddingKind::Midpoint | EmbeddingKind::Trapezoidal, Scheme::Direct) => Ok(NodeRule {
            formula: NodeFormula::CentredVelocity,
            order: 2,
        }),
        // A one-step map of (q_k, p_k): its momenta are part of the solution, order 2s.
        (EmbeddingKind::GaussLegendre { stages }, Scheme::Variational) => Ok(NodeRule {
            formula: NodeFormula::SchemeMomenta,
            order: 2 * stages as u32,
        }),
        (EmbeddingKind::GaussLegendre { .. }, Scheme::Direct)
        | (
            EmbeddingKind::GrunwaldLetnikov { .. }
            | EmbeddingKind::Caputo { .. }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { .. }
            | EmbeddingKind::CorrectedCaputo { .. },
            _,
        ) => Err(unsupported()),
    }
}

/// A solution's state at one time: at a node, `(t_k, Q_k, v_k, p_k)` and the energy there
/// ([`NodeValues::get`], [`NodeValues::iter`]); or at any `t` of `[a, b]`, interpolated
/// between the nodes ([`Solution::state_at`](crate::Solution::state_at)).
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
///
/// #[lagrangian]
/// fn oscillator(x: f64, v: f64) -> f64 {
///     0.5 * v * v - 0.5 * x * x
/// }
///
/// let grid = Grid::new(0.0, 1.0, 10)?;
/// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
/// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
/// let last = nodes.get(10).expect("N = 10");
/// assert_eq!(last.t, 1.0);
/// assert_eq!(last.p, last.v); // p = ∂L/∂v = v
/// assert!((last.energy.unwrap() - 0.5).abs() < 0.05); // E = ½v² + ½x² = ½, to O(h)
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeState<const D: usize> {
    /// The time: `t_k = a + k h` at a node (`t_N = b` exactly), the time asked for otherwise.
    pub t: f64,
    /// The position: `Q_k` at a node.
    pub q: Vector<D>,
    /// The velocity (at a node see [`NodeRule`]).
    pub v: Vector<D>,
    /// The momentum (at a node see [`NodeRule`]).
    pub p: Vector<D>,
    /// `E = v·∂L/∂v(q, v, t) − L(q, v, t)` when the Lagrangian is autonomous (does not depend
    /// on `t`), `None` otherwise.
    pub energy: Option<f64>,
}

/// A solution's values at its nodes `t_0, …, t_N`, index `k` being node `k` in every field.
///
/// Built by [`Solution::node_values`](crate::Solution::node_values).
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
///
/// #[lagrangian]
/// fn oscillator(x: f64, v: f64) -> f64 {
///     0.5 * v * v - 0.5 * x * x
/// }
///
/// let grid = Grid::new(0.0, 1.0, 10)?;
/// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
/// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
/// assert_eq!(nodes.len(), 11);
/// assert_eq!(nodes.t[10], 1.0);
/// let max_error = nodes.iter().map(|n| (n.q[0] - n.t.cos()).abs()).fold(0.0, f64::max);
/// assert!(max_error < 0.05);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct NodeValues<const D: usize> {
    /// `t_k = a + k h` (`t_N = b` exactly).
    pub t: Vec<f64>,
    /// The positions `Q_k`.
    pub q: Vec<Vector<D>>,
    /// The velocities.
    pub v: Vec<Vector<D>>,
    /// The momenta.
    pub p: Vec<Vector<D>>,
    /// The energies `v·∂L/∂v − L` at `(Q_k, v_k, t_k)` for an autonomous Lagrangian (one that
    /// does not depend on `t`, as [`Lagrangian::dependence`] declares); `None` otherwise, where
    /// the flow does not conserve it.
    pub energy: Option<Vec<f64>>,
    /// How `v` and `p` were computed, and their order.
    pub rule: NodeRule,
}

impl<const D: usize> NodeValues<D> {
    /// The values of the curve `q` (a solution of `scheme` under `embedding` on `grid`, with
    /// the momenta the scheme carries, if any) at its nodes, by the formulas written once for
    /// both paths (the engine module).
    pub(crate) fn new<L: Lagrangian<D> + ?Sized>(
        lagrangian: &L,
        grid: &Grid,
        embedding: &Embedding,
        scheme: Scheme,
        (q, momenta): (&[Vector<D>], &[Vector<D>]),
    ) -> Result<Self> {
        let mut engine = NodeEngine::new(embedding, scheme, *grid, D)?;
        let n = grid.n();
        crate::error::check_len("solution nodes", n + 1, q.len())?;
        if engine.rule.formula == NodeFormula::SchemeMomenta {
            crate::error::check_len("solution momenta", n + 1, momenta.len())?;
        }
        let t = grid.nodes();
        let mut model = ConstModel::<L, D>(lagrangian);
        let (mut v, mut p) = (
            vec![Vector::<D>::zeros(); n + 1],
            vec![Vector::<D>::zeros(); n + 1],
        );
        for k in 0..=n {
            let carried = momenta.get(k).map(|m| m.as_slice());
            let (vk, pk) = (v[k].as_mut_slice(), p[k].as_mut_slice());
            engine.at(&mut model, k, |j| q[j].as_slice(), carried, (vk, pk))?;
        }
        let energy = (0..=n)
            .map(|k| {
                let node = (q[k].as_slice(), v[k].as_slice(), p[k].as_slice());
                NodeEngine::energy(&mut model, node, t[k])
            })
            .collect();
        Ok(NodeValues {
            t,
            q: q.to_vec(),
            v,
            p,
            energy,
            rule: engine.rule,
        })
    }

    /// The number of nodes, `N + 1`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
    /// assert_eq!(nodes.len(), 11);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Always `false`: a solution has at least two nodes.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
    /// assert!(!nodes.is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Node `k`, `None` when `k > N`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
    /// assert_eq!(nodes.get(0).map(|n| n.t), Some(0.0));
    /// assert!(nodes.get(11).is_none());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn get(&self, k: usize) -> Option<NodeState<D>> {
        (k < self.len()).then(|| NodeState {
            t: self.t[k],
            q: self.q[k],
            v: self.v[k],
            p: self.p[k],
            energy: self.energy.as_ref().map(|e| e[k]),
        })
    }

    /// The nodes in order, each as `(t, q, v, p)` with its energy.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let nodes = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?.node_values(&Oscillator)?;
    /// let times: Vec<f64> = nodes.iter().map(|node| node.t).collect();
    /// assert_eq!(times, nodes.t);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn iter(&self) -> impl ExactSizeIterator<Item = NodeState<D>> + '_ {
        (0..self.len()).map(|k| self.get(k).expect("k ≤ N"))
    }
}

/// A [`Lagrangian<D>`] read at flat slices of length `D`: what the node formulas evaluate.
pub(crate) struct ConstModel<'l, L: ?Sized, const D: usize>(pub(crate) &'l L);

impl<const D: usize, L: Lagrangian<D> + ?Sized> NodeModel for ConstModel<'_, L, D> {
    fn gradient(&mut self, x: &[f64], v: &[f64], t: f64, f: &mut [f64], p: &mut [f64]) {
        let (fx, pv) = self.0.gradient(&vector(x), &vector(v), t);
        f.copy_from_slice(fx.as_slice());
        p.copy_from_slice(pv.as_slice());
    }
    fn momentum(&mut self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        p.copy_from_slice(self.0.gradient(&vector(x), &vector(v), t).1.as_slice());
    }
    fn value(&mut self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.0.value(&vector(x), &vector(v), t)
    }
    fn solve_vv(&mut self, x: &[f64], v: &[f64], t: f64, r: &mut [f64]) -> (f64, bool) {
        let vv = self.0.hessian(&vector(x), &vector(v), t).vv;
        let norm = vv
            .row_iter()
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        match solve_small(&vv, &vector(r)) {
            Some(z) => {
                r.copy_from_slice(z.as_slice());
                (norm, true)
            }
            None => (norm, false),
        }
    }
    fn subtract_vx_product(&mut self, x: &[f64], v: &[f64], t: f64, u: &[f64], out: &mut [f64]) {
        let xv = self.0.hessian(&vector(x), &vector(v), t).xv;
        let product = xv.transpose() * vector::<D>(u);
        for (o, p) in out.iter_mut().zip(product.iter()) {
            *o -= p;
        }
    }
    fn depends_on_time(&self) -> bool {
        self.0.dependence().t
    }
}

/// A slice of length `D` as a vector.
fn vector<const D: usize>(x: &[f64]) -> Vector<D> {
    Vector::<D>::from_column_slice(x)
}

/// The velocity `v` with `∂L/∂v(x, v, t) = p`, from `guess`: the engine's
/// [`invert_momentum`](engine::invert_momentum) for a [`Lagrangian<D>`].
pub(crate) fn invert_momentum<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    x: &Vector<D>,
    t: f64,
    p: &Vector<D>,
    guess: Vector<D>,
    k: usize,
) -> Result<Vector<D>> {
    let mut v = guess;
    let mut r = Vector::<D>::zeros();
    let model = &mut ConstModel::<L, D>(lagrangian);
    let node = (x.as_slice(), t, p.as_slice());
    engine::invert_momentum(model, node, v.as_mut_slice(), r.as_mut_slice(), k)?;
    Ok(v)
}
