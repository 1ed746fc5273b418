//! Typed errors: every failure of the library is one of these, never a panic or a silent NaN.

use thiserror::Error;

/// Where a solver failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A step of an initial value problem: the index `n` of the node `Q_n` being computed
    /// (`n = 1` is the discrete Legendre start).
    Step(usize),
    /// A Newton iteration of a boundary value problem (the global system).
    Newton(usize),
    /// The evaluation of the Lagrangian at node `Q_k`.
    Node(usize),
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Location::Step(n) => write!(f, "step {n} (node Q_{n})"),
            Location::Newton(i) => write!(f, "global Newton iteration {i}"),
            Location::Node(k) => write!(f, "node Q_{k}"),
        }
    }
}

/// Everything that can go wrong in varembed.
#[derive(Clone, Debug, Error, PartialEq)]
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
    /// An input value is NaN or infinite.
    #[error("non-finite input: {what}")]
    NonFiniteInput {
        /// Which input.
        what: String,
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
    /// A Jacobian is singular (e.g. `∂²L/∂v²` degenerate).
    #[error("singular Jacobian at {at}")]
    SingularJacobian {
        /// Where.
        at: Location,
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
    #[error("the scheme is unstable at {at}: its step map has the eigenvalue {re:.4} {im:+.4}i")]
    Unstable {
        /// Where the check ran.
        at: Location,
        /// Real part of the offending eigenvalue.
        re: f64,
        /// Imaginary part of the offending eigenvalue.
        im: f64,
    },
    /// The Krylov solver of the fractional fast path (conjugate gradients, then GMRES) did not
    /// solve a Newton system `J δ = r` to the forcing tolerance: the Jacobian is (nearly)
    /// singular or so indefinite that the preconditioner cannot tame it. Solve with
    /// `FractionalSolver::Dense` for small `N`, or from a better initial guess.
    #[error(
        "the Krylov solver did not converge at {at} after {iterations} iterations: relative linear residual {residual:.3e}"
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
    /// (`Problem::with_blow_up_guard(false)`), are in `docs/solvers.md`.
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
    /// The computed solution stopped being finite (overflow of an unstable scheme, or a
    /// Lagrangian evaluated outside its domain).
    #[error("solution is no longer finite at {at}")]
    NotFinite {
        /// Where it happened.
        at: Location,
    },
}

/// `Result` with [`Error`](enum@Error).
pub type Result<T> = std::result::Result<T, Error>;

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
