//! Cost per step of the variational Gauss–Legendre integrators (s = 2 and s = 4, a Newton solve
//! of `2s` unknowns per step) next to today's implicit variational step (Gauss-FDE−, a Newton
//! solve of 2 unknowns), all on the generated double pendulum and in one run: a whole initial
//! value problem of 1000 steps each, with criterion's throughput in steps per second.
//!
//! `cargo bench -p varembed-examples --bench gauss_step`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput};
use varembed::{Embedding, Grid, Problem, Scheme, Side};
use varembed_tests::models::generated::DoublePendulum;

/// The model and the chaotic state of the `implicit_step` bench.
const PARAMS: DoublePendulum = DoublePendulum {
    m1: 1.2,
    m2: 0.7,
    l1: 1.1,
    l2: 0.8,
    g: 9.81,
};
const Q0: [f64; 2] = [2.0, 2.5];
const V0: [f64; 2] = [1.0, -1.5];
const STEPS: usize = 1000;
/// `h = 1e-3`.
const T_END: f64 = 1.0;

fn gauss_step(c: &mut Criterion) {
    let grid = Grid::new(0.0, T_END, STEPS).unwrap();
    let schemes = [
        (
            "variational FDE−",
            Embedding::finite_difference(Side::Backward),
        ),
        (
            "Gauss–Legendre s = 2",
            Embedding::gauss_legendre(2).unwrap(),
        ),
        (
            "Gauss–Legendre s = 4",
            Embedding::gauss_legendre(4).unwrap(),
        ),
    ];
    let mut group = c.benchmark_group("double pendulum, 1000 steps");
    group.throughput(Throughput::Elements(STEPS as u64));
    for (name, embedding) in schemes {
        let problem = Problem::new(&PARAMS, grid, embedding);
        // Once, outside timing: the run succeeds, and its Newton iterations per step.
        let run = problem.solve_ivp(Scheme::Variational, Q0, V0).unwrap();
        println!(
            "{name}: {:.2} Newton iterations per step",
            run.newton_iterations as f64 / STEPS as f64
        );
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| {
                problem
                    .solve_ivp(Scheme::Variational, black_box(Q0), black_box(V0))
                    .unwrap()
            })
        });
    }
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); gauss_step);
