//! The variational Gauss–Legendre integrators on the run-time path: the same nodes and
//! momenta as the const-generic run of the same model, their order `2s` against an exact
//! solution, the band of the stage system, the node values, and the typed errors.

use nalgebra::{DMatrix, SymmetricEigen};
use varembed::{
    DynProblem, Embedding, Error, Grid, Lagrangian, Location, Scheme, Solution, Vector, lagrangian,
};
use varembed_tests::models::chain::{FputChain, displacement};

pub(super) const M: usize = 8;

/// Eight coupled pendula whose mass depends on the position (`L_vv` depends on `x`), with a
/// magnetic-like coupling `x_i v_{i+1}` (`L_xv` not symmetric) and a time-dependent drive.
#[lagrangian]
pub(super) fn twisted(x: [f64; M], v: [f64; M], t: f64, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..M {
        l += 0.5 * (1.0 + 0.3 * x[i] * x[i]) * v[i] * v[i] - k * (1.0 - x[i].cos())
            + 0.1 * t.sin() * x[i];
    }
    for i in 0..M - 1 {
        l += 0.2 * x[i] * v[i + 1] - 0.5 * (x[i + 1] - x[i]) * (x[i + 1] - x[i]);
    }
    l
}

pub(super) fn initial() -> (Vec<f64>, Vec<f64>) {
    let q0 = displacement(M, 0.6, 0.3);
    let v0 = (0..M).map(|i| 0.2 * (i as f64 * 0.9).cos()).collect();
    (q0, v0)
}

