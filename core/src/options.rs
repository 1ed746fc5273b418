//! Solver settings: the stopping rule of Newton's method, the linear solver of the fractional
//! boundary value problems and its Krylov budget, and the sizes at which the algorithms switch.

/// Stopping rule of Newton's method.
///
/// Every rule is relative to the scale of the equations it solves, the size of the terms
/// their rows balance, with no absolute part: `c L` (`c > 0`) has the Euler–Lagrange equations
/// of `L`, and every solve gives it the same nodes.
///
/// A step of an initial value problem has converged when the max-norm of its residual
/// `G(y) − π` (in momentum units) is at most `tolerance · max(‖π‖∞, ‖p‖∞, h ‖f‖∞)`, with
/// `p = ∂L/∂v` and `f = ∂L/∂x` the terms of `G` at the iterate `y` (`h f` only where `G` has
/// it). The global system of a boundary value problem has converged when its max-norm residual
/// is at most `tolerance · (‖f‖∞ + h^{−α} ‖p‖∞)`, the size of the terms each row balances:
/// `f` at the nodes of the rows, `p` at the quadrature nodes. A value no row reads (`∂L/∂x` at
/// the end node `t = a` or `t = b` outside the rows) plays no part.
///
/// Either has also converged when the residual is down to the round-off it cannot go below,
/// [`ROUND_OFF_FLOOR`](Self::ROUND_OFF_FLOOR)` · ε · ‖J‖∞ · ‖y‖∞` (with `J` the Jacobian and
/// `y` the unknowns): the velocity `(y − b)/h` loses `ε|y|/h` to cancellation, which
/// `J ∼ L_vv/h` carries into the residual, so with small `h` and large coordinates no tolerance
/// below that is reachable. A state where every term is exactly zero (a body at rest at an
/// equilibrium) has an exactly zero residual, which meets the tolerance.
///
/// ```
/// let options = varembed::NewtonOptions { tolerance: 1e-10, ..Default::default() };
/// assert_eq!(options.max_iterations, 50);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Relative tolerance (default `1e-12`).
    pub tolerance: f64,
    /// Iterations before giving up with
    /// [`Error::NewtonDidNotConverge`](crate::error::Error::NewtonDidNotConverge) (default 50).
    pub max_iterations: usize,
}

impl NewtonOptions {
    /// Multiple of `ε ‖J‖∞ ‖y‖∞` below which a residual is round-off (see [`NewtonOptions`]).
    ///
    /// ```
    /// assert_eq!(varembed::NewtonOptions::ROUND_OFF_FLOOR, 64.0);
    /// ```
    pub const ROUND_OFF_FLOOR: f64 = 64.0;
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            tolerance: 1e-12,
            max_iterations: 50,
        }
    }
}

/// Which linear algebra solves the Newton systems of a fractional (Gauss-GLEσ) boundary value
/// problem. Set with `Problem::with_fractional_solver`.
///
/// ```
/// assert_eq!(varembed::FractionalSolver::default(), varembed::FractionalSolver::Auto);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FractionalSolver {
    /// Dense LU when the system is small (`(N − 1)·d ≤`
    /// [`DENSE_LIMIT`](Self::DENSE_LIMIT)), the fast path otherwise; when the fast path's Krylov
    /// solver fails on a system of at most [`DENSE_FALLBACK_LIMIT`](Self::DENSE_FALLBACK_LIMIT)
    /// unknowns, the problem is solved again by dense LU.
    #[default]
    Auto,
    /// Always dense LU: `O((N d)²)` memory and `O((N d)³)` time per Newton iteration (its
    /// residual, like `Problem::residual`, goes by FFT on grids of more than 256 steps). The
    /// reference the fast path is tested against: the assembled Jacobian and LU share nothing
    /// with it.
    Dense,
    /// Always the FFT Newton–Krylov path (`O(N log N)` per iteration, `O(N)` memory), without
    /// dense fallback.
    Fast,
}

impl FractionalSolver {
    /// Unknowns `(N − 1)·d` up to which [`FractionalSolver::Auto`] uses dense LU.
    ///
    /// ```
    /// assert!(varembed::FractionalSolver::DENSE_LIMIT > 0);
    /// ```
    pub const DENSE_LIMIT: usize = 400;
    /// Unknowns up to which [`FractionalSolver::Auto`] falls back to dense LU when the Krylov
    /// solver fails.
    ///
    /// ```
    /// assert!(varembed::FractionalSolver::DENSE_FALLBACK_LIMIT > 0);
    /// ```
    pub const DENSE_FALLBACK_LIMIT: usize = 1500;
    /// Unknowns above which [`FractionalSolver::Dense`] refuses, up front, with
    /// [`Error::TooLarge`](crate::Error::TooLarge): its LU of `(N d)³/3` flops a Newton
    /// iteration would take minutes to hours (at `N = 10⁴`, 3·10¹¹ flops and 800 MB per
    /// iteration), where the fast path takes seconds.
    ///
    /// ```
    /// use varembed::{Embedding, Error, FractionalSolver, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn free(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v
    /// }
    ///
    /// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 10_000)?, gle)
    ///     .with_fractional_solver(FractionalSolver::Dense);
    /// let error = problem.solve_bvp(Scheme::Variational, 0.0, 1.0).unwrap_err();
    /// assert!(matches!(&error, Error::TooLarge { what } if what.contains("FractionalSolver::Fast")));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub const DENSE_MAX: usize = 5000;
}

