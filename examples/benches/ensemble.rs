//! Serial against parallel, side by side in one run, on this machine's cores:
//!
//! - an ensemble of 8 members: the chaotic double pendulum of the implicit-step benches from 8
//!   nearby initial states, each run by the variational midpoint scheme (the recommended one,
//!   implicit: two Newton iterations per step) over 140 000 steps of `h = 10⁻⁴`, some 50 ms
//!   per member; `Ensemble::serial()` against `Ensemble::new()`;
//! - a convergence study of 4 levels (`N, 2N, 4N, 8N`, `N = 17 500`) of the same run: timed
//!   (serial, the default) against untimed (its levels in parallel). Its levels cost about
//!   `1 : 2 : 4 : 8`, so the finest one bounds its speed-up near `15/8` on any number of cores.
//!
//! The solutions are checked equal, bit for bit, before timing.
//!
//! `cargo bench -p varembed-examples --bench ensemble`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{CompareOptions, Embedding, Ensemble, Grid, Problem, Scheme};
use varembed_tests::models::generated::DoublePendulum;

const PARAMS: DoublePendulum = varembed_tests::bench::DOUBLE_PENDULUM;
const MEMBERS: usize = 8;
const STEPS: usize = 140_000;
const T_END: f64 = 14.0;

/// The benches' chaotic start, its angles moved a little per member.
fn members() -> Vec<([f64; 2], [f64; 2])> {
    let ([a, b], v) = varembed_tests::bench::DOUBLE_PENDULUM_START;
    (0..MEMBERS)
        .map(|i| ([a + 1e-3 * i as f64, b - 2e-3 * i as f64], v))
        .collect()
}

fn ensemble(c: &mut Criterion) {
    let grid = Grid::new(0.0, T_END, STEPS).unwrap();
    let problem = Problem::new(&PARAMS, grid, Embedding::midpoint());
    let members = members();
    let scheme = Scheme::Variational;
    let serial = problem.solve_ivp_ensemble(scheme, &members, &Ensemble::serial());
    let parallel = problem.solve_ivp_ensemble(scheme, &members, &Ensemble::new());
    assert!(serial.iter().all(Result::is_ok));
    assert_eq!(serial, parallel, "parallel differs from serial");
    println!(
        "{MEMBERS} members of {STEPS} steps, {} threads",
        rayon_threads()
    );

    let mut group = c.benchmark_group("ensemble_8_double_pendulum");
    group.sample_size(10);
    for (name, runner) in [
        ("serial", Ensemble::serial()),
        ("parallel", Ensemble::new()),
    ] {
        group.bench_function(BenchmarkId::from_parameter(name), |bch| {
            bch.iter(|| problem.solve_ivp_ensemble(scheme, black_box(&members), &runner))
        });
    }
    group.finish();

    let coarse = Grid::new(0.0, T_END, STEPS / 8).unwrap();
    let problem = Problem::new(&PARAMS, coarse, Embedding::midpoint());
    let (q0, v0) = members[0];
    let timed = CompareOptions::default();
    let untimed = CompareOptions {
        timing: false,
        ..CompareOptions::default()
    };
    let a = problem.convergence_ivp(scheme, q0, v0, &timed, 4);
    let b = problem.convergence_ivp(scheme, q0, v0, &untimed, 4);
    for (x, y) in a.levels.iter().zip(&b.levels) {
        assert_eq!(x.solution, y.solution, "N = {}", x.n());
    }
    let mut group = c.benchmark_group("convergence_4_levels_double_pendulum");
    group.sample_size(10);
    for (name, options) in [("timed (serial)", timed), ("untimed (parallel)", untimed)] {
        group.bench_function(BenchmarkId::from_parameter(name), |bch| {
            bch.iter(|| problem.convergence_ivp(scheme, black_box(q0), v0, &options, 4))
        });
    }
    group.finish();
}

/// The threads of rayon's global pool (the cores, or `RAYON_NUM_THREADS`), as the parallel
/// runs see it.
fn rayon_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|n| n.parse().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from))
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); ensemble);