/// The largest entry of `a − b` over the largest entry of `b`, flat.
fn relative_gap(a: &[f64], b: &[f64]) -> f64 {
    let gap = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    gap / b.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

fn flat<const D: usize>(nodes: &[Vector<D>]) -> Vec<f64> {
    nodes.iter().flat_map(|q| q.iter().copied()).collect()
}

/// For every `s`, the run-time run of the model and the const-generic run of the same
/// `[f64; 8]` model (the macro emits both) give the same nodes and momenta to 1e-12, with the
/// same Newton iterations, and the node values of both paths agree.
#[test]
fn every_stage_count_gives_the_const_generic_nodes_and_momenta() {
    let model = Twisted { k: 1.5 };
    let grid = Grid::new(0.0, 3.0, 60).unwrap();
    let (q0, v0) = initial();
    for s in 1..=4 {
        let embedding = Embedding::gauss_legendre(s).unwrap();
        let run = DynProblem::new(&model, grid, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        let reference: Solution<M> = varembed_tests::problem(&model, grid, embedding)
            .solve_ivp(
                Scheme::Variational,
                Vector::<M>::from_column_slice(&q0),
                Vector::<M>::from_column_slice(&v0),
            )
            .unwrap();
        let gap = relative_gap(&run.q, &flat(&reference.q));
        assert!(gap <= 1e-12, "s = {s}: nodes {gap:e}");
        let gap = relative_gap(&run.momenta, &flat(&reference.momenta));
        assert!(gap <= 1e-12, "s = {s}: momenta {gap:e}");
        assert_eq!(
            run.run.newton_iterations, reference.newton_iterations,
            "s = {s}"
        );
        // The model's band: a chain (half-width 1), so the stage system's is 2s − 1.
        assert_eq!(
            (run.run.band, run.run.reordered),
            (2 * s - 1, false),
            "s = {s}"
        );
        let values = run.node_values(&model).unwrap();
        let expected = reference.node_values(&model).unwrap();
        let v: Vec<f64> = expected.v.iter().flat_map(|v| v.iter().copied()).collect();
        let gap = relative_gap(&values.v, &v);
        assert!(gap <= 1e-12, "s = {s}: velocities {gap:e}");
        assert_eq!(values.rule, expected.rule);
    }
}

/// `Problem` hands a Gauss–Legendre run of a model at or above `RUN_TIME_FROM` degrees of
/// freedom to the run-time engine: the nodes and momenta of `DynProblem`, bit for bit, on a
/// 2 MiB stack (the const-generic stage system of a 256-site ring is `4 × 256` unknowns of
/// dense blocks), and the node values read the carried momenta.
#[test]
fn a_ring_of_256_runs_gauss_legendre_through_problem_on_a_two_megabyte_stack() {
    use super::through_problem::{RING, SineGordon, displaced, on_stack};
    let model = SineGordon { c: 4.0 };
    let grid = Grid::new(0.0, 0.5, 10).unwrap();
    let (q0, v0) = displaced(RING);
    on_stack(2 << 20, || {
        for s in 1..=4 {
            let embedding = Embedding::gauss_legendre(s).unwrap();
            // The concrete model: the stack use under test is that of a user's `Problem<Model, D>`.
            let run = varembed::Problem::new(&model, grid, embedding)
                .solve_ivp(
                    Scheme::Variational,
                    Vector::<RING>::from_column_slice(&q0),
                    Vector::<RING>::from_column_slice(&v0),
                )
                .unwrap();
            let reference = DynProblem::new(&model, grid, embedding)
                .solve_ivp(Scheme::Variational, &q0, &v0)
                .unwrap();
            assert_eq!(flat(&run.q), reference.q, "s = {s}");
            assert_eq!(flat(&run.momenta), reference.momenta, "s = {s}");
            // The ring's wrap-around is reordered to a band of half-width 2: 3s − 1 stacked.
            assert_eq!(
                (reference.run.band, reference.run.reordered),
                (3 * s - 1, true)
            );
        }
    });
}

/// The exact solution of the harmonic chain (an FPUT chain with α = β = 0 between walls) by its
/// normal modes: `q(t) = Φ (cos(ω t) Φᵀ q0 + sin(ω t)/ω Φᵀ v0)`, `t` for the zero mode.
pub(super) fn harmonic_chain_at(n: usize, (q0, v0): (&[f64], &[f64]), t: f64) -> Vec<f64> {
    let mut k = DMatrix::<f64>::zeros(n, n);
    // The walls: a bond from each end mass to a fixed point.
    k[(0, 0)] += 1.0;
    k[(n - 1, n - 1)] += 1.0;
    for i in 0..n - 1 {
        k[(i, i)] += 1.0;
        k[(i + 1, i + 1)] += 1.0;
        k[(i, i + 1)] -= 1.0;
        k[(i + 1, i)] -= 1.0;
    }
    let modes = SymmetricEigen::new(k);
    let phi = &modes.eigenvectors;
    let (a, b) = (
        phi.transpose() * nalgebra::DVector::from_column_slice(q0),
        phi.transpose() * nalgebra::DVector::from_column_slice(v0),
    );
    let mut amplitudes = nalgebra::DVector::<f64>::zeros(n);
    for j in 0..n {
        let omega = modes.eigenvalues[j].max(0.0).sqrt();
        amplitudes[j] = if omega < 1e-9 {
            a[j] + b[j] * t
        } else {
            a[j] * (omega * t).cos() + b[j] * (omega * t).sin() / omega
        };
    }
    (phi * amplitudes).iter().copied().collect()
}

/// The harmonic chain of 24 masses between walls and its initial data, for the order tests.
pub(super) fn harmonic_chain() -> (FputChain, Vec<f64>, Vec<f64>) {
    let n = 24;
    let chain = FputChain {
        n,
        alpha: 0.0,
        beta: 0.0,
        periodic: false,
    };
    let q0 = displacement(n, 0.5, 0.1);
    let v0: Vec<f64> = (0..n).map(|i| 0.3 * (i as f64 * 0.4).sin()).collect();
    (chain, q0, v0)
}

/// The observed orders of the run-time Gauss–Legendre integrators on a harmonic chain of 24
/// masses against its exact solution: `2s` for every `s` (the error at `t = 10` over two
/// halvings of the step).
#[test]
fn the_order_on_a_harmonic_chain_is_two_s() {
    let (chain, q0, v0) = harmonic_chain();
    let n = chain.n;
    let t_end = 10.0;
    let exact = harmonic_chain_at(n, (&q0, &v0), t_end);
    for (s, steps) in [
        (1, [100, 200, 400]),
        (2, [50, 100, 200]),
        (3, [25, 50, 100]),
        (4, [20, 40, 80]),
    ] {
        let error = |steps: usize| {
            let grid = Grid::new(0.0, t_end, steps).unwrap();
            let embedding = Embedding::gauss_legendre(s).unwrap();
            let run = DynProblem::new(&chain, grid, embedding)
                .solve_ivp(Scheme::Variational, &q0, &v0)
                .unwrap();
            let last = &run.run.last;
            last.iter()
                .zip(&exact)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        };
        let errors = steps.map(error);
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            let expected = 2.0 * s as f64;
            assert!(
                (order - expected).abs() < 0.25,
                "s = {s}: errors {errors:?}, order {order:.3} (expected {expected})"
            );
        }
    }
}

/// `run_ivp_with_values` hands each node the values `node_values` gives the stored run, bit for
/// bit, with the momentum the scheme carries; `run_ivp` hands that momentum too (it costs
/// nothing) and no velocity.
#[test]
fn the_observer_is_handed_the_carried_momenta_and_the_node_values() {
    let model = Twisted { k: 1.5 };
    let (q0, v0) = initial();
    for steps in [1, 2, 3, 17] {
        let grid = Grid::new(0.0, 1.0, steps).unwrap();
        let problem = DynProblem::new(&model, grid, Embedding::gauss_legendre(3).unwrap());
        let stored = problem.solve_ivp(Scheme::Variational, &q0, &v0).unwrap();
        let values = stored.node_values(&model).unwrap();
        let mut seen = 0;
        problem
            .run_ivp_with_values(Scheme::Variational, &q0, &v0, |node| {
                let k = node.index;
                assert_eq!(k, seen);
                seen += 1;
                assert_eq!(node.q, stored.node(k));
                assert_eq!(node.previous, stored.node(k.max(1) - 1));
                assert_eq!(node.p, &stored.momenta[k * M..(k + 1) * M]);
                assert_eq!(node.v, &values.v[k * M..(k + 1) * M]);
                assert_eq!(node.energy, None, "the drive depends on t");
            })
            .unwrap();
        assert_eq!(seen, steps + 1);
        let mut seen = 0;
        problem
            .run_ivp(Scheme::Variational, &q0, &v0, |node| {
                assert_eq!(node.p, &stored.momenta[seen * M..(seen + 1) * M]);
                assert!(node.v.is_empty());
                seen += 1;
            })
            .unwrap();
        assert_eq!(seen, steps + 1);
    }
}

/// On an autonomous nonlinear chain the energy of the run-time Gauss–Legendre run, read from
/// its node values (the carried momenta, the velocities they invert to), is conserved to order
/// `2s`: halving the step divides its largest deviation over the run by about `2^{2s}`.
#[test]
fn the_energy_of_a_nonlinear_run_is_conserved_to_order_two_s() {
    let chain = FputChain {
        n: 32,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let q0 = displacement(32, 0.5, 0.0);
    let v0 = vec![0.0; 32];
    for (s, steps) in [(1, 400), (2, 200), (3, 400)] {
        let deviation = |steps: usize| {
            let grid = Grid::new(0.0, 100.0, steps).unwrap();
            let problem = DynProblem::new(&chain, grid, Embedding::gauss_legendre(s).unwrap());
            let mut energies = Vec::new();
            problem
                .run_ivp_with_values(Scheme::Variational, &q0, &v0, |node| {
                    energies.push(node.energy.expect("autonomous"));
                })
                .unwrap();
            let e0 = energies[0];
            energies.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max)
        };
        let ratio = deviation(steps) / deviation(2 * steps);
        let expected = 4f64.powi(s as i32);
        assert!(
            (ratio.log2() - 2.0 * s as f64).abs() < 0.3,
            "s = {s}: ratio {ratio:.2} (expected about {expected})"
        );
    }
}

/// The direct scheme of a Gauss–Legendre integrator is `Unsupported` on the run-time path as on
/// the const-generic one, and a bad initial datum is named.
#[test]
fn bad_requests_get_the_const_generic_paths_errors() {
    let model = Twisted { k: 1.5 };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let (q0, v0) = initial();
    let problem = DynProblem::new(&model, grid, Embedding::gauss_legendre(2).unwrap());
    let direct = problem.solve_ivp(Scheme::Direct, &q0, &v0).unwrap_err();
    let twin = varembed_tests::problem(&model, grid, Embedding::gauss_legendre(2).unwrap())
        .solve_ivp(Scheme::Direct, Vector::<M>::zeros(), Vector::<M>::zeros())
        .unwrap_err();
    assert_eq!(direct, twin);
    assert!(matches!(
        problem.solve_ivp(Scheme::Variational, &q0[..7], &v0),
        Err(Error::WrongLength {
            what: "q0",
            expected: 8,
            found: 7
        })
    ));
    let mut bad = q0.clone();
    bad[3] = f64::NAN;
    let err = problem
        .solve_ivp(Scheme::Variational, &bad, &v0)
        .unwrap_err();
    assert!(err.to_string().contains("q0[3]"), "{err}");
    // The model's own dimension and its `Lagrangian` twin agree.
    assert_eq!(
        Lagrangian::<M>::run_time(&model).map(|m| m.dimension()),
        Some(M)
    );
}

/// The resolution check of a Gauss–Legendre run (limit `2s` on `hω`) on the run-time path: a
/// step too coarse for the fastest motion at the initial data is warned about with the limit
/// of its stage count, as on the const-generic path (same warning variant and limit, `hω`
/// within 1 %), and not when the check is off; a fine step is not warned about.
#[test]
fn a_coarse_step_is_warned_about_as_on_the_const_generic_path() {
    let model = Twisted { k: 400.0 };
    let (q0, v0) = initial();
    for s in 1..=3 {
        let embedding = Embedding::gauss_legendre(s).unwrap();
        // ω ≈ 20 at the initial data: h ω ≈ 8 > 2s for s ≤ 3 at h = 0.4.
        let coarse = Grid::new(0.0, 2.0, 5).unwrap();
        let run = DynProblem::new(&model, coarse, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        let reference = varembed_tests::problem(&model, coarse, embedding)
            .solve_ivp(
                Scheme::Variational,
                Vector::<M>::from_column_slice(&q0),
                Vector::<M>::from_column_slice(&v0),
            )
            .unwrap();
        match (&run.warnings[..], &reference.warnings[..]) {
            (
                [varembed::Warning::UnderResolved { h_omega, limit }],
                [
                    varembed::Warning::UnderResolved {
                        h_omega: expected,
                        limit: expected_limit,
                    },
                ],
            ) => {
                assert_eq!((*limit, *expected_limit), (2.0 * s as f64, 2.0 * s as f64));
                assert!(
                    (h_omega / expected - 1.0).abs() < 0.01,
                    "{h_omega} vs {expected}"
                );
            }
            other => panic!("s = {s}: {other:?}"),
        }
        let unchecked = DynProblem::new(&model, coarse, embedding)
            .with_resolution_check(false)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        assert!(unchecked.warnings.is_empty());
        let fine = Grid::new(0.0, 2.0, 400).unwrap();
        let resolved = DynProblem::new(&model, fine, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        assert!(
            resolved.warnings.is_empty(),
            "s = {s}: {:?}",
            resolved.warnings
        );
    }
}

const F: usize = 4;

/// Free particles whose mass fades as `e^{−40 t}`: `∂²L/∂v²` stays a multiple of the
/// identity (its pivot ratio 1) while shrinking below 1e-12 of its start by `t = 0.7`.
#[lagrangian]
fn fading(x: [f64; F], v: [f64; F], t: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..F {
        l += 0.5 * (-40.0 * t).exp() * v[i] * v[i] - 0.01 * x[i] * x[i];
    }
    l
}

/// The degeneracy check along a run measures `∂²L/∂v²` against its size at the initial data
/// on both paths: a mass that fades as a whole is reported at the last step by both, with the
/// same measure to 1e-6.
#[test]
fn a_fading_mass_is_degenerate_on_both_paths() {
    let grid = Grid::new(0.0, 1.0, 100).unwrap();
    let embedding = Embedding::gauss_legendre(2).unwrap();
    let (q0, v0) = ([0.1; F], [0.2; F]);
    let run = DynProblem::new(&Fading, grid, embedding).solve_ivp(Scheme::Variational, &q0, &v0);
    let reference = varembed_tests::problem(&Fading, grid, embedding).solve_ivp(
        Scheme::Variational,
        Vector::<F>::from_column_slice(&q0),
        Vector::<F>::from_column_slice(&v0),
    );
    match (run, reference) {
        (
            Err(Error::DegenerateLagrangian { at, measure, .. }),
            Err(Error::DegenerateLagrangian {
                at: expected_at,
                measure: expected,
                ..
            }),
        ) => {
            assert_eq!(
                (at, expected_at),
                (Location::Step(100), Location::Step(100))
            );
            assert!(
                (measure / expected - 1.0).abs() < 1e-6,
                "{measure:e} vs {expected:e}"
            );
        }
        other => panic!("{other:?}"),
    }
}

/// The boundary value problem of a Gauss–Legendre integrator between the first and last nodes
/// of its own initial value run returns that run's nodes and momenta (the run is the unique
/// solution near the straight line), for every `s`, on a nonlinear chain with walls and on the
/// model whose every block varies.
#[test]
fn the_boundary_value_problem_returns_the_nodes_of_the_initial_value_run() {
    let chain = FputChain {
        n: 12,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let q0 = displacement(12, 0.3, 0.2);
    let v0: Vec<f64> = q0.iter().map(|q| 0.4 * q).collect();
    let twisted = Twisted { k: 1.5 };
    let (tq0, tv0) = initial();
    let models: [(&dyn varembed::DynLagrangian, &[f64], &[f64]); 2] =
        [(&chain, &q0, &v0), (&twisted, &tq0, &tv0)];
    for (model, q0, v0) in models {
        for s in 1..=4 {
            let grid = Grid::new(0.0, 1.0, 16).unwrap();
            let problem = DynProblem::new(model, grid, Embedding::gauss_legendre(s).unwrap());
            let run = problem.solve_ivp(Scheme::Variational, q0, v0).unwrap();
            let bvp = problem
                .solve_bvp(Scheme::Variational, run.node(0), run.node(16))
                .unwrap();
            let gap = relative_gap(&bvp.q, &run.q);
            assert!(gap <= 1e-12, "s = {s}: nodes {gap:e}");
            let gap = relative_gap(&bvp.momenta, &run.momenta);
            assert!(gap <= 1e-11, "s = {s}: momenta {gap:e}");
            assert!(bvp.run.newton_iterations >= 2, "s = {s}");
            assert!(bvp.warnings.is_empty(), "s = {s}: {:?}", bvp.warnings);
        }
    }
}

/// The observed order of the Gauss–Legendre boundary value problems at the nodes on a harmonic
/// chain of 24 masses against its exact solution: `2s` (the largest node error over two
/// halvings of the step; `T = 1.2` keeps every mode short of a conjugate point).
#[test]
fn the_boundary_value_order_on_a_harmonic_chain_is_two_s() {
    let (chain, q0, v0) = harmonic_chain();
    let n = chain.n;
    let t_end = 1.2;
    let exact = |t: f64| harmonic_chain_at(n, (&q0, &v0), t);
    let qb = exact(t_end);
    for (s, steps) in [
        (1, [8, 16, 32]),
        (2, [4, 8, 16]),
        (3, [2, 4, 8]),
        (4, [2, 3, 4]),
    ] {
        let error = |steps: usize| {
            let grid = Grid::new(0.0, t_end, steps).unwrap();
            let embedding = Embedding::gauss_legendre(s).unwrap();
            let solution = DynProblem::new(&chain, grid, embedding)
                .solve_bvp(Scheme::Variational, &q0, &qb)
                .unwrap();
            (0..=steps)
                .flat_map(|k| {
                    let node = solution.node(k).to_vec();
                    node.into_iter()
                        .zip(exact(grid.t(k)))
                        .map(|(a, b)| (a - b).abs())
                })
                .fold(0.0, f64::max)
        };
        let errors = steps.map(error);
        for (pair, ratio) in errors.windows(2).zip(steps.windows(2)) {
            let order = (pair[0] / pair[1]).ln() / (ratio[1] as f64 / ratio[0] as f64).ln();
            let expected = 2.0 * s as f64;
            assert!(
                (order - expected).abs() < 0.3,
                "s = {s}: errors {errors:?}, order {order:.3} (expected {expected})"
            );
        }
    }
}

/// Two uncoupled unit oscillators (both kinds of model).
#[varembed::lagrangian]
fn oscillators(x: [f64; 2], v: [f64; 2]) -> f64 {
    let mut l = 0.0;
    for i in 0..2 {
        l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    }
    l
}

/// `q̈ = −q` from 0 to 1 over `[0, π]` has no solution: every Gauss–Legendre boundary value
/// problem says so, on both paths — flagged `IllPosed` where the discrete system is solvable
/// (amplitudes of thousands), `IllConditioned` where it is singular to working precision (the
/// higher orders, closer to the exact resonance) — and says nothing away from the resonance;
/// with the check off, a solvable one is returned without the flag.
#[test]
fn a_resonant_gauss_legendre_boundary_value_problem_is_flagged() {
    use std::f64::consts::PI;
    use varembed::Warning;
    let model = Oscillators;
    let mut flagged = 0;
    for s in 1..=4 {
        let embedding = Embedding::gauss_legendre(s).unwrap();
        let resonant = Grid::new(0.0, PI, 100).unwrap();
        let problem = || DynProblem::new(&model, resonant, embedding);
        let solved = problem().solve_bvp(Scheme::Variational, &[0.0; 2], &[1.0; 2]);
        let fixed = varembed_tests::problem(&model, resonant, embedding)
            .solve_bvp(Scheme::Variational, [0.0; 2], [1.0; 2])
            .map(|solution| solution.warnings);
        for warnings in [solved.map(|run| run.warnings), fixed] {
            match warnings {
                Ok(warnings) => {
                    assert!(
                        matches!(warnings[..], [Warning::IllPosed { .. }]),
                        "s = {s}: {warnings:?}"
                    );
                    flagged += 1;
                }
                Err(Error::IllConditioned { .. }) => {}
                Err(other) => panic!("s = {s}: {other}"),
            }
        }
        if let Ok(quiet) = problem().with_posedness_check(false).solve_bvp(
            Scheme::Variational,
            &[0.0; 2],
            &[1.0; 2],
        ) {
            assert!(quiet.warnings.is_empty());
        }
        let away = DynProblem::new(&model, Grid::new(0.0, 2.0, 100).unwrap(), embedding)
            .solve_bvp(Scheme::Variational, &[0.0; 2], &[1.0; 2])
            .unwrap();
        assert!(away.warnings.is_empty(), "s = {s}: {:?}", away.warnings);
    }
    // The flag itself is exercised (s = 1 and 2 are solvable here).
    assert!(flagged >= 4, "{flagged}");
}
