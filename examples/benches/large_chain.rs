//! Large models: the FPUT chain of run-time dimension `d` through `DynProblem`, against the
//! loops a user would write by hand for this chain alone, side by side in one group each.
//!
//! Each group has three lines: `generated`, the library's run of the chain written with loops
//! and `#[lagrangian]` (`x: &[f64]` with a run-time `n`); `hand_model`, the same run of the
//! chain implemented by hand as a `DynLagrangian`; and `hand_written`, the loop a user writes
//! for this chain and this scheme alone.
//!
//! - `fput_explicit_variational_d1024_{10000, 100000}`: the variational Gauss-FDE+ run
//!   (Störmer–Verlet; the step is affine with `h J = I`, so it is taken in closed form), 10⁴
//!   and 10⁵ steps of `h = 0.05`, against the two-step Störmer–Verlet loop with the force
//!   written out over the bonds. The blow-up guard samples the energy every 8th step of the
//!   shorter run and every 64th of the longer; the `_guard_off` lines run without it.
//! - `fput_direct_backward_d{64, 1024, 4096}`: the direct Gauss-FDE− run, every step implicit,
//!   200 steps of `h = 0.05`, against a hand-written Newton with the tridiagonal Jacobian
//!   (Thomas algorithm), the same residual, guess and stopping rule (tolerance `1e-12`).
//! - `fput_midpoint_variational_d{64, 1024, 4096}`: the variational midpoint run, every step
//!   implicit, 200 steps of `h = 0.05`, against a hand-written Newton for the midpoint discrete
//!   Euler–Lagrange equation with its tridiagonal Jacobian (Thomas algorithm), the discrete
//!   Legendre start, the guess `2b − a` and the stopping rule `1e-12 (1 + |π|∞)`.
//!
//! - `fput_gauss_legendre_s2_d{64, 1024, 4096}`: the variational Gauss–Legendre run with two
//!   stages (order 4), 200 steps of `h = 0.05`: how its cost grows with `d`. No hand-written
//!   loop (a collocation Newton for this chain alone is beyond what a user would write to
//!   compare); the generated model's run is checked against the hand-written model's.
//!
//! The chain is `α = 0.25`, `β = 0.7` between walls, from a smooth displacement of amplitude
//! 0.8 with velocity `−0.3 q0`. Each run keeps only its last nodes (an observer that does
//! nothing), as a long run at large `d` would. Before timing, each library run's last node is
//! checked against the hand-written run's (to 1e-10 per 10⁴ steps).
//!
//! `cargo bench -p varembed-examples --bench large_chain`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{DynLagrangian, DynProblem, Embedding, Grid, Scheme, Side};
use varembed_tests::models::chain::{
    FputChain, HandWrittenRun, direct_backward_by_hand, midpoint_variational_by_hand,
    stormer_verlet_by_hand,
};
use varembed_tests::models::generated::FputChain as GeneratedChain;

const PARAMS: (f64, f64) = (0.25, 0.7);
const H: f64 = 0.05;

/// The initial data at dimension `d`: a smooth displacement and a velocity `−0.3 q0`.
fn initial(d: usize) -> (Vec<f64>, Vec<f64>) {
    let q0: Vec<f64> = (0..d)
        .map(|i| 0.8 * ((i as f64 + 1.0) * 0.05).sin())
        .collect();
    let v0 = q0.iter().map(|q| -0.3 * q).collect();
    (q0, v0)
}

/// The last node of a hand-written run.
fn last_by_hand(by_hand: HandWrittenRun, q0: &[f64], v0: &[f64], steps: usize) -> Vec<f64> {
    let mut last = Vec::new();
    by_hand(q0, v0, (H, steps), PARAMS, &mut |node: &[f64]| {
        last.clear();
        last.extend_from_slice(node);
    });
    last
}

