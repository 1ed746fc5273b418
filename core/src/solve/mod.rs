//! Solvers of the discrete systems: the step-by-step recurrence of the initial value problems,
//! Newton on the whole system for the boundary value problems (banded or dense LU, or the
//! FFT Newton–Krylov path of the fractional embeddings), and what they return.

pub mod bvp;
pub(crate) mod conditioning;
pub mod constrained;
pub(crate) mod dense;
pub mod fractional;
pub(crate) mod gauss;
pub(crate) mod guard;
pub mod ivp;
pub mod krylov;
pub mod minres;
pub mod newton;
pub mod nodes;
pub(crate) mod resolution;
pub mod solution;
pub(crate) mod stability;
pub mod start;
