//! What varembed's tests and benches share, written once: the models they solve, the random
//! generator that draws their inputs, exact discrete solutions to check against, and the
//! criterion set-up of every bench.
//!
//! - [`models`]: hand-written Lagrangians (plain formulas, the trait's defaults for everything
//!   else), the same models through `#[lagrangian]`, and the double pendulum differentiated by
//!   num-dual.
//! - [`rng`]: a seeded SplitMix64 generator, so that a failing case reproduces.
//! - [`reference`](mod@reference): closed-form discrete solutions of the harmonic oscillator's
//!   schemes, and the pendulum's exact solution.
//! - [`curve`]: max-norms of discrete curves and of their differences.
//! - [`special`]: the Gamma function, for exact fractional solutions.
//! - [`fractional`]: exact solutions of fractional boundary value problems and the forced model
//!   they solve.
//! - [`bench`](mod@bench): the criterion configurations and the `bench_main!` entry point.
//!
//! The integration tests of the workspace live in this package's `tests/` folder; the
//! examples' tests and benches use this crate as a dev-dependency, and so do the macro crate's
//! unit tests (for [`rng::Rng`]).
#![deny(missing_docs)]

pub mod bench;
pub mod curve;
pub mod fractional;
pub mod models;
pub mod reference;
pub mod rng;
pub mod special;
pub mod warnings;
