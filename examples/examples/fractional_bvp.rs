//! A fractional boundary value problem: `cargo run --example fractional_bvp [-- N]`.
//!
//! The pendulum `L = ½v² + cos x` on `[0, 1]` with `q(0) = 0`, `q(1) = 1`, under the
//! Grünwald–Letnikov embedding Gauss-GLE− of order α: the velocity is the discrete fractional
//! derivative `Δ^α_− Q`, which reads every earlier node. The embedding is coherent, so the
//! direct scheme's residual vanishes on the variational solution. As α → 1 the solutions tend
//! to the classical one.
use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};

#[lagrangian]
fn pendulum(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.cos()
}

fn main() -> varembed::Result<()> {
    let n = std::env::args()
        .nth(1)
        .map_or(200, |n| n.parse().expect("N, a number of steps"));
    let grid = Grid::new(0.0, 1.0, n)?;
    let classical = Problem::new(&Pendulum, grid, Embedding::asymmetric(Side::Backward))
        .solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    println!(
        "{:>5}  {:>10}  {:>22}  {:>20}",
        "α", "Q(1/2)", "direct residual on it", "distance to α = 1"
    );
    for alpha in [0.6, 0.8, 0.9, 0.99, 1.0] {
        let problem = Problem::new(
            &Pendulum,
            grid,
            Embedding::grunwald_letnikov(Side::Backward, alpha)?,
        );
        let solution = problem.solve_bvp(Scheme::Variational, 0.0, 1.0)?;
        for warning in &solution.warnings {
            println!("warning: {warning}");
        }
        let coherence = problem
            .residual(Scheme::Direct, &solution.q)?
            .iter()
            .map(|r| r.amax())
            .fold(0.0, f64::max);
        let distance = solution.max_distance(&classical.q).expect("same grid");
        println!(
            "{alpha:>5}  {:>10.6}  {coherence:>22.2e}  {distance:>20.2e}",
            solution.q[n / 2][0]
        );
    }
    Ok(())
}
