//! The midpoint and trapezoidal embeddings against closed forms: on the harmonic oscillator the
//! midpoint variational map is the Cayley transform (`tan(θ/2) = ωh/2`, A-stable), the
//! trapezoidal one and both direct schemes are Störmer–Verlet (`cos θ = 1 − (ωh)²/2`, stable
//! for `ωh < 2` and stopped past it); neither embedding is coherent, and the rows by which they
//! differ are the ones core/docs/schemes.md derives; the initial value runs zero the global residual
//! rows that the boundary value solver uses.

use varembed::{Embedding, Error, Grid, Scheme, Vector, lagrangian};
use varembed_tests::curve::{max_diff, max_norm};
use varembed_tests::models::generated::Kepler;
use varembed_tests::models::hand::Coupled;
use varembed_tests::reference::DiscreteOscillation;
use varembed_tests::rng::Rng;

#[lagrangian]
fn oscillator(x: f64, v: f64, omega: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * x * x
}

const SCHEMES: [Scheme; 2] = [Scheme::Direct, Scheme::Variational];

fn symmetric() -> [Embedding; 2] {
    [Embedding::midpoint(), Embedding::trapezoidal()]
}

/// The phase per step of each scheme on the oscillator: the midpoint variational map is the
/// Cayley transform, every other one Störmer–Verlet.
fn closed_form(
    embedding: Embedding,
    scheme: Scheme,
    omega_h: f64,
    q0: f64,
    q1: f64,
) -> DiscreteOscillation {
    if embedding == Embedding::midpoint() && scheme == Scheme::Variational {
        DiscreteOscillation::through(1.0, 2.0 * (omega_h / 2.0).atan(), q0, q1)
    } else {
        // cos θ = 1 − (ωh)²/2, as θ = 2 asin(ωh/2): `acos` near 1 would lose ε/θ per step.
        DiscreteOscillation::through(1.0, 2.0 * (omega_h / 2.0).asin(), q0, q1)
    }
}

/// 10⁴ steps of each scheme from the discrete Legendre start equal the closed form node for
/// node to 1e-12 of the amplitude (the Störmer–Verlet schemes at ωh = 1.9: 3e-11): the phase
/// per step is exact to ~1e-16.
#[test]
fn oscillator_runs_are_the_cayley_transform_and_stormer_verlet() {
    let steps = 10_000;
    for omega_h in [0.05, 0.7, 1.9] {
        let omega = 2.0;
        let model = Oscillator { omega };
        let grid = Grid::new(0.0, steps as f64 * omega_h / omega, steps).unwrap();
        for embedding in symmetric() {
            let problem = varembed_tests::problem(&model, grid, embedding);
            for scheme in SCHEMES {
                let run = problem.solve_ivp(scheme, 1.0, 0.3).unwrap();
                let exact = closed_form(embedding, scheme, omega_h, run.q[0][0], run.q[1][0]);
                let gap = (0..=steps)
                    .map(|k| (run.q[k][0] - exact.at(k)).abs())
                    .fold(0.0, f64::max);
                // Störmer–Verlet near its limit: the rounding of each step moves the phase more
                // (1.2e-11 measured for the midpoint direct scheme at ωh = 1.9).
                let cayley = embedding == Embedding::midpoint() && scheme == Scheme::Variational;
                let tolerance = if cayley || omega_h < 1.0 {
                    1e-12
                } else {
                    3e-11
                };
                assert!(
                    gap <= tolerance * exact.amplitude(),
                    "{embedding} {scheme}, ωh = {omega_h}: gap {gap:e}"
                );
            }
        }
    }
}

