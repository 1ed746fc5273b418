//! The variational Gauss–Legendre integrators against closed forms and exact invariants: the
//! oscillator's map is the rotation by the phase of the diagonal Padé approximant of `e^z`
//! (the midpoint rule's Cayley transform for s = 1), for every `ωh` (A-stability); quadratic
//! and linear invariants (the oscillator's energy, angular momentum on Kepler, a charged
//! particle's angular momentum and guiding centre) are conserved to round-off; the errors.

use varembed::{
    Embedding, Error, Grid, Location, NewtonOptions, Scheme, Solution, Vector, lagrangian,
};
use varembed_tests::models::generated::Kepler;

#[lagrangian]
fn oscillator(x: f64, v: f64, omega: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * x * x
}

/// A unit charge in the uniform field `B` (symmetric gauge `A = (B/2)(−y, x)`).
#[lagrangian]
fn magnetic(x: [f64; 2], v: [f64; 2], b: f64) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) + 0.5 * b * (x[0] * v[1] - x[1] * v[0])
}

/// The spherical pendulum in polar angle θ and azimuth φ (singular coordinates at the pole).
#[lagrangian]
fn spherical(x: [f64; 2], v: [f64; 2], g: f64) -> f64 {
    0.5 * (v[0] * v[0] + x[0].sin().powi(2) * v[1] * v[1]) + g * x[0].cos()
}

fn gauss(s: usize) -> Embedding {
    Embedding::gauss_legendre(s).unwrap()
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// `θ = 2 arg N_s(iy)` with `N_s(z) = Σ_k (2s − k)! s! / ((2s)! k! (s − k)!) zᵏ` the numerator of
/// the `(s, s)` Padé approximant of `e^z`, the stability function of Gauss–Legendre
/// `R(z) = N_s(z)/N_s(−z)`: on the oscillator, `|R(iy)| = 1` and `R(iy) = e^{iθ}`.
fn pade_phase(s: usize, y: f64) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for k in 0..=s {
        let c = factorial(2 * s - k) * factorial(s)
            / (factorial(2 * s) * factorial(k) * factorial(s - k));
        // (iy)^k = y^k i^k.
        let term = c * y.powi(k as i32);
        match k % 4 {
            0 => re += term,
            1 => im += term,
            2 => re -= term,
            _ => im -= term,
        }
    }
    2.0 * im.atan2(re)
}

/// The largest deviation of `invariant(q_k, p_k)` from its first value.
fn drift<const D: usize>(
    run: &Solution<D>,
    invariant: impl Fn(&Vector<D>, &Vector<D>) -> f64,
) -> f64 {
    assert_eq!(run.momenta.len(), run.q.len());
    let first = invariant(&run.q[0], &run.momenta[0]);
    run.q
        .iter()
        .zip(&run.momenta)
        .map(|(q, p)| (invariant(q, p) - first).abs())
        .fold(0.0, f64::max)
}

