//! Newton on the step Jacobian of a chain: the banded factorisation against the dense one.
//!
//! An FPUT chain with fixed ends, written with loops (`#[lagrangian]` states its Hessian is
//! tridiagonal: `hessian_bandwidth() = Some(1)`), run by the direct Gauss-FDE− scheme, whose
//! every step is implicit (`L_xx` depends on `x`). The same run through a wrapper that hides
//! the bandwidth takes the dense `d × d` elimination; the two runs are checked to agree before
//! timing. Both evaluate the Hessian densely: only the factorisation differs.
//!
//! The run-time engine (`DynProblem`, the engine `Problem` hands this model to from
//! `RUN_TIME_FROM` degrees of freedom on) runs the same steps on slices with a tridiagonal
//! Jacobian: the line that says where each path is faster.
//!
//! A last line is the run a user would write by hand for this chain: the direct Gauss-FDE−
//! step of `L = ½|v|² − U(x)` is `y + h² ∇U(y) = 2b − a`, solved by Newton with the
//! tridiagonal Jacobian `I + h² ∇²U(y)` (Thomas algorithm), from the same start `Q_1 = q0 + h v0`
//! and with the same stopping rule on the same residual.
//!
//! `cargo bench -p varembed-examples --bench banded_newton`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{DynLagrangian, DynProblem, Embedding, Grid, Lagrangian, Problem, Scheme, Side};
use varembed_tests::models::chain::direct_backward_by_hand;
use varembed_tests::models::dense::{ConstGeneric, Dense};
use varembed_tests::models::generated::{fput16, fput32, fput64};

/// 200 steps of `h = 0.05`, amplitude 0.8 in the first normal mode, the default Newton
/// tolerance `1e-12`.
const STEPS: usize = 200;
const T_END: f64 = 10.0;
const AMPLITUDE: f64 = 0.8;

/// The first normal mode of the linear chain of `D` particles, at [`AMPLITUDE`].
fn first_mode<const D: usize>() -> [f64; D] {
    std::array::from_fn(|i| {
        AMPLITUDE * (std::f64::consts::PI * (i + 1) as f64 / (D + 1) as f64).sin()
    })
}

/// The direct Gauss-FDE− run of the chain written by hand (the support crate's
/// `direct_backward_by_hand`: Thomas algorithm, the library's residual and stopping rule),
/// from rest, collecting its nodes.
fn hand_written(q0: &[f64], params: (f64, f64)) -> Vec<Vec<f64>> {
    let mut q = Vec::with_capacity(STEPS + 1);
    let v0 = vec![0.0; q0.len()];
    let h = T_END / STEPS as f64;
    direct_backward_by_hand(q0, &v0, (h, STEPS), params, |node| q.push(node.to_vec()));
    q
}

/// The direct Gauss-FDE− run of `lag`, banded and dense, side by side in one group, with the
/// hand-written run of the same chain.
fn side_by_side<const D: usize, L: Lagrangian<D> + DynLagrangian>(
    c: &mut Criterion,
    lag: &L,
    q0: [f64; D],
) {
    let grid = Grid::new(0.0, T_END, STEPS).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let dense = Dense(lag);
    // The const-generic banded path: from `RUN_TIME_FROM` degrees of freedom on, `Problem`
    // hands a model with loops to the run-time engine, which the wrapper prevents.
    let banded = ConstGeneric(lag);
    let banded_problem = Problem::new(&banded, grid, embedding);
    let run_time_problem = DynProblem::new(lag, grid, embedding);
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
    let run_time = run_time_problem
        .solve_ivp(Scheme::Direct, &q0, &[0.0; D])
        .unwrap();
    let run_time_gap = (0..=STEPS)
        .map(|k| {
            (0..D)
                .map(|i| (run_time.node(k)[i] - a.q[k][i]).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    assert!(
        run_time_gap <= 1e-12,
        "run-time and const-generic runs differ by {run_time_gap:e}"
    );
    let by_hand = hand_written(&q0, PARAMS);
    let hand_gap =
        a.q.iter()
            .zip(&by_hand)
            .map(|(p, q)| {
                p.iter()
                    .zip(q)
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            })
            .fold(0.0, f64::max);
    assert!(
        hand_gap <= 1e-10,
        "library and hand-written runs differ by {hand_gap:e}"
    );
    println!(
        "d = {D}: bandwidth {:?}, Newton iterations {} (banded) / {} (dense), gap {gap:.1e}, \
         gap to the hand-written run {hand_gap:.1e}",
        Lagrangian::<D>::hessian_bandwidth(lag),
        a.newton_iterations,
        b.newton_iterations
    );
    let mut group = c.benchmark_group(format!("fput_d{D}_direct_backward"));
    let id = format!("{STEPS} steps");
    group.bench_function(BenchmarkId::new("banded", &id), |bch| {
        bch.iter(|| banded_problem.solve_ivp(Scheme::Direct, black_box(q0), [0.0; D]))
    });
    group.bench_function(BenchmarkId::new("run_time", &id), |bch| {
        bch.iter(|| run_time_problem.solve_ivp(Scheme::Direct, black_box(&q0), &[0.0; D]))
    });
    group.bench_function(BenchmarkId::new("dense", &id), |bch| {
        bch.iter(|| dense_problem.solve_ivp(Scheme::Direct, black_box(q0), [0.0; D]))
    });
    group.bench_function(BenchmarkId::new("hand_written", &id), |bch| {
        bch.iter(|| hand_written(black_box(&q0), PARAMS))
    });
    group.finish();
}

/// `(α, β)` of the chain.
const PARAMS: (f64, f64) = (0.25, 0.7);

fn banded_newton(c: &mut Criterion) {
    let (alpha, beta) = PARAMS;
    side_by_side(c, &fput16::Fput { alpha, beta }, first_mode());
    side_by_side(c, &fput32::Fput { alpha, beta }, first_mode());
    side_by_side(c, &fput64::Fput { alpha, beta }, first_mode());
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); banded_newton);
