//! The fractional BVP solve time against N, fast path vs dense LU, in one run.
//!
//! Pendulum `L = ½v² + cos x`, Gauss-GLE− with α = 0.7 on `[0, 1]`, `Q_0 = 0`, `Q_N = 1`.
//! Three solves side by side: dense LU, the fast path at the default Newton tolerance (1e-12
//! relative), and the fast path run to round-off (`fast_floor`: tolerance 1e-16, so Newton stops
//! when the residual stops falling; `tests/tests/classical/residual_floor.rs` shows that this is the residual of
//! the exact discrete solution rounded to doubles). Before timing each size, the solve is run
//! once and its Newton iterations and reached residual are printed (see `report`).
//!
//! `cargo bench -p varembed-examples --bench fractional -- --warm-up-time 1 --measurement-time 3`;
//! set `VAREMBED_BENCH_MILLION=1` to include N = 10⁶.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::__private::fft_operator::FftOperator;
use varembed::__private::operator::Operator;
use varembed::{Embedding, FractionalSolver, Grid, NewtonOptions, Problem, Scheme, Side};
use varembed_tests::models::hand::Pendulum;

/// One of the timed solves: its name, its linear algebra, its Newton tolerance.
#[derive(Clone, Copy)]
struct Variant {
    name: &'static str,
    solver: FractionalSolver,
    tolerance: f64,
}

const DEFAULT_TOLERANCE: f64 = 1e-12;

fn problem(n: usize, variant: Variant) -> Problem<'static, Pendulum, 1> {
    let grid = Grid::new(0.0, 1.0, n).expect("valid grid");
    let embedding = Embedding::grunwald_letnikov(Side::Backward, 0.7).expect("valid α");
    Problem::new(&Pendulum { g: 1.0, l: 1.0 }, grid, embedding)
        .with_fractional_solver(variant.solver)
        .with_newton(NewtonOptions {
            tolerance: variant.tolerance,
            ..NewtonOptions::default()
        })
}

/// Solves once and prints the Newton iterations and the reached residual
/// `r_j = f_j + (Δᵀ p)_j` (σ = −, so `D = Δ^α_−`), computed independently of the solver by
/// [`FftOperator`] (V through the curve's differences, as accurate as the dense loops): as
/// `max|r|`, as the action gradient `h max|r| = max|∂S_h/∂Q_j|`, and relative to the Newton
/// scale `1 + max|f| + h^{−α} max|p|`.
fn report(n: usize, variant: Variant) {
    let p = problem(n, variant);
    let sol = p
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .expect("the pendulum BVP converges");
    let op = Operator::grunwald_letnikov(Side::Backward, 0.7, p.grid()).expect("valid α");
    let mut fast = FftOperator::new(&op);
    let v = fast.apply_by_differences(&sol.q).expect("N + 1 nodes");
    let dt_p = fast.apply_transpose(&v).expect("N rows"); // p = ∂L/∂v = v
    let r_max = (1..n).fold(0.0f64, |m, j| {
        m.max((-sol.q[j][0].sin() + dt_p[j][0]).abs())
    });
    let p_max = v.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let h = p.grid().h();
    let scale = 1.0
        + 1.0f64.min(sol.q.iter().fold(0.0f64, |m, x| m.max(x[0].sin().abs())))
        + h.powf(-0.7) * p_max;
    eprintln!(
        "{} N = {n}: {} Newton iterations, max|r| = {r_max:.2e}, h·max|r| = {:.2e}, \
         max|r|/scale = {:.2e}",
        variant.name,
        sol.newton_iterations,
        h * r_max,
        r_max / scale
    );
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("fractional_bvp_pendulum_alpha0.7");
    group.sample_size(10);
    let mut fast_sizes = vec![1_000, 10_000, 100_000];
    if std::env::var_os("VAREMBED_BENCH_MILLION").is_some() {
        fast_sizes.push(1_000_000);
    }
    let dense = Variant {
        name: "dense",
        solver: FractionalSolver::Dense,
        tolerance: DEFAULT_TOLERANCE,
    };
    let fast = Variant {
        name: "fast",
        solver: FractionalSolver::Fast,
        tolerance: DEFAULT_TOLERANCE,
    };
    let fast_floor = Variant {
        name: "fast_floor",
        tolerance: 1e-16,
        ..fast
    };
    for (variant, sizes) in [
        (dense, vec![250, 500, 1_000]),
        (fast, fast_sizes.clone()),
        (fast_floor, fast_sizes),
    ] {
        for n in sizes {
            report(n, variant);
            let p = problem(n, variant);
            group.bench_with_input(BenchmarkId::new(variant.name, n), &n, |b, _| {
                b.iter(|| {
                    black_box(
                        p.solve_bvp(Scheme::Variational, 0.0, 1.0)
                            .expect("converges"),
                    )
                })
            });
        }
    }
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); bench);
