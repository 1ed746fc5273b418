//! Solvers: small dense systems, banded and dense LU, Newton for initial and boundary value
//! problems.

pub mod linear;
