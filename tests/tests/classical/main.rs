//! Classical (integer-order) problems: the schemes of each embedding, Newton, starts, guards, errors, orders and comparisons, against exact solutions and independent computations. One test binary for the group: each file is a module, so the group links once.

mod banded_newton;
mod blow_up;
mod bvp_returns_ivp;
mod coherence;
mod compare;
mod dense_output;
mod errors;
mod gauss_legendre;
mod general_embedding;
mod hard_input;
mod hard_long_runs;
mod harmonic_exact;
mod ill_posed;
mod node_values;
mod parallel;
mod regularity;
mod residual_floor;
mod resolution;
mod scale_invariance;
mod sizes;
mod stability_limits;
mod start_order;
mod stormer_verlet;
mod symmetric_embeddings;
mod symmetric_orders;
mod variational_gradient;
