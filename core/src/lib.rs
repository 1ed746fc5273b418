//! # varembed
//!
//! Write a Lagrangian as a Rust function and get its dynamics discretised both ways that
//! L. Bourdin's *Variational integrators of fractional Lagrangian systems in the framework of
//! discrete embeddings* compares: the **direct** scheme (a discrete embedding applied to the
//! Euler–Lagrange equation) and the **variational** scheme (the critical points of the discrete
//! action), classical and fractional (Grünwald–Letnikov), solved and compared side by side.
//!
//! # Quick start
//!
//! A pendulum, `L = ½v² + cos x`. The [`lagrangian`](macro@lagrangian) attribute turns the
//! function into a model (a struct implementing [`Lagrangian`], its derivatives generated at
//! compile time); a [`Problem`] puts the model on a [`Grid`] under an [`Embedding`]; a solve
//! returns the nodes, and [`Solution::node_values`] the velocities, momenta and energy there.
//!
//! ```
//! use varembed::{Grid, Problem, Scheme, lagrangian};
//!
//! /// A pendulum of unit mass and length under unit gravity.
//! #[lagrangian]
//! fn pendulum(x: f64, v: f64) -> f64 {
//!     0.5 * v * v + x.cos()
//! }
//!
//! fn main() -> varembed::Result<()> {
//!     // 1000 steps over [0, 10] under the recommended embedding (midpoint).
//!     let problem = Problem::recommended(&Pendulum, Grid::new(0.0, 10.0, 1000)?);
//!     // The variational scheme from q(0) = 1, q̇(0) = 0.
//!     let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
//!
//!     // Time, position, velocity, momentum and energy at every node.
//!     let nodes = solution.node_values(&Pendulum)?;
//!     let end = nodes.get(1000).expect("N + 1 nodes");
//!     println!("t = {}: q = {:.6}, v = {:.6}", end.t, end.q[0], end.v[0]);
//!     // The scheme is symplectic: the energy error stays small and does not drift.
//!     let energy = nodes.energy.expect("L does not depend on t");
//!     let drift = energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max);
//!     assert!(drift < 1e-4, "{drift}");
//!
//!     // Both schemes side by side: errors, energy, orders, cross residuals, time.
//!     println!("{}", problem.compare_ivp(1.0, 0.0)?);
//!     Ok(())
//! }
//! ```
//!
//! # The guide
//!
//! The conventions and derivations are the pages of [`guide`], each with compiled examples:
//!
//! - [choosing a scheme](guide::choosing): every embedding and scheme with its order, what it
//!   conserves, its cost per step and its stability limit; the recommended scheme; when the
//!   direct scheme is the right choice;
//! - [conventions](guide::conventions): the grid, the side σ ([`Side`]), the operators `Δ_±`
//!   and `Δ^α_±` with their exact index ranges, the quadrature rows `I_σ`, `f_k` and `p_k`;
//! - [schemes](guide::schemes): the direct and the variational scheme of each [`Embedding`],
//!   their rows, coherence, Störmer–Verlet, the Gauss–Legendre integrators, the general direct
//!   embedding;
//! - [solvers](guide::solvers): initial value problems (the starts, the step kernels, when a
//!   step is explicit), boundary value problems (banded Newton; dense LU and FFT Newton–Krylov
//!   for the fractional embeddings), large models, values at the nodes, the typed errors;
//! - [forces and constraints](guide::forces): damping, drives, generated and hand-written
//!   forces ([`Forced`], [`Rayleigh`], [`force`](macro@force), [`Force`]), the equations each scheme solves under a force
//!   (the discrete Lagrange–d'Alembert principle), which steps stay explicit, the forced
//!   discrete Noether theorem and the energy balance, what is not supported; holonomic
//!   constraints by multipliers ([`Constraint`], [`constraint`](macro@constraint),
//!   [`Holonomic`]), consistent initial data, what the constrained schemes conserve;
//! - [the macro](guide::lagrangian_macro): what the [`lagrangian`](macro@lagrangian) attribute
//!   accepts (loops, sums, helpers, run-time dimensions) and generates;
//! - [architecture](guide::architecture): the workspace, the module graph, where the tests
//!   live.
//!
//! The repository holds more: runnable programs to start from (`cargo run --example NAME` in
//! its `examples/` package) and the tour of scenes (`cargo run --release -p
//! varembed-examples`), which compares every scheme on thirteen problems and writes a report.
//!
//! # Which scheme
//!
//! In short ([choosing a scheme](guide::choosing) has the full table, the stability limits and
//! where each number comes from):
//!
//! | the problem | embedding and scheme | order | keeps | a step |
//! | --- | --- | --- | --- | --- |
//! | any smooth `L`, nothing else known | [`Problem::recommended`] (midpoint), [`Scheme::Variational`] | 2 | symplectic; A-stable | Newton on `d` unknowns |
//! | `L = ½vᵀMv − U(x, t)`, `M` constant, speed first | [`Embedding::finite_difference`] (Gauss-FDE−), variational, [`Start::SecondOrder`]: Störmer–Verlet | 2 | symplectic; stable for `ωh < 2` | explicit |
//! | thousands of degrees of freedom | [`DynProblem`], the same choice | 2 | as above | explicit on `½v² − U` |
//! | long, accurate runs | [`Embedding::gauss_legendre`] with `s` stages, variational; initial value problems | `2s` | symplectic; A-stable | Newton on `s·d` stage velocities |
//! | stiff, only stability matters | Gauss-FDE−, [`Scheme::Direct`] | 1 | dissipative; stable at every `h` | implicit |
//! | an equation, not a Lagrangian | [`DifferentialOperator`], [`DirectEmbedding`] | 1 | nothing | implicit |
//! | a fractional boundary value problem | [`Embedding::corrected_grunwald_letnikov`], [`Scheme::Direct`] | 2 where the momentum does not vanish at the ends | nothing | a dense global system (FFT Newton–GMRES) |
//! | the same, the paper's scheme | [`Embedding::grunwald_letnikov`], either scheme (coherent) | 0.5–0.8 on such data, 2 on compatible data | nothing | a dense global system (FFT Newton–Krylov) |
//! | the same, with data not vanishing where the derivative starts (the Caputo derivative) | [`Embedding::corrected_caputo`], [`Scheme::Direct`] | 2 where the momentum does not vanish at the ends | nothing | as the corrected form |
//! | the same, uncorrected | [`Embedding::caputo`], either scheme (coherent) | α, or more where the momentum vanishes there | nothing | as above |
//!
//! The paper's Gauss-FDEσ schemes are first order, and their direct schemes do not conserve
//! energy (σ = − loses it, σ = + gains it): use them to reproduce the paper or in the cases
//! above, not for long conservative runs.
//!
//! # The two roads
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
//! private, apart from [`guide`], which holds documentation only. The whole public surface:
//!
//! - Setting up a problem: [`Problem`], [`Grid`], [`Embedding`], [`EmbeddingKind`], [`Side`],
//!   [`Scheme`], [`curve_from_flat`].
//! - Lagrangians: the [`Lagrangian`] trait, its [`Hessian`], what the Hessian blocks depend on
//!   ([`HessianDependence`], [`Dependence`]), [`IntoVector`], [`Vector`], [`Matrix`], and the
//!   [`lagrangian`](macro@lagrangian) attribute that derives an implementation from a function.
//! - Generalised forces ([forces and constraints](guide::forces)): [`Forced`], a Lagrangian under a
//!   force; the [`Force`] trait, its [`ForceJacobian`] and what its blocks depend on
//!   ([`ForceDependence`]); the [`force`](macro@force) attribute that derives an implementation
//!   from a vector-valued function; [`Rayleigh`], the force `−∂R/∂v` of a dissipation function;
//!   on the run-time path, [`DynForce`] and its [`SparseForceJacobian`].
//! - Holonomic constraints ([forces and constraints](guide::forces)): the
//!   [`Constraint`] trait, the [`constraint`](macro@constraint) attribute that derives an
//!   implementation of `M` constraints from a function of `x`, [`Holonomic`] (one constraint
//!   written as a `#[lagrangian]` fn),
//!   [`project_initial_data`] and its [`CONSISTENCY_TOLERANCE`];
//!   `Problem::solve_constrained_ivp` and `Problem::solve_constrained_bvp` return a
//!   [`ConstrainedSolution`].
//! - Models of run-time dimension with sparse second derivatives (chains, lattices, discretised
//!   fields): [`DynLagrangian`], [`SparseHessian`], [`SparseBlock`] (written in a loop through
//!   [`HessianWriter`], [`BlockWriter`]; a force's through [`ForceJacobianWriter`]); solved by
//!   [`DynProblem`] into a [`DynSolution`] (its state between the nodes: [`DynState`]) or,
//!   node by node, an observer of [`DynNode`]s and a [`DynRun`]; its values at the nodes
//!   (velocities, momenta, energy; CSV export): [`DynNodeValues`], [`DynNodeState`], by the
//!   formulas of [`NodeRule`]. A `#[lagrangian]` model with
//!   loops over `[f64; N]` is both kinds of model, and from [`RUN_TIME_FROM`] degrees of
//!   freedom on a [`Problem`] runs it on the run-time engine. Its boundary value problems go
//!   by sparse LU or, for a variational scheme, by MINRES ([`BvpSolver`]; what was used:
//!   [`LinearSolve`]).
//! - Solving: [`Solution`] and its [`Warning`]s, [`Start`], [`NewtonOptions`],
//!   [`FractionalSolver`]; a solution's values at its nodes (times, positions, velocities,
//!   momenta, energy; CSV export): [`NodeValues`], [`NodeState`], [`NodeRule`],
//!   [`NodeFormula`]; its values at any time between the nodes (dense output) are methods
//!   of the solutions (`Solution::at`, `Solution::state_at`, `DynSolution::at`).
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
#![deny(missing_docs)]