/// The library's run of `scheme` on `model`: checked against the hand-written run's last node
/// `reference`, reported, and timed as the line `name` of `group` (with a guard-off line for
/// the variational scheme).
fn library_line<L: DynLagrangian>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    (model, embedding, scheme): (&L, Embedding, Scheme),
    (steps, reference): (usize, &[f64]),
) {
    let (q0, v0) = initial(model.dimension());
    let grid = Grid::new(0.0, H * steps as f64, steps).unwrap();
    let problem = DynProblem::new(model, grid, embedding);
    let run = problem.run_ivp(scheme, &q0, &v0, |_| {}).unwrap();
    let gap = run
        .last
        .iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    // Round-off, summed in another order, grows along the run (like a phase error): 1e-10
    // per 10⁴ steps.
    let tolerance = 1e-10 * (steps as f64 / 1e4).max(1.0);
    assert!(
        gap <= tolerance,
        "{name}: library and hand-written runs differ by {gap:e}"
    );
    println!(
        "{name}: band {}, Newton iterations {}, closed-form steps {}, gap {gap:.1e}",
        run.band, run.newton_iterations, run.explicit_steps
    );
    let id = format!("{steps} steps");
    group.bench_function(BenchmarkId::new(name, &id), |b| {
        b.iter(|| {
            problem
                .run_ivp(scheme, black_box(&q0), &v0, |_| {})
                .unwrap()
        })
    });
    if scheme == Scheme::Variational {
        let unguarded = problem.with_blow_up_guard(false);
        group.bench_function(BenchmarkId::new(format!("{name}_guard_off"), &id), |b| {
            b.iter(|| {
                unguarded
                    .run_ivp(scheme, black_box(&q0), &v0, |_| {})
                    .unwrap()
            })
        });
    }
}

/// One group at dimension `d`: the library's run of `scheme` on the generated and on the
/// hand-written model, and the hand-written loop `by_hand`.
fn side_by_side(
    c: &mut Criterion,
    group: &str,
    (d, embedding, scheme): (usize, Embedding, Scheme),
    by_hand: HandWrittenRun,
    steps: usize,
) {
    let (alpha, beta) = PARAMS;
    let (q0, v0) = initial(d);
    let reference = last_by_hand(by_hand, &q0, &v0, steps);
    let mut g = c.benchmark_group(group);
    let generated = GeneratedChain { n: d, alpha, beta };
    let hand_model = FputChain {
        n: d,
        alpha,
        beta,
        periodic: false,
    };
    library_line(
        &mut g,
        "generated",
        (&generated, embedding, scheme),
        (steps, &reference),
    );
    library_line(
        &mut g,
        "hand_model",
        (&hand_model, embedding, scheme),
        (steps, &reference),
    );
    g.bench_function(
        BenchmarkId::new("hand_written", format!("{steps} steps")),
        |b| b.iter(|| last_by_hand(by_hand, black_box(&q0), &v0, steps)),
    );
    g.finish();
}

fn large_chain(c: &mut Criterion) {
    // 10⁴ steps, where the blow-up guard samples every 8th step, and 10⁵, every 64th.
    for steps in [10_000, 100_000] {
        side_by_side(
            c,
            &format!("fput_explicit_variational_d1024_{steps}"),
            (
                1024,
                Embedding::finite_difference(Side::Forward),
                Scheme::Variational,
            ),
            |q, v, g, p, o| stormer_verlet_by_hand(q, v, g, p, o),
            steps,
        );
    }
    for d in [64, 1024, 4096] {
        side_by_side(
            c,
            &format!("fput_direct_backward_d{d}"),
            (
                d,
                Embedding::finite_difference(Side::Backward),
                Scheme::Direct,
            ),
            |q, v, g, p, o| direct_backward_by_hand(q, v, g, p, o),
            200,
        );
    }
    for d in [64, 1024, 4096] {
        side_by_side(
            c,
            &format!("fput_midpoint_variational_d{d}"),
            (d, Embedding::midpoint(), Scheme::Variational),
            |q, v, g, p, o| midpoint_variational_by_hand(q, v, g, p, o),
            200,
        );
    }
    for d in [64, 1024, 4096] {
        gauss_legendre_side_by_side(c, d, 200);
    }
}

/// The Gauss–Legendre group at dimension `d`: the library's run on the generated and on the
/// hand-written model, the first checked against the second.
fn gauss_legendre_side_by_side(c: &mut Criterion, d: usize, steps: usize) {
    let (alpha, beta) = PARAMS;
    let (q0, v0) = initial(d);
    let embedding = Embedding::gauss_legendre(2).unwrap();
    let grid = Grid::new(0.0, H * steps as f64, steps).unwrap();
    let hand_model = FputChain {
        n: d,
        alpha,
        beta,
        periodic: false,
    };
    let reference = DynProblem::new(&hand_model, grid, embedding)
        .run_ivp(Scheme::Variational, &q0, &v0, |_| {})
        .unwrap()
        .last;
    let mut g = c.benchmark_group(format!("fput_gauss_legendre_s2_d{d}"));
    let generated = GeneratedChain { n: d, alpha, beta };
    let line = (steps, reference.as_slice());
    library_line(
        &mut g,
        "generated",
        (&generated, embedding, Scheme::Variational),
        line,
    );
    library_line(
        &mut g,
        "hand_model",
        (&hand_model, embedding, Scheme::Variational),
        line,
    );
    g.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); large_chain);
