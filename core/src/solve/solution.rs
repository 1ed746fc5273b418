//! [`Solution`]: what every solver returns.

use crate::embedding::{Embedding, Scheme};
use crate::error::Result;
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::side::Side;
use crate::solve::nodes::NodeValues;
use crate::stack::with_room_for;
use std::fmt;

/// Something a caller should know about a returned solution that is not an error: the solve
/// succeeded, but the numbers may not mean what they seem.
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, Warning, lagrangian};
/// #[lagrangian]
/// fn pendulum(x: f64, v: f64) -> f64 {
///     0.5 * v * v + x.cos()
/// }
/// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.4)?;
/// let solution = Problem::new(&Pendulum, Grid::new(0.0, 1.0, 20)?, gle).solve_bvp(Scheme::Variational, 0.0, 1.0)?;
/// assert_eq!(solution.warnings, [Warning::IllPosedFractional { alpha: 0.4 }]);
/// // q(0) = 0.5 ≠ 0 under Gauss-GLE− at α = 0.7: infinite action.
/// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
/// let solution = Problem::new(&Pendulum, Grid::new(0.0, 1.0, 20)?, gle).solve_bvp(Scheme::Variational, 0.5, 1.0)?;
/// assert_eq!(
///     solution.warnings,
///     [Warning::InfiniteFractionalAction { alpha: 0.7, side: Side::Backward, value: 0.5 }]
/// );
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// A fractional boundary value problem of order `α ≤ 1/2` with values imposed at both ends.
    ///
    /// The action's natural space is `H^α`, whose curves have point values only for
    /// `α > 1/2`: the end value `q(b)` cannot be imposed on the continuous problem, which in
    /// general has no solution. The discrete system is still solvable, but its solutions need
    /// not converge as `N` grows (a boundary layer forms at `t = b`; on the pendulum
    /// `L = ½v² + cos x` at `α = 1/2` on `[0, 1]`, `Q_0 = 0`, `Q_N = 1`, `Q(1/2)` is 0.466,
    /// 0.426, 0.392 at `N` = 250, 1000, 4000 and still 0.332 at `N = 10⁵`). With compatible data — end values the problem without the
    /// condition at `b` reaches by itself — they do converge; deciding that would take another
    /// solve, so every such problem carries the warning.
    IllPosedFractional {
        /// The order α of the Grünwald–Letnikov embedding.
        alpha: f64,
    },
    /// A Gauss-GLEσ boundary value problem of order `1/2 ≤ α < 1` whose value at the end where
    /// the derivative starts is not zero: `q(a)` for σ = −, `q(b)` for σ = +.
    ///
    /// The Riemann–Liouville derivative of such a curve behaves like
    /// `q(a) (t − a)^{−α} / Γ(1 − α)` next to `a` (σ = −; `(b − t)^{−α}` next to `b` for
    /// σ = +), whose square is not integrable for `α ≥ 1/2`: every curve with these end values
    /// has infinite action, the continuous problem has no minimiser, and the discrete solutions
    /// do not converge as `N` grows (on `L = ½v² − ½x² + x`, `q(0) = 0.3`, `q(1) = 1`, σ = −,
    /// `α = 0.9`, the convergence study's error estimates are 0.0145, 0.0147, 0.0148, 0.0149 at
    /// `N = 50, 100, 200, 400`).
    /// The Caputo forms ([`Embedding::caputo`](crate::Embedding::caputo), and
    /// [`Embedding::corrected_caputo`](crate::Embedding::corrected_caputo), second order on such
    /// data) differentiate `q − q(a)` instead and have a finite action for any end values. For
    /// `α < 1/2` the singular term is square integrable and nothing is flagged here (such
    /// problems carry [`Warning::IllPosedFractional`]); at
    /// `α = 1` the operator is the classical difference, which has no singular term. The end
    /// value counts as not zero above `10⁻⁸` times the solution's largest node
    /// ([solvers](crate::guide::solvers) says why).
    InfiniteFractionalAction {
        /// The order α of the Grünwald–Letnikov embedding.
        alpha: f64,
        /// The side σ: the end is `a` for [`Side::Backward`], `b` for [`Side::Forward`].
        side: Side,
        /// The end value's size `|q(a)|∞` (σ = −) or `|q(b)|∞` (σ = +).
        value: f64,
    },
    /// An implicit initial value run whose step does not resolve the fastest motion of the
    /// equation linearised at the initial data: `h ω` above `limit` (2 per stage: 2 for the
    /// three-point recurrences, `2s` for Gauss–Legendre with `s` stages), where `ω = √|μ|`,
    /// `μ` the eigenvalue of largest modulus of `(∂²L/∂v²)⁻¹(−∂²L/∂x²)` (by power iteration).
    /// An implicit scheme stays stable there (the midpoint rule at any step), so the run
    /// returns `Ok`, but it samples that motion at fewer than `π` points a period: its phase
    /// means nothing (the midpoint rule at `ωh = 10` advances the oscillator's phase by
    /// `2 atan(5) ≈ 2.75` a step, not 10). Take a smaller step, or, for a stiff run made on purpose (a fast mode whose
    /// phase does not matter), turn the check off with `Problem::with_resolution_check(false)`
    /// (`DynProblem::with_resolution_check(false)` for a run-time-dimension model).
    /// Explicit runs are not checked: their stability check stops them first.
    UnderResolved {
        /// The step times the fastest rate, at the initial data.
        h_omega: f64,
        /// The largest accepted `h ω` for this scheme.
        limit: f64,
    },
    /// A boundary value problem whose linearisation at the solution is (nearly) singular: a
    /// resonance, where the continuous problem has no solution or many, and the discrete
    /// nodes grow with `N` or depend on the guess. `measure` is the smallest eigenvalue of the
    /// converged Newton system over the lowest eigenvalue of its kinetic part, `a (πh/T)^{2α}`
    /// (`a` the largest coupling between neighbouring nodes, `T = b − a`): it converges with
    /// the grid (`min_j |(jπ/T)² m − k| / ((π/T)² m)` on `L = ½mv² − ½kx²`), unlike a
    /// condition number, and is flagged below `10⁻²`. `q̈ = −q` on `[0, π]` with `q(0) = 0`,
    /// `q(π) = 1` has none, and is flagged; over `[0, π/2]` it reads ¾. Computed by inverse
    /// iteration on the last factorisation of the banded and dense solves and of the sparse LU
    /// solve of run-time-dimension models; on the fractional fast path from the Ritz values of
    /// a few Lanczos steps, past `2¹⁸` steps first on a grid of `2¹⁸` steps, which decides alone
    /// only where it has Ritz values and each one's modulus, less its bound, lies above 0.1
    /// (the measure converges
    /// with the grid, slowly; see `core/docs/solvers.md`).
    IllPosed {
        /// The measure above.
        measure: f64,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::IllPosedFractional { alpha } => write!(
                f,
                "ill-posed: a fractional boundary value problem of order α = {alpha} ≤ 1/2 with \
                 both end values imposed has no continuous solution for generic data; the \
                 discrete solutions need not converge as N grows"
            ),
            Warning::InfiniteFractionalAction { alpha, side, value } => {
                let (end, sign) = match side {
                    Side::Backward => ("a", "(t − a)^{−α}"),
                    Side::Forward => ("b", "(b − t)^{−α}"),
                };
                write!(
                    f,
                    "infinite action: the curve's value at {end} is not zero (|q({end})| = \
                     {value:.3e}), so its Riemann–Liouville derivative of order α = {alpha} \
                     behaves like {sign} there, whose square is not integrable for α ≥ 1/2: \
                     every curve with these end values has infinite action and the discrete \
                     solutions need not converge as N grows. Use a Caputo form \
                     (Embedding::corrected_caputo, second order, or Embedding::caputo), which \
                     differentiates q − q({end}), or data vanishing at {end}"
                )
            }
            Warning::IllPosed { measure } => write!(
                f,
                "ill-posed: the linearised boundary value problem is nearly singular (smallest \
                 eigenvalue {measure:.2e} of its kinetic part's lowest, below 1e-2): a \
                 resonance, with no solution or many; the nodes may grow with N or depend on \
                 the guess. Change the interval or the end values, or check the model"
            ),
            Warning::UnderResolved { h_omega, limit } => write!(
                f,
                "under-resolved: h·ω = {h_omega:.3} at the initial data (above {limit}): the step \
                 samples the fastest linearised motion at fewer than π points a period, so the \
                 run's phase means nothing; take a smaller step, or turn this check off with \
                 Problem::with_resolution_check(false) for a stiff run made on purpose"
            ),
        }
    }
}

