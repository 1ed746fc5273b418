//! A Fermi–Pasta–Ulam–Tsingou chain written with loops: `cargo run --example chain`.
//!
//! Sixteen unit masses between two fixed walls, joined by springs with the cubic term `α`. The
//! first normal mode is excited; the energy of a variational run stays where it started.
use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};

/// The number of moving particles.
const N: usize = 16;

/// `L = Σ ½v_i² − Σ V(x_{i+1} − x_i)`, `V(d) = d²/2 + α d³/3`, walls at `x_{−1} = x_N = 0`.
#[lagrangian]
fn fput(x: [f64; N], v: [f64; N], alpha: f64) -> f64 {
    let mut kinetic = 0.0;
    for i in 0..N {
        kinetic += 0.5 * v[i] * v[i];
    }
    let mut springs = 0.0;
    for i in 0..N - 1 {
        let d = x[i + 1] - x[i];
        springs += 0.5 * d * d + alpha / 3.0 * d * d * d;
    }
    // V(x_0 − x_{−1}) + V(x_N − x_{N−1}) with the walls at 0.
    let walls = 0.5 * x[0] * x[0] + alpha / 3.0 * x[0] * x[0] * x[0] + 0.5 * x[N - 1] * x[N - 1]
        - alpha / 3.0 * x[N - 1] * x[N - 1] * x[N - 1];
    kinetic - springs - walls
}

fn main() -> varembed::Result<()> {
    let chain = Fput { alpha: 0.25 };
    // The first normal mode of the linear chain, amplitude 1.
    let q0: [f64; N] =
        std::array::from_fn(|i| (std::f64::consts::PI * (i + 1) as f64 / (N + 1) as f64).sin());
    let grid = Grid::new(0.0, 200.0, 4000)?; // h = 0.05
    // ½|v|² − U(x): the variational Gauss-FDE− scheme is Störmer–Verlet, explicit.
    let problem = Problem::new(&chain, grid, Embedding::finite_difference(Side::Backward));
    let solution = problem.solve_ivp(Scheme::Variational, q0, [0.0; N])?;
    println!(
        "explicit steps: {} of {}",
        solution.explicit_steps,
        grid.n() - 1
    );
    let energy = solution.node_values(&chain)?.energy.expect("autonomous");
    for k in (0..=grid.n()).step_by(500) {
        println!("t = {:>5.1}  E = {:.6}", grid.t(k), energy[k]);
    }
    let drift = energy
        .iter()
        .map(|e| (e - energy[0]).abs())
        .fold(0.0, f64::max);
    println!(
        "largest |E − E₀| over the run: {drift:.2e} (E₀ = {:.6})",
        energy[0]
    );
    Ok(())
}