/// Grids with more steps than this apply the dense fractional operators by FFT in the
/// residuals, velocity, action and energy. Below it the dense loops cost less than planning the
/// FFT (at `N = 256` a dense product is about 3·10⁴ multiply–adds).
pub(crate) const FFT_OPERATOR_THRESHOLD: usize = 256;

/// The number of degrees of freedom from which [`Problem`](crate::Problem) solves the initial
/// value problems (and the Gauss-FDEσ and asymmetric boundary value problems) of a model that
/// is also a [`DynLagrangian`](crate::DynLagrangian) (every `#[lagrangian]` model with loops
/// over `[f64; N]`, see [`Lagrangian::run_time`](crate::Lagrangian::run_time)) with the
/// run-time-dimension engine:
/// from there on its steps are as fast or faster, and nothing of size `D × D` is put on the
/// stack ([solvers](crate::guide::solvers#large-models-run-time-dimension-and-sparse-newton)).
///
/// ```
/// assert!(varembed::RUN_TIME_FROM <= 256);
/// ```
pub const RUN_TIME_FROM: usize = 64;

/// Iteration budgets of the Krylov solvers (per Newton system of the fractional fast path).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct KrylovBudget {
    pub minres_iterations: usize,
    pub gmres_iterations: usize,
    pub restart: usize,
}

impl Default for KrylovBudget {
    fn default() -> Self {
        KrylovBudget {
            minres_iterations: 1000,
            gmres_iterations: 300,
            restart: 30,
        }
    }
}

/// How the Newton systems of a boundary value problem of run-time dimension
/// ([`DynProblem::solve_bvp`](crate::DynProblem::solve_bvp)) are solved
/// ([`DynProblem::with_bvp_solver`](crate::DynProblem::with_bvp_solver)); what was used is
/// [`DynRun::linear_solve`](crate::DynRun::linear_solve).
///
/// ```
/// assert_eq!(varembed::BvpSolver::default(), varembed::BvpSolver::Auto);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BvpSolver {
    /// Preconditioned MINRES for a variational scheme with at least
    /// [`MINRES_FROM`](Self::MINRES_FROM) unknowns, sparse LU otherwise.
    #[default]
    Auto,
    /// Always sparse LU after a fill-reducing ordering: memory grows with the factors' fill
    /// (about 3.4 GB at `10⁶` unknowns of a chain).
    SparseLu,
    /// Preconditioned MINRES for the variational schemes of the three-point embeddings (whose
    /// Jacobian, the Hessian of the discrete action, is symmetric), with `O(N d)` memory;
    /// sparse LU where the Jacobian is not symmetric: the direct schemes, a forced model, and
    /// Gauss–Legendre's collocation system. When the preconditioner is not positive definite
    /// or MINRES does not converge, the problem is solved again by sparse LU from the initial
    /// guess and the reason is reported ([`LinearSolve::SparseLuAfterMinres`]).
    Minres,
}

impl BvpSolver {
    /// Unknowns `(N − 1) d` from which [`BvpSolver::Auto`] solves a variational scheme by
    /// MINRES.
    ///
    /// ```
    /// assert!(varembed::BvpSolver::MINRES_FROM > 0);
    /// ```
    pub const MINRES_FROM: usize = 100_000;
}

/// How the Newton systems of a boundary value problem of run-time dimension were solved.
#[derive(Clone, Debug, PartialEq)]
pub enum LinearSolve {
    /// By sparse LU.
    SparseLu,
    /// By preconditioned MINRES, `products` products with the Jacobian in all (the inverse
    /// iteration of the conditioning check at the solution included).
    Minres {
        /// Products with the Jacobian.
        products: usize,
    },
    /// MINRES was tried and the problem was solved again by sparse LU, for `reason`.
    SparseLuAfterMinres {
        /// Why MINRES gave way.
        reason: String,
        /// The products with the Jacobian MINRES made before it gave way (the cost of the
        /// attempt, on top of the sparse LU's).
        products: usize,
    },
}

/// Everything the solvers are told besides the discretisation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SolverOptions {
    pub newton: NewtonOptions,
    pub fractional: FractionalSolver,
    pub krylov: KrylovBudget,
    /// Whether the initial value problems run the blow-up guard (default on).
    pub blow_up_guard: bool,
    /// Whether implicit initial value runs check their step against the fastest linearised
    /// motion at the initial data (default on; `Warning::UnderResolved`).
    pub resolution_check: bool,
    /// Whether boundary value problems measure how close their linearisation is to singular
    /// (default on; `Warning::IllPosed`).
    pub posedness_check: bool,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            newton: NewtonOptions::default(),
            fractional: FractionalSolver::default(),
            krylov: KrylovBudget::default(),
            blow_up_guard: true,
            resolution_check: true,
            posedness_check: true,
        }
    }
}