/// The midpoint rule (s = 1) is the Cayley transform: on `q̈ = −ω²q` its map is the rotation of
/// `(ωq, p)` by `θ` with `tan(θ/2) = ωh/2`, checked over 10⁴ steps against that closed form,
/// computed by hand; and every s rotates by its Padé phase, at `ωh = 0.7` and at `ωh = 50`.
#[test]
fn the_oscillator_map_is_the_rotation_by_the_pade_phase() {
    let omega = 1.3;
    let model = Oscillator { omega };
    let (q0, p0) = (0.8, -0.5);
    for (s, omega_h, steps) in [
        (1, 0.7, 10_000),
        (2, 0.7, 2000),
        (3, 0.7, 2000),
        (4, 0.7, 2000),
        (1, 50.0, 2000),
        (2, 50.0, 2000),
        (3, 50.0, 2000),
        (4, 50.0, 2000),
    ] {
        let h = omega_h / omega;
        let theta = if s == 1 {
            2.0 * (0.5 * omega_h).atan()
        } else {
            pade_phase(s, omega_h)
        };
        assert!(
            (pade_phase(s, omega_h).rem_euclid(std::f64::consts::TAU)
                - theta.rem_euclid(std::f64::consts::TAU))
            .abs()
                < 1e-14
        );
        let grid = Grid::new(0.0, h * steps as f64, steps).unwrap();
        let run = varembed_tests::problem(&model, grid, gauss(s))
            .with_newton(TO_ROUND_OFF)
            .solve_ivp(Scheme::Variational, q0, p0)
            .unwrap();
        let mut worst = 0.0f64;
        for (k, (q, p)) in run.q.iter().zip(&run.momenta).enumerate() {
            let (sin, cos) = (k as f64 * theta).sin_cos();
            let q_exact = q0 * cos + p0 / omega * sin;
            let p_exact = p0 * cos - omega * q0 * sin;
            worst = worst
                .max((q[0] - q_exact).abs())
                .max((p[0] - p_exact).abs() / omega);
        }
        println!("s = {s}, ωh = {omega_h}: {worst:e}");
        // The stage system's condition number grows as (ωh)²: its round-off with it.
        let tolerance = if omega_h < 1.0 { 1e-12 } else { 1e-11 };
        assert!(worst < tolerance, "s = {s}, ωh = {omega_h}: {worst:e}");
    }
}

/// A-stability: the oscillator's energy `½p² + ½ω²q²` (a quadratic invariant) is conserved to
/// round-off by every s at every step size up to `ωh = 1000`, with the blow-up guard on (no
/// false alarm). Measured over 5000 steps: at most 5e-15 at `ωh = 0.01`, 2e-13 at 1, 4.4e-12
/// at 10 and 5.4e-12 at 1000.
#[test]
fn the_oscillator_energy_is_conserved_at_every_step_size() {
    let model = Oscillator { omega: 1.0 };
    for s in 1..=4 {
        for h in [0.01, 1.0, 10.0, 1000.0] {
            let steps = 5000;
            let grid = Grid::new(0.0, h * steps as f64, steps).unwrap();
            let run = varembed_tests::problem(&model, grid, gauss(s))
                .with_newton(TO_ROUND_OFF)
                .solve_ivp(Scheme::Variational, 1.0, 0.0)
                .unwrap();
            let e = drift(&run, |q, p| 0.5 * p[0] * p[0] + 0.5 * q[0] * q[0]);
            println!("s = {s}, h = {h}: energy drift {e:e}");
            // 5000 steps of round-off (a few ε each), times the stage system's condition
            // number, which grows as (ωh)².
            let tolerance = if h <= 1.0 { 1e-12 } else { 1e-11 };
            assert!(e < tolerance, "s = {s}, h = {h}: energy drift {e:e}");
        }
    }
}

/// Newton iterated to round-off (the stopping rule's floor ends it): the invariants are exact
/// for the exact stage solution, so with the default tolerance `1e-12` they drift by that
/// tolerance per step instead (1.1e-12 over these 4000 Kepler steps for s = 1).
const TO_ROUND_OFF: NewtonOptions = NewtonOptions {
    tolerance: 1e-16,
    max_iterations: 50,
};

/// Discrete Noether: the angular momentum `q × p` of Kepler (e = 0.9, two orbits) is conserved to
/// round-off by every s.
#[test]
fn kepler_angular_momentum_is_conserved() {
    let e: f64 = 0.9;
    let (q0, v0) = ([1.0 - e, 0.0], [0.0, ((1.0 + e) / (1.0 - e)).sqrt()]);
    let grid = Grid::new(0.0, 4.0 * std::f64::consts::PI, 4000).unwrap();
    for s in 1..=4 {
        let problem = varembed_tests::problem(&Kepler, grid, gauss(s)).with_newton(TO_ROUND_OFF);
        let run = problem.solve_ivp(Scheme::Variational, q0, v0).unwrap();
        let j = drift(&run, |q, p| q[0] * p[1] - q[1] * p[0]);
        println!("Kepler s = {s}: {j:e}");
        assert!(j < 1e-13, "s = {s}: angular momentum drift {j:e}");
    }
}