/// The discrete Legendre start solves `p_0 = −D₁L_d(Q_0, Q_1)`, written out by hand for the
/// oscillator: `(Q_1 − Q_0)/h + h ω² (Q_0 + Q_1)/4 = v_0` (midpoint) and
/// `(Q_1 − Q_0)/h + h ω² Q_0/2 = v_0` (trapezoidal).
#[test]
fn legendre_start_is_minus_d1_of_the_discrete_lagrangian() {
    let (omega, h, q0, v0) = (1.5, 0.1, 0.8, -0.4);
    let model = Oscillator { omega };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let w = omega * omega;
    let midpoint = (v0 + q0 * (1.0 / h - h * w / 4.0)) / (1.0 / h + h * w / 4.0);
    let trapezoidal = q0 + h * v0 - h * h * w * q0 / 2.0;
    for (embedding, expected) in [
        (Embedding::midpoint(), midpoint),
        (Embedding::trapezoidal(), trapezoidal),
    ] {
        let q1 = varembed_tests::problem(&model, grid, embedding)
            .legendre_start(q0, v0)
            .unwrap();
        assert!(
            (q1[0] - expected).abs() < 1e-14,
            "{embedding}: {} vs {expected}",
            q1[0]
        );
    }
}

/// The midpoint variational scheme has no stability limit on the oscillator (A-stable): at
/// ωh = 3, 20 and 1000 it runs 10⁴ steps with neither the stability check nor the blow-up
/// guard stopping it, on the closed form, its amplitude kept.
#[test]
fn midpoint_variational_is_a_stable_at_any_step() {
    let steps = 10_000;
    for omega_h in [3.0, 20.0, 1000.0] {
        let model = Oscillator { omega: 1.0 };
        let grid = Grid::new(0.0, steps as f64 * omega_h, steps).unwrap();
        let problem = varembed_tests::problem(&model, grid, Embedding::midpoint());
        let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
        let exact = closed_form(
            Embedding::midpoint(),
            Scheme::Variational,
            omega_h,
            1.0,
            run.q[1][0],
        );
        let gap = (0..=steps)
            .map(|k| (run.q[k][0] - exact.at(k)).abs())
            .fold(0.0, f64::max);
        // 9e-11 measured at ωh = 1000, where θ is within 0.002 of π.
        assert!(
            gap <= 2e-10 * exact.amplitude(),
            "ωh = {omega_h}: gap {gap:e}"
        );
        assert!(max_norm(&run.q) <= exact.amplitude() * (1.0 + 1e-10));
    }
}

/// Past ωh = 2 the Störmer–Verlet schemes (trapezoidal variational, both direct schemes) are
/// unstable: the run stops with [`Error::Unstable`] (an eigenvalue of the step map below −1)
/// at the first stability check, or with [`Error::BlowUp`]; just below the limit it runs.
#[test]
fn stormer_verlet_schemes_are_stopped_past_omega_h_two() {
    let steps = 2000;
    let model = Oscillator { omega: 1.0 };
    let cases = [
        (Embedding::trapezoidal(), Scheme::Variational),
        (Embedding::trapezoidal(), Scheme::Direct),
        (Embedding::midpoint(), Scheme::Direct),
    ];
    for (embedding, scheme) in cases {
        for (omega_h, stable) in [(1.98, true), (2.02, false), (2.5, false)] {
            let grid = Grid::new(0.0, steps as f64 * omega_h, steps).unwrap();
            let run = varembed_tests::problem(&model, grid, embedding).solve_ivp(scheme, 1.0, 0.0);
            match run {
                Ok(_) if stable => {}
                Err(Error::Unstable { re, .. }) if !stable => assert!(re < -1.0, "λ = {re}"),
                Err(Error::BlowUp { .. }) if !stable => {}
                other => panic!("{embedding} {scheme} at ωh = {omega_h}: {other:?}"),
            }
        }
    }
}

