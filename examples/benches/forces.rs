//! The cost of a generalised force, side by side with the conservative run of the same model,
//! in one run:
//!
//! - the double pendulum, 1000 implicit steps of `h = 10⁻³` (the `implicit_schemes` bench's
//!   state) under the midpoint and the Gauss-FDE− variational schemes: conservative; under a
//!   position-dependent force (a torque `−0.5 sin θ₁` on each joint: one more evaluation per
//!   Newton iteration, its Jacobian constant in `v`); under Rayleigh friction `R = ½ γ |v|²`
//!   (velocity-dependent, through the macro's derivatives of `R`);
//! - Kepler's orbit, 10⁵ explicit Gauss-FDE− variational steps (Störmer–Verlet):
//!   conservative; under linear drag `f = −γ v`. The drag's Jacobian is constant, so every step
//!   stays in closed form (the step's equation `p@right = π` does not read the force; the
//!   force enters the momentum `π`).
//! - the FPUT chain of run-time dimension `d = 1024` and `4096` (`DynProblem`), 100 midpoint
//!   variational steps: conservative; under dashpots between neighbours (Rayleigh
//!   `R = Σ ½ γ (v_{i+1} − v_i)²`, velocity-dependent, its Jacobian tridiagonal like the
//!   chain's Hessian). The force's pattern joins the band of the step Jacobian, so the forced
//!   run costs what the conservative one does and both grow linearly in `d`; a dense solve
//!   would cost `d³`.
//!
//! `cargo bench -p varembed-examples --bench forces`; figures in BENCHMARKS.md.

use std::hint::black_box;

use criterion::Criterion;
use varembed::{
    DynProblem, Embedding, Force, ForceDependence, ForceJacobian, Forced, Grid, Matrix, Problem,
    Rayleigh, Scheme, Side, Vector, lagrangian,
};
use varembed_tests::models::generated::{DoublePendulum, FputChain, Kepler};

const PARAMS: DoublePendulum = varembed_tests::bench::DOUBLE_PENDULUM;
const Q0: [f64; 2] = varembed_tests::bench::DOUBLE_PENDULUM_START.0;
const V0: [f64; 2] = varembed_tests::bench::DOUBLE_PENDULUM_START.1;

/// `R = ½ γ |v|²`: `f = −γ v`.
#[lagrangian]
fn friction(_x: [f64; 2], v: [f64; 2], gamma: f64) -> f64 {
    0.5 * gamma * (v[0] * v[0] + v[1] * v[1])
}

/// `R = Σ ½ γ (v_{i+1} − v_i)²` over the `n` sites of a chain of run-time dimension.
#[lagrangian]
fn dashpots(_x: &[f64], v: &[f64], n: usize, gamma: f64) -> f64 {
    let mut r = 0.0;
    for i in 0..n - 1 {
        let w = v[i + 1] - v[i];
        r += 0.5 * gamma * w * w;
    }
    r
}

/// A torque `−0.5 sin θ₁` on each joint: position-dependent, its Jacobian not constant in `x`.
struct Torque;

impl Force<2> for Torque {
    #[inline]
    fn force(&self, x: &Vector<2>, _v: &Vector<2>, _t: f64) -> Vector<2> {
        let s = -0.5 * x[0].sin();
        Vector::<2>::new(s, s)
    }
    #[inline]
    fn jacobian(&self, x: &Vector<2>, _v: &Vector<2>, _t: f64) -> ForceJacobian<2> {
        let c = -0.5 * x[0].cos();
        ForceJacobian {
            x: Matrix::<2>::new(c, 0.0, c, 0.0),
            v: Matrix::<2>::zeros(),
        }
    }
    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence {
            x: varembed::Dependence {
                x: true,
                v: false,
                t: false,
            },
            v: varembed::Dependence::NONE,
        }
    }
}

