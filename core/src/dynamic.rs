//! Models whose dimension is a run-time value: the [`DynLagrangian`] trait, its sparse
//! second derivatives ([`SparseHessian`](crate::SparseHessian)), and the run-time-dimension problem
//! ([`DynProblem`](crate::DynProblem)) that integrates them step by step with sparse Newton and an observer.
//!
//! The const-generic [`Lagrangian<D>`](crate::Lagrangian) keeps every vector and block on the
//! stack, which is the fastest path for the few degrees of freedom of a pendulum or an orbit,
//! and impossible for a chain of 10⁴ particles (one dense `D × D` block is 800 MB). A
//! [`DynLagrangian`] reads its state as slices, writes its gradient into buffers the solver
//! owns, and lists the entries of its second-derivative blocks that may be nonzero, so a step
//! costs `O(d · b²)` for a Hessian of half-bandwidth `b` ([solvers, "Large
//! models"](crate::guide::solvers#large-models-run-time-dimension-and-sparse-newton)).
//!
//! The step equations are those of the const-generic path, entry for entry (the step module's
//! tables); only the storage differs.

pub(crate) mod band;
pub(crate) mod bvp;
mod bvp_minres;
pub(crate) mod dense;
mod ensembles;
mod gauss;
mod gauss_bvp;
pub(crate) mod ivp;
pub(crate) mod nodes;
pub(crate) mod observer;
pub(crate) mod problem;
pub(crate) mod rows;
pub(crate) mod slices;
pub(crate) mod sparse;
pub(crate) mod sparse_lu;
pub(crate) mod stability;
pub(crate) mod step;

pub(crate) use crate::lagrangian::DynLagrangian;