/// The blow-up guard watches the symmetric schemes too: Störmer–Verlet at ωh = 2 exactly has a
/// double eigenvalue −1, which the stability check cannot see, and nodes that grow linearly
/// (`Q_n = (−1)ⁿ(1 + 2n)` from `Q_0 = 1`, `Q_1 = −3`); the guard stops it.
#[test]
fn the_blow_up_guard_stops_the_double_root_at_omega_h_two() {
    let model = Oscillator { omega: 1.0 };
    let steps = 10_000;
    let grid = Grid::new(0.0, 2.0 * steps as f64, steps).unwrap();
    for (embedding, scheme) in [
        (Embedding::trapezoidal(), Scheme::Variational),
        (Embedding::trapezoidal(), Scheme::Direct),
        (Embedding::midpoint(), Scheme::Direct),
    ] {
        let problem = varembed_tests::problem(&model, grid, embedding);
        let run = problem.solve_ivp_from_nodes(scheme, 1.0, -3.0);
        assert!(
            matches!(run, Err(Error::BlowUp { .. })),
            "{embedding} {scheme}: {run:?}"
        );
        let unguarded = problem
            .with_blow_up_guard(false)
            .solve_ivp_from_nodes(scheme, 1.0, -3.0)
            .unwrap();
        assert!((unguarded.q[steps][0] - (1.0 + 2.0 * steps as f64)).abs() < 1e-6);
    }
}

/// Neither embedding is coherent, and the library says so; the direct and variational rows
/// differ exactly by the force term, `f(Q_k, (Q_{k+1} − Q_{k−1})/2h) − ½(F_w + F_u)`, which is
/// `O(h²)` on a smooth curve (the gap falls by 4 when h halves) and `O(1)` on a rough one.
#[test]
fn neither_symmetric_embedding_is_coherent() {
    let mut rng = Rng(17);
    for embedding in symmetric() {
        assert!(!embedding.is_coherent());
        // Rough curves: the gap is O(1), as for Gauss-FDEσ.
        let grid = Grid::new(0.0, 2.0, 40).unwrap();
        let problem = varembed_tests::problem(&Coupled, grid, embedding);
        assert_eq!(problem.residual_rows(Scheme::Direct), 1..=39);
        assert_eq!(problem.residual_rows(Scheme::Variational), 1..=39);
        let q = rng.curve::<2>(grid.n(), 1.0);
        let direct = problem.residual(Scheme::Direct, &q).unwrap();
        let variational = problem.residual(Scheme::Variational, &q).unwrap();
        assert!(
            max_diff(&direct, &variational) > 1e-2 * max_norm(&variational),
            "{embedding}"
        );
        // Smooth curves: O(h²).
        let gaps: Vec<f64> = [50, 100, 200]
            .iter()
            .map(|&n| {
                let grid = Grid::new(0.0, 1.0, n).unwrap();
                let q: Vec<Vector<2>> = (0..=n)
                    .map(|k| {
                        let t = grid.t(k);
                        Vector::<2>::new((2.0 * t).sin(), (1.5 * t).cos() - 0.3 * t)
                    })
                    .collect();
                let problem = varembed_tests::problem(&Coupled, grid, embedding);
                let direct = problem.residual(Scheme::Direct, &q).unwrap();
                let variational = problem.residual(Scheme::Variational, &q).unwrap();
                max_diff(&direct, &variational)
            })
            .collect();
        for pair in gaps.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            assert!((order - 2.0).abs() < 0.1, "{embedding}: gaps {gaps:?}");
        }
    }
}

