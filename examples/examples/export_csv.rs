//! Exporting a solution as CSV: `cargo run --example export_csv [-- FILE [N]]`.
//!
//! Kepler's problem at eccentricity 0.5 by the variational Gauss-FDE+ scheme. The CSV has one
//! line per node `t_k` with the columns `t,q0,q1,v0,v1,p0,p1,E`; every number is written in
//! Rust's shortest round-trip form, so reading it back (in Python, Julia, a spreadsheet…) gives
//! exactly the computed values. Without FILE the CSV goes to standard output.
use std::io::Write as _;
use varembed::{Embedding, Grid, Problem, Scheme, Side, lagrangian};

/// `L = ½|v|² + 1/|x|`.
#[lagrangian]
fn kepler(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) + 1.0 / (x[0] * x[0] + x[1] * x[1]).sqrt()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let file = args.next();
    let n = args.next().map_or(Ok(200), |n| n.parse())?;
    // Perihelion at (0.5, 0) with speed √3: e = 0.5, period 2π.
    let grid = Grid::new(0.0, 2.0 * std::f64::consts::PI, n)?;
    let problem = Problem::new(&Kepler, grid, Embedding::finite_difference(Side::Forward));
    let solution = problem.solve_ivp(Scheme::Variational, [0.5, 0.0], [0.0, 3f64.sqrt()])?;
    let csv = solution.node_values(&Kepler)?.to_csv();
    match file {
        Some(path) => {
            std::fs::write(&path, &csv).map_err(|e| format!("could not write {path}: {e}"))?;
            eprintln!("{} nodes written to {path}", n + 1);
        }
        None => std::io::stdout().write_all(csv.as_bytes())?,
    }
    Ok(())
}
