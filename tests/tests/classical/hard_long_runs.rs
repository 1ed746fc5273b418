//! Hard cases: stability limits, stiffness, and long runs (10⁶–10⁷ steps).

use varembed::{
    Embedding, Error, Grid, Lagrangian, Location, Problem, Scheme, Side, Vector, lagrangian,
};
use varembed_tests::models::generated::{Kepler, UnitPendulum};
use varembed_tests::reference::DiscreteOscillation;

#[lagrangian]
fn oscillator(x: f64, v: f64, omega: f64) -> f64 {
    0.5 * v * v - 0.5 * omega * omega * x * x
}

/// Double pendulum, unit masses and lengths: a configuration-dependent mass matrix.
#[lagrangian]
fn double_pendulum(x: [f64; 2], v: [f64; 2], g: f64) -> f64 {
    v[0] * v[0]
        + 0.5 * v[1] * v[1]
        + v[0] * v[1] * (x[0] - x[1]).cos()
        + 2.0 * g * x[0].cos()
        + g * x[1].cos()
}

fn energies<L: Lagrangian<D> + ?Sized, const D: usize>(
    problem: &Problem<'_, L, D>,
    q: &[Vector<D>],
) -> Vec<f64> {
    let rows = problem.quadrature_energies(q).unwrap();
    rows.into_iter().map(|(_, e)| e).collect()
}

/// Max |E − E₀| over a slice of energies.
fn deviation(e: &[f64], e0: f64) -> f64 {
    e.iter().map(|x| (x - e0).abs()).fold(0.0, f64::max)
}

#[test]
fn oscillator_at_the_stability_limit() {
    let oscillator = Oscillator { omega: 1.0 };
    // ωh = 1.99: stable; the run is the exact discrete rotation, bounded by √(A² + B²).
    let steps = 1_000_000;
    let grid = Grid::new(0.0, 1.99 * steps as f64, steps).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&oscillator, grid, Embedding::finite_difference(side));
        let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
        let bound = DiscreteOscillation::variational(1.99, run.q[0][0], run.q[1][0]).amplitude();
        let max = run.q.iter().map(|x| x[0].abs()).fold(0.0, f64::max);
        assert!(
            max <= bound * (1.0 + 1e-9),
            "{side:?}: max |Q| = {max}, bound {bound}"
        );
        assert!(
            max >= 0.99 * bound,
            "the discrete rotation reaches its amplitude"
        );
    }
    // ωh = 2.01: reported, never returned.
    let grid = Grid::new(0.0, 2.01 * steps as f64, steps).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&oscillator, grid, Embedding::finite_difference(side));
        assert!(matches!(
            problem.solve_ivp(Scheme::Variational, 1.0, 0.0),
            Err(Error::Unstable { .. })
        ));
    }
}

#[test]
fn stiff_oscillator_explicit_schemes_report_implicit_direct_survives() {
    // ω = 10³, h = 10⁻²: ωh = 10.
    let oscillator = Oscillator { omega: 1e3 };
    let grid = Grid::new(0.0, 10.0, 1000).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&oscillator, grid, Embedding::finite_difference(side));
        let variational = problem.solve_ivp(Scheme::Variational, 1.0, 0.0);
        assert!(
            matches!(
                variational,
                Err(Error::Unstable {
                    at: Location::Step(2),
                    ..
                })
            ),
            "{variational:?}"
        );
    }
    let forward = varembed_tests::problem(
        &oscillator,
        grid,
        Embedding::finite_difference(Side::Forward),
    );
    let direct_forward = forward.solve_ivp(Scheme::Direct, 1.0, 0.0);
    assert!(
        matches!(direct_forward, Err(Error::Unstable { .. })),
        "{direct_forward:?}"
    );
    // The implicit direct σ = − scheme: amplitude multiplied by r = (1 + ω²h²)^{−1/2} each step.
    let backward = varembed_tests::problem(
        &oscillator,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    let run = backward
        .solve_ivp_from_nodes(Scheme::Direct, 1.0, 1.0)
        .unwrap();
    let max = run.q.iter().map(|x| x[0].abs()).fold(0.0, f64::max);
    assert!(max <= 1.0 + 1e-12, "max |Q| = {max}");
    assert!(
        run.last()[0].abs() < 1e-100,
        "damped out: {}",
        run.last()[0]
    );
}

