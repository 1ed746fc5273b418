//! Degenerate Lagrangians and bad input are typed errors that name the node or the input,
//! reported before any step is taken (or, for a Lagrangian that degenerates along a run, at
//! the checked node), never an `Ok` with a meaningless curve.

use varembed::{
    Embedding, Error, FractionalSolver, Grid, Hessian, Lagrangian, Location, Matrix, Scheme, Side,
    Start, Vector, lagrangian,
};
use varembed_tests::curve::{max_diff, v1};
use varembed_tests::models::generated::Kepler;

/// `L = x·v − ½x²`: `∂²L/∂v² ≡ 0`, while the step Jacobians (`L_vx + L_vv/h = 1`, `h`, …) are
/// regular, so nothing but the check on `L_vv` stops its runs.
#[lagrangian]
fn first_order(x: f64, v: f64) -> f64 {
    x * v - 0.5 * x * x
}

/// `L = ω (½v² − ½x²)`: the oscillator scaled by `ω`, the same Euler–Lagrange equation.
#[lagrangian]
fn scaled_oscillator(x: [f64; 2], v: [f64; 2], scale: f64) -> f64 {
    scale * 0.5 * (v[0] * v[0] + v[1] * v[1] - x[0] * x[0] - x[1] * x[1])
}

/// `L = −m c² √(1 − v²/c²) − ½k x²`: defined for speeds below `c` only.
#[lagrangian]
fn relativistic(x: f64, v: f64, m: f64, c: f64, k: f64) -> f64 {
    -m * c * c * (1.0 - v * v / (c * c)).sqrt() - 0.5 * k * x * x
}

/// The error of a one-dimensional Lagrangian whose `∂²L/∂v²` vanishes: its one degenerate
/// direction is `v₀`.
fn degenerate(at: Location) -> Error {
    Error::DegenerateLagrangian {
        at,
        measure: 0.0,
        directions: vec![vec![(0, 1.0)]],
    }
}

/// The first node at which the Lagrangian is evaluated (`I_−` starts at 1, `I_+` at 0).
fn first_quadrature_node(side: Side) -> usize {
    match side {
        Side::Backward => 1,
        Side::Forward => 0,
    }
}

#[test]
fn first_order_lagrangian_fails_every_solver_at_its_first_node() {
    let grid = Grid::new(0.0, 2.0, 40).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let fde = varembed_tests::problem(&FirstOrder, grid, Embedding::finite_difference(side));
        for scheme in [Scheme::Direct, Scheme::Variational] {
            for start in [Start::Legendre, Start::SecondOrder] {
                assert_eq!(
                    fde.solve_ivp_with(scheme, 1.0, 0.0, start).unwrap_err(),
                    degenerate(Location::Step(0)),
                    "{side:?} {scheme} {start:?}"
                );
            }
            let err = fde.solve_bvp(scheme, 1.0, 0.5).unwrap_err();
            assert_eq!(
                err,
                degenerate(Location::Node(first_quadrature_node(side))),
                "{side:?} {scheme}"
            );
            assert_eq!(
                err.to_string(),
                format!(
                    "the Lagrangian is degenerate at node Q_{}: ∂²L/∂v² has the pivot ratio \
                     0.000e0 (below 1e-12), and vanishes along (v₀ 1.000); give every \
                     coordinate a kinetic term (regularise L), or remove the coordinates it \
                     does not govern",
                    first_quadrature_node(side)
                )
            );
        }
        let gle = Embedding::grunwald_letnikov(side, 0.6).unwrap();
        for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
            let problem =
                varembed_tests::problem(&FirstOrder, grid, gle).with_fractional_solver(solver);
            assert_eq!(
                problem
                    .solve_bvp(Scheme::Variational, 1.0, 0.5)
                    .unwrap_err(),
                degenerate(Location::Node(first_quadrature_node(side))),
                "{side:?} {solver:?}"
            );
        }
    }
}

/// The measure is scale-free: `L_vv = 10⁻⁸ I` is as regular as `I`, and the run equals the
/// unscaled one (the same equation; the closed-form steps are invariant under the scale).
#[test]
fn a_small_but_regular_kinetic_term_passes() {
    let grid = Grid::new(0.0, 3.0, 3000).unwrap();
    let (q0, v0) = (Vector::<2>::new(1.0, 0.0), Vector::<2>::new(0.0, 1.0));
    let run = |scale: f64| {
        let lag = ScaledOscillator { scale };
        let problem =
            varembed_tests::problem(&lag, grid, Embedding::finite_difference(Side::Forward));
        problem.solve_ivp(Scheme::Variational, q0, v0).unwrap()
    };
    let (small, unit) = (run(1e-8), run(1.0));
    assert!(max_diff(&small.q, &unit.q) < 1e-12);
    // Against the exact q = (cos t, sin t): first order in h from the Legendre start.
    let exact: Vec<Vector<2>> = grid
        .nodes()
        .iter()
        .map(|t| Vector::<2>::new(t.cos(), t.sin()))
        .collect();
    assert!(max_diff(&small.q, &exact) < 5e-3);
}

