//! # varembed
//!
//! Direct discrete embeddings and variational integrators of classical and fractional
//! Lagrangian systems, after L. Bourdin, *Variational integrators of fractional Lagrangian
//! systems in the framework of discrete embeddings*.
//!
//! The paper's diagram, in words: a Lagrangian `L(x, v, t)` gives a functional
//! `∫ L(q, q̇, t) dt` and, by the variational principle, an Euler–Lagrange equation. A discrete
//! embedding (a grid, a discrete derivative, a quadrature) can be applied on either road:
//! to the equation (the **direct** scheme: substitute the discrete operators into
//! Euler–Lagrange) or to the functional (the **variational** scheme: the critical points of the
//! discrete action `S_h(Q) = h Σ_{k∈I_σ} L(Q_k, V_k, t_k)`). The embedding is **coherent** when the
//! two roads meet. Gauss-FDEσ is not coherent; its asymmetric version and Gauss-GLEσ are. The
//! midpoint and trapezoidal embeddings ([`Embedding::midpoint`], [`Embedding::trapezoidal`])
//! are second order, both schemes, and not coherent.
//!
//! # Public API
//!
//! Everything a user needs is re-exported here, at the crate root; the modules themselves are
//! private. The whole public surface:
//!
//! - Setting up a problem: [`Problem`], [`Grid`], [`Embedding`], [`EmbeddingKind`], [`Side`],
//!   [`Scheme`], [`curve_from_flat`].
//! - Lagrangians: the [`Lagrangian`] trait, its [`Hessian`], what the Hessian blocks depend on
//!   ([`HessianDependence`], [`Dependence`]), [`IntoVector`], [`Vector`], [`Matrix`], and the
//!   [`lagrangian`](macro@lagrangian) attribute that derives an implementation from a function.
//! - Models of run-time dimension with sparse second derivatives (chains, lattices, discretised
//!   fields): [`DynLagrangian`], [`SparseHessian`], [`SparseBlock`]; solved by
//!   [`DynProblem`] into a [`DynSolution`] or, node by node, an observer of [`DynNode`]s and a
//!   [`DynRun`].
//! - Solving: [`Solution`] and its [`Warning`]s, [`Start`], [`NewtonOptions`],
//!   [`FractionalSolver`]; a solution's values at its nodes (times, positions, velocities,
//!   momenta, energy; CSV export): [`NodeValues`], [`NodeState`], [`NodeRule`],
//!   [`NodeFormula`].
//! - Comparing the two schemes: [`Comparison`], [`CompareOptions`], [`Reference`],
//!   [`SchemeReport`], for a [`Problem`] and a [`DynProblem`] alike (generic over the
//!   [`ComparedSolution`]); convergence over `N, 2N, 4N, …`: [`Convergence`], [`Level`], and the one
//!   definition of the observed order, [`observed_order`] ([`observed_orders`] along a run)
//!   and how far it can be trusted, [`OrderStatus`],
//!   with [`max_error`] against a reference curve.
//! - Many runs at once: [`Ensemble`], which maps the members of an ensemble (initial
//!   conditions: `Problem::solve_ivp_ensemble`; parameter sets: `Problem::solve_ivp_models`;
//!   the same on a `DynProblem`) over rayon's work-stealing pool with the `parallel` feature
//!   (on by default), serially without it, the results in input order and bit for bit the
//!   serial ones, with an optional progress callback. Untimed convergence studies and
//!   comparisons (`CompareOptions::timing` off) solve their grids the same way.
//! - Errors: [`Error`], [`Location`], [`Result`].
//! - The direct embedding of a general differential operator (no Lagrangian):
//!   [`DifferentialOperator`], [`DirectEmbedding`].
//!
//! # Conventions
//!
//! The conventions these docs use — index ranges, signs, the schemes, the solvers — are
//! written out, with derivations and compiled examples, in the repository's `docs/` folder:
//!
//! - `docs/conventions.md`: the grid, the side σ ([`Side`]), the operators `Δ_±` and
//!   `Δ^α_±` with their exact index ranges, the quadrature rows `I_σ`, `f_k` and `p_k`;
//! - `docs/schemes.md`: the direct and the variational scheme of each [`Embedding`], their rows,
//!   coherence, Störmer–Verlet, the general direct embedding;
//! - `docs/solvers.md`: initial value problems (the starts, the step kernels, when a step is
//!   explicit), boundary value problems (banded Newton; dense LU and FFT Newton–Krylov for the
//!   fractional embeddings), the typed errors;
//! - `docs/choosing.md`: which embedding and scheme for which problem — orders, what each
//!   conserves, cost per step, stability limits, the recommended scheme;
//! - `docs/macro.md`: what the [`lagrangian`](macro@lagrangian) attribute accepts and generates;
//! - `docs/architecture.md`: the workspace, the module graph, where the tests live.
#![deny(missing_docs)]