#[test]
fn pendulum_ten_million_steps_energy_bounded_without_drift() {
    let steps = 10_000_000;
    let grid = Grid::new(0.0, 1e5, steps).unwrap(); // h = 0.01
    let problem = varembed_tests::problem(
        &UnitPendulum,
        grid,
        Embedding::finite_difference(Side::Forward),
    );
    let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
    let e = energies(&problem, &run.q);
    let e0 = UnitPendulum.energy(&Vector::<1>::new(1.0), &Vector::<1>::new(0.0), 0.0);
    let (first, second) = e.split_at(e.len() / 2);
    let (d1, d2) = (deviation(first, e0), deviation(second, e0));
    // E is evaluated with the one-sided velocity V_k = v(t_k + h/2) + O(h²), so it carries an
    // O(h) oscillation of size ≈ (h/2)·max|v U′(x)| ≤ 0.005 · 0.96 · 0.85 ≈ 4e-3, not a drift.
    assert!(d1 < 5e-3 && d2 < 5e-3, "energy error {d1:e}, {d2:e}");
    assert!(
        d2 <= 1.5 * d1,
        "drift: first half {d1:e}, second half {d2:e}"
    );
}

/// The discrete angular momentum of the variational scheme, `J_k = Q_k × Q_{k+1} / h`
/// (its Noether quantity: `J_k − J_{k−1} = −h Q_k × ∇U(Q_k) = 0` for a central force).
fn angular_momentum(q: &[Vector<2>], h: f64) -> Vec<f64> {
    q.windows(2)
        .map(|w| (w[0][0] * w[1][1] - w[0][1] * w[1][0]) / h)
        .collect()
}

/// Kepler energy with the centred velocity `(Q_{k+1} − Q_{k−1})/2h`, the one Störmer–Verlet
/// keeps to `O(h²)`.
fn centred_energy(q: &[Vector<2>], h: f64) -> Vec<f64> {
    q.windows(3)
        .map(|w| 0.5 * ((w[2] - w[0]) / (2.0 * h)).norm_squared() - 1.0 / w[1].norm())
        .collect()
}