/// A discrete curve computed by a solver, with how it was computed.
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
///
/// #[lagrangian]
/// fn pendulum(x: f64, v: f64) -> f64 {
///     0.5 * v * v + x.cos()
/// }
///
/// let problem = Problem::new(&Pendulum, Grid::new(0.0, 1.0, 100)?, Embedding::finite_difference(Side::Forward));
/// let solution = problem.solve_ivp(Scheme::Direct, 0.5, 0.0)?;
/// assert_eq!((solution.scheme, solution.q.len()), (Scheme::Direct, 101));
/// assert!(solution.newton_iterations > 0 || solution.explicit_steps > 0);
/// assert!(solution.warnings.is_empty());
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Solution<const D: usize> {
    /// The scheme solved.
    pub scheme: Scheme,
    /// The embedding.
    pub embedding: Embedding,
    /// The grid.
    pub grid: Grid,
    /// The nodes `Q_0..=Q_N`.
    pub q: Vec<Vector<D>>,
    /// The discrete momenta `p_0..=p_N` at the nodes, for the schemes that carry them as their
    /// state (the Gauss–Legendre integrators, one-step maps of `(q_k, p_k)`); empty otherwise.
    pub momenta: Vec<Vector<D>>,
    /// Newton iterations, summed over the steps (IVP) or of the global system (BVP).
    pub newton_iterations: usize,
    /// Steps taken by the closed-form update, with no Newton iteration (IVP).
    pub explicit_steps: usize,
    /// What the caller should know about this solution (empty when nothing): e.g.
    /// [`Warning::IllPosedFractional`].
    pub warnings: Vec<Warning>,
}