// Imports go one way. From the bottom up, each module imports only modules before it:
// ensemble, lagrangian, error, side, weights, toeplitz, gauss_legendre, grid, linalg, regularity, options,
// operator, fft_operator, embedding, step, ode, discretisation,
// solve (krylov, newton, start, nodes, solution, guard, fractional, bvp, gauss, ivp),
// dynamic (sparse, step, ivp, problem), compare, problem.
mod compare;
mod discretisation;
mod dynamic;
mod embedding;
mod ensemble;
mod error;
mod fft_operator;
mod gauss_legendre;
mod grid;
mod interval;
mod lagrangian;
mod linalg;
mod ode;
mod operator;
mod options;
mod problem;
mod regularity;
mod side;
mod solve;
mod step;
#[cfg(test)]
mod test_models;
mod toeplitz;
mod weights;

pub use compare::compared::ComparedSolution;
pub use compare::convergence::{Convergence, Level};
pub use compare::order::{OrderStatus, observed_order, observed_orders};
pub use compare::{CompareOptions, Comparison, Reference, SchemeReport, max_error};
pub use dynamic::DynLagrangian;
pub use dynamic::ivp::{DynNode, DynRun};
pub use dynamic::problem::{DynProblem, DynSolution};
pub use dynamic::sparse::{SparseBlock, SparseHessian};
pub use embedding::{Embedding, EmbeddingKind, Scheme};
pub use ensemble::Ensemble;
pub use error::{Error, Location, Result};
pub use grid::Grid;
pub use lagrangian::{
    Dependence, Hessian, HessianDependence, IntoVector, Lagrangian, Matrix, Vector,
};
pub use ode::{DifferentialOperator, DirectEmbedding};
pub use options::{FractionalSolver, NewtonOptions};
pub use problem::{Problem, curve_from_flat};
pub use side::Side;
pub use solve::nodes::{NodeFormula, NodeRule, NodeState, NodeValues};
pub use solve::solution::{Solution, Warning};
pub use solve::start::Start;
pub use varembed_macros::lagrangian;

/// What the code generated by `#[lagrangian]` names, and the internals the benchmarks and
/// integration tests reach into. Not part of the public API: it changes without notice.
#[doc(hidden)]
pub mod __private {
    pub use crate::dynamic::DynLagrangian;
    pub use crate::dynamic::sparse::SparseHessian;
    pub use crate::lagrangian::{
        Dependence, Hessian, HessianDependence, Lagrangian, Matrix, Vector,
    };
    /// The relay that hands `#[lagrangian(helper)]` fns to the Lagrangians that call them.
    pub use varembed_macros::__lagrangian_helpers as lagrangian_helpers;

    /// The step kernels of the classical schemes.
    pub mod step {
        pub use crate::step::*;
    }
    /// Small dense and banded linear algebra.
    pub mod linalg {
        pub use crate::linalg::*;
    }
    /// The discrete operators `Δ_±`, `Δ^α_±` as dense loops.
    pub mod operator {
        pub use crate::operator::*;
    }
    /// The same operators applied by FFT.
    pub mod fft_operator {
        pub use crate::fft_operator::*;
    }
    /// Triangular Toeplitz products by FFT.
    pub mod toeplitz {
        pub use crate::toeplitz::*;
    }
    /// The Grünwald–Letnikov weights and those of the inverse matrix.
    pub mod weights {
        pub use crate::weights::*;
    }
    /// Conjugate gradients and GMRES on systems known through products.
    pub mod krylov {
        pub use crate::solve::krylov::*;
    }
}

/// The README's quick start, compiled and run as a doctest.
#[doc = include_str!("../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The pages of `docs/`, their code blocks compiled and run as doctests.
#[doc = include_str!("../../docs/README.md")]
#[cfg(doctest)]
pub struct DocsIndex;

/// `docs/conventions.md`.
#[doc = include_str!("../../docs/conventions.md")]
#[cfg(doctest)]
pub struct DocsConventions;

/// `docs/schemes.md`.
#[doc = include_str!("../../docs/schemes.md")]
#[cfg(doctest)]
pub struct DocsSchemes;

/// `docs/solvers.md`.
#[doc = include_str!("../../docs/solvers.md")]
#[cfg(doctest)]
pub struct DocsSolvers;

/// `docs/choosing.md`.
#[doc = include_str!("../../docs/choosing.md")]
#[cfg(doctest)]
pub struct DocsChoosing;

/// `docs/macro.md`.
#[doc = include_str!("../../docs/macro.md")]
#[cfg(doctest)]
pub struct DocsMacro;

/// `docs/architecture.md`.
#[doc = include_str!("../../docs/architecture.md")]
#[cfg(doctest)]
pub struct DocsArchitecture;
