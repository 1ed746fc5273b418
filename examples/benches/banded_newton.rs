//! Newton on the step Jacobian of a chain: the banded factorisation against the dense one.
//!
//! An FPUT chain with fixed ends, written with loops (`#[lagrangian]` states its Hessian is
//! tridiagonal: `hessian_bandwidth() = Some(1)`), run by the direct Gauss-FDE− scheme, whose
//! every step is implicit (`L_xx` depends on `x`). The same run through a wrapper that hides
//! the bandwidth takes the dense `d × d` elimination; the two runs are checked to agree before
//! timing. Both evaluate the Hessian densely: only the factorisation differs.
//!
//! `cargo bench -p varembed-examples --bench banded_newton`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{Embedding, Grid, Lagrangian, Problem, Scheme, Side, lagrangian};
use varembed_tests::models::dense::Dense;

/// 200 steps of `h = 0.05`, amplitude 0.8 in the first normal mode, the default Newton
/// tolerance `1e-12`.
const STEPS: usize = 200;
const T_END: f64 = 10.0;
const AMPLITUDE: f64 = 0.8;

macro_rules! chain {
    ($module:ident, $n:expr) => {
        mod $module {
            use super::*;
            pub const N: usize = $n;

            /// `L = Σ ½v_i² − Σ V(x_{i+1} − x_i)`, `V(d) = d²/2 + α d³/3 + β d⁴/4`, walls at 0.
            #[lagrangian]
            pub fn fput(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
                let mut kinetic = 0.0;
                for i in 0..N {
                    kinetic += 0.5 * v[i] * v[i];
                }
                let mut potential = 0.0;
                for i in 0..N - 1 {
                    let d = x[i + 1] - x[i];
                    potential += 0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4);
                }
                let (first, last) = (x[0], -x[N - 1]);
                potential +=
                    0.5 * first * first + alpha / 3.0 * first.powi(3) + beta / 4.0 * first.powi(4);
                potential +=
                    0.5 * last * last + alpha / 3.0 * last.powi(3) + beta / 4.0 * last.powi(4);
                kinetic - potential
            }

            /// The first normal mode of the linear chain.
            pub fn start() -> [f64; N] {
                std::array::from_fn(|i| {
                    AMPLITUDE * (std::f64::consts::PI * (i + 1) as f64 / (N + 1) as f64).sin()
                })
            }
        }
    };
}

chain!(d16, 16);
chain!(d64, 64);

/// The direct Gauss-FDE− run of `lag`, banded and dense, side by side in one group.
fn side_by_side<const D: usize, L: Lagrangian<D>>(c: &mut Criterion, lag: &L, q0: [f64; D]) {
    let grid = Grid::new(0.0, T_END, STEPS).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let dense = Dense(lag);
    let banded_problem = Problem::new(lag, grid, embedding);
    let dense_problem = Problem::new(&dense, grid, embedding);
    // Once, outside timing: both paths take the same run.
    let a = banded_problem
        .solve_ivp(Scheme::Direct, q0, [0.0; D])
        .unwrap();
    let b = dense_problem
        .solve_ivp(Scheme::Direct, q0, [0.0; D])
        .unwrap();
    assert_eq!(a.explicit_steps, 0, "every step is implicit");
    let gap =
        a.q.iter()
            .zip(&b.q)
            .map(|(p, q)| (p - q).amax())
            .fold(0.0, f64::max);
    assert!(gap <= 1e-12, "banded and dense runs differ by {gap:e}");
    println!(
        "d = {D}: bandwidth {:?}, Newton iterations {} (banded) / {} (dense), gap {gap:.1e}",
        lag.hessian_bandwidth(),
        a.newton_iterations,
        b.newton_iterations
    );
    let mut group = c.benchmark_group(format!("fput_d{D}_direct_backward"));
    let id = format!("{STEPS} steps");
    group.bench_function(BenchmarkId::new("banded", &id), |bch| {
        bch.iter(|| banded_problem.solve_ivp(Scheme::Direct, black_box(q0), [0.0; D]))
    });
    group.bench_function(BenchmarkId::new("dense", &id), |bch| {
        bch.iter(|| dense_problem.solve_ivp(Scheme::Direct, black_box(q0), [0.0; D]))
    });
    group.finish();
}

fn banded_newton(c: &mut Criterion) {
    let (alpha, beta) = (0.25, 0.7);
    side_by_side(c, &d16::Fput { alpha, beta }, d16::start());
    side_by_side(c, &d64::Fput { alpha, beta }, d64::start());
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); banded_newton);
