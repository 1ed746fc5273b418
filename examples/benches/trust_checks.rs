//! What the checks that make a solve trustworthy cost, side by side with the same solve
//! without them (`Problem::with_resolution_check(false)`, `with_posedness_check(false)`):
//!
//! - the resolution check of an implicit initial value run (a `d × d` factorisation and 30
//!   products at the initial data): the pendulum by the midpoint rule, `N = 2000`
//!   (`d = 1`), and the 16-particle FPUT chain by the midpoint rule, `N = 2000` (`d = 16`);
//! - the ill-posedness measure of a boundary value problem (2 back-substitutions on the last
//!   factorisation): the pendulum's banded solve (midpoint, `N = 2000`) and a fractional
//!   dense solve (Gauss-GLE−, `α = 0.7`, `N = 200`); on the fractional fast path (4 Lanczos
//!   steps on the last Newton linearisation), the pendulum under Gauss-GLE−, `α = 0.7`,
//!   `N = 10⁵`;
//! - the same two checks on run-time-dimension models (`DynProblem`), on the FPUT chain
//!   (`α = 0.25`, `β = 0.7`, walls at both ends): the resolution check of an implicit direct
//!   Gauss-FDE− run (`d = 1024`, 200 steps of `h = 0.05`) and of an explicit Störmer–Verlet
//!   run (`d = 1024`, 10⁴ steps), and the ill-posedness measure (2 back-substitutions on the
//!   last sparse LU and one pass over the Jacobian's entries) of the boundary value problems of
//!   a chain with a banded Hessian (`d = 16`, `N = 2000`), a ring (`d = 64`, `N = 1000`, not
//!   banded) and the large chain of the `large_bvp` bench (`d = 1024`, `N = 1000`, `≈ 10⁶`
//!   unknowns, about 10 s a solve: its own group, `dyn_posedness_check_large_bvp`).
//!
//! `nice cargo bench -p varembed-examples --bench trust_checks -- --warm-up-time 1
//! --measurement-time 3 <filter>`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{DynProblem, Embedding, FractionalSolver, Grid, Problem, Scheme, Side};
use varembed_tests::models::chain::{FputChain, displacement};
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

/// The FPUT chain of the run-time-dimension benches: `d` masses, walls at both ends, or a ring.
fn chain(d: usize, periodic: bool) -> FputChain {
    FputChain {
        n: d,
        alpha: 0.25,
        beta: 0.7,
        periodic,
    }
}

fn dyn_trust_checks(c: &mut Criterion) {
    let large = chain(1024, false);
    let q0: Vec<f64> = (0..1024)
        .map(|i| 0.8 * ((i as f64 + 1.0) * 0.05).sin())
        .collect();
    let v0: Vec<f64> = q0.iter().map(|q| -0.3 * q).collect();
    let mut group = c.benchmark_group("dyn_resolution_check_ivp");
    for (name, side, scheme, steps) in [
        (
            "fput d=1024 direct FDE- 200 steps",
            Side::Backward,
            Scheme::Direct,
            200,
        ),
        (
            "fput d=1024 Verlet 10^4 steps",
            Side::Forward,
            Scheme::Variational,
            10_000,
        ),
    ] {
        let grid = Grid::new(0.0, 0.05 * steps as f64, steps).unwrap();
        for on in [true, false] {
            let problem = DynProblem::new(&large, grid, Embedding::finite_difference(side))
                .with_resolution_check(on);
            let id = format!("{name}, check {}", if on { "on" } else { "off" });
            group.bench_function(BenchmarkId::from_parameter(id), |b| {
                b.iter(|| {
                    problem
                        .run_ivp(scheme, black_box(&q0), &v0, |_| {})
                        .unwrap()
                })
            });
        }
    }
    group.finish();

    let mut group = c.benchmark_group("dyn_posedness_check_bvp");
    for (name, model, steps) in [
        ("banded chain d=16 N=2000", chain(16, false), 2000),
        ("ring d=64 N=1000", chain(64, true), 1000),
    ] {
        let d = model.n;
        let (qa, qb) = (displacement(d, 0.3, 0.0), displacement(d, 0.3, 1.1));
        let grid = Grid::new(0.0, 2.0, steps).unwrap();
        for scheme in [Scheme::Direct, Scheme::Variational] {
            for on in [true, false] {
                let problem =
                    DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward))
                        .with_posedness_check(on);
                let id = format!("{name} {scheme}, check {}", if on { "on" } else { "off" });
                group.bench_function(BenchmarkId::from_parameter(id), |b| {
                    b.iter(|| problem.solve_bvp(scheme, black_box(&qa), &qb).unwrap())
                });
            }
        }
    }
    group.finish();

    // The large_bvp bench's problem: two smooth displacements of amplitude 0.3 on [0, 1].
    let mut group = c.benchmark_group("dyn_posedness_check_large_bvp");
    group.sample_size(10);
    let x = |i: usize| (i as f64 + 1.0) / 1025.0 * std::f64::consts::PI;
    let qa: Vec<f64> = (0..1024).map(|i| 0.3 * x(i).sin()).collect();
    let qb: Vec<f64> = (0..1024).map(|i| 0.3 * (2.0 * x(i)).sin()).collect();
    let grid = Grid::new(0.0, 1.0, 1000).unwrap();
    for on in [true, false] {
        let problem = DynProblem::new(&large, grid, Embedding::finite_difference(Side::Backward))
            .with_posedness_check(on);
        let id = format!(
            "fput d=1024 N=1000 variational, check {}",
            if on { "on" } else { "off" }
        );
        group.bench_function(BenchmarkId::from_parameter(id), |b| {
            b.iter(|| {
                problem
                    .solve_bvp(Scheme::Variational, black_box(&qa), &qb)
                    .unwrap()
            })
        });
    }
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); trust_checks, dyn_trust_checks);
