//! The Lagrangians the tests and benches solve, each written once.
//!
//! - [`hand`]: `value`, `gradient` and `hessian` written out by hand, everything else the
//!   trait's defaults. They are the oracles for the solvers and for `#[lagrangian]`, and what a
//!   user without the macro writes.
//! - [`generated`]: models through `#[lagrangian]`, as a user of the macro writes them.
//! - [`num_dual`]: the double pendulum with every derivative from num-dual's (hyper-)dual
//!   numbers, an independent oracle for the macro and the usual alternative to it.
//! - [`chain`]: the FPUT chain (between walls or periodic) as a hand-written
//!   [`DynLagrangian`](varembed::DynLagrangian) of run-time dimension, and the loops a user
//!   writes by hand for its two schemes.
//! - [`dual_chains`]: chains and lattices of any length for num-dual, the oracles of the loop
//!   models.
//! - [`dense`]: a wrapper that hides a model's Hessian bandwidth, so that its implicit steps
//!   take the dense step solve (the reference for the banded one).
//! - [`scaled`]: `c L`, a model times a constant, whose nodes must be the model's (the
//!   scale-invariance tests).
//!
//! Models used by one test only stay in that test, next to what it checks.

pub mod chain;
pub mod dense;
pub mod dual_chains;
pub mod generated;
pub mod hand;
pub mod num_dual;
pub mod scaled;
