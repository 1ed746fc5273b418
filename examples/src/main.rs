//! The main job: solve and compare the direct and variational schemes.
//!
//! Run with `cargo run --release -p varembed-examples`. (The full tour of scenes, with the
//! report folder and plots, is built on top of this; see issue 4.)

use varembed::{
    CompareOptions, Embedding, Grid, Problem, Reference, Side, Start, Vector, lagrangian,
};

/// Harmonic oscillator `L = ½v² − ½ω²x²`: exact solution `q(t) = q₀ cos ωt + (v₀/ω) sin ωt`.
#[lagrangian]
fn oscillator(x: f64, v: f64, omega: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * x * x
}

fn main() -> varembed::Result<()> {
    let oscillator = Oscillator { omega: 1.0 };
    let exact = |t: f64| Vector::<1>::new(t.cos()); // q(0) = 1, q̇(0) = 0
    println!("Harmonic oscillator ω = 1, q(0) = 1, q̇(0) = 0, t ∈ [0, 20]\n");
    for side in [Side::Backward, Side::Forward] {
        let grid = Grid::new(0.0, 20.0, 2000)?;
        for (embedding, start) in [
            (Embedding::finite_difference(side), Start::Legendre),
            (Embedding::finite_difference(side), Start::SecondOrder),
            (Embedding::asymmetric(side), Start::Legendre),
        ] {
            let options = CompareOptions {
                reference: Reference::Exact(&exact),
                start,
                order: true,
            };
            let cmp =
                Problem::new(&oscillator, grid, embedding).compare_ivp_with(1.0, 0.0, &options)?;
            println!("{cmp}\n  (start: {start:?})\n");
        }
    }
    println!("Fractional boundary value problems, q(0) = 0, q(1) = 1, N = 200\n");
    let grid = Grid::new(0.0, 1.0, 200)?;
    for alpha in [0.6, 0.8, 0.95, 1.0] {
        let problem = Problem::new(
            &oscillator,
            grid,
            Embedding::grunwald_letnikov(Side::Backward, alpha)?,
        );
        println!("{}\n", problem.compare_bvp(0.0, 1.0)?);
    }
    let classical = Problem::new(
        &oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    println!("{}", classical.compare_bvp(0.0, 1.0)?);
    Ok(())
}
