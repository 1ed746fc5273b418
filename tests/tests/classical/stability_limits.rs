//! The stability limits on the harmonic oscillator `q̈ = −ω²q` that `core/docs/choosing.md` states,
//! from the characteristic polynomial of each recurrence (`z = ωh`), checked just below and
//! just above each limit through the library's own checks.
//!
//! | scheme | recurrence | characteristic polynomial | roots | limit |
//! | --- | --- | --- | --- | --- |
//! | variational Gauss-FDEσ, both asymmetric schemes | `Q_{k+1} − 2Q_k + Q_{k−1} = −z²Q_k` | `λ² − (2 − z²)λ + 1` | on the unit circle iff `z < 2`; real, one below −1, when `z > 2` | `ωh < 2` |
//! | direct Gauss-FDE− | `Q_k − 2Q_{k−1} + Q_{k−2} = −z²Q_k` | `(1 + z²)λ² − 2λ + 1` | `(1 ± iz)/(1 + z²)`, modulus `(1 + z²)^{−1/2} < 1` | none: stable (and damped) at every `h` |
//! | direct Gauss-FDE+ | `Q_{k+2} − 2Q_{k+1} + Q_k = −z²Q_k` | `λ² − 2λ + 1 + z²` | `1 ± iz`, modulus `(1 + z²)^{1/2} > 1` | none: grows at every `h`; refused at `ωh ≥ √3` (modulus ≥ 2) |

use varembed::{Embedding, Error, Grid, Scheme, Side, Solution, lagrangian};

/// `ω = 1`: `z = h`.
#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * x * x
}

/// A run of `n` steps of size `h` from `Q_0 = 1`, `Q_1 = cos h` (the exact solution's nodes).
fn run(embedding: Embedding, scheme: Scheme, h: f64, n: usize) -> varembed::Result<Solution<1>> {
    let grid = Grid::new(0.0, h * n as f64, n)?;
    varembed_tests::problem(&Oscillator, grid, embedding).solve_ivp_from_nodes(scheme, 1.0, h.cos())
}

fn max_abs(solution: &Solution<1>) -> f64 {
    solution.q.iter().fold(0.0f64, |m, q| m.max(q[0].abs()))
}

/// Störmer–Verlet (the variational scheme of every Gauss-FDEσ, and both schemes of the
/// asymmetric embeddings): bounded below `ωh = 2`, refused above it.
#[test]
fn stormer_verlet_is_stable_below_omega_h_two_and_refused_above() {
    let schemes = [
        (
            Embedding::finite_difference(Side::Backward),
            Scheme::Variational,
        ),
        (
            Embedding::finite_difference(Side::Forward),
            Scheme::Variational,
        ),
        (Embedding::asymmetric(Side::Backward), Scheme::Variational),
        (Embedding::asymmetric(Side::Backward), Scheme::Direct),
        (Embedding::asymmetric(Side::Forward), Scheme::Variational),
        (Embedding::asymmetric(Side::Forward), Scheme::Direct),
    ];
    for (embedding, scheme) in schemes {
        let label = format!("{scheme} {embedding}");
        // Below: Q_k = A cos kθ + B sin kθ with cos θ = 1 − z²/2, bounded by √(A² + B²).
        let z: f64 = 1.99;
        let cos_theta = 1.0 - z * z / 2.0;
        let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
        let (a, b) = (1.0, (z.cos() - cos_theta) / sin_theta);
        let bound = (a * a + b * b).sqrt();
        let below = run(embedding, scheme, z, 5000).expect(&label);
        let peak = max_abs(&below);
        assert!(peak <= bound * (1.0 + 1e-9), "{label}: {peak} > {bound}");
        assert!(peak > 0.9 * bound, "{label}: {peak} ≪ {bound}");
        // Above: a real root below −1, refused by the step-map check.
        let above = run(embedding, scheme, 2.01, 5000);
        assert!(
            matches!(above, Err(Error::Unstable { .. })),
            "{label}: {above:?}"
        );
    }
}

/// The direct Gauss-FDE− scheme has no limit: at `ωh = 10` and `ωh = 100` it runs and loses
/// the factor `(1 + z²)^{−1/2}` of amplitude per step.
#[test]
fn direct_backward_is_stable_at_every_step_and_damps() {
    for z in [0.5f64, 10.0, 100.0] {
        let n = 40;
        let solution = run(
            Embedding::finite_difference(Side::Backward),
            Scheme::Direct,
            z,
            n,
        )
        .unwrap_or_else(|e| panic!("ωh = {z}: {e}"));
        let r = (1.0 + z * z).powf(-0.5);
        // Q_k = r^k (A cos kφ + B sin kφ): |Q_k| ≤ r^k √(A² + B²) with the amplitude from Q_0, Q_1.
        let phi = z.atan();
        let (a, b) = (1.0, (z.cos() / r - phi.cos()) / phi.sin());
        let amplitude = (a * a + b * b).sqrt();
        for (k, q) in solution.q.iter().enumerate() {
            let envelope = amplitude * r.powi(k as i32);
            assert!(
                q[0].abs() <= envelope * (1.0 + 1e-9) + 1e-300,
                "ωh = {z}, k = {k}: |Q_k| = {} > {envelope}",
                q[0].abs()
            );
        }
    }
}

/// The direct Gauss-FDE+ scheme has no stable step: the amplitude grows by `(1 + z²)^{1/2}` per
/// step at every `h`; the library refuses a step map with a root of modulus ≥ 2, `ωh ≥ √3`.
#[test]
fn direct_forward_grows_at_every_step_and_is_refused_from_root_three() {
    let fde_plus = Embedding::finite_difference(Side::Forward);
    for z in [0.01f64, 0.5, 0.99 * 3f64.sqrt()] {
        let n = 12;
        let solution =
            run(fde_plus, Scheme::Direct, z, n).unwrap_or_else(|e| panic!("ωh = {z}: {e}"));
        // The exact discrete solution: Q_k = ρ^k (A cos kφ + B sin kφ), ρ = √(1 + z²),
        // tan φ = z; ρ² Q_{k} + … is checked through the norm of (Q_k, Q_{k+1}) in the
        // eigenbasis: the quadratic form ρ^{−2k}(Q_{k+1}² − 2Q_kQ_{k+1} + ρ²Q_k²) is constant.
        let rho2 = 1.0 + z * z;
        let form = |k: usize| {
            let (q0, q1) = (solution.q[k][0], solution.q[k + 1][0]);
            (q1 * q1 - 2.0 * q0 * q1 + rho2 * q0 * q0) / rho2.powi(k as i32)
        };
        let first = form(0);
        for k in 1..n {
            assert!(
                (form(k) / first - 1.0).abs() < 1e-9,
                "ωh = {z}, k = {k}: {} vs {first}",
                form(k)
            );
        }
    }
    let above = run(fde_plus, Scheme::Direct, 1.01 * 3f64.sqrt(), 12);
    assert!(matches!(above, Err(Error::Unstable { .. })), "{above:?}");
}
