//! The resolution check of run-time-dimension initial value runs: `Warning::UnderResolved` when
//! `h ω` at the initial data exceeds 2, `ω` the fastest rate of the linearised equation by
//! power iteration on the sparse blocks; checked against the closed-form spectra of linear
//! chains (fixed ends with diagonal or coupled masses, and a ring) and against the
//! const-generic path on a nonlinear chain.

use varembed::{DynLagrangian, DynProblem, Embedding, Grid, Scheme, Side, Warning};
use varembed_tests::models::generated::fput16;
use varembed_tests::warnings::under_resolved;

/// `n` masses `m` joined by springs `k`, and to walls at both ends by springs `k`: the fastest
/// frequency is `2√(k/m) sin(nπ/(2(n + 1)))`.
#[varembed::lagrangian]
fn springs(x: &[f64], v: &[f64], n: usize, m: f64, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v[i] * v[i];
    }
    for i in 0..n - 1 {
        let d = x[i + 1] - x[i];
        l += -0.5 * k * d * d;
    }
    l + -0.5 * k * (x[0] * x[0] + x[n - 1] * x[n - 1])
}

/// The chain of [`springs`] with neighbouring velocities coupled, `½ vᵀMv` with
/// `M = m (I + c (S + Sᵀ))`, `S` the shift: `M` and the stiffness share the sine modes, so the
/// fastest frequency is `√(k (2 + 2 cos θ) / (m (1 − 2c cos θ)))`, `θ = π/(n + 1)`.
#[varembed::lagrangian]
fn coupled_masses(x: &[f64], v: &[f64], n: usize, m: f64, k: f64, c: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v[i] * v[i];
    }
    for i in 0..n - 1 {
        let d = x[i + 1] - x[i];
        l += m * c * v[i] * v[i + 1] - 0.5 * k * d * d;
    }
    l + -0.5 * k * (x[0] * x[0] + x[n - 1] * x[n - 1])
}

/// `n` masses `m` in a ring of springs `k`: for even `n` the fastest frequency is `2√(k/m)`
/// (neighbours in opposite phase).
#[varembed::lagrangian]
fn ring(x: &[f64], v: &[f64], n: usize, m: f64, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let d = x[(i + 1) % n] - x[i];
        l += 0.5 * m * v[i] * v[i] - 0.5 * k * d * d;
    }
    l
}

/// A direct Gauss-FDE− run (implicit, stable at any step) of `model` from a displacement at
/// rest, on `steps` steps of `h`.
fn direct_run<L: DynLagrangian>(model: &L, h: f64, steps: usize) -> DynProblem<'_, L> {
    let grid = Grid::new(0.0, h * steps as f64, steps).unwrap();
    DynProblem::new(model, grid, Embedding::finite_difference(Side::Backward))
}

/// The initial displacement of `d` masses.
fn displaced(d: usize) -> Vec<f64> {
    (0..d).map(|i| 0.1 * (i as f64 * 0.7).sin()).collect()
}

#[test]
fn an_under_resolved_implicit_run_is_flagged_and_a_resolved_one_is_not() {
    let chain = Springs {
        n: 32,
        m: 2.0,
        k: 3.0,
    };
    let q0 = displaced(32);
    let v0 = vec![0.0; 32];
    // ω ≈ 2.446: h = 1 is past the limit, h = 0.05 well within it.
    let coarse = direct_run(&chain, 1.0, 20);
    let run = coarse.solve_ivp(Scheme::Direct, &q0, &v0).unwrap();
    let found = under_resolved(&run.warnings);
    assert_eq!(found.len(), 1, "{:?}", run.warnings);
    assert_eq!(found[0].1, 2.0);
    assert_eq!(run.warnings, run.run.warnings);
    // The observer's run reports it too.
    let observed = coarse.run_ivp(Scheme::Direct, &q0, &v0, |_| {}).unwrap();
    assert_eq!(observed.warnings, run.warnings);
    // Silenced on purpose.
    let quiet = coarse
        .with_resolution_check(false)
        .solve_ivp(Scheme::Direct, &q0, &v0)
        .unwrap();
    assert!(quiet.warnings.is_empty() && quiet.run.warnings.is_empty());
    // Resolved: no warning, both schemes, with a diagonal mass matrix (proved by a norm bound)
    // and a coupled one (by the power iteration).
    let coupled = CoupledMasses {
        n: 32,
        m: 2.0,
        k: 3.0,
        c: 0.1,
    };
    let fine = direct_run(&chain, 0.05, 40);
    let coupled_fine = DynProblem::new(
        &coupled,
        Grid::new(0.0, 2.0, 40).unwrap(),
        Embedding::finite_difference(Side::Backward),
    );
    for scheme in [Scheme::Direct, Scheme::Variational] {
        let runs = [
            fine.solve_ivp(scheme, &q0, &v0).unwrap(),
            coupled_fine.solve_ivp(scheme, &q0, &v0).unwrap(),
        ];
        for run in runs {
            assert!(run.warnings.is_empty(), "{scheme}: {:?}", run.warnings);
        }
    }
}

