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

/// `Problem::new` with the model as a `dyn Lagrangian<D> + Sync`: every problem of a dimension
/// then shares one copy of the solvers' code, where `Problem<Model, D>` compiles the whole
/// const-generic engine again for each model type (the `classical` test binary compiled in half
/// the time this way: 137 s of CPU against 262 s). The code is the same generic code, so the
/// nodes are the same bit for bit (a call through the vtable does not change the arithmetic).
/// What a concrete model changes, its derivatives inlined into the steps, is speed and the
/// stack frames of the steps: the benches and the tour measure the speed on concrete models,
/// and the tests of stack use (a 256-site ring through `Problem` on a 2 MiB thread, the stack
/// segments of a const-generic solve) build their problems with the concrete model.
pub fn problem<'l, const D: usize>(
    model: &'l (dyn varembed::Lagrangian<D> + Sync),
    grid: varembed::Grid,
    embedding: varembed::Embedding,
) -> varembed::Problem<'l, dyn varembed::Lagrangian<D> + Sync + 'l, D> {
    varembed::Problem::new(model, grid, embedding)
}
