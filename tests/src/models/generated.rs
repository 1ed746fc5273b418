//! Models through `#[lagrangian]`, each written as a user of the macro writes it.
//!
//! The benches time these exact bodies (BENCHMARKS.md), so a change to one changes the figures.

use varembed::lagrangian;

/// Planar pendulum of length `l` under gravity `g` (the same model as
/// [`hand::Pendulum`](crate::models::hand::Pendulum)).
#[lagrangian]
pub fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
    0.5 * l * l * v * v + g * l * x.cos()
}

/// Pendulum with `g = l = 1`, `L = ½v² + cos x`.
#[lagrangian]
pub fn unit_pendulum(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.cos()
}

/// Kepler, `μ = 1`: `L = ½|v|² + 1/|x|`, singular at the origin.
#[lagrangian]
pub fn kepler(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) + 1.0 / (x[0] * x[0] + x[1] * x[1]).sqrt()
}

/// Double pendulum: a configuration-dependent mass matrix, so its implicit steps run Newton.
#[lagrangian]
pub fn double_pendulum(
    x: [f64; 2],
    v: [f64; 2],
    m1: f64,
    m2: f64,
    l1: f64,
    l2: f64,
    g: f64,
) -> f64 {
    let kinetic = 0.5 * (m1 + m2) * l1 * l1 * v[0] * v[0]
        + 0.5 * m2 * l2 * l2 * v[1] * v[1]
        + m2 * l1 * l2 * v[0] * v[1] * (x[0] - x[1]).cos();
    let potential = -(m1 + m2) * g * l1 * x[0].cos() - m2 * g * l2 * x[1].cos();
    kinetic - potential
}

/// A charged particle in the plane under a uniform magnetic field `b`, symmetric gauge:
/// `L = ½|v|² + (b/2)(x₀v₁ − x₁v₀)`. Not separable (`∂²L/∂x∂v ≠ 0`); the motion is a circle of
/// radius `|v|/|b|` about a fixed guiding centre `(x₀ + v₁/b, x₁ − v₀/b)`, run clockwise at the
/// angular speed `b`.
#[lagrangian]
pub fn magnetic(x: [f64; 2], v: [f64; 2], b: f64) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) + 0.5 * b * (x[0] * v[1] - x[1] * v[0])
}
