//! Typed errors: every failure of the library is one of these, never a panic or a silent NaN.

use thiserror::Error;

/// Where a solver failed.
///
/// ```
/// use varembed::Location;
/// assert_eq!(Location::Step(3).to_string(), "step 3 (node Q_3)");
/// assert_eq!(Location::Node(0).to_string(), "node Q_0");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A step of an initial value problem: the index `n` of the node `Q_n` being computed
    /// (`n = 1` is the discrete Legendre start; `n = 0` names the initial data `q(a)`, `q̇(a)`).
    Step(usize),
    /// A Newton iteration of a boundary value problem (the global system).
    Newton(usize),
    /// The evaluation of the Lagrangian at node `Q_k`.
    Node(usize),
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Location::Step(0) => write!(f, "the initial data (node Q_0)"),
            Location::Step(n) => write!(f, "step {n} (node Q_{n})"),
            Location::Newton(i) => write!(f, "global Newton iteration {i}"),
            Location::Node(k) => write!(f, "node Q_{k}"),
        }
    }
}

/// Everything that can go wrong in varembed.
///
/// ```
/// use varembed::{Embedding, Error, Side};
/// let error = Embedding::grunwald_letnikov(Side::Backward, 1.5).unwrap_err();
/// assert!(matches!(error, Error::AlphaOutOfRange { alpha } if alpha == 1.5));
/// ```
///
/// New variants may be added (the enum is `#[non_exhaustive]`): match with a wildcard arm, and
/// on a variant's fields with `..`, since a variant may gain a field.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The grid `[a, b]` with `N` steps is not usable.
    #[error("invalid grid [{a}, {b}] with N = {n}: {reason}")]
    InvalidGrid {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
        /// Number of steps.
        n: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// The Grünwald–Letnikov order must satisfy `0 < α ≤ 1`.
    #[error("fractional order α = {alpha} is outside (0, 1]")]
    AlphaOutOfRange {
        /// The order given.
        alpha: f64,
    },
    /// The number of stages of a Gauss–Legendre integrator must lie in `1..=4`.
    #[error("a Gauss–Legendre integrator of {stages} stages is not offered: stages must be 1 to 4")]
    StagesOutOfRange {
        /// The number of stages given.
        stages: usize,
    },
    /// An input value is NaN or infinite.
    #[error("non-finite input: {what}")]
    NonFiniteInput {
        /// Which input.
        what: String,
    },
    /// A time asked of a solution's dense output ([`Solution::at`](crate::Solution::at),
    /// [`DynSolution::at`](crate::DynSolution::at) and their Lagrangian forms) is NaN or lies
    /// outside the interval `[a, b]` the solution was computed on.
    #[error("the time t = {t} is outside the solution's interval [{a}, {b}]")]
    TimeOutOfRange {
        /// The time asked for.
        t: f64,
        /// The left end `a` of the grid.
        a: f64,
        /// The right end `b` of the grid.
        b: f64,
    },
    /// A discrete curve or vector has the wrong number of entries.
    #[error("wrong length for {what}: expected {expected}, found {found}")]
    WrongLength {
        /// Which input.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Length given.
        found: usize,
    },
    /// A flat array does not split into points of the Lagrangian's dimension.
    #[error(
        "wrong dimension for {what}: {found} values do not split into points of dimension {dimension}"
    )]
    WrongDimension {
        /// Which input.
        what: &'static str,
        /// The dimension `d` expected.
        dimension: usize,
        /// Number of values given.
        found: usize,
    },
    /// The operation needs another kind of embedding (e.g. an initial value problem of a
    /// fractional embedding, whose operator is not a three-point recurrence).
    #[error("{operation} is not available for {embedding}")]
    Unsupported {
        /// What was asked.
        operation: &'static str,
        /// The embedding it was asked of.
        embedding: String,
    },
    /// A model of run-time dimension cannot be evaluated at its dimension: it reads a component
    /// beyond it, or a loop's range needs more components (see
    /// [`DynLagrangian::invalid_dimension`](crate::DynLagrangian::invalid_dimension)).
    #[error("invalid model: {reason}")]
    InvalidModel {
        /// What is wrong, naming the model's dimension.
        reason: String,
    },
    /// A finite input lies outside the domain of the Lagrangian: `L`, its gradient or its
    /// Hessian is not finite there (an initial velocity above the speed of light of a
    /// relativistic particle; a boundary value or initial guess at the singularity of a
    /// potential). Checked before any step is taken.
    #[error(
        "{what} is outside the domain of the Lagrangian: L or its derivatives are not finite there"
    )]
    OutsideDomain {
        /// Which input, with its value.
        what: String,
    },
    /// The Lagrangian is degenerate: `∂²L/∂v²` is singular (relative to its own scale) at a
    /// node, so the Euler–Lagrange equation does not determine the acceleration there and no
    /// scheme's solution means anything.
    ///
    /// The `measure` is `min |u_ii| / max(max |u_ii|, s)` over the pivots `u_ii` of the LU
    /// factorisation with partial pivoting of `∂²L/∂v²` at the node, where `s` is the largest
    /// pivot at the start of the run (the initial data of an initial value problem, the nodes
    /// of the initial guess or of the solution of a boundary value problem): scale-free, so
    /// `10⁻⁸ I` passes, and for `d = 1` it measures `L_vv` against its size at the start. It is
    /// degenerate below `10⁻¹²`: a singular `∂²L/∂v²` computed in floating point has pivots of
    /// the order of the round-off `10⁻¹⁶` of its scale, and above the threshold the
    /// acceleration `L_vv⁻¹ (…)` keeps at least four significant digits. Checked at the
    /// initial data before any step, and along an initial value problem where its stability
    /// check runs (every 1024 steps) and at the last node; on the initial guess and the
    /// solution of a boundary value problem.
    ///
    /// [`SingularJacobian`](Error::SingularJacobian) is a different failure: the Jacobian of a
    /// *step* (or of the global Newton system) is singular, which a regular Lagrangian can meet
    /// at one step size (e.g. the implicit direct step of `½v² + ½x²` at `h = 1`), and which a
    /// degenerate one need not meet at all (`L = x·v − ½x²` has `L_vv ≡ 0` but regular step
    /// Jacobians: its runs would return a meaningless curve). A Lagrangian degenerate only at
    /// isolated points, such as the spherical pendulum at the pole, is reported here when a
    /// checked node lands on one, and otherwise shows through the steps near it.
    ///
    /// `directions` names where `∂²L/∂v²` degenerates: a basis of its numerical null space
    /// (the eigenvectors whose eigenvalue is at most `10⁻¹⁰` of the largest in modulus, or the
    /// one of the smallest), each as its largest components `(index, value)` of a unit vector.
    /// A velocity along one of them changes `∂L/∂v` by nothing: a coordinate whose velocity
    /// does not enter `L` (a missing kinetic term, a gauge freedom), or one that enters only
    /// linearly. Computed up to `d = 1024` (empty above).
    ///
    /// ```
    /// use varembed::{Error, Location};
    /// let e = Error::DegenerateLagrangian {
    ///     at: Location::Step(0),
    ///     measure: 0.0,
    ///     directions: vec![vec![(0, 0.7071), (1, -0.7071)]],
    /// };
    /// assert!(e.to_string().contains("along (v₀ 0.707, v₁ -0.707)"));
    /// ```
    #[error(
        "the Lagrangian is degenerate at {at}: ∂²L/∂v² has the pivot ratio {measure:.3e} (below 1e-12){}; give every coordinate a kinetic term (regularise L), or remove the coordinates it does not govern",
        null_directions(.directions)
    )]
    DegenerateLagrangian {
        /// The node where `∂²L/∂v²` was found degenerate: `Step(k)` for node `Q_k` of an
        /// initial value problem (`Step(0)`: the initial data), `Node(k)` for a boundary value
        /// problem.
        at: Location,
        /// The pivot ratio that failed (see above).
        measure: f64,
        /// The degenerate directions (see above).
        directions: Vec<Vec<(usize, f64)>>,
    },
    /// A Jacobian is singular: a step's or the global Newton system's (see
    /// [`DegenerateLagrangian`](Error::DegenerateLagrangian) for a degenerate `∂²L/∂v²`).
    #[error("singular Jacobian at {at}")]
    SingularJacobian {
        /// Where.
        at: Location,
    },
    /// Newton's method met its tolerance at a point where the system it solves is singular to
    /// working precision (condition number at least `1/ε ≈ 4.5e15`): the nodes it would return
    /// are round-off, however small their residual. A boundary value problem at a resonance
    /// (see [`Warning::IllPosed`](crate::Warning::IllPosed)), or scales that double precision
    /// cannot hold in one system (masses or stiffnesses more than about `1e8` apart, whose
    /// Jacobian entries differ by that squared over the step), end here.
    #[error(
        "the Newton system is singular to working precision at {at}: its condition number is at \
         least {condition:.1e} (1/ε = 4.5e15), so the nodes would be round-off; check that the \
         problem has a solution (no resonance between the boundary data), nondimensionalise a \
         model whose masses or stiffnesses are many orders of magnitude apart, or remove a \
         degree of freedom too light or too stiff to matter"
    )]
    IllConditioned {
        /// Where (the converged Newton iteration).
        at: Location,
        /// A lower bound of the 2-norm condition number of the Newton system there.
        condition: f64,
    },
    /// Newton's method did not reach the tolerance.
    #[error(
        "Newton did not converge at {at} after {iterations} iterations: residual {residual:.3e}"
    )]
    NewtonDidNotConverge {
        /// Where (the step index for an IVP).
        at: Location,
        /// Iterations run.
        iterations: usize,
        /// Max-norm of the last residual.
        residual: f64,
    },
    /// The recurrence is numerically unstable at this step size: its linearisation has an
    /// eigenvalue `λ` that is real and below `−1` (the sawtooth mode of an under-resolved step)
    /// or of modulus at least 2 (see `Problem::solve_ivp`).
    ///
    /// `largest_stable_step` is the remedy: the largest step at which this scheme is stable on
    /// the linearisation at the node where the check ran, `h_c / ω`, with `ω` the fastest
    /// frequency of the linearised equation there (the square root of the largest eigenvalue of
    /// `(∂²L/∂v²)⁻¹(−∂²L/∂x²)`) and `h_c` the scheme's limit of `hω` on the harmonic oscillator
    /// (2 for Störmer–Verlet and the other explicit variational steps). `None` when it could not
    /// be measured (no positive frequency). The limits `h_c` on the oscillator: 2 for the
    /// variational Gauss-FDE, trapezoidal and direct midpoint steps, `√3` for the direct
    /// Gauss-FDE+ step; the midpoint variational integrator and the Gauss–Legendre integrators
    /// are A-stable (no limit), and the direct Gauss-FDE− step, implicit, has none either.
    ///
    /// ```
    /// use varembed::{Error, Location};
    /// let e = Error::Unstable { at: Location::Step(2), re: -3.0, im: 0.0, largest_stable_step: Some(0.5) };
    /// assert!(e.to_string().contains("use a step h ≤ 5.000e-1"));
    /// ```
    #[error(
        "the scheme is unstable at {at}: its step map has the eigenvalue {re:.4} {im:+.4}i{}",
        stable_step_remedy(.largest_stable_step)
    )]
    Unstable {
        /// Where the check ran.
        at: Location,
        /// Real part of the offending eigenvalue.
        re: f64,
        /// Imaginary part of the offending eigenvalue.
        im: f64,
        /// The largest stable step of this scheme on the measured linearisation (see above).
        largest_stable_step: Option<f64>,
    },
    /// A problem too large for this machine or this solver, reported before any work: `what`
    /// names what would not fit and what to do instead (a grid whose nodes cannot be stored,
    /// a dense fractional solve of hours).
    #[error("too large: {what}")]
    TooLarge {
        /// What would not fit, and the remedy.
        what: String,
    },
    /// The Krylov solver of the fractional fast path (MINRES, or GMRES where some `∂²L/∂v²` is
    /// not positive definite) did not solve a Newton system `J δ = r` to the forcing tolerance
    /// (nor below 0.1, which still makes an inexact Newton step): the Jacobian is (nearly)
    /// singular, or so indefinite that the preconditioner cannot tame it. The message names the
    /// remedies: the dense solver, `FractionalSolver::Dense`, up to
    /// [`FractionalSolver::DENSE_MAX`](crate::FractionalSolver::DENSE_MAX) unknowns (LU does not
    /// care about indefiniteness), or an initial guess nearer the solution
    /// (`Problem::solve_bvp_from`), where the Jacobian is the one of the solution.
    ///
    /// ```
    /// use varembed::{Error, Location};
    /// let e = Error::KrylovDidNotConverge { at: Location::Newton(2), iterations: 1000, residual: 0.8 };
    /// assert!(e.to_string().contains("FractionalSolver::Dense"));
    /// ```
    #[error(
        "the Krylov solver did not converge at {at} after {iterations} iterations: relative linear residual {residual:.3e}; the Newton system is (nearly) singular or strongly indefinite: solve with FractionalSolver::Dense (up to FractionalSolver::DENSE_MAX unknowns), or from an initial guess nearer the solution (Problem::solve_bvp_from)"
    )]
    KrylovDidNotConverge {
        /// Where (the global Newton iteration).
        at: Location,
        /// Products with the Jacobian made by the last Krylov solver tried.
        iterations: usize,
        /// Its relative residual `‖r − J δ‖₂ / ‖r‖₂`.
        residual: f64,
    },
    /// The energy of an initial value problem of an autonomous Lagrangian grew, in the window
    /// of steps `from..=to`, far beyond what the early run shows: the step is too large for
    /// the motion (Störmer–Verlet at `ωh = 2` exactly, a pendulum passing near a singular
    /// point of its coordinates). The rule, and how to disable it
    /// (`Problem::with_blow_up_guard(false)`), are in [solvers](crate::guide::solvers).
    #[error(
        "blow-up between step {from} and step {to}: the energy gained {growth:.3e} times its early gain; try a smaller step h"
    )]
    BlowUp {
        /// The first step of the window where the growth was seen.
        from: usize,
        /// The last step of that window.
        to: usize,
        /// The window's largest energy gain over the gain of the first window.
        growth: f64,
    },
    /// Initial data violate a holonomic constraint `g(q) = 0` or its derivative
    /// `G(q) q̇ = 0` beyond the tolerance `1e-10` relative to the constraint's terms
    /// (`|G_i(q)| |q|` or `|G_i(q)| |q̇|`).
    #[error(
        "the initial {what} violates constraint {constraint}: residual {residual:.3e}; project the data onto the constraints with `project_initial_data`"
    )]
    InconsistentInitialData {
        /// `"position"` (`g_i(q(a)) ≠ 0`) or `"velocity"` (`G_i(q(a)) q̇(a) ≠ 0`).
        what: &'static str,
        /// The index `i` of the violated constraint.
        constraint: usize,
        /// `g_i(q(a))` or `G_i(q(a)) q̇(a)`.
        residual: f64,
    },
    /// An end value of a boundary value problem violates a holonomic constraint `g(q) = 0`
    /// beyond the tolerance `1e-10` relative to the constraint's terms
    /// (`|G_i(q)| max(|q|, 1)`).
    #[error(
        "the end value at {end} violates constraint {constraint}: residual {residual:.3e}; give end values on the constraints (`project_initial_data` projects a position)"
    )]
    InconsistentBoundaryData {
        /// `"a"` (`Q_0`) or `"b"` (`Q_N`).
        end: &'static str,
        /// The index `i` of the violated constraint.
        constraint: usize,
        /// `g_i` at the end value.
        residual: f64,
    },
    /// The constraint Jacobian `G = ∂g/∂x` has dependent rows at a node: the ratio of its
    /// smallest to its largest singular value is below `1e-12`, so the multipliers are not
    /// determined (two constraints that say the same thing, or a singular point of the
    /// constraint manifold).
    #[error(
        "the constraint Jacobian is rank-deficient at {at}: singular value ratio {ratio:.3e}; remove a redundant constraint or move off the singular configuration"
    )]
    RankDeficientConstraints {
        /// Where.
        at: Location,
        /// Smallest over largest singular value of `G`.
        ratio: f64,
    },
    /// The operation needs every node of a run, and the solution stores only some of them (a
    /// run of [`DynProblem::solve_ivp_every`](crate::DynProblem::solve_ivp_every) with a
    /// stride above 1): the velocities and momenta at the nodes read the nodes next to each.
    #[error(
        "{operation} needs every node, and the solution stores {stored} of its {nodes}: solve \
         with DynProblem::solve_ivp (not solve_ivp_every), or read each node's velocity and \
         momentum from the observer of DynProblem::run_ivp, which stores nothing"
    )]
    NodesNotStored {
        /// What was asked.
        operation: &'static str,
        /// The number of nodes the solution stores.
        stored: usize,
        /// The number of nodes of the run, `N + 1`.
        nodes: usize,
    },
    /// The computed solution stopped being finite (overflow of an unstable scheme, or a
    /// Lagrangian evaluated outside its domain).
    #[error("solution is no longer finite at {at}")]
    NotFinite {
        /// Where it happened.
        at: Location,
    },
}