#[test]
fn kepler_hundred_orbits_at_eccentricity_point_nine() {
    // a = 1, e = 0.9, period 2π; start at aphelion r = 1.9 with speed √(0.1/1.9).
    let orbits = 100.0;
    let steps = 628_319; // h ≈ 1e-3: ≈ 23 steps across the perihelion passage (r = 0.1, |v| ≈ 4.4)
    let grid = Grid::new(0.0, orbits * std::f64::consts::TAU, steps).unwrap();
    let (q0, v0) = (
        Vector::<2>::new(1.9, 0.0),
        Vector::<2>::new(0.0, (0.1f64 / 1.9).sqrt()),
    );
    let e_exact = Kepler.energy(&q0, &v0, 0.0); // −1/(2a) = −0.5
    assert!((e_exact + 0.5).abs() < 1e-12);
    let problem =
        varembed_tests::problem(&Kepler, grid, Embedding::finite_difference(Side::Forward));
    let run = problem.solve_ivp(Scheme::Variational, q0, v0).unwrap();
    assert!(run.q.iter().all(|x| x.iter().all(|c| c.is_finite())));
    // Every perihelion passage is reached (r ≈ 0.1) and none goes through the singularity.
    let r_min = run.q.iter().map(|x| x.norm()).fold(f64::INFINITY, f64::min);
    assert!((0.09..0.11).contains(&r_min), "r_min = {r_min}");
    let e = energies(&problem, &run.q);
    let (first, second) = e.split_at(e.len() / 2);
    let (d1, d2) = (deviation(first, e_exact), deviation(second, e_exact));
    // One-sided velocities carry an O(h·|v·∇U|) error, largest at perihelion (measured 5.5e-2
    // in both halves); the centred energy is Störmer–Verlet's O(h²) one (measured 1.17e-3,
    // 0.23 % of |E| = 0.5, the same in both halves to six digits: no drift).
    assert!(
        d1 < 0.06 && d2 <= 1.5 * d1,
        "one-sided energy deviation {d1:e} then {d2:e}"
    );
    let centred = centred_energy(&run.q, grid.h());
    let (c1, c2) = centred.split_at(centred.len() / 2);
    let (d1, d2) = (deviation(c1, e_exact), deviation(c2, e_exact));
    assert!(
        d1 < 2e-3 && d2 <= 1.5 * d1,
        "centred energy deviation {d1:e} then {d2:e}"
    );
    // Newton at every step through all 100 perihelion passages: the same variational scheme
    // with the closed-form update hidden. It converges everywhere and reproduces the run.
    let newton = varembed_tests::problem(
        &NewtonOnly(Kepler),
        grid,
        Embedding::finite_difference(Side::Forward),
    );
    let implicit_run = newton.solve_ivp(Scheme::Variational, q0, v0).unwrap();
    assert!(implicit_run.newton_iterations >= steps - 1 && implicit_run.explicit_steps == 0);
    let gap = implicit_run.max_distance(&run.q).unwrap();
    assert!(
        gap < 1e-6,
        "Newton and closed-form runs differ by {gap:e} after 100 orbits"
    );
    // The direct σ = − scheme is dissipative: each perihelion passage costs it energy
    // (measured E: −0.50, −1.17, −2.19, … in the first orbit), its orbit falls towards the
    // singularity, and Newton's failure there is reported with its step, never returned.
    let implicit =
        varembed_tests::problem(&Kepler, grid, Embedding::finite_difference(Side::Backward));
    match implicit.solve_ivp(Scheme::Direct, q0, v0) {
        Err(
            Error::NewtonDidNotConverge {
                at: Location::Step(n),
                ..
            }
            | Error::NotFinite {
                at: Location::Step(n),
            },
        ) => {
            assert!(n < steps, "step {n}");
        }
        other => panic!(
            "expected a located failure of the dissipative scheme, got {:?}",
            other.map(|s| s.last())
        ),
    }
    let j = angular_momentum(&run.q, grid.h());
    let spread = j.iter().map(|x| (x - j[0]).abs()).fold(0.0, f64::max) / j[0].abs();
    assert!(
        spread < 1e-10,
        "angular momentum relative spread {spread:e}"
    );
}

#[test]
fn double_pendulum_chaotic_million_implicit_steps() {
    // Both arms raised past horizontal, released at rest: the chaotic regime.
    let lag = DoublePendulum { g: 9.81 };
    let steps = 1_000_000;
    let grid = Grid::new(0.0, 1000.0, steps).unwrap(); // h = 1e-3
    let problem = varembed_tests::problem(&lag, grid, Embedding::finite_difference(Side::Backward));
    let (q0, v0) = (Vector::<2>::new(2.0, 2.5), Vector::<2>::zeros());
    // Newton converges at every step or the solve is an error: unwrap is the assertion.
    let run = problem.solve_ivp(Scheme::Variational, q0, v0).unwrap();
    assert_eq!(run.q.len(), steps + 1);
    assert!(
        run.newton_iterations >= steps - 1,
        "a configuration-dependent mass matrix needs Newton"
    );
    let e0 = lag.energy(&q0, &v0, 0.0);
    let e = energies(&problem, &run.q);
    let (first, second) = e.split_at(e.len() / 2);
    let (d1, d2) = (deviation(first, e0), deviation(second, e0));
    assert!(
        d1 < 0.05 * e0.abs() && d2 < 0.05 * e0.abs(),
        "energy deviation {d1:e}, {d2:e} of |E0| = {}",
        e0.abs()
    );
    assert!(d2 <= 1.5 * d1, "drift: {d1:e} then {d2:e}");
    // Chaotic: the lower arm flips over at least once.
    assert!(run.q.iter().any(|x| x[1].abs() > std::f64::consts::PI));
}

/// A Lagrangian with only `value`, `gradient` and `hessian`: the trait's generic step kernels,
/// no closed-form update, so every step runs Newton.
struct NewtonOnly<L>(L);

impl<L: Lagrangian<2>> Lagrangian<2> for NewtonOnly<L> {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> f64 {
        self.0.value(x, v, t)
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> (Vector<2>, Vector<2>) {
        self.0.gradient(x, v, t)
    }
    fn hessian(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> varembed::Hessian<2> {
        self.0.hessian(x, v, t)
    }
}