// The guide's link labels as intra-doc links, put before each page (see guide.rs).
macro_rules! guide_links {
    () => {
        "[conventions]: crate::guide::conventions\n\
         [schemes]: crate::guide::schemes\n\
         [solvers]: crate::guide::solvers\n\
         [forces]: crate::guide::forces\n\
         [choosing]: crate::guide::choosing\n\
         [macro]: crate::guide::lagrangian_macro\n\
         [architecture]: crate::guide::architecture\n"
    };
}

#[doc = guide_links!()]
/// The guide: conventions, derivations and the choice of a scheme, one page per module.
#[doc = include_str!("../docs/README.md")]
pub mod guide;

// Imports go one way. From the bottom up, each module imports only modules before it:
// ensemble, lagrangian, error, side, weights, toeplitz, gauss_legendre, grid, linalg, regularity, options,
// operator, fft_operator, embedding, step, ode, discretisation,
// solve (krylov, minres, newton, start, nodes, solution, dense, guard, fractional, bvp, gauss, ivp),
// dynamic (sparse, step, ivp, problem, dense), compare, problem.
mod compare;
mod constraint;
mod degenerate;
mod discretisation;
mod dynamic;
mod embedding;
mod end_correction;
mod ensemble;
mod error;
mod fft_operator;
mod force;
mod gauss_legendre;
mod grid;
mod halves;
mod interval;
mod lagrangian;
mod linalg;
mod memory;
mod ode;
mod operator;
mod options;
mod problem;
mod regularity;
mod side;
mod solve;
mod stack;
mod step;
#[cfg(test)]
mod test_models;
mod toeplitz;
mod weights;

