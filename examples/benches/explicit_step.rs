//! The explicit variational run of a `#[lagrangian]` model, through the public API, against a
//! hand-written Störmer–Verlet loop that writes the same nodes into a `Vec`.
//!
//! `generated` is `Problem::solve_ivp(Scheme::Variational, q0, v0)` under Gauss-FDE−: the
//! discrete Legendre start, then the variational recurrence with core's closed-form step (the
//! macro reports `L_xv` and `L_vv` constant, so every step is affine: no Newton iteration, and
//! `J⁻¹ = h` computed once per run), returning a `Solution`. `hand_written` is the loop a user
//! would write for the same scheme, `p = (Q_{n−1} − Q_{n−2})/h + h f(Q_{n−1})`,
//! `Q_n = Q_{n−1} + h p`, with `1/h` precomputed and the force written out by hand, pushing the
//! same `Vector<D>` nodes into a `Vec` of the same capacity. Both are checked once, outside the timing, to give the
//! same nodes (to 1e-12; in fact bit for bit).
//!
//! `generated_guard_off` is the same run with the blow-up guard disabled
//! (`Problem::with_blow_up_guard(false)`): the difference to `generated` is the guard's cost
//! (one energy evaluation every 64 steps and its window bookkeeping).
//!
//! `cargo bench -p varembed-examples --bench explicit_step`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use varembed::{Embedding, Grid, Lagrangian, Problem, Scheme, Side, Solution, Vector};
use varembed_tests::curve::max_diff;
use varembed_tests::models::generated::{Kepler, UnitPendulum};

/// Steps per run.
const STEPS: usize = 1_000_000;

/// The run as a user makes it: a `Problem`, then `solve_ivp`.
fn generated<L: Lagrangian<D>, const D: usize>(
    lagrangian: &L,
    grid: Grid,
    q0: Vector<D>,
    v0: Vector<D>,
) -> Solution<D> {
    run(lagrangian, grid, q0, v0, true)
}

/// [`generated`] with the blow-up guard on or off.
fn run<L: Lagrangian<D>, const D: usize>(
    lagrangian: &L,
    grid: Grid,
    q0: Vector<D>,
    v0: Vector<D>,
    guard: bool,
) -> Solution<D> {
    let problem = Problem::new(
        lagrangian,
        grid,
        Embedding::finite_difference(Side::Backward),
    )
    .with_blow_up_guard(guard);
    problem
        .solve_ivp(Scheme::Variational, q0, v0)
        .expect("a resolved explicit run")
}

/// The nodes of [`generated`], checked to come from the closed-form step alone.
fn generated_nodes<L: Lagrangian<D>, const D: usize>(
    lagrangian: &L,
    grid: Grid,
    q0: Vector<D>,
    v0: Vector<D>,
) -> Vec<Vector<D>> {
    let run = generated(lagrangian, grid, q0, v0);
    assert_eq!(
        run.explicit_steps,
        STEPS - 1,
        "every step Q_2..=Q_N explicit"
    );
    assert_eq!(run.newton_iterations, 0);
    run.q
}

/// Störmer–Verlet for `L = ½v² + cos x` in momentum form.
fn pendulum_by_hand(grid: Grid, q0: f64, v0: f64) -> Vec<Vector<1>> {
    let n = grid.n();
    let h = grid.h();
    let inv_h = 1.0 / h;
    let mut q = Vec::with_capacity(n + 1);
    let (mut a, mut b) = (q0, q0 + h * v0);
    q.push(Vector::<1>::new(a));
    q.push(Vector::<1>::new(b));
    for _ in 2..=n {
        let p = (b - a) * inv_h - b.sin() * h;
        let y = b + h * p;
        q.push(Vector::<1>::new(y));
        (a, b) = (b, y);
    }
    q
}

/// Störmer–Verlet for `L = ½|v|² + 1/|x|` in momentum form, with the textbook force
/// `∇U(x) = x/|x|³`: one square root and one division per step.
fn kepler_by_hand(grid: Grid, q0: Vector<2>, v0: Vector<2>) -> Vec<Vector<2>> {
    kepler_loop(grid, q0, v0, |b| {
        let r2 = b[0] * b[0] + b[1] * b[1];
        let k = 1.0 / (r2 * r2.sqrt());
        [b[0] * k, b[1] * k]
    })
}

/// The same loop with the force written the way the macro's derivative of `1/|x|` evaluates
/// it, `(1/|x|)²·(x_i/|x|)` (three divisions, each one deep after the square root): the
/// generated arithmetic bit for bit, so its difference to `generated` is the solver loop
/// alone. (On this run the textbook force gives the same nodes too: its last-bit differences
/// vanish in `p = v − h ∇U`, since `h |∇U| ≪ |v|`.)
fn kepler_macro_formula(grid: Grid, q0: Vector<2>, v0: Vector<2>) -> Vec<Vector<2>> {
    kepler_loop(grid, q0, v0, |b| {
        let s = (b[0] * b[0] + b[1] * b[1]).sqrt();
        let n = 1.0 / s;
        [n * n * (b[0] / s), n * n * (b[1] / s)]
    })
}

