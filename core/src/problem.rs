//! [`Problem`], the entry point: a Lagrangian on a grid under a discrete embedding, with the
//! solver settings. It evaluates through its [`Discretisation`] and hands the parts each solver
//! needs to the solvers.

use crate::discretisation::Discretisation;
use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::options::{FractionalSolver, NewtonOptions, SolverOptions};
use crate::solve::start::Start;
use std::ops::RangeInclusive;

mod boundary_value;
mod comparisons;
mod constrained;
mod ensembles;
mod initial_value;

/// A discrete curve from a flat array `[Q_0[0], …, Q_0[D−1], Q_1[0], …]`.
///
/// # Example
///
/// ```
/// let q = varembed::curve_from_flat::<2>(&[0.0, 1.0, 2.0, 3.0])?;
/// assert_eq!(q[1][0], 2.0);
/// assert!(varembed::curve_from_flat::<2>(&[0.0, 1.0, 2.0]).is_err());
/// # Ok::<(), varembed::Error>(())
/// ```
pub fn curve_from_flat<const D: usize>(values: &[f64]) -> Result<Vec<Vector<D>>> {
    if D == 0 || !values.len().is_multiple_of(D) {
        return Err(Error::WrongDimension {
            what: "flat curve",
            dimension: D,
            found: values.len(),
        });
    }
    Ok(values
        .chunks_exact(D)
        .map(Vector::<D>::from_column_slice)
        .collect())
}

/// A Lagrangian on a grid under a discrete embedding.
///
/// The Grünwald–Letnikov operators are dense: on grids of more than 256 steps,
/// [`quadrature_velocities`](Self::quadrature_velocities), [`residual`](Self::residual),
/// [`action`](Self::action) and [`quadrature_energies`](Self::quadrature_energies) (and so the comparisons and the dense-LU Newton's residual) apply
/// them by FFT, `O(N log N)`, instead of `O(N²)` loops, with the weights transformed once per
/// problem. The two routes agree to round-off. The corrected Gauss-GLEσ
/// ([`Embedding::corrected_grunwald_letnikov`]) adds its starting columns beside the FFT
/// products.
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Hessian, Lagrangian, Matrix, Problem, Scheme, Side, Vector};
///
/// struct Free; // L = ½v²
/// impl Lagrangian<1> for Free {
///     fn value(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 { 0.5 * v[0] * v[0] }
///     fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
///         (Vector::<1>::zeros(), *v)
///     }
///     fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
///         Hessian { xx: Matrix::<1>::zeros(), xv: Matrix::<1>::zeros(), vv: Matrix::<1>::identity() }
///     }
/// }
///
/// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 4)?, Embedding::finite_difference(Side::Backward));
/// // A straight line is a solution of both schemes.
/// let q: Vec<Vector<1>> = (0..=4).map(|k| Vector::<1>::new(0.25 * k as f64)).collect();
/// assert!(problem.residual(Scheme::Direct, &q)?.iter().all(|r| r[0].abs() < 1e-14));
/// assert!((problem.action(&q)? - 0.5).abs() < 1e-14);
/// # Ok::<(), varembed::Error>(())
/// ```
pub struct Problem<'l, L: ?Sized, const D: usize> {
    discretisation: Discretisation<'l, L, D>,
    options: SolverOptions,
    /// The start of [`solve_ivp`](Self::solve_ivp) ([`with_start`](Self::with_start)).
    start: Start,
}

