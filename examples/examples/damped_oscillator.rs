//! A damped oscillator under every classical embedding: `cargo run --example damped_oscillator
//! [-- N]`.
//!
//! `q̈ + γ q̇ + q = 0` from `q(0) = 1`, `q̇(0) = 0` on `[0, 10]`: the oscillator
//! `L = ½v² − ½x²` under the Rayleigh friction `R = ½γv²` (`f = −∂R/∂v = −γv`), against the
//! exact solution `q = e^{−γt/2} (cos ωt + γ/(2ω) sin ωt)`, `ω = √(1 − γ²/4)`. For each
//! embedding and scheme: the max error over the nodes at `N` and `2N` steps (N = 200 by
//! default), the observed order, and the energy balance `max_k |E_k − E_0 − W_k|` at `2N` with
//! its observed order (`W_k` the work of the friction by the embedding's quadrature,
//! `Forced::work`; not for Gauss–Legendre, whose solutions keep no per-interval impulse; `ε`:
//! at round-off). `core/docs/forces.md` derives what each scheme solves under the force.
use varembed::{
    Embedding, Forced, Grid, Problem, Rayleigh, Scheme, Side, Vector, lagrangian, max_error,
    observed_order,
};

/// `L = ½v² − ½x²`.
#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * x * x
}

/// The Rayleigh dissipation function `R = ½γv²`.
#[lagrangian]
fn friction(_x: f64, v: f64, gamma: f64) -> f64 {
    0.5 * gamma * v * v
}

const GAMMA: f64 = 0.5;
const END: f64 = 10.0;

fn exact(t: f64) -> Vector<1> {
    let omega = (1.0 - GAMMA * GAMMA / 4.0).sqrt();
    let q =
        (-GAMMA * t / 2.0).exp() * ((omega * t).cos() + GAMMA / (2.0 * omega) * (omega * t).sin());
    Vector::<1>::new(q)
}

/// The max error over the nodes at `n` steps, and the energy balance `max_k |E_k − E_0 − W_k|`
/// where `Forced::work` applies.
fn run<L: varembed::Lagrangian<1>, F: varembed::Force<1>>(
    damped: &Forced<L, F>,
    embedding: Embedding,
    scheme: Scheme,
    n: usize,
) -> varembed::Result<(f64, Option<f64>)> {
    let grid = Grid::new(0.0, END, n)?;
    let solution = Problem::new(damped, grid, embedding).solve_ivp(scheme, 1.0, 0.0)?;
    let error = max_error(&grid, &solution.q, exact);
    // Gauss–Legendre keeps no per-interval impulse: `work` is Error::Unsupported there.
    let balance = match damped.work(&solution) {
        Ok(work) => {
            // The node momenta of a variational run are the forced discrete Legendre
            // transforms: pass the forced model, not the bare Lagrangian.
            let energy = solution
                .node_values(damped)?
                .energy
                .expect("L is autonomous");
            let worst = (0..=n)
                .map(|k| (energy[k] - energy[0] - work[k]).abs())
                .fold(0.0, f64::max);
            Some(worst)
        }
        Err(varembed::Error::Unsupported { .. }) => None,
        Err(e) => return Err(e),
    };
    Ok((error, balance))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(200), |n| n.parse())?;
    let damped = Forced::new(Oscillator, Rayleigh(Friction { gamma: GAMMA }));
    let mut runs = Vec::new();
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::asymmetric(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ] {
        runs.push((embedding, Scheme::Direct));
        runs.push((embedding, Scheme::Variational));
    }
    for stages in 1..=3 {
        runs.push((Embedding::gauss_legendre(stages)?, Scheme::Variational));
    }
    println!("q̈ + {GAMMA} q̇ + q = 0 on [0, {END}], q(0) = 1, q̇(0) = 0");
    println!(
        "{:<22} {:<12} {:>10} {:>10} {:>6} {:>10} {:>6}",
        "embedding",
        "scheme",
        format!("err N={n}"),
        format!("err N={}", 2 * n),
        "order",
        "balance",
        "order"
    );
    for (embedding, scheme) in runs {
        let (coarse, coarse_balance) = run(&damped, embedding, scheme, n)?;
        let (fine, fine_balance) = run(&damped, embedding, scheme, 2 * n)?;
        let order = observed_order((n, coarse), (2 * n, fine));
        let balance = match (coarse_balance, fine_balance) {
            // Kept to round-off (the midpoint variational scheme on this quadratic L): no order.
            (Some(_), Some(fine)) if fine < 1e-12 => format!("{fine:>10.2e} {:>6}", "ε"),
            (Some(coarse), Some(fine)) => format!(
                "{fine:>10.2e} {:>6.2}",
                observed_order((n, coarse), (2 * n, fine))
            ),
            _ => format!("{:>10} {:>6}", "—", "—"),
        };
        println!(
            "{:<22} {:<12} {coarse:>10.2e} {fine:>10.2e} {order:>6.2} {balance}",
            embedding.to_string(),
            format!("{scheme:?}").to_lowercase(),
        );
    }
    Ok(())
}
