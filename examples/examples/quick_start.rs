//! The README's quick start, verbatim (`examples/tests/tour/readme.rs` keeps the two equal):
//! `cargo run --example quick_start`.

use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};

/// Planar pendulum of length `l` under gravity `g`.
#[lagrangian]
fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
    0.5 * l * l * v * v + g * l * x.cos()
}

fn main() -> varembed::Result<()> {
    // The macro generated `struct Pendulum { g, l }` implementing `Lagrangian<1>`, with ∂L/∂x,
    // ∂L/∂v and the Hessian blocks derived at compile time.
    println!("{}", Pendulum::DERIVATIVES);
    let lag = Pendulum { g: 9.81, l: 1.0 };
    let grid = Grid::new(0.0, 10.0, 1000)?; // a, b, N
    let problem = Problem::new(&lag, grid, Embedding::finite_difference(Side::Backward));

    // Initial value problem, both schemes from the same discrete Legendre start.
    let direct = problem.solve_ivp(Scheme::Direct, 1.0, 0.0)?;
    let variational = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
    let distance = direct.max_distance(&variational.q).unwrap();
    println!("max |Q_direct − Q_variational| = {distance:.3e}");

    // Time, position, velocity, momentum and energy at every node, and as CSV.
    let nodes = variational.node_values(&lag)?;
    assert_eq!((nodes.t[0], nodes.t[1000]), (0.0, 10.0));
    let csv = nodes.to_csv(); // header t,q0,v0,p0,E
    assert_eq!(csv.lines().count(), 1 + 1001);

    // Position and velocity at any t of [a, b], between the nodes too (dense output).
    let (q, v) = variational.at(std::f64::consts::PI)?;
    println!("q(π) = {:.4}, q̇(π) = {:.4}", q[0], v[0]);

    // Gauss-FDE− is not coherent: the direct solution does not solve the variational scheme.
    let cross = problem.residual(Scheme::Variational, &direct.q)?;
    assert!(cross.iter().any(|r| r.amax() > 1e-6));

    // Everything at once: errors, energy, orders, cross residuals, time.
    println!("{}", problem.compare_ivp(1.0, 0.0)?);

    // A fractional boundary value problem under Gauss-GLE−, α = 0.7 (coherent: both schemes
    // agree).
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
    let gle = Problem::new(&lag, Grid::new(0.0, 1.0, 100)?, gle);
    let sol = gle.solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    let direct_rows = gle.residual(Scheme::Direct, &sol.q)?;
    assert!(direct_rows.iter().all(|r| r.amax() < 1e-8));
    Ok(())
}