/// `Result` with [`Error`](enum@Error).
///
/// ```
/// fn steps(n: usize) -> varembed::Result<f64> {
///     Ok(varembed::Grid::new(0.0, 1.0, n)?.h())
/// }
/// assert_eq!(steps(4)?, 0.25);
/// assert!(steps(0).is_err());
/// # Ok::<(), varembed::Error>(())
/// ```
pub type Result<T> = std::result::Result<T, Error>;

/// The remedy of [`Error::Unstable`]: the largest stable step, and the schemes without one.
fn stable_step_remedy(step: &Option<f64>) -> String {
    let unlimited =
        "the midpoint variational integrator and the Gauss–Legendre integrators have no step limit";
    match step {
        Some(h) => format!(
            "; use a step h ≤ {h:.3e} (the limit of this scheme on the linearisation there), or a scheme without a limit: {unlimited}"
        ),
        None => format!("; use a smaller step, or a scheme without a limit: {unlimited}"),
    }
}

/// The degenerate directions of [`Error::DegenerateLagrangian`], as ` along (v₀ 0.707, v₁ −0.707)`.
fn null_directions(directions: &[Vec<(usize, f64)>]) -> String {
    const SUBSCRIPTS: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
    let name = |i: usize| -> String {
        let digits: String = i
            .to_string()
            .chars()
            .map(|c| SUBSCRIPTS[c.to_digit(10).unwrap_or(0) as usize])
            .collect();
        format!("v{digits}")
    };
    if directions.is_empty() {
        return String::new();
    }
    let each: Vec<String> = directions
        .iter()
        .map(|d| {
            let parts: Vec<String> = d
                .iter()
                .map(|&(i, c)| format!("{} {c:.3}", name(i)))
                .collect();
            format!("({})", parts.join(", "))
        })
        .collect();
    format!(", and vanishes along {}", each.join(" and "))
}

/// [`Error::WrongLength`] unless `found == expected`.
pub(crate) fn check_len(what: &'static str, expected: usize, found: usize) -> Result<()> {
    if expected == found {
        Ok(())
    } else {
        Err(Error::WrongLength {
            what,
            expected,
            found,
        })
    }
}