/// The direct and variational rows of both embeddings on Kepler (`f = −x/|x|³`, `p = v`),
/// written out by hand: the variational one averages the force over the two intervals (at
/// their midpoints, or at the node for the trapezoid), the direct one takes it at the node.
#[test]
fn rows_on_kepler_are_those_derived_by_hand() {
    let n = 12;
    let grid = Grid::new(0.0, 1.2, n).unwrap();
    let h = grid.h();
    let q: Vec<Vector<2>> = (0..=n)
        .map(|k| {
            let t = grid.t(k);
            Vector::<2>::new(1.0 + 0.3 * t.cos(), 0.8 * t.sin() + 0.1 * t * t)
        })
        .collect();
    let force = |x: Vector<2>| -x / x.norm().powi(3);
    for embedding in symmetric() {
        let problem = varembed_tests::problem(&Kepler, grid, embedding);
        let direct = problem.residual(Scheme::Direct, &q).unwrap();
        let variational = problem.residual(Scheme::Variational, &q).unwrap();
        for k in 1..n {
            let second = (q[k + 1] - q[k] * 2.0 + q[k - 1]) / (h * h);
            let averaged = if embedding == Embedding::midpoint() {
                (force((q[k - 1] + q[k]) / 2.0) + force((q[k] + q[k + 1]) / 2.0)) / 2.0
            } else {
                force(q[k])
            };
            assert!(
                (variational[k - 1] - (averaged - second)).amax() < 1e-9,
                "{embedding} {k}"
            );
            assert!(
                (direct[k - 1] - (force(q[k]) - second)).amax() < 1e-9,
                "{embedding} {k}"
            );
        }
    }
    // On a separable Lagrangian the trapezoidal schemes coincide (both take the force at the
    // node); the midpoint ones do not.
    let problem = varembed_tests::problem(&Kepler, grid, Embedding::trapezoidal());
    let gap = max_diff(
        &problem.residual(Scheme::Direct, &q).unwrap(),
        &problem.residual(Scheme::Variational, &q).unwrap(),
    );
    assert!(gap < 1e-12, "{gap:e}");
}

/// The comparison's coherence column (the other scheme's residual on each solution) shows it:
/// nonzero on a non-separable Lagrangian, for both embeddings, in an initial value problem. The
/// rows differ by `O(h²)` and their momentum terms are of size `|p|/h`, so the residual relative
/// to them is `O(h³)`.
#[test]
fn the_comparison_shows_the_incoherence() {
    for embedding in symmetric() {
        let mut gaps = Vec::new();
        for n in [200, 400] {
            let problem =
                varembed_tests::problem(&Coupled, Grid::new(0.0, 2.0, n).unwrap(), embedding);
            let comparison = problem.compare_ivp([0.3, -0.2], [0.5, 0.1]).unwrap();
            let gap = comparison.direct.residual_of_other;
            assert!(gap > 1e-10, "{embedding}: {gap:e}");
            gaps.push(gap);
        }
        let order = (gaps[0] / gaps[1]).log2();
        assert!((order - 3.0).abs() < 0.2, "{embedding}: {gaps:?}");
    }
}

/// The nodes of an initial value run (step kernels, one node at a time) zero the global
/// residual rows (interval values, every row at once), for each scheme, on a Lagrangian whose
/// every block depends on `x`, `v` and `t`; and the boundary value solver, given the run's end
/// values, returns the run.
#[test]
fn initial_value_runs_solve_the_global_rows_and_the_boundary_value_problem() {
    let n = 60;
    let grid = Grid::new(0.0, 1.5, n).unwrap();
    for embedding in symmetric() {
        let problem = varembed_tests::problem(&Coupled, grid, embedding);
        for scheme in SCHEMES {
            let run = problem.solve_ivp(scheme, [0.4, -0.3], [0.2, 0.5]).unwrap();
            let residual = problem.residual(scheme, &run.q).unwrap();
            assert!(
                max_norm(&residual) < 1e-9,
                "{embedding} {scheme}: {:e}",
                max_norm(&residual)
            );
            let bvp = problem.solve_bvp(scheme, run.q[0], run.q[n]).unwrap();
            let gap = max_diff(&bvp.q, &run.q);
            assert!(gap < 1e-9, "{embedding} {scheme}: BVP vs IVP {gap:e}");
        }
    }
}

