//! The classical boundary value problem of a large model: the FPUT chain of `d = 1024`
//! particles between walls on `N = 1000` steps of `[0, 1]`, `(N − 1) d ≈ 10⁶` unknowns, solved
//! by `DynProblem::solve_bvp` (Newton on the global system), direct and variational
//! Gauss-FDE−: its sparse Jacobian factorised by sparse LU after a fill-reducing ordering
//! (`BvpSolver::SparseLu`), and for the variational scheme by preconditioned MINRES
//! (`BvpSolver::Minres`, what `BvpSolver::Auto` chooses at this size), side by side.
//!
//! Before timing, one solve of each scheme is run alone and reported: Newton iterations, wall
//! time, and the peak heap memory of the solve (the peak bytes allocated during the solve minus
//! those allocated before it, counted by dhat's heap profiler as the global allocator), beside the
//! size of the solution itself. A ring of the same size (periodic, so not banded) is reported
//! the same way, untimed by criterion.
//!
//! `nice -n -19 cargo bench -p varembed-examples --bench large_bvp -- --warm-up-time 1
//! --measurement-time 3`; figures in core/docs/solvers.md.

use std::hint::black_box;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use varembed::{BvpSolver, DynProblem, Embedding, Grid, Scheme, Side};
use varembed_tests::models::chain::FputChain;

#[global_allocator]
static HEAP: dhat::Alloc = dhat::Alloc;

const D: usize = 1024;
const STEPS: usize = 1000;
const T: f64 = 1.0;

/// The boundary values: two smooth displacements of amplitude 0.3.
fn ends(d: usize) -> (Vec<f64>, Vec<f64>) {
    let x = |i: usize| (i as f64 + 1.0) / (d as f64 + 1.0) * std::f64::consts::PI;
    let qa = (0..d).map(|i| 0.3 * x(i).sin()).collect();
    let qb = (0..d).map(|i| 0.3 * (2.0 * x(i)).sin()).collect();
    (qa, qb)
}

/// One solve alone: its iterations, time and peak heap memory, printed.
fn report(name: &str, chain: &FputChain, scheme: Scheme, solver: BvpSolver) -> Vec<f64> {
    let grid = Grid::new(0.0, T, STEPS).unwrap();
    let problem = DynProblem::new(chain, grid, Embedding::finite_difference(Side::Backward))
        .with_bvp_solver(solver);
    let (qa, qb) = ends(chain.n);
    // The heap profiler counts from here: its peak is the solve's alone. (Its bookkeeping per
    // allocation is negligible against a solve of seconds.)
    let profiler = dhat::Profiler::builder().testing().build();
    let start = Instant::now();
    let solution = problem.solve_bvp(scheme, &qa, &qb).unwrap();
    let elapsed = start.elapsed();
    let peak = dhat::HeapStats::get().max_bytes;
    drop(profiler);
    let mib = |bytes: usize| bytes as f64 / (1024.0 * 1024.0);
    println!(
        "{name} {scheme} ({:?}): d = {}, N = {STEPS}, {} unknowns: {} Newton iterations in \
         {:.2} s; peak heap of the solve {:.0} MiB (the solution itself {:.0} MiB)",
        solution.run.linear_solve,
        chain.n,
        (STEPS - 1) * chain.n,
        solution.run.newton_iterations,
        elapsed.as_secs_f64(),
        mib(peak),
        mib(solution.q.len() * 8),
    );
    solution.q
}

fn large_bvp(c: &mut Criterion) {
    let chain = FputChain {
        n: D,
        alpha: 0.25,
        beta: 0.7,
        periodic: false,
    };
    let ring = FputChain {
        periodic: true,
        ..chain
    };
    report("chain", &chain, Scheme::Direct, BvpSolver::SparseLu);
    let lu = report("chain", &chain, Scheme::Variational, BvpSolver::SparseLu);
    let minres = report("chain", &chain, Scheme::Variational, BvpSolver::Minres);
    let gap = lu
        .iter()
        .zip(&minres)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!("chain variational: max |Q_LU − Q_MINRES| = {gap:.1e}");
    report("ring", &ring, Scheme::Variational, BvpSolver::SparseLu);
    report("ring", &ring, Scheme::Variational, BvpSolver::Minres);

    let grid = Grid::new(0.0, T, STEPS).unwrap();
    let problem_with = |solver| {
        DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward))
            .with_bvp_solver(solver)
    };
    let (qa, qb) = ends(D);
    let mut group = c.benchmark_group(format!("fput_bvp_d{D}_n{STEPS}"));
    group.sample_size(10);
    let runs = [
        ("sparse_lu", Scheme::Direct, BvpSolver::SparseLu),
        ("sparse_lu", Scheme::Variational, BvpSolver::SparseLu),
        ("minres", Scheme::Variational, BvpSolver::Minres),
    ];
    for (name, scheme, solver) in runs {
        let problem = problem_with(solver);
        group.bench_function(BenchmarkId::new(name, scheme), |b| {
            b.iter(|| {
                problem
                    .solve_bvp(scheme, black_box(&qa), black_box(&qb))
                    .unwrap()
            })
        });
    }
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); large_bvp);