impl<'l, L: Lagrangian<D> + ?Sized, const D: usize> Problem<'l, L, D> {
    /// The problem of `lagrangian` on `grid` under `embedding`, with default Newton options.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(problem.grid().n(), 10);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn new(lagrangian: &'l L, grid: Grid, embedding: Embedding) -> Self {
        Problem {
            discretisation: Discretisation::new(lagrangian, grid, embedding),
            options: SolverOptions::default(),
            start: Start::Legendre,
        }
    }

    /// The problem of `lagrangian` on `grid` under the [recommended
    /// embedding](Embedding::recommended) (midpoint), to be solved with
    /// [`Scheme::Variational`]: second order on every smooth Lagrangian, symplectic, no
    /// stability limit on linear oscillations. What the other schemes are for is in
    /// [choosing a scheme](crate::guide::choosing).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Grid, Problem, Scheme, lagrangian};
    ///
    /// /// A double pendulum: `L` couples `x` and `v`, so Gauss-FDEσ would be first order.
    /// #[lagrangian]
    /// fn double_pendulum(x: [f64; 2], v: [f64; 2]) -> f64 {
    ///     v[0] * v[0] + 0.5 * v[1] * v[1] + v[0] * v[1] * (x[0] - x[1]).cos()
    ///         + 2.0 * x[0].cos() + x[1].cos()
    /// }
    ///
    /// let error = |n: usize| -> varembed::Result<f64> {
    ///     let coarse = Problem::recommended(&DoublePendulum, Grid::new(0.0, 1.0, n)?)
    ///         .solve_ivp(Scheme::Variational, [1.0, 0.5], [0.0, 0.0])?;
    ///     let fine = Problem::recommended(&DoublePendulum, Grid::new(0.0, 1.0, 8 * n)?)
    ///         .solve_ivp(Scheme::Variational, [1.0, 0.5], [0.0, 0.0])?;
    ///     Ok((coarse.last() - fine.last()).amax())
    /// };
    /// // Second order: halving h divides the error by 4.
    /// let ratio = error(50)? / error(100)?;
    /// assert!((ratio - 4.0).abs() < 0.3, "{ratio}");
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn recommended(lagrangian: &'l L, grid: Grid) -> Self {
        Problem::new(lagrangian, grid, Embedding::recommended())
    }

    /// With `start` for the node `Q_1` of the initial value problems of
    /// [`solve_ivp`](Self::solve_ivp) (default [`Start::Legendre`]; ignored by the one-step
    /// Gauss–Legendre integrators): the same builder as
    /// [`DynProblem::with_start`](crate::DynProblem::with_start), so a run moves between the
    /// two paths unchanged. [`solve_ivp_with`](Self::solve_ivp_with) takes a start for one run.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, Problem, Scheme, Side, Start, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward))
    ///     .with_start(Start::SecondOrder);
    /// let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// // Q_1 = q0 + h v0 + ½h² q̈(0) with q̈ = −q.
    /// assert!((run.q[1][0] - 0.995).abs() < 1e-12);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_start(mut self, start: Start) -> Self {
        self.start = start;
        self
    }

    /// The same problem with other Newton options.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let strict = NewtonOptions { tolerance: 1e-14, max_iterations: 20 };
    /// assert_eq!(problem.with_newton(strict).newton_options().tolerance, 1e-14);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_newton(mut self, newton: NewtonOptions) -> Self {
        self.options.newton = newton;
        self
    }

    /// The same problem with another linear solver for the boundary value problems of the
    /// fractional embeddings (default [`FractionalSolver::Auto`]: dense LU for small systems,
    /// the FFT Newton–Krylov fast path above). The classical embeddings ignore it.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, FractionalSolver, Grid, Problem, Side};
    /// # use varembed::{Hessian, Lagrangian, Matrix, Vector};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     fn value(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 { 0.5 * v[0] * v[0] }
    /// #     fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
    /// #         (Vector::<1>::zeros(), *v)
    /// #     }
    /// #     fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
    /// #         Hessian { xx: Matrix::<1>::zeros(), xv: Matrix::<1>::zeros(), vv: Matrix::<1>::identity() }
    /// #     }
    /// # }
    /// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 100)?, gle)
    ///     .with_fractional_solver(FractionalSolver::Fast);
    /// let fast = problem.solve_bvp(varembed::Scheme::Variational, 0.0, 1.0)?;
    /// let dense = problem
    ///     .with_fractional_solver(FractionalSolver::Dense)
    ///     .solve_bvp(varembed::Scheme::Variational, 0.0, 1.0)?;
    /// assert!(fast.max_distance(&dense.q).unwrap() < 1e-10);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_fractional_solver(mut self, solver: FractionalSolver) -> Self {
        self.options.fractional = solver;
        self
    }

    /// The same problem with the blow-up guard of the initial value problems on (the default)
    /// or off.
    ///
    /// For a Lagrangian that does not depend on `t`, every run of
    /// [`solve_ivp`](Self::solve_ivp) samples the energy `E = v·∂L/∂v − L` at a stride (every
    /// 64 steps on long runs) and fails with [`Error::BlowUp`] when, over a window of 16
    /// samples, the energy gains more than 16 times what it gained over the first window and
    /// more than a tenth of the largest `|v·∂L/∂v|` seen: Störmer–Verlet at `ωh = 2` exactly,
    /// or a spherical pendulum passing near its pole. Oscillation of the discrete energy (up to
    /// its full amplitude near `ωh = 2`) and the energy lost by the direct Gauss-FDE− scheme do
    /// not trigger it; a Lagrangian that depends on `t` is never guarded (its energy may grow
    /// physically). The rule is in [solvers](crate::guide::solvers). Turn it off to get the
    /// nodes of a growing run anyway.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Error, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// // ω = 1, h = 2: Störmer–Verlet's nodes grow linearly, (−1)ⁿ(1 + 2n).
    /// let grid = Grid::new(0.0, 2000.0, 1000)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_ivp_from_nodes(Scheme::Variational, 1.0, -3.0);
    /// assert!(matches!(run, Err(Error::BlowUp { .. })));
    /// let run = problem
    ///     .with_blow_up_guard(false)
    ///     .solve_ivp_from_nodes(Scheme::Variational, 1.0, -3.0)?;
    /// assert_eq!(run.last()[0], 2001.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_blow_up_guard(mut self, on: bool) -> Self {
        self.options.blow_up_guard = on;
        self
    }

    /// Turns the resolution check of implicit initial value runs on or off (on by default).
    ///
    /// An implicit run (the midpoint rule, the direct Gauss-FDE− step, Gauss–Legendre, and
    /// every step of a model that is not explicit) whose `h ω` at the initial data exceeds 2
    /// per stage carries [`Warning::UnderResolved`](crate::Warning::UnderResolved): it is
    /// stable, but does not follow the fastest motion's phase. A stiff run made on purpose
    /// turns it off.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Scheme, Warning, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// // ω = 1, h = 10: the midpoint rule is stable, and meaningless.
    /// let grid = Grid::new(0.0, 100.0, 10)?;
    /// let problem = Problem::new(&Oscillator, grid, Embedding::midpoint());
    /// let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// assert!(matches!(run.warnings[..], [Warning::UnderResolved { h_omega, .. }] if (h_omega - 10.0).abs() < 1e-6));
    /// let quiet = problem.with_resolution_check(false).solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    /// assert!(quiet.warnings.is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_resolution_check(mut self, on: bool) -> Self {
        self.options.resolution_check = on;
        self
    }

    /// Turns the ill-posedness check of boundary value problems on or off (on by default).
    ///
    /// A solve that converges measures, from its last factorisation, how close the linearised
    /// problem is to singular (a resonance), and flags it with
    /// [`Warning::IllPosed`](crate::Warning::IllPosed); the check costs a few back-substitutions.
    /// Turn it off to time a solve without it, or for a problem known to sit at a resonance.
    ///
    /// # Example
    ///
    /// ```
    /// use std::f64::consts::PI;
    /// use varembed::{Embedding, Grid, Problem, Scheme, Warning, lagrangian};
    ///
    /// #[lagrangian]
    /// fn oscillator(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v - 0.5 * x * x
    /// }
    ///
    /// // q̈ = −q, q(0) = 0, q(π) = 1: no solution. The discrete one exists, and is flagged.
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, PI, 100)?, Embedding::midpoint());
    /// let run = problem.solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    /// assert!(matches!(run.warnings[..], [Warning::IllPosed { .. }]));
    /// let quiet = problem.with_posedness_check(false).solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    /// assert!(quiet.warnings.is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_posedness_check(mut self, on: bool) -> Self {
        self.options.posedness_check = on;
        self
    }

    /// Whether the initial value problems run the blow-up guard.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert!(problem.blow_up_guard());
    /// assert!(!problem.with_blow_up_guard(false).blow_up_guard());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn blow_up_guard(&self) -> bool {
        self.options.blow_up_guard
    }

    /// The linear solver of the fractional boundary value problems.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(problem.fractional_solver(), varembed::FractionalSolver::Auto);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn fractional_solver(&self) -> FractionalSolver {
        self.options.fractional
    }

    /// The grid.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(problem.grid().h(), 0.1);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn grid(&self) -> &Grid {
        self.discretisation.grid()
    }
    /// The embedding.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(problem.embedding().side(), Side::Backward);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn embedding(&self) -> &Embedding {
        self.discretisation.embedding()
    }
    /// The Lagrangian.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(problem.lagrangian().value(&Vector::<1>::new(1.0), &Vector::<1>::new(0.0), 0.0), -0.5);
    /// # use varembed::Lagrangian;
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn lagrangian(&self) -> &'l L {
        self.discretisation.lagrangian()
    }
    /// The Newton options.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(*problem.newton_options(), NewtonOptions::default());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn newton_options(&self) -> &NewtonOptions {
        &self.options.newton
    }

    /// The nodes `k` of the equations of `scheme` (the table in
    /// [schemes](crate::guide::schemes)); entry `i` of [`residual`](Self::residual) is row
    /// `rows.start() + i`.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// assert_eq!(problem.residual_rows(Scheme::Direct), 2..=10);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn residual_rows(&self, scheme: Scheme) -> RangeInclusive<usize> {
        self.discretisation.rows(scheme)
    }

    /// The discrete velocity `V_k = −σ Δ_σ Q_k` (or `−σ Δ^α_σ Q_k`) on the quadrature rows
    /// `k ∈ I_σ`, each paired with its node index `k` (`1..=N` for σ = −, `0..=N−1` for σ = +).
    /// The velocities of a solution at all its nodes are
    /// [`Solution::node_values`](crate::Solution::node_values).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Side, Vector, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(_x: f64, v: f64) -> f64 {
    ///     0.5 * v * v
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 2)?;
    /// let q = [0.0, 1.0, 3.0].map(Vector::<1>::new);
    /// let backward = Problem::new(&Free, grid, Embedding::finite_difference(Side::Backward));
    /// let v = backward.quadrature_velocities(&q)?;
    /// assert_eq!(v, [(1, Vector::<1>::new(2.0)), (2, Vector::<1>::new(4.0))]);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn quadrature_velocities(&self, q: &[Vector<D>]) -> Result<Vec<(usize, Vector<D>)>> {
        let rows = self.embedding().quadrature_rows(self.grid().n());
        Ok(rows.zip(self.discretisation.velocity(q)?).collect())
    }

    /// The residual of `scheme` at `Q` (`N + 1` nodes), one entry per row of
    /// [`residual_rows`](Self::residual_rows).
    ///
    /// - [`Scheme::Direct`] substitutes the operators into Euler–Lagrange:
    ///   `f_k + σ (Δ_σ p)_k` for Gauss-FDEσ, `f_k − σ (Δ_{−σ} p)_k` for the asymmetric
    ///   Gauss-FDEσ, `f_k − σ (Δ^α_{−σ} p)_k` for Gauss-GLEσ.
    /// - [`Scheme::Variational`] is the gradient of the discrete action,
    ///   `(1/h) ∂S_h/∂Q_j = f_j + (Dᵀ p)_j`, `j = 1..=N−1`, assembled through the transpose of
    ///   the velocity operator `D = −σ Δ_σ`.
    ///
    /// The two are computed by separate code: comparing them is the paper's coherence test.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let q: Vec<Vector<1>> = (0..=10).map(|k| Vector::<1>::new((0.1 * k as f64).cos())).collect();
    /// // cos t solves the oscillator up to the scheme's O(h) truncation.
    /// let rows = problem.residual(Scheme::Variational, &q)?;
    /// assert_eq!(rows.len(), 9);
    /// assert!(rows.iter().all(|r| r[0].abs() < 1e-2));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn residual(&self, scheme: Scheme, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        self.discretisation.residual(scheme, q)
    }

    /// The discrete action `S_h(Q) = h Σ_{k∈I_σ} L(Q_k, V_k, t_k)`; for the midpoint and
    /// trapezoidal embeddings `Σ_{k=1}^{N} L_d(Q_{k−1}, Q_k)`
    /// ([schemes](crate::guide::schemes)).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let rest = vec![Vector::<1>::zeros(); 11];
    /// assert_eq!(problem.action(&rest)?, 0.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn action(&self, q: &[Vector<D>]) -> Result<f64> {
        self.discretisation.action(q)
    }

    /// `E_k = V_k·∂L/∂v(Q_k, V_k, t_k) − L(Q_k, V_k, t_k)` on the quadrature rows `k ∈ I_σ`,
    /// each paired with its node index `k`, `V` being the discrete velocity of
    /// [`quadrature_velocities`](Self::quadrature_velocities); for the midpoint and trapezoidal
    /// embeddings, per interval `k = 1..=N`, where their `L_d` evaluates `L`: at
    /// `((Q_{k−1} + Q_k)/2, V_k, t_k − h/2)`, or the mean of the values at both ends. The energy of a solution at all
    /// its nodes is [`Solution::node_values`](crate::Solution::node_values).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Problem, Side, Vector, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(_x: f64, v: f64) -> f64 {
    ///     0.5 * v * v
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 2)?;
    /// let q = [0.0, 1.0, 3.0].map(Vector::<1>::new);
    /// let forward = Problem::new(&Free, grid, Embedding::finite_difference(Side::Forward));
    /// assert_eq!(forward.quadrature_energies(&q)?, [(0, 2.0), (1, 8.0)]);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn quadrature_energies(&self, q: &[Vector<D>]) -> Result<Vec<(usize, f64)>> {
        let rows = self.embedding().quadrature_rows(self.grid().n());
        Ok(rows.zip(self.discretisation.energy(q)?).collect())
    }
}
