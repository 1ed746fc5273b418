//! The cost of a holonomic constraint: the spherical pendulum in Cartesian coordinates under
//! `|x| = 1` (`Problem::solve_constrained_ivp`, three unknowns and one multiplier per step, a
//! 4 × 4 saddle-point Newton system) against the same pendulum in angles (minimal coordinates,
//! a `#[lagrangian]` model in `θ, φ`, two unknowns per step), side by side in one run: the
//! midpoint variational scheme, 1000 steps of `h = 10⁻²` from `θ = 1`, `φ̇ = 0.8`.
//!
//! `cargo bench -p varembed-examples --bench constraints`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::Criterion;
use varembed::{Embedding, Grid, Holonomic, Problem, Scheme, Vector, lagrangian};

/// A unit mass under unit gravity along `−z`.
#[lagrangian]
fn falling(x: [f64; 3], v: [f64; 3]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - x[2]
}

/// The unit sphere, `g = ½(|x|² − 1)`.
#[lagrangian]
fn sphere(x: [f64; 3], _v: [f64; 3]) -> f64 {
    0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 1.0)
}

/// The same pendulum in angles: `L = ½(θ̇² + sin²θ φ̇²) + cos θ`.
#[lagrangian]
fn angles(x: [f64; 2], v: [f64; 2]) -> f64 {
    let s = x[0].sin();
    0.5 * (v[0] * v[0] + s * s * v[1] * v[1]) + x[0].cos()
}

const THETA0: f64 = 1.0;
const PHI_RATE0: f64 = 0.8;
const STEPS: usize = 1000;

fn cartesian(theta: f64, phi: f64) -> Vector<3> {
    Vector::<3>::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        -theta.cos(),
    )
}

fn constraints(c: &mut Criterion) {
    let grid = Grid::new(0.0, 10.0, STEPS).unwrap();
    let embedding = Embedding::midpoint();
    let constrained = Problem::new(&Falling, grid, embedding);
    let minimal = Problem::new(&Angles, grid, embedding);
    let q0 = cartesian(THETA0, 0.0);
    let v0 = Vector::<3>::new(0.0, THETA0.sin() * PHI_RATE0, 0.0);
    let (a0, w0) = ([THETA0, 0.0], [0.0, PHI_RATE0]);

    // The two runs are one pendulum: their end points agree to the scheme's O(h²).
    let run = constrained
        .solve_constrained_ivp(Scheme::Variational, &Holonomic(Sphere), q0, v0)
        .unwrap();
    let reduced = minimal.solve_ivp(Scheme::Variational, a0, w0).unwrap();
    let end = reduced.last();
    let gap = (run.solution.last() - cartesian(end[0], end[1])).amax();
    assert!(gap < 1e-3, "the two forms differ by {gap:e}");
    println!(
        "Newton iterations per step: Cartesian under |x| = 1 {:.2}, angles {:.2}; end points \
         {gap:.1e} apart",
        run.solution.newton_iterations as f64 / STEPS as f64,
        reduced.newton_iterations as f64 / STEPS as f64,
    );

    let mut g = c.benchmark_group("spherical_pendulum_midpoint_variational_1000_steps");
    g.bench_function("cartesian_constrained", |b| {
        b.iter(|| {
            constrained.solve_constrained_ivp(
                Scheme::Variational,
                &Holonomic(Sphere),
                black_box(q0),
                v0,
            )
        })
    });
    g.bench_function("angles", |b| {
        b.iter(|| minimal.solve_ivp(Scheme::Variational, black_box(a0), w0))
    });
    g.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); constraints);
