//! Forced and constrained classical problems: generalised forces (Rayleigh dissipation, general
//! forces, the discrete Lagrange–d'Alembert principle of each embedding) and holonomic
//! constraints (initial and boundary value problems, Gauss–Legendre under constraints), against
//! exact solutions and independent computations. A binary of its own beside `classical`, so that
//! the two compile side by side on two cores; each file is a module.

mod constrained_bvp;
mod constrained_gauss;
mod constraints;
mod forces;
mod generated_forces;
