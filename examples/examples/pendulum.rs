//! A pendulum in twenty lines: `cargo run --example pendulum`.
use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};

/// `L = ½ l² v² + g l cos x`.
#[lagrangian]
fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
    0.5 * l * l * v * v + g * l * x.cos()
}

fn main() -> varembed::Result<()> {
    let lag = Pendulum { g: 9.81, l: 1.0 };
    let grid = Grid::new(0.0, 10.0, 1000)?; // t from 0 to 10 in 1000 steps
    let problem = Problem::new(&lag, grid, Embedding::finite_difference(Side::Backward));
    let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?; // q(0) = 1, q̇(0) = 0
    let nodes = solution.node_values(&lag)?; // t, q, v, p and E at every node
    for node in nodes.iter().step_by(100) {
        let (t, q, v, e) = (node.t, node.q[0], node.v[0], node.energy.unwrap());
        println!("t = {t:>4.1}  q = {q:>9.6}  v = {v:>9.6}  E = {e:.9}");
    }
    Ok(())
}
