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
//! two roads meet. Gauss-FDEσ is not coherent; its asymmetric version and Gauss-GLEσ are.
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
//! - `docs/macro.md`: what [`#[lagrangian]`](macro@lagrangian) accepts and generates;
//! - `docs/architecture.md`: the workspace, the module graph, where the tests live.
#![deny(missing_docs)]

pub mod compare;
pub mod embedding;
pub mod error;
pub mod fft_operator;
pub mod grid;
pub mod lagrangian;
pub mod ode;
pub mod operator;
pub mod problem;
pub mod solve;
#[cfg(test)]
mod test_models;
pub mod toeplitz;
pub mod weights;

pub use compare::{CompareOptions, Comparison, Reference, SchemeReport};
pub use embedding::{Embedding, EmbeddingKind, Side};
pub use error::{Error, Location, Result};
pub use fft_operator::FftOperator;
pub use grid::Grid;
pub use lagrangian::{Hessian, IntoVector, Lagrangian, Matrix, StepKind, StepTimes, Vector};
pub use operator::Operator;
pub use problem::{Problem, Scheme, curve_from_flat};
pub use solve::Solution;
pub use solve::fractional::FractionalSolver;
pub use solve::ivp::Start;
pub use solve::newton::NewtonOptions;
pub use varembed_macros::lagrangian;

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

/// `docs/macro.md`.
#[doc = include_str!("../../docs/macro.md")]
#[cfg(doctest)]
pub struct DocsMacro;

/// `docs/architecture.md`.
#[doc = include_str!("../../docs/architecture.md")]
#[cfg(doctest)]
pub struct DocsArchitecture;