/// The action and the energy of both embeddings on the oscillator, written out by hand:
/// `S_h = Σ_k h L(Q̄_k, V_k)` or `Σ_k h/2 [L(Q_{k−1}, V_k) + L(Q_k, V_k)]`, and `E` per interval
/// at the same points.
#[test]
fn action_and_energy_are_those_of_the_discrete_lagrangian() {
    let omega = 1.3;
    let model = Oscillator { omega };
    let n = 7;
    let grid = Grid::new(0.5, 1.9, n).unwrap();
    let h = grid.h();
    let q: Vec<Vector<1>> = (0..=n)
        .map(|k| Vector::<1>::new((1.1 * k as f64).sin() + 0.2))
        .collect();
    let lagrangian = |x: f64, v: f64| 0.5 * v * v - 0.5 * omega * omega * x * x;
    let energy = |x: f64, v: f64| 0.5 * v * v + 0.5 * omega * omega * x * x;
    for embedding in symmetric() {
        let midpoint = embedding == Embedding::midpoint();
        let at = |f: &dyn Fn(f64, f64) -> f64, k: usize| {
            let (a, b) = (q[k - 1][0], q[k][0]);
            let v = (b - a) / h;
            if midpoint {
                f((a + b) / 2.0, v)
            } else {
                (f(a, v) + f(b, v)) / 2.0
            }
        };
        let problem = varembed_tests::problem(&model, grid, embedding);
        let action: f64 = (1..=n).map(|k| h * at(&lagrangian, k)).sum();
        assert!(
            (problem.action(&q).unwrap() - action).abs() < 1e-13,
            "{embedding}"
        );
        let energies = problem.quadrature_energies(&q).unwrap();
        assert_eq!(energies.len(), n);
        for (j, &(k, e)) in (1..=n).zip(&energies) {
            assert_eq!(j, k, "{embedding}: interval k sits on row k");
            assert!(
                (e - at(&energy, k)).abs() < 1e-12,
                "{embedding} interval {k}"
            );
        }
        let v = problem.quadrature_velocities(&q).unwrap();
        assert_eq!(
            v[0].0, 1,
            "{embedding}: the first interval's velocity on row 1"
        );
        assert!((v[0].1[0] - (q[1][0] - q[0][0]) / h).abs() < 1e-12);
    }
}

/// The midpoint variational map on the oscillator, in the variables `(Q_k, p_k)` with the
/// discrete momentum `p_k = D₂L_d(Q_{k−1}, Q_k) = V_k − (h/2) ω² Q̄_k`, is the Cayley transform
/// `C = (I − hA/2)⁻¹ (I + hA/2)` of `A = [[0, 1], [−ω², 0]]`: every step of a 10⁴-step run
/// is `C` applied to the previous state, to round-off.
#[test]
fn midpoint_variational_map_is_the_cayley_transform() {
    let (omega, steps) = (1.7, 10_000);
    let model = Oscillator { omega };
    for omega_h in [0.1, 1.0, 5.0] {
        let h = omega_h / omega;
        let grid = Grid::new(0.0, h * steps as f64, steps).unwrap();
        let run = varembed_tests::problem(&model, grid, Embedding::midpoint())
            .solve_ivp(Scheme::Variational, 0.6, -0.8)
            .unwrap();
        let a = nalgebra::Matrix2::new(0.0, 1.0, -omega * omega, 0.0);
        let identity = nalgebra::Matrix2::<f64>::identity();
        let cayley = (identity - a * (h / 2.0)).try_inverse().unwrap() * (identity + a * (h / 2.0));
        let state = |k: usize| {
            let (q_prev, q) = (run.q[k - 1][0], run.q[k][0]);
            let p = (q - q_prev) / h - h / 2.0 * omega * omega * (q + q_prev) / 2.0;
            nalgebra::Vector2::new(q, p)
        };
        let scale = state(1).amax();
        let gap = (1..steps)
            .map(|k| (state(k + 1) - cayley * state(k)).amax())
            .fold(0.0, f64::max);
        // p_k loses ε|Q|/h to the cancellation in (Q_k − Q_{k−1})/h: 2e-15 measured.
        assert!(
            gap < 1e-13 * scale.max(1.0) / h.min(1.0),
            "ωh = {omega_h}: {gap:e}"
        );
    }
}