/// The charged particle: the canonical angular momentum `x p_y − y p_x` and the guiding centre
/// `(x/2 + p_y/B, y/2 − p_x/B)` are conserved to round-off by every s, over 50 gyrations.
#[test]
fn magnetic_angular_momentum_and_guiding_centre_are_conserved() {
    let b = 2.0;
    let model = Magnetic { b };
    let grid = Grid::new(0.0, 50.0 * std::f64::consts::PI, 2000).unwrap();
    for s in 1..=4 {
        let problem = varembed_tests::problem(&model, grid, gauss(s)).with_newton(TO_ROUND_OFF);
        let run = problem
            .solve_ivp(Scheme::Variational, [0.3, -0.2], [0.5, 0.9])
            .unwrap();
        let j = drift(&run, |q, p| q[0] * p[1] - q[1] * p[0]);
        let cx = drift(&run, |q, p| 0.5 * q[0] + p[1] / b);
        let cy = drift(&run, |q, p| 0.5 * q[1] - p[0] / b);
        println!("magnetic s = {s}: {j:e} {cx:e} {cy:e}");
        assert!(j.max(cx).max(cy) < 1e-13, "s = {s}: {j:e} {cx:e} {cy:e}");
    }
}

/// The blow-up guard covers the Gauss–Legendre runs (sampling the energy at a stage): the
/// spherical pendulum from θ = 0.3 towards the pole at h = 0.01, where the azimuthal speed
/// `p_φ/sin²θ` is not resolved. For s = 1, 2 the unguarded run returns, its energy (computed
/// here from its nodes and momenta, `E = ½(p_θ² + p_φ²/sin²θ) − g cos θ`, from −9.4) gaining 7
/// and 200, and the guarded run fails with `Error::BlowUp` within the first passage. For s = 3, 4
/// Newton fails in that passage (from the extrapolated guess), guarded or not: an error either
/// way, never a returned curve.
#[test]
fn the_blow_up_guard_covers_gauss_legendre() {
    let g = 9.81;
    let model = Spherical { g };
    let grid = Grid::new(0.0, 10.0, 1000).unwrap();
    let (q0, v0) = ([0.3, 0.0], [-1.0, 0.02]);
    let energy = |q: &Vector<2>, p: &Vector<2>| {
        0.5 * (p[0] * p[0] + (p[1] / q[0].sin()).powi(2)) - g * q[0].cos()
    };
    for s in [1, 2] {
        let run = varembed_tests::problem(&model, grid, gauss(s))
            .with_blow_up_guard(false)
            .solve_ivp(Scheme::Variational, q0, v0)
            .unwrap();
        let e0 = energy(&run.q[0], &run.momenta[0]);
        let gain = run
            .q
            .iter()
            .zip(&run.momenta)
            .map(|(q, p)| energy(q, p) - e0)
            .fold(0.0, f64::max);
        assert!(gain > 5.0, "s = {s}: the energy gained only {gain}");
        match varembed_tests::problem(&model, grid, gauss(s)).solve_ivp(Scheme::Variational, q0, v0)
        {
            Err(Error::BlowUp { from, to, growth }) => {
                assert!(
                    from <= to && to < 100 && growth > 16.0,
                    "s = {s}: {from}..={to}, {growth}"
                );
            }
            other => panic!("s = {s}: {other:?}"),
        }
    }
    for s in [3, 4] {
        for guard in [true, false] {
            let problem = varembed_tests::problem(&model, grid, gauss(s)).with_blow_up_guard(guard);
            let run = problem.solve_ivp(Scheme::Variational, q0, v0);
            assert!(
                matches!(
                    run,
                    Err(Error::NewtonDidNotConverge { .. } | Error::BlowUp { .. })
                ),
                "s = {s}: {run:?}"
            );
        }
    }
}

