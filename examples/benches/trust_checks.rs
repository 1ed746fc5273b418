//! What the checks that make a solve trustworthy cost, side by side with the same solve
//! without them (`Problem::with_resolution_check(false)`, `with_posedness_check(false)`):
//!
//! - the resolution check of an implicit initial value run (a `d × d` factorisation and 30
//!   products at the initial data): the pendulum by the midpoint rule, `N = 2000`
//!   (`d = 1`), and the 16-particle FPUT chain by the midpoint rule, `N = 2000` (`d = 16`);
//! - the ill-posedness measure of a boundary value problem (2 back-substitutions on the last
//!   factorisation): the pendulum's banded solve (midpoint, `N = 2000`) and a fractional
//!   dense solve (Gauss-GLE−, `α = 0.7`, `N = 200`); on the fractional fast path (6 Lanczos
//!   steps at the converged iterate), the pendulum under Gauss-GLE−, `α = 0.7`, `N = 10⁵`.
//!
//! `cargo bench -p varembed-examples --bench trust_checks`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{Embedding, FractionalSolver, Grid, Problem, Scheme, Side};
use varembed_tests::models::generated::{Pendulum, fput16};

fn trust_checks(c: &mut Criterion) {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let grid = Grid::new(0.0, 10.0, 2000).unwrap();
    let mut group = c.benchmark_group("resolution_check_ivp");
    for (name, on) in [
        ("pendulum d=1, check on", true),
        ("pendulum d=1, check off", false),
    ] {
        let problem =
            Problem::new(&pendulum, grid, Embedding::midpoint()).with_resolution_check(on);
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| problem.solve_ivp(Scheme::Variational, black_box(1.0), 0.0))
        });
    }
    let chain = fput16::Fput {
        alpha: 0.25,
        beta: 0.0,
    };
    let q0: [f64; 16] = std::array::from_fn(|i| 0.1 * (i as f64 * 0.7).sin());
    for (name, on) in [
        ("fput d=16, check on", true),
        ("fput d=16, check off", false),
    ] {
        let problem = Problem::new(&chain, grid, Embedding::midpoint()).with_resolution_check(on);
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| problem.solve_ivp(Scheme::Variational, black_box(q0), [0.0; 16]))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("posedness_check_bvp");
    for (name, on) in [
        ("banded N=2000, check on", true),
        ("banded N=2000, check off", false),
    ] {
        let problem = Problem::new(&pendulum, grid, Embedding::midpoint()).with_posedness_check(on);
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| problem.solve_bvp(Scheme::Variational, black_box(0.0), 1.0))
        });
    }
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let fine = Grid::new(0.0, 1.0, 200).unwrap();
    for (name, on) in [
        ("dense fractional N=200, check on", true),
        ("dense fractional N=200, check off", false),
    ] {
        let problem = Problem::new(&pendulum, fine, gle)
            .with_fractional_solver(FractionalSolver::Dense)
            .with_posedness_check(on);
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| problem.solve_bvp(Scheme::Variational, black_box(0.0), 1.0))
        });
    }
    let large = Grid::new(0.0, 1.0, 100_000).unwrap();
    for (name, on) in [
        ("fast fractional N=1e5, check on", true),
        ("fast fractional N=1e5, check off", false),
    ] {
        let problem = Problem::new(&pendulum, large, gle)
            .with_fractional_solver(FractionalSolver::Fast)
            .with_posedness_check(on);
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| problem.solve_bvp(Scheme::Variational, black_box(0.0), 1.0))
        });
    }
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); trust_checks);