pub use compare::compared::ComparedSolution;
pub use compare::convergence::{Convergence, Level};
pub use compare::order::{OrderStatus, observed_order, observed_orders};
pub use compare::{CompareOptions, Comparison, Reference, SchemeReport, max_error};
pub use constraint::{CONSISTENCY_TOLERANCE, Constraint, Holonomic, project_initial_data};
pub use dynamic::dense::DynState;
pub use dynamic::ivp::DynRun;
pub use dynamic::nodes::{DynNodeState, DynNodeValues};
pub use dynamic::observer::DynNode;
pub use dynamic::problem::{DynProblem, DynSolution};
pub use dynamic::sparse::{
    BlockWriter, ForceJacobianWriter, HessianWriter, SparseBlock, SparseForceJacobian,
    SparseHessian,
};
pub use embedding::kind::EmbeddingKind;
pub use embedding::{Embedding, Scheme};
pub use ensemble::Ensemble;
pub use error::{Error, Location, Result};
pub use force::run_time::DynForce;
pub use force::{Force, ForceDependence, Forced, Rayleigh};
pub use grid::Grid;
pub use lagrangian::run_time::DynLagrangian;
pub use lagrangian::{
    Dependence, ForceJacobian, Hessian, HessianDependence, IntoVector, Lagrangian, Matrix, Vector,
};
pub use ode::{DifferentialOperator, DirectEmbedding};
pub use options::{BvpSolver, FractionalSolver, LinearSolve, NewtonOptions, RUN_TIME_FROM};
pub use problem::{Problem, curve_from_flat};
pub use side::Side;
pub use solve::constrained::ConstrainedSolution;
pub use solve::nodes::{NodeFormula, NodeRule, NodeState, NodeValues};
pub use solve::solution::{Solution, Warning};
pub use solve::start::Start;
pub use varembed_macros::{constraint, force, lagrangian};

/// What the code generated by `#[lagrangian]`, `#[force]` and `#[constraint]` names, and the
/// internals the benchmarks and integration tests reach into. Not part of the public API: it changes without notice.
#[doc(hidden)]
pub mod __private {
    pub use crate::constraint::Constraint;
    pub use crate::dynamic::sparse::{SparseForceJacobian, SparseHessian};
    pub use crate::force::run_time::DynForce;
    pub use crate::force::{Force, ForceDependence};
    pub use crate::lagrangian::{
        Dependence, DynLagrangian, ForceJacobian, Hessian, HessianDependence, Lagrangian, Matrix,
        Vector,
    };
    pub use nalgebra::{SMatrix, SVector};
    /// The relay that hands `#[lagrangian(helper)]` fns to the Lagrangians that call them.
    pub use varembed_macros::__lagrangian_helpers as lagrangian_helpers;

    /// `sech² a`, the derivative of `tanh` in generated code: `4u/(1 + u)²` with
    /// `u = e^{−2|a|}`, accurate to a few ulps at every `a` (`1 − tanh² a` cancels where `|a|`
    /// is large, to exactly 0 from `|a| ≈ 19` on) and without overflow.
    #[inline]
    pub fn sech2(a: f64) -> f64 {
        let u = (-2.0 * a.abs()).exp();
        4.0 * u / ((1.0 + u) * (1.0 + u))
    }

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
    /// Conjugate gradients, GMRES and MINRES on systems known through products.
    pub mod krylov {
        pub use crate::solve::krylov::*;
        pub use crate::solve::minres::*;
    }
}

/// The README's quick start, compiled and run as a doctest.
#[doc = include_str!("../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
