//! The main job: solve and compare the direct and variational schemes.
//!
//! Run with `cargo run --release -p varembed-examples`. (The full tour of scenes, with the
//! report folder and plots, is built on top of this; see issue 4.)

use std::time::Instant;
use varembed::{Embedding, Grid, Hessian, Lagrangian, Matrix, Problem, Scheme, Side, Vector};

/// Harmonic oscillator `L = ½v² − ½ω²x²`: exact solution `q(t) = q₀ cos ωt + (v₀/ω) sin ωt`.
struct Oscillator {
    omega: f64,
}

impl Lagrangian<1> for Oscillator {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * v[0] * v[0] - 0.5 * self.omega.powi(2) * x[0] * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (Vector::<1>::new(-self.omega.powi(2) * x[0]), *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-self.omega.powi(2)),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// `max_k |E(Q_k, V_k) − E_0|` along a run, with `V` the scheme's backward/forward velocity.
fn energy_deviation(
    problem: &Problem<'_, Oscillator, 1>,
    q: &[Vector<1>],
) -> varembed::Result<f64> {
    let v = problem.velocity(q)?;
    let rows = problem.embedding().quadrature_rows(problem.grid().n());
    let energies: Vec<f64> = rows
        .zip(&v)
        .map(|(k, vk)| problem.lagrangian().energy(&q[k], vk, problem.grid().t(k)))
        .collect();
    Ok(energies
        .iter()
        .map(|e| (e - energies[0]).abs())
        .fold(0.0, f64::max))
}

fn main() -> varembed::Result<()> {
    let oscillator = Oscillator { omega: 1.0 };
    let (q0, v0) = (1.0, 0.0);
    let exact = |t: f64| {
        q0 * (oscillator.omega * t).cos() + v0 / oscillator.omega * (oscillator.omega * t).sin()
    };

    println!("Harmonic oscillator ω = 1, q(0) = 1, q̇(0) = 0, t ∈ [0, 100]: initial value problems");
    println!(
        "{:<22} {:<12} {:>8} {:>12} {:>12} {:>14} {:>10}",
        "embedding", "scheme", "N", "max error", "max |ΔE|", "other's resid.", "time"
    );
    for side in [Side::Backward, Side::Forward] {
        for n in [1000, 10_000] {
            let grid = Grid::new(0.0, 100.0, n)?;
            let problem = Problem::new(&oscillator, grid, Embedding::finite_difference(side));
            let mut runs = Vec::new();
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let start = Instant::now();
                let run = problem.solve_ivp(scheme, q0, v0)?;
                runs.push((scheme, run, start.elapsed()));
            }
            for (i, (scheme, run, time)) in runs.iter().enumerate() {
                let error = (0..=n)
                    .map(|k| (run.q[k][0] - exact(grid.t(k))).abs())
                    .fold(0.0, f64::max);
                let other = if i == 0 {
                    Scheme::Variational
                } else {
                    Scheme::Direct
                };
                let cross = problem
                    .residual(other, &run.q)?
                    .iter()
                    .map(|r| r.amax())
                    .fold(0.0, f64::max);
                println!(
                    "{:<22} {:<12} {:>8} {:>12.3e} {:>12.3e} {:>14.3e} {:>8.2?}",
                    problem.embedding().to_string(),
                    scheme.to_string(),
                    n,
                    error,
                    energy_deviation(&problem, &run.q)?,
                    cross,
                    time
                );
            }
            let distance = runs[0].1.max_distance(&runs[1].1.q).unwrap_or(f64::NAN);
            println!("{:<22} max |Q_direct − Q_variational| = {distance:.3e}", "");
        }
    }

    println!();
    println!("Fractional boundary value problem, Gauss-GLE−, q(0) = 0, q(1) = 1, N = 200");
    println!(
        "{:>6} {:>14} {:>14} {:>10} {:>10}",
        "α", "Q at t = 1/2", "coherence gap", "Newton", "time"
    );
    let grid = Grid::new(0.0, 1.0, 200)?;
    for alpha in [0.6, 0.8, 0.95, 1.0] {
        let problem = Problem::new(
            &oscillator,
            grid,
            Embedding::grunwald_letnikov(Side::Backward, alpha)?,
        );
        let start = Instant::now();
        let sol = problem.solve_bvp(Scheme::Variational, 0.0, 1.0)?;
        let time = start.elapsed();
        let direct = problem.residual(Scheme::Direct, &sol.q)?;
        let variational = problem.residual(Scheme::Variational, &sol.q)?;
        let gap = direct
            .iter()
            .zip(&variational)
            .map(|(a, b)| (a - b).amax())
            .fold(0.0, f64::max);
        println!(
            "{alpha:>6} {:>14.8} {gap:>14.3e} {:>10} {time:>10.2?}",
            sol.q[100][0], sol.newton_iterations
        );
    }
    let classical = Problem::new(
        &oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    )
    .solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    println!(
        "{:>6} {:>14.8}   (classical variational scheme, for comparison with α = 1)",
        "FDE−", classical.q[100][0]
    );
    Ok(())
}
