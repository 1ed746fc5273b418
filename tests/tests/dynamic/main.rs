//! Run-time-dimension models (`DynProblem`): initial and boundary value problems, their trust checks and comparisons, against the const-generic path and hand-written loops. One test binary for the group.

mod bvp;
mod compare;
mod every_embedding;
mod forces;
mod gauss_legendre;
mod ill_posed;
mod ivp;
mod node_values;
mod resolution;
mod scale_invariance;
mod stability;
mod stack_segments;
mod through_problem;