fn forces(c: &mut Criterion) {
    let torque = Forced::new(PARAMS, Torque);
    let friction = Forced::new(PARAMS, Rayleigh(Friction { gamma: 0.2 }));
    for (embedding, group) in [
        (Embedding::midpoint(), "double_pendulum_midpoint_1000_steps"),
        (
            Embedding::finite_difference(Side::Backward),
            "double_pendulum_gauss_fde_minus_1000_steps",
        ),
    ] {
        let grid = Grid::new(0.0, 1.0, 1000).unwrap();
        let mut g = c.benchmark_group(group);
        let conservative = Problem::new(&PARAMS, grid, embedding);
        let torqued = Problem::new(&torque, grid, embedding);
        let rubbed = Problem::new(&friction, grid, embedding);
        for (name, iterations) in [
            (
                "conservative",
                conservative.solve_ivp(Scheme::Variational, Q0, V0),
            ),
            ("torque", torqued.solve_ivp(Scheme::Variational, Q0, V0)),
            ("friction", rubbed.solve_ivp(Scheme::Variational, Q0, V0)),
        ] {
            let run = iterations.unwrap();
            println!(
                "{embedding} {name}: {:.2} Newton iterations per step",
                run.newton_iterations as f64 / 1000.0
            );
        }
        g.bench_function("conservative", |b| {
            b.iter(|| conservative.solve_ivp(Scheme::Variational, black_box(Q0), V0))
        });
        g.bench_function("torque", |b| {
            b.iter(|| torqued.solve_ivp(Scheme::Variational, black_box(Q0), V0))
        });
        g.bench_function("friction", |b| {
            b.iter(|| rubbed.solve_ivp(Scheme::Variational, black_box(Q0), V0))
        });
        g.finish();
    }

    // Kepler at e = 0.5 from the pericentre, 10⁵ explicit steps over ten orbits.
    let (q0, v0) = ([0.5, 0.0], [0.0, 3.0f64.sqrt()]);
    let grid = Grid::new(0.0, 20.0 * std::f64::consts::PI, 100_000).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let dragged = Forced::new(Kepler, Rayleigh(Friction { gamma: 1e-3 }));
    let conservative = Problem::new(&Kepler, grid, embedding);
    let drag = Problem::new(&dragged, grid, embedding);
    let run = drag.solve_ivp(Scheme::Variational, q0, v0).unwrap();
    assert_eq!(
        run.newton_iterations, 0,
        "linear drag keeps the steps explicit"
    );
    let mut g = c.benchmark_group("kepler_explicit_100000_steps");
    g.bench_function("conservative", |b| {
        b.iter(|| conservative.solve_ivp(Scheme::Variational, black_box(q0), v0))
    });
    g.bench_function("linear_drag", |b| {
        b.iter(|| drag.solve_ivp(Scheme::Variational, black_box(q0), v0))
    });
    g.finish();
}

/// The chain of run-time dimension, conservative and under dashpots, at two sizes.
fn chain_forces(c: &mut Criterion) {
    let mut g = c.benchmark_group("chain_midpoint_100_steps");
    for d in [1024, 4096] {
        let chain = FputChain {
            n: d,
            alpha: 0.25,
            beta: 0.7,
        };
        let damped = Forced::new(chain, Rayleigh(Dashpots { n: d, gamma: 0.3 }));
        let q0: Vec<f64> = (0..d)
            .map(|i| 0.8 * ((i as f64 + 1.0) * 0.05).sin())
            .collect();
        let v0: Vec<f64> = q0.iter().map(|q| -0.3 * q).collect();
        let grid = Grid::new(0.0, 5.0, 100).unwrap();
        let conservative = DynProblem::new(&chain, grid, Embedding::midpoint());
        let forced = DynProblem::new(&damped, grid, Embedding::midpoint());
        for (name, run) in [
            (
                "conservative",
                conservative.solve_ivp(Scheme::Variational, &q0, &v0),
            ),
            ("dashpots", forced.solve_ivp(Scheme::Variational, &q0, &v0)),
        ] {
            let run = run.unwrap();
            println!(
                "d = {d} {name}: {:.2} Newton iterations per step, band {}, reordered {}",
                run.run.newton_iterations as f64 / 100.0,
                run.run.band,
                run.run.reordered
            );
        }
        g.bench_function(format!("conservative_d{d}"), |b| {
            b.iter(|| conservative.solve_ivp(Scheme::Variational, black_box(&q0), &v0))
        });
        g.bench_function(format!("dashpots_d{d}"), |b| {
            b.iter(|| forced.solve_ivp(Scheme::Variational, black_box(&q0), &v0))
        });
    }
    g.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); forces, chain_forces);