/// The typed errors: stages outside 1..=4, the direct scheme, whole-curve evaluations and
/// boundary value problems, a run from two nodes, Newton out of iterations (with the step and
/// the residual), non-finite data.
#[test]
fn the_errors_name_what_is_not_offered() {
    for stages in [0, 5, 100] {
        assert_eq!(
            Embedding::gauss_legendre(stages),
            Err(Error::StagesOutOfRange { stages })
        );
    }
    let model = Oscillator { omega: 1.0 };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = varembed_tests::problem(&model, grid, gauss(2));
    let unsupported = |r: Result<(), Error>| matches!(r, Err(Error::Unsupported { .. }));
    assert!(unsupported(
        problem.solve_ivp(Scheme::Direct, 1.0, 0.0).map(|_| ())
    ));
    let q = vec![Vector::<1>::zeros(); 11];
    assert!(unsupported(
        problem.residual(Scheme::Variational, &q).map(|_| ())
    ));
    assert!(unsupported(problem.quadrature_energies(&q).map(|_| ())));
    assert!(unsupported(problem.action(&q).map(|_| ())));
    assert!(unsupported(
        problem.solve_bvp(Scheme::Direct, 0.0, 1.0).map(|_| ())
    ));
    assert!(unsupported(
        problem
            .solve_ivp_from_nodes(Scheme::Variational, 0.0, 0.1)
            .map(|_| ())
    ));
    assert!(unsupported(problem.legendre_start(0.0, 1.0).map(|_| ())));
    assert!(unsupported(problem.compare_ivp(1.0, 0.0).map(|_| ())));
    // The variational run of a comparison's convergence sweep works.
    let run = problem.convergence_ivp(Scheme::Variational, 1.0, 0.0, &Default::default(), 3);
    assert!(
        run.failures.is_empty() && run.levels.len() == 3,
        "{:?}",
        run.failures
    );

    // One Newton iteration is not enough for the pendulum's first step at h = 0.5.
    let pendulum = varembed_tests::models::generated::UnitPendulum;
    let one = NewtonOptions {
        tolerance: 1e-12,
        max_iterations: 1,
    };
    let problem = varembed_tests::problem(&pendulum, Grid::new(0.0, 5.0, 10).unwrap(), gauss(3))
        .with_newton(one);
    match problem.solve_ivp(Scheme::Variational, 2.0, 0.0) {
        Err(Error::NewtonDidNotConverge {
            at,
            iterations,
            residual,
        }) => {
            assert_eq!((at, iterations), (Location::Step(1), 1));
            assert!(residual > 1e-12 && residual.is_finite(), "{residual}");
        }
        other => panic!("{other:?}"),
    }
    let problem = varembed_tests::problem(&pendulum, Grid::new(0.0, 5.0, 10).unwrap(), gauss(3));
    assert!(matches!(
        problem.solve_ivp(Scheme::Variational, f64::NAN, 0.0),
        Err(Error::NonFiniteInput { .. })
    ));
}

/// `L = eᵗ(½v² − ½x²)`, whose Euler–Lagrange equation is `q̈ + q̇ + q = 0`.
#[lagrangian]
fn damped(x: f64, v: f64, t: f64) -> f64 {
    t.exp() * (0.5 * v * v - 0.5 * x * x)
}

/// A Lagrangian that depends on `t` (the stages at `t_k + c_i h`): order `2s` against the
/// closed form `q = e^{−t/2}(cos ωt + sin(ωt)/(2ω))`, `ω = √3/2`, of `q(0) = 1`, `q̇(0) = 0`.
#[test]
fn a_time_dependent_lagrangian_is_of_order_two_s() {
    let omega = 0.75f64.sqrt();
    let exact = |t: f64| (-0.5 * t).exp() * ((omega * t).cos() + (omega * t).sin() / (2.0 * omega));
    let sizes: [&[usize]; 4] = [
        &[400, 800, 1600],
        &[20, 40, 80, 160],
        &[10, 20, 40],
        &[5, 10, 20],
    ];
    for (s, sizes) in (1..=4).zip(sizes) {
        let errors: Vec<(usize, f64)> = sizes
            .iter()
            .map(|&n| {
                let grid = Grid::new(0.0, 5.0, n).unwrap();
                let run = varembed_tests::problem(&Damped, grid, gauss(s))
                    .solve_ivp(Scheme::Variational, 1.0, 0.0)
                    .unwrap();
                (
                    n,
                    varembed::max_error(&grid, &run.q, |t| Vector::<1>::new(exact(t))),
                )
            })
            .collect();
        let orders = varembed::observed_orders(&errors);
        println!("damped s = {s}: {errors:?} {orders:?}");
        assert!(
            orders.iter().all(|o| (o - 2.0 * s as f64).abs() <= 0.3),
            "s = {s}: {errors:?} {orders:?}"
        );
    }
}

