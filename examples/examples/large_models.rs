//! Two models written with loops, at sizes where unrolling would not do: a ten-link pendulum
//! (a double sum over the links) integrated by the recommended scheme, and a Fermi–Pasta–Ulam–
//! Tsingou chain of 10⁴ particles whose value and gradient are evaluated:
//! `cargo run --release --example large_models`.
//!
//! The derivatives of a loop stay loops, so the generated code of the 10⁴ chain is as long as
//! that of a chain of 4. The solvers store the Hessian blocks densely (`d²` entries each): at
//! `d = 10⁴` that is 800 MB a block, so the chain is not integrated here.
use varembed::{Grid, Lagrangian, Problem, Scheme, Vector};

mod pendulum {
    use varembed::lagrangian;
    pub const N: usize = 10;
    /// A ten-link pendulum of unit masses and lengths `l`, angles from the downward vertical:
    /// `T = ½ l² Σ_i Σ_j (N − max(i, j)) cos(x_i − x_j) v_i v_j`, `U = −g l Σ_i (N − i) cos x_i`.
    #[lagrangian]
    pub fn n_link(x: [f64; N], v: [f64; N], g: f64, l: f64) -> f64 {
        let mut kinetic = 0.0;
        for i in 0..N {
            for j in 0..N {
                let mass_below = (N - i.max(j)) as f64;
                kinetic += 0.5 * l * l * mass_below * (x[i] - x[j]).cos() * v[i] * v[j];
            }
        }
        let potential: f64 = (0..N).map(|i| -g * l * (N - i) as f64 * x[i].cos()).sum();
        kinetic - potential
    }
}

mod chain {
    use varembed::lagrangian;
    pub const N: usize = 10_000;
    /// An FPUT chain of 10⁴ particles between two walls, the springs to the walls harmonic.
    #[lagrangian]
    pub fn fput(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..N {
            l += 0.5 * v[i] * v[i];
        }
        for i in 0..N - 1 {
            let d = x[i + 1] - x[i];
            l -= 0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4);
        }
        l - 0.5 * x[0] * x[0] - 0.5 * x[N - 1] * x[N - 1]
    }
}

fn main() -> varembed::Result<()> {
    let links = pendulum::NLink { g: 9.81, l: 0.1 };
    let problem = Problem::recommended(&links, Grid::new(0.0, 1.0, 1000)?);
    let run = problem.solve_ivp(Scheme::Variational, [0.3; 10], [0.0; 10])?;
    let energy = run.node_values(&links)?.energy.expect("autonomous");
    println!("ten links: E from {:.9} to {:.9}", energy[0], energy[1000]);
    let fput = chain::Fput {
        alpha: 0.25,
        beta: 0.5,
    };
    let x = Box::new(Vector::<{ chain::N }>::from_fn(|i, _| {
        (0.01 * i as f64).sin()
    }));
    let v = Box::new(Vector::<{ chain::N }>::zeros());
    let (f, _) = fput.gradient(&x, &v, 0.0);
    println!(
        "chain: L = {:.6}, f[1] = {:.3e}",
        fput.value(&x, &v, 0.0),
        f[1]
    );
    Ok(())
}
