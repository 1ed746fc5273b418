//! [`Problem`], the entry point: a Lagrangian on a grid under a discrete embedding, with the
//! solver settings. It evaluates through its [`Discretisation`] and hands the parts each solver
//! needs to the solvers.

use crate::compare::{CompareOptions, Comparer, Comparison, Convergence};
use crate::discretisation::Discretisation;
use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::lagrangian::{IntoVector, Lagrangian, Vector};
use crate::options::{FractionalSolver, NewtonOptions, SolverOptions};
use crate::solve::bvp;
use crate::solve::ivp::{Ivp, Start};
use crate::solve::solution::Solution;
use std::ops::RangeInclusive;

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
/// [`velocity`](Self::velocity), [`residual`](Self::residual), [`action`](Self::action) and
/// [`energy`](Self::energy) (and so the comparisons and the dense-LU Newton's residual) apply
/// them by FFT, `O(N log N)`, instead of `O(N²)` loops, with the weights transformed once per
/// problem. The two routes agree to round-off.
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
}

impl<'l, L: Lagrangian<D> + ?Sized, const D: usize> Problem<'l, L, D> {
    /// The problem of `lagrangian` on `grid` under `embedding`, with default Newton options.
    pub fn new(lagrangian: &'l L, grid: Grid, embedding: Embedding) -> Self {
        Problem {
            discretisation: Discretisation::new(lagrangian, grid, embedding),
            options: SolverOptions::default(),
        }
    }

    /// The same problem with other Newton options.
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
    /// physically). The rule is in `docs/solvers.md`. Turn it off to get the nodes of a
    /// growing run anyway.
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

    /// Whether the initial value problems run the blow-up guard.
    pub fn blow_up_guard(&self) -> bool {
        self.options.blow_up_guard
    }

    /// The linear solver of the fractional boundary value problems.
    pub fn fractional_solver(&self) -> FractionalSolver {
        self.options.fractional
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        self.discretisation.grid()
    }
    /// The embedding.
    pub fn embedding(&self) -> &Embedding {
        self.discretisation.embedding()
    }
    /// The Lagrangian.
    pub fn lagrangian(&self) -> &'l L {
        self.discretisation.lagrangian()
    }
    /// The Newton options.
    pub fn newton_options(&self) -> &NewtonOptions {
        &self.options.newton
    }

    /// The nodes `k` of the equations of `scheme` (the table in `docs/schemes.md`); entry `i`
    /// of [`residual`](Self::residual) is row `rows.start() + i`.
    pub fn residual_rows(&self, scheme: Scheme) -> RangeInclusive<usize> {
        self.discretisation.rows(scheme)
    }

    /// The discrete velocity `V = −σ Δ_σ Q` (or `−σ Δ^α_σ Q`) on the quadrature rows `I_σ`.
    pub fn velocity(&self, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        self.discretisation.velocity(q)
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
    pub fn residual(&self, scheme: Scheme, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        self.discretisation.residual(scheme, q)
    }

    /// The discrete action `S_h(Q) = h Σ_{k∈I_σ} L(Q_k, V_k, t_k)`; for the midpoint and
    /// trapezoidal embeddings `Σ_{k=1}^{N} L_d(Q_{k−1}, Q_k)` (docs/schemes.md).
    pub fn action(&self, q: &[Vector<D>]) -> Result<f64> {
        self.discretisation.action(q)
    }

    /// `E_k = V_k·∂L/∂v(Q_k, V_k, t_k) − L(Q_k, V_k, t_k)` on the quadrature nodes `I_σ`; for
    /// the midpoint and trapezoidal embeddings, per interval `k = 1..=N`, where their `L_d`
    /// evaluates `L`: at `((Q_{k−1} + Q_k)/2, V_k, t_k − h/2)`, or the mean of the values at
    /// both ends.
    pub fn energy(&self, q: &[Vector<D>]) -> Result<Vec<f64>> {
        self.discretisation.energy(q)
    }

    /// Solves the boundary value problem `Q_0 = qa`, `Q_N = qb` for `scheme`, from the straight
    /// line between them. Works for every embedding.
    ///
    /// Newton's method on the rows of [`residual`](Self::residual), with a backtracking line
    /// search on the max-norm of the residual. Errors: [`Error::SingularJacobian`],
    /// [`Error::NewtonDidNotConverge`] (iterations, last residual) and [`Error::NotFinite`],
    /// located at the global Newton iteration; on the fractional fast path (see
    /// [`FractionalSolver`]) also [`Error::KrylovDidNotConverge`].
    pub fn solve_bvp(
        &self,
        scheme: Scheme,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        let guess = bvp::straight_line(qa.into_vector(), qb.into_vector(), self.grid().n());
        self.solve_bvp_from(scheme, &guess)
    }

    /// Solves the boundary value problem from an initial guess of all `N + 1` nodes; its first
    /// and last nodes are the boundary values.
    pub fn solve_bvp_from(&self, scheme: Scheme, guess: &[Vector<D>]) -> Result<Solution<D>> {
        bvp::solve(&self.discretisation, &self.options, scheme, guess)
    }
}