/// The values at the nodes of a Gauss–Legendre run are the scheme's own `(q_k, p_k)`, with the
/// velocity from `∂L/∂v = p_k`: on the oscillator `p = v = q̇ = −sin t`, of order `2s` at every
/// node, the last included.
#[test]
fn node_values_carry_the_schemes_momenta_at_order_2s() {
    let model = Oscillator { omega: 1.0 };
    for s in 1..=3 {
        let errors: Vec<(usize, f64)> = [20, 40]
            .into_iter()
            .map(|n| {
                let grid = Grid::new(0.0, 2.0, n).unwrap();
                let run = varembed_tests::problem(&model, grid, gauss(s))
                    .with_newton(NewtonOptions {
                        tolerance: 1e-15,
                        ..NewtonOptions::default()
                    })
                    .solve_ivp(Scheme::Variational, 1.0, 0.0)
                    .unwrap();
                let nodes = run.node_values(&model).unwrap();
                assert_eq!(nodes.rule.order, 2 * s as u32);
                assert_eq!(nodes.p, run.momenta);
                let error = nodes
                    .iter()
                    .map(|node| {
                        assert!((node.v[0] - node.p[0]).abs() <= 1e-12);
                        (node.p[0] + node.t.sin()).abs()
                    })
                    .fold(0.0, f64::max);
                (n, error)
            })
            .collect();
        let order = varembed::observed_order(errors[0], errors[1]);
        assert!(
            (order - 2.0 * s as f64).abs() < 0.3,
            "s = {s}: errors {errors:?}, order {order}"
        );
    }
}

/// The boundary value problem of a Gauss–Legendre integrator between the ends of its own
/// initial value run returns the run's nodes and carried momenta, for every `s`: Kepler's
/// orbit (a quarter of it, away from conjugate points) and the magnetic model, whose `L_xv`
/// is not symmetric.
#[test]
fn the_boundary_value_problem_returns_the_initial_value_run() {
    let kepler = Kepler;
    let magnetic = Magnetic { b: 1.3 };
    let grid = Grid::new(0.0, 1.5, 20).unwrap();
    for s in 1..=4 {
        let problem = varembed_tests::problem(&kepler, grid, gauss(s));
        let run = problem
            .solve_ivp(Scheme::Variational, [1.0, 0.0], [0.0, 1.1])
            .unwrap();
        let bvp = problem
            .solve_bvp(Scheme::Variational, run.q[0], run.q[20])
            .unwrap();
        let problem = varembed_tests::problem(&magnetic, grid, gauss(s));
        let run_m = problem
            .solve_ivp(Scheme::Variational, [0.2, -0.1], [0.5, 0.3])
            .unwrap();
        let bvp_m = problem
            .solve_bvp(Scheme::Variational, run_m.q[0], run_m.q[20])
            .unwrap();
        // The magnetic model's equations are linear: one Newton step solves them.
        for (name, run, bvp, least) in [("Kepler", &run, &bvp, 2), ("magnetic", &run_m, &bvp_m, 1)]
        {
            assert_eq!(bvp.q.len(), 21);
            for k in 0..=20 {
                let gap = (bvp.q[k] - run.q[k]).amax();
                assert!(gap <= 1e-12, "{name} s = {s}, node {k}: {gap:e}");
                let gap = (bvp.momenta[k] - run.momenta[k]).amax();
                assert!(gap <= 1e-11, "{name} s = {s}, momentum {k}: {gap:e}");
            }
            assert!(bvp.newton_iterations >= least, "{name} s = {s}");
        }
    }
}