/// `p = (b − a)/h − h ∇U(b)`, `Q_n = b + h p`; `grad_u(b)` is `∇U(b) = x/|x|³`.
#[inline(always)]
fn kepler_loop(
    grid: Grid,
    q0: Vector<2>,
    v0: Vector<2>,
    grad_u: impl Fn([f64; 2]) -> [f64; 2],
) -> Vec<Vector<2>> {
    let n = grid.n();
    let h = grid.h();
    let inv_h = 1.0 / h;
    let mut q = Vec::with_capacity(n + 1);
    let (mut a, mut b) = ([q0[0], q0[1]], [q0[0] + h * v0[0], q0[1] + h * v0[1]]);
    q.push(Vector::<2>::from(a));
    q.push(Vector::<2>::from(b));
    for _ in 2..=n {
        let g = grad_u(b);
        let mut y = [0.0; 2];
        for i in 0..2 {
            let p = (b[i] - a[i]) * inv_h - g[i] * h;
            y[i] = b[i] + h * p;
        }
        q.push(Vector::<2>::from(y));
        (a, b) = (b, y);
    }
    q
}

fn explicit_step(c: &mut Criterion) {
    // Pendulum: q(0) = 1, q̇(0) = 0 over t ∈ [0, 100], h = 1e-4.
    let grid = Grid::new(0.0, 100.0, STEPS).unwrap();
    let (q0, v0) = (1.0, 0.0);
    let by_macro = generated_nodes(
        &UnitPendulum,
        grid,
        Vector::<1>::new(q0),
        Vector::<1>::new(v0),
    );
    let by_hand = pendulum_by_hand(grid, q0, v0);
    let d = max_diff(&by_macro, &by_hand);
    eprintln!("pendulum: max |generated − hand_written| = {d:e}");
    assert!(d <= 1e-12, "pendulum: the two runs differ by {d:e}");
    let mut group = c.benchmark_group("explicit_step/pendulum");
    group.sample_size(20);
    group.bench_function(BenchmarkId::new("generated", STEPS), |bch| {
        bch.iter(|| {
            generated(
                &UnitPendulum,
                black_box(grid),
                Vector::<1>::new(black_box(q0)),
                Vector::<1>::new(black_box(v0)),
            )
        })
    });
    group.bench_function(BenchmarkId::new("generated_guard_off", STEPS), |bch| {
        bch.iter(|| {
            run(
                &UnitPendulum,
                black_box(grid),
                Vector::<1>::new(black_box(q0)),
                Vector::<1>::new(black_box(v0)),
                false,
            )
        })
    });
    group.bench_function(BenchmarkId::new("hand_written", STEPS), |bch| {
        bch.iter(|| pendulum_by_hand(black_box(grid), black_box(q0), black_box(v0)))
    });
    group.finish();

    // Kepler, a = 1, e = 0.7 (period 2π): from aphelion r = 1.7 with speed √(0.3/1.7), 100
    // orbits, h ≈ 6.3e-4 (≈ 25 steps across the perihelion passage at r = 0.3).
    let grid = Grid::new(0.0, 100.0 * std::f64::consts::TAU, STEPS).unwrap();
    let (q0, v0) = (
        Vector::<2>::new(1.7, 0.0),
        Vector::<2>::new(0.0, (0.3f64 / 1.7).sqrt()),
    );
    let by_macro = generated_nodes(&Kepler, grid, q0, v0);
    let by_hand = kepler_by_hand(grid, q0, v0);
    let d = max_diff(&by_macro, &by_hand);
    eprintln!("kepler: max |generated − hand_written| = {d:e}");
    assert!(d <= 1e-12, "kepler: the two runs differ by {d:e}");
    let d = max_diff(&by_macro, &kepler_macro_formula(grid, q0, v0));
    eprintln!("kepler: max |generated − hand_written_macro_formula| = {d:e}");
    assert!(d <= 1e-12, "kepler: the two runs differ by {d:e}");
    let mut group = c.benchmark_group("explicit_step/kepler");
    group.sample_size(20);
    group.bench_function(BenchmarkId::new("generated", STEPS), |bch| {
        bch.iter(|| generated(&Kepler, black_box(grid), black_box(q0), black_box(v0)))
    });
    group.bench_function(BenchmarkId::new("generated_guard_off", STEPS), |bch| {
        bch.iter(|| {
            run(
                &Kepler,
                black_box(grid),
                black_box(q0),
                black_box(v0),
                false,
            )
        })
    });
    group.bench_function(BenchmarkId::new("hand_written", STEPS), |bch| {
        bch.iter(|| kepler_by_hand(black_box(grid), black_box(q0), black_box(v0)))
    });
    group.bench_function(
        BenchmarkId::new("hand_written_macro_formula", STEPS),
        |bch| bch.iter(|| kepler_macro_formula(black_box(grid), black_box(q0), black_box(v0))),
    );
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); explicit_step);