impl<const D: usize> Solution<D> {
    /// The times of the nodes, `t_k = a + k h` for `k = 0..=N` (`t_N = b` exactly), aligned
    /// with [`q`](Self::q).
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
    /// let grid = Grid::new(0.0, 0.3, 3)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// let t = solution.times();
    /// assert_eq!(t.len(), solution.q.len());
    /// assert_eq!((t[0], t[3]), (0.0, 0.3));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn times(&self) -> Vec<f64> {
        self.grid.nodes()
    }

    /// Time, position, velocity, momentum and (for an autonomous Lagrangian) energy at every
    /// node `t_k`, `k = 0..=N`. `lagrangian` must be the one the solution was computed with.
    ///
    /// The velocities and momenta of a variational scheme are its discrete Legendre
    /// transforms; those of a direct scheme come from its velocity operator
    /// ([`NodeFormula`](crate::NodeFormula)). Both are first order at every node, the end nodes
    /// included, for the Gauss-FDEσ embeddings ([`NodeRule::order`](crate::NodeRule::order)
    /// says so for each embedding and scheme).
    ///
    /// Errors: [`Error::Unsupported`](crate::Error::Unsupported) for Gauss-GLEσ (the fractional
    /// velocity has no value at the end node outside `I_σ`); at node `k`,
    /// [`Error::SingularJacobian`](crate::Error::SingularJacobian) or
    /// [`Error::NewtonDidNotConverge`](crate::Error::NewtonDidNotConverge) when `∂L/∂v = p_k`
    /// cannot be solved for the velocity, [`Error::NotFinite`](crate::Error::NotFinite) when a
    /// value is not finite.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// /// `L = ½mv² − ½kx²`: `p = m v`.
    /// #[lagrangian]
    /// fn spring(x: f64, v: f64, m: f64, k: f64) -> f64 {
    ///     0.5 * m * v * v - 0.5 * k * x * x
    /// }
    ///
    /// let lag = Spring { m: 2.0, k: 2.0 }; // ω = 1
    /// let grid = Grid::new(0.0, 1.0, 1000)?;
    /// let problem = Problem::new(&lag, grid, Embedding::finite_difference(Side::Backward));
    /// let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// let nodes = solution.node_values(&lag)?;
    /// assert_eq!(nodes.rule.order, 1);
    /// for node in nodes.iter() {
    ///     assert!((node.p[0] - 2.0 * node.v[0]).abs() < 1e-12);
    ///     assert!((node.v[0] + node.t.sin()).abs() < 1e-3); // q = cos t, first order
    /// }
    /// let energy = nodes.energy.expect("autonomous");
    /// assert!(energy.iter().all(|e| (e - 1.0).abs() < 1e-3)); // E = ½mv² + ½kx² = 1
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn node_values<L: Lagrangian<D> + ?Sized>(&self, lagrangian: &L) -> Result<NodeValues<D>> {
        with_room_for::<D, _>(|| {
            NodeValues::new(
                lagrangian,
                &self.grid,
                &self.embedding,
                self.scheme,
                (&self.q, &self.momenta),
            )
        })
    }

    /// Component `i` of every node, `None` when `i ≥ D`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(_x: [f64; 2], v: [f64; 2]) -> f64 {
    ///     0.5 * (v[0] * v[0] + v[1] * v[1])
    /// }
    ///
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 4)?, Embedding::finite_difference(Side::Backward));
    /// let line = problem.solve_bvp(Scheme::Variational, [0.0, 1.0], [2.0, -1.0])?;
    /// assert_eq!(line.component(0).unwrap(), [0.0, 0.5, 1.0, 1.5, 2.0]);
    /// assert!(line.component(2).is_none());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn component(&self, i: usize) -> Option<Vec<f64>> {
        (i < D).then(|| self.q.iter().map(|x| x[i]).collect())
    }
    /// The last node `Q_N`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(_x: [f64; 2], v: [f64; 2]) -> f64 {
    ///     0.5 * (v[0] * v[0] + v[1] * v[1])
    /// }
    ///
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 4)?, Embedding::finite_difference(Side::Backward));
    /// let line = problem.solve_bvp(Scheme::Variational, [0.0, 1.0], [2.0, -1.0])?;
    /// assert_eq!(line.last(), varembed::Vector::<2>::new(2.0, -1.0));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn last(&self) -> Vector<D> {
        *self.q.last().expect("a solution has N + 1 ≥ 2 nodes")
    }
    /// Max over nodes of `|Q_k − other_k|∞`; `None` when the lengths differ.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(_x: [f64; 2], v: [f64; 2]) -> f64 {
    ///     0.5 * (v[0] * v[0] + v[1] * v[1])
    /// }
    ///
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 4)?, Embedding::finite_difference(Side::Backward));
    /// let line = problem.solve_bvp(Scheme::Variational, [0.0, 1.0], [2.0, -1.0])?;
    /// let shifted: Vec<_> = line.q.iter().map(|q| q.add_scalar(0.25)).collect();
    /// assert_eq!(line.max_distance(&shifted), Some(0.25));
    /// assert_eq!(line.max_distance(&shifted[1..]), None);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn max_distance(&self, other: &[Vector<D>]) -> Option<f64> {
        (other.len() == self.q.len()).then(|| {
            self.q
                .iter()
                .zip(other)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).amax()))
        })
    }
}