// Initial value problems: each method hands the problem's parts to the IVP solver.
impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// The parts of this problem an initial value problem needs.
    fn ivp(&self) -> Ivp<'_, L, D> {
        Ivp::new(&self.discretisation, &self.options)
    }

    /// The discrete Legendre start: `Q_1` from `Q_0 = q(a)` and `π_0 = ∂L/∂v(q(a), q̇(a), a)`,
    /// by the variational step equation of this side (σ=−: `∂L/∂v(Q_1, (Q_1−Q_0)/h, t_1) = π_0`;
    /// σ=+: `p_0 − h f_0 = π_0` at `(Q_0, (Q_1−Q_0)/h, t_0)`; midpoint and trapezoidal:
    /// `−D₁L_d(Q_0, Q_1) = π_0`).
    pub fn legendre_start(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Vector<D>> {
        self.ivp()
            .legendre_start(q0.into_vector(), v0.into_vector())
    }

    /// The second-order start `Q_1 = Q_0 + h q̇(a) + ½h² q̈(a)`, with `q̈(a)` solved from the
    /// Euler–Lagrange equation at `a`: `L_vv q̈ = ∂L/∂x − L_vx q̇ − ∂²L/∂v∂t`.
    ///
    /// `∂²L/∂v∂t` is not among the Hessian blocks; it is taken by a central difference of
    /// `∂L/∂v` in `t` with step `10⁻⁵ (1 + |a|)` (error `O(10⁻¹⁰)`, far below the `O(h³)` of the
    /// start itself; exactly zero for a Lagrangian that does not depend on `t`).
    /// Errors with [`Error::SingularJacobian`] at step 1 when `L_vv` is singular.
    pub fn second_order_start(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Vector<D>> {
        self.ivp()
            .second_order_start(q0.into_vector(), v0.into_vector())
    }

    /// Solves the initial value problem with the chosen [`Start`] for `Q_1`.
    pub fn solve_ivp_with(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        start: Start,
    ) -> Result<Solution<D>> {
        self.ivp()
            .solve(scheme, q0.into_vector(), v0.into_vector(), start)
    }

    /// Solves the initial value problem `q(a) = q0`, `q̇(a) = v0` with `scheme`, starting from
    /// the discrete Legendre start (the same `Q_1` for both schemes).
    ///
    /// A step whose equation is affine in the newest node (as declared by
    /// [`Lagrangian::hessian_dependence`]) is taken in closed form, with no Newton iteration.
    ///
    /// Errors: [`Error::Unsupported`] for Gauss-GLEσ; at step `n`,
    /// [`Error::SingularJacobian`], [`Error::NewtonDidNotConverge`] (with the last residual) or
    /// [`Error::Unstable`] (the linearised step map, checked at step 2 and every 1024 steps, has
    /// a real eigenvalue below −1 or one of modulus ≥ 2: the step is too large for the scheme)
    /// or [`Error::NotFinite`] (e.g. a recurrence overflowing between two checks); for a
    /// Lagrangian that does not depend on `t`, [`Error::BlowUp`] over a window of steps where the
    /// energy grew far beyond the early run's (see
    /// [`with_blow_up_guard`](Self::with_blow_up_guard)).
    pub fn solve_ivp(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        self.ivp()
            .solve(scheme, q0.into_vector(), v0.into_vector(), Start::Legendre)
    }

    /// Runs the recurrence of `scheme` from given first nodes `Q_0`, `Q_1`.
    pub fn solve_ivp_from_nodes(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        q1: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        self.ivp()
            .solve_from_nodes(scheme, q0.into_vector(), q1.into_vector())
    }
}

// Comparisons of the two schemes: each method hands the problem's parts to the comparison.
impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    fn comparer(&self) -> Comparer<'_, '_, L, D> {
        Comparer {
            discretisation: &self.discretisation,
            options: &self.options,
        }
    }

    /// Compares both schemes on the initial value problem `q(a) = q0`, `q̇(a) = v0` (discrete
    /// Legendre start, no reference, observed order by self-convergence).
    pub fn compare_ivp(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Comparison<D>> {
        self.compare_ivp_with(q0, v0, &CompareOptions::default())
    }

    /// [`compare_ivp`](Self::compare_ivp) with options.
    pub fn compare_ivp_with(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        options: &CompareOptions<'_, D>,
    ) -> Result<Comparison<D>> {
        self.comparer()
            .compare_ivp(q0.into_vector(), v0.into_vector(), options)
    }

    /// Compares both schemes on the boundary value problem `Q_0 = qa`, `Q_N = qb`.
    pub fn compare_bvp(
        &self,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<Comparison<D>> {
        self.compare_bvp_with(qa, qb, &CompareOptions::default())
    }

    /// [`compare_bvp`](Self::compare_bvp) with options (the start is not used).
    pub fn compare_bvp_with(
        &self,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
        options: &CompareOptions<'_, D>,
    ) -> Result<Comparison<D>> {
        self.comparer()
            .compare_bvp(qa.into_vector(), qb.into_vector(), options)
    }

    /// Solves the initial value problem `q(a) = q0`, `q̇(a) = v0` with `scheme` on
    /// `N, 2N, …, 2^{levels−1} N` steps (`N` this problem's), with `options.start`, timing each
    /// solve and measuring its error against `options.reference`. A size that fails is recorded
    /// in [`Convergence::failures`] and the run goes on.
    pub fn convergence_ivp(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        options: &CompareOptions<'_, D>,
        levels: usize,
    ) -> Convergence<D> {
        self.comparer()
            .convergence_ivp(scheme, q0.into_vector(), v0.into_vector(), options, levels)
    }

    /// [`convergence_ivp`](Self::convergence_ivp) for the boundary value problem `Q_0 = qa`,
    /// `Q_N = qb` (the start is not used).
    pub fn convergence_bvp(
        &self,
        scheme: Scheme,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
        options: &CompareOptions<'_, D>,
        levels: usize,
    ) -> Convergence<D> {
        self.comparer()
            .convergence_bvp(scheme, qa.into_vector(), qb.into_vector(), options, levels)
    }

    /// The comparison at this problem's grid from a run of each scheme that solved it (same
    /// data and options, e.g. the sweeps of a work–precision report): nothing is solved again,
    /// the solutions, errors and wall times are the runs', and each order is
    /// [`Convergence::order_at`] this `N`. Errors if a run failed at this `N` (that failure), or
    /// is of the wrong scheme, or did not solve this problem's grid and embedding.
    pub fn compare_runs(
        &self,
        direct: &Convergence<D>,
        variational: &Convergence<D>,
    ) -> Result<Comparison<D>> {
        self.comparer().compare_runs(direct, variational)
    }
}