#[test]
fn the_fastest_rate_matches_the_closed_form_spectrum_of_linear_chains() {
    // 30 power iterations from the check's start vector: measured within 3.5e-4 relative of the
    // closed form between walls (the top of the spectrum clusters as d grows), 3.8e-4 with
    // coupled masses (the band solve with ∂²L/∂v²), 5e-7 on the ring.
    let (m, k) = (2.0, 3.0);
    for d in [8, 64, 512] {
        let chain = Springs { n: d, m, k };
        let exact = 2.0
            * (k / m).sqrt()
            * (d as f64 * std::f64::consts::PI / (2.0 * (d as f64 + 1.0))).sin();
        let run = direct_run(&chain, 1.0, 4)
            .solve_ivp(Scheme::Direct, &displaced(d), &vec![0.0; d])
            .unwrap();
        let omega = under_resolved(&run.warnings)[0].0;
        let gap = (omega - exact).abs() / exact;
        assert!(gap < 2e-3, "d = {d}: ω = {omega} against {exact} ({gap:e})");
    }
    for d in [8, 64, 512] {
        let c = 0.1;
        let chain = CoupledMasses { n: d, m, k, c };
        let cos = (std::f64::consts::PI / (d as f64 + 1.0)).cos();
        let exact = (k * (2.0 + 2.0 * cos) / (m * (1.0 - 2.0 * c * cos))).sqrt();
        let run = direct_run(&chain, 1.0, 4)
            .solve_ivp(Scheme::Direct, &displaced(d), &vec![0.0; d])
            .unwrap();
        let omega = under_resolved(&run.warnings)[0].0;
        let gap = (omega - exact).abs() / exact;
        assert!(
            gap < 2e-3,
            "coupled masses d = {d}: ω = {omega} against {exact} ({gap:e})"
        );
    }
    for d in [8, 64, 512] {
        let chain = Ring { n: d, m, k };
        let exact = 2.0 * (k / m).sqrt();
        let run = direct_run(&chain, 1.0, 4)
            .solve_ivp(Scheme::Direct, &displaced(d), &vec![0.0; d])
            .unwrap();
        let omega = under_resolved(&run.warnings)[0].0;
        let gap = (omega - exact).abs() / exact;
        assert!(
            gap < 2e-3,
            "ring d = {d}: ω = {omega} against {exact} ({gap:e})"
        );
    }
}

#[test]
fn the_fastest_rate_is_the_const_generic_rate_on_a_nonlinear_chain() {
    // The same power iteration on the same blocks, dense on one path and sparse on the other.
    let model = fput16::Fput {
        alpha: 0.25,
        beta: 0.7,
    };
    let q0: [f64; 16] = std::array::from_fn(|i| 0.4 * (i as f64 * 0.7).sin());
    let v0 = [0.0; 16];
    let grid = Grid::new(0.0, 20.0, 20).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let problem = varembed_tests::problem(&model, grid, embedding);
    let dynamic = DynProblem::new(&model, grid, embedding);
    let reference = problem.solve_ivp(Scheme::Direct, q0, v0).unwrap();
    let run = dynamic.solve_ivp(Scheme::Direct, &q0, &v0).unwrap();
    same_warning(&reference.warnings, &run.warnings);
    // From given first nodes both paths warn at `Q_0` with `(Q_1 − Q_0)/h`, not at `Q_1`,
    // where this chain's stiffness is another (`h ω` 2.81 there against 2.14 at `Q_0`).
    let q1: [f64; 16] = std::array::from_fn(|i| q0[i] + 0.5 * (i as f64 * 1.3).cos());
    let reference = problem
        .solve_ivp_from_nodes(Scheme::Direct, q0, q1)
        .unwrap();
    let run = dynamic
        .solve_ivp_from_nodes(Scheme::Direct, &q0, &q1)
        .unwrap();
    same_warning(&reference.warnings, &run.warnings);
}

/// One `UnderResolved` warning in each list, with the same `h ω` to 1e-10.
fn same_warning(expected: &[Warning], found: &[Warning]) {
    let (expected, found) = (under_resolved(expected), under_resolved(found));
    assert_eq!(
        (expected.len(), found.len()),
        (1, 1),
        "{found:?} against {expected:?}"
    );
    let gap = (found[0].0 - expected[0].0).abs() / expected[0].0;
    assert!(gap < 1e-10, "{found:?} against {expected:?}");
}