/// `L = ½ m(t) v² + x v − ½x²` with `m = 1` before `t_off` and `0` from it on: regular at the
/// initial data, degenerate later. The variational steps and the direct σ = − step keep a
/// regular Jacobian (`L_vx + m/h`, `m/h − L_xv`, `m/h + h`), so the runs go on and the check
/// along the run must catch it.
struct SwitchedOff {
    t_off: f64,
}

impl SwitchedOff {
    fn mass(&self, t: f64) -> f64 {
        if t < self.t_off { 1.0 } else { 0.0 }
    }
}

impl Lagrangian<1> for SwitchedOff {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * self.mass(t) * v[0] * v[0] + x[0] * v[0] - 0.5 * x[0] * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (v1(v[0] - x[0]), v1(self.mass(t) * v[0] + x[0]))
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-1.0),
            xv: Matrix::<1>::new(1.0),
            vv: Matrix::<1>::new(self.mass(t)),
        }
    }
}

#[test]
fn a_lagrangian_degenerate_away_from_the_initial_data_is_caught_along_the_run() {
    let lag = SwitchedOff { t_off: 1.5 };
    for (side, scheme) in [
        (Side::Backward, Scheme::Variational),
        (Side::Forward, Scheme::Variational),
        (Side::Backward, Scheme::Direct),
    ] {
        // h = 10⁻³: m = 0 from node 1500 on. The checks run before steps 2, 1026, 2050, …, at
        // nodes 1, 1025, 2049: the first that sees m = 0 is node 2049.
        let grid = Grid::new(0.0, 3.0, 3000).unwrap();
        let problem = varembed_tests::problem(&lag, grid, Embedding::finite_difference(side));
        assert_eq!(
            problem.solve_ivp(scheme, 1.0, 0.0).unwrap_err(),
            degenerate(Location::Step(2049)),
            "{side:?} {scheme}"
        );
        // A run that ends at node 1800 passes no check after the switch but the last node's.
        let short = varembed_tests::problem(
            &lag,
            Grid::new(0.0, 1.8, 1800).unwrap(),
            Embedding::finite_difference(side),
        );
        assert_eq!(
            short.solve_ivp(scheme, 1.0, 0.0).unwrap_err(),
            degenerate(Location::Step(1800)),
            "{side:?} {scheme}"
        );
        // Before the switch the run is the oscillator's: q = cos t.
        let early = varembed_tests::problem(
            &lag,
            Grid::new(0.0, 1.4, 1400).unwrap(),
            Embedding::finite_difference(side),
        );
        let run = early.solve_ivp(scheme, 1.0, 0.0).unwrap();
        assert!(
            (run.last()[0] - 1.4f64.cos()).abs() < 5e-3,
            "{side:?} {scheme}"
        );
    }
}

#[test]
fn a_non_finite_model_constant_is_named() {
    let lag = Relativistic {
        m: 1.0,
        c: f64::NAN,
        k: 1.0,
    };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let expected = Error::NonFiniteInput {
        what: "model constant `c` = NaN".to_string(),
    };
    for side in [Side::Backward, Side::Forward] {
        let problem = varembed_tests::problem(&lag, grid, Embedding::finite_difference(side));
        assert_eq!(
            problem.solve_ivp(Scheme::Direct, 0.0, 0.1),
            Err(expected.clone())
        );
        assert_eq!(
            problem.solve_ivp_from_nodes(Scheme::Variational, 0.0, 0.01),
            Err(expected.clone())
        );
        assert_eq!(
            problem.solve_bvp(Scheme::Variational, 0.0, 0.1),
            Err(expected.clone())
        );
    }
    let infinite = Relativistic {
        m: f64::INFINITY,
        c: 1.0,
        k: 1.0,
    };
    let problem = varembed_tests::problem(
        &infinite,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    assert_eq!(
        problem
            .solve_ivp(Scheme::Variational, 0.0, 0.1)
            .unwrap_err()
            .to_string(),
        "non-finite input: model constant `m` = inf"
    );
}

#[test]
fn a_non_finite_end_value_is_named_as_its_end() {
    let lag = ScaledOscillator { scale: 1.0 };
    let grid = Grid::new(0.5, 1.5, 10).unwrap();
    let (fine, nan) = (Vector::<2>::new(1.0, 0.0), Vector::<2>::new(0.0, f64::NAN));
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::grunwald_letnikov(Side::Forward, 0.5).unwrap(),
    ] {
        let problem = varembed_tests::problem(&lag, grid, embedding);
        assert_eq!(
            problem
                .solve_bvp(Scheme::Variational, fine, nan)
                .unwrap_err()
                .to_string(),
            "non-finite input: the end value Q_10 at b = 1.5: [0.0, NaN]"
        );
        assert_eq!(
            problem
                .solve_bvp(Scheme::Direct, nan, fine)
                .unwrap_err()
                .to_string(),
            "non-finite input: the end value Q_0 at a = 0.5: [0.0, NaN]"
        );
        // A NaN inside a given guess is named by its node.
        let mut guess = vec![fine; 11];
        guess[4] = nan;
        assert_eq!(
            problem.solve_bvp_from(Scheme::Variational, &guess),
            Err(Error::NonFiniteInput {
                what: "Q_4 = [0.0, NaN]".to_string()
            })
        );
    }
}

