//! Run-time-dimension models (`DynProblem`): initial and boundary value problems and comparisons, against the const-generic path and hand-written loops. One test binary for the group.

mod bvp;
mod compare;
mod ivp;
mod scale_invariance;