#[test]
fn a_non_finite_initial_value_is_named() {
    let lag = ScaledOscillator { scale: 1.0 };
    let problem = varembed_tests::problem(
        &lag,
        Grid::new(0.0, 1.0, 10).unwrap(),
        Embedding::finite_difference(Side::Forward),
    );
    let (fine, bad) = (
        Vector::<2>::new(1.0, 0.0),
        Vector::<2>::new(f64::INFINITY, 0.0),
    );
    for start in [Start::Legendre, Start::SecondOrder] {
        assert_eq!(
            problem
                .solve_ivp_with(Scheme::Variational, bad, fine, start)
                .unwrap_err()
                .to_string(),
            "non-finite input: q0[0] = inf (the initial position q(a))"
        );
        assert_eq!(
            problem
                .solve_ivp_with(Scheme::Direct, fine, bad, start)
                .unwrap_err()
                .to_string(),
            "non-finite input: v0[0] = inf (the initial velocity q̇(a))"
        );
    }
}

#[test]
fn an_initial_velocity_faster_than_light_is_outside_the_domain() {
    let lag = Relativistic {
        m: 2.0,
        c: 3.0,
        k: 1.0,
    };
    let grid = Grid::new(0.0, 1.0, 100).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let problem = varembed_tests::problem(&lag, grid, Embedding::finite_difference(side));
        for scheme in [Scheme::Direct, Scheme::Variational] {
            for start in [Start::Legendre, Start::SecondOrder] {
                // v₀ = 1.5c.
                let err = problem.solve_ivp_with(scheme, 0.5, 4.5, start).unwrap_err();
                assert_eq!(
                    err,
                    Error::OutsideDomain {
                        what: "the initial velocity q̇(a) = [4.5] (at q(a) = [0.5], t = 0)"
                            .to_string()
                    }
                );
                assert_eq!(
                    err.to_string(),
                    "the initial velocity q̇(a) = [4.5] (at q(a) = [0.5], t = 0) is outside \
                     the domain of the Lagrangian: L or its derivatives are not finite there"
                );
                // v₀ = 0.5c is inside: the run returns, at speeds below c.
                let run = problem.solve_ivp_with(scheme, 0.5, 1.5, start).unwrap();
                let h = grid.h();
                assert!(
                    run.q
                        .windows(2)
                        .all(|w| ((w[1][0] - w[0][0]) / h).abs() < 3.0)
                );
            }
        }
        // Two given nodes whose velocity (Q_1 − Q_0)/h = 4 is faster than light.
        let err = problem
            .solve_ivp_from_nodes(Scheme::Variational, 0.0, 0.04)
            .unwrap_err();
        assert!(
            matches!(&err, Error::OutsideDomain { what } if what.starts_with("the first nodes Q_0 = [0.0], Q_1 = [0.04]")),
            "{err:?}"
        );
    }
}

/// Kepler's `1/|x|` at an end: the end value is outside the domain, named as that end (each
/// side evaluates the Lagrangian at its own end node: σ = − at `Q_N`, σ = + at `Q_0`).
#[test]
fn an_end_value_at_a_singularity_is_outside_the_domain() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let (origin, away) = (Vector::<2>::zeros(), Vector::<2>::new(1.0, 0.0));
    let backward =
        varembed_tests::problem(&Kepler, grid, Embedding::finite_difference(Side::Backward));
    let err = backward
        .solve_bvp(Scheme::Variational, away, origin)
        .unwrap_err();
    assert!(
        matches!(&err, Error::OutsideDomain { what } if what.starts_with("the end value Q_10 = [0.0, 0.0] at b")),
        "{err:?}"
    );
    let forward =
        varembed_tests::problem(&Kepler, grid, Embedding::finite_difference(Side::Forward));
    let err = forward.solve_bvp(Scheme::Direct, origin, away).unwrap_err();
    assert!(
        matches!(&err, Error::OutsideDomain { what } if what.starts_with("the end value Q_0 = [0.0, 0.0] at a")),
        "{err:?}"
    );
}
