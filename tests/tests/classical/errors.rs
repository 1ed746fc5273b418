//! Every error variant is produced, by user input or by a failing solve, as a
//! typed error carrying where it happened; nothing panics.

use varembed::{
    DifferentialOperator, Embedding, Error, Grid, Hessian, Lagrangian, Location, Matrix,
    NewtonOptions, Scheme, Side, Vector, curve_from_flat,
};
use varembed_tests::curve::v1;
use varembed_tests::models::hand::{Oscillator, Pendulum};

#[test]
fn invalid_grids() {
    for (a, b, n) in [
        (0.0, 1.0, 0),
        (1.0, 1.0, 5),
        (2.0, 1.0, 5),
        (f64::NAN, 1.0, 5),
        (0.0, f64::INFINITY, 5),
    ] {
        assert!(
            matches!(Grid::new(a, b, n), Err(Error::InvalidGrid { .. })),
            "{a} {b} {n}"
        );
    }
    // h too small to move t: a + h == a.
    assert!(matches!(
        Grid::new(1e20, 1e20 + 1e5, 1_000_000),
        Err(Error::InvalidGrid { .. })
    ));
}

#[test]
fn alpha_out_of_range() {
    for alpha in [0.0, -0.1, 1.0001, f64::NAN, f64::INFINITY] {
        assert_eq!(
            Embedding::grunwald_letnikov(Side::Backward, alpha)
                .map(|_| ())
                .unwrap_err()
                .to_string(),
            Error::AlphaOutOfRange { alpha }.to_string()
        );
    }
}

#[test]
fn wrong_length_dimension_and_non_finite_input() {
    let grid = Grid::new(0.0, 1.0, 4).unwrap();
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let problem = varembed_tests::problem(
        &pendulum,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    let short = vec![v1(0.0); 4];
    assert_eq!(
        problem.residual(Scheme::Direct, &short),
        Err(Error::WrongLength {
            what: "discrete curve Q",
            expected: 5,
            found: 4
        })
    );
    assert!(matches!(
        problem.action(&short),
        Err(Error::WrongLength { .. })
    ));
    assert!(matches!(
        problem.solve_bvp_from(Scheme::Direct, &short),
        Err(Error::WrongLength { .. })
    ));
    let mut bad = vec![v1(0.0); 5];
    bad[3] = v1(f64::NAN);
    assert!(matches!(
        problem.residual(Scheme::Variational, &bad),
        Err(Error::NonFiniteInput { .. })
    ));
    assert!(matches!(
        problem.solve_ivp(Scheme::Direct, f64::INFINITY, 0.0),
        Err(Error::NonFiniteInput { .. })
    ));
    assert!(matches!(
        problem.solve_ivp(Scheme::Direct, 0.0, f64::NAN),
        Err(Error::NonFiniteInput { .. })
    ));
    assert!(matches!(
        problem.solve_bvp(Scheme::Direct, 0.0, f64::NAN),
        Err(Error::NonFiniteInput { .. })
    ));
    assert_eq!(
        curve_from_flat::<3>(&[1.0; 7]),
        Err(Error::WrongDimension {
            what: "flat curve",
            dimension: 3,
            found: 7
        })
    );
    let op = DifferentialOperator::<1>::new().linear(2, 1.0);
    assert!(matches!(
        op.embed(Side::Backward, grid).solve_ivp(&[v1(0.0)]),
        Err(Error::WrongLength { .. })
    ));
}

#[test]
fn fractional_initial_value_problems_are_unsupported() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let problem = varembed_tests::problem(
        &pendulum,
        grid,
        Embedding::grunwald_letnikov(Side::Forward, 0.5).unwrap(),
    );
    let err = problem
        .solve_ivp(Scheme::Variational, 0.1, 0.0)
        .unwrap_err();
    assert!(matches!(err, Error::Unsupported { .. }));
    assert_eq!(
        err.to_string(),
        "an initial value problem is not available for Gauss-GLE+ (α = 0.5)"
    );
}

/// `L = x`: no velocity at all, so `∂²L/∂v² ≡ 0` (and every step Jacobian vanishes).
struct Degenerate;
impl Lagrangian<1> for Degenerate {
    fn value(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> f64 {
        x[0]
    }
    fn gradient(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (v1(1.0), v1(0.0))
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::zeros(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::zeros(),
        }
    }
}

#[test]
fn degenerate_lagrangians_are_located_before_any_step() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    // L_vv ≡ 0: the one direction of its null space is v₀ itself.
    let degenerate = |at| Error::DegenerateLagrangian {
        at,
        measure: 0.0,
        directions: vec![vec![(0, 1.0)]],
    };
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&Degenerate, grid, Embedding::finite_difference(side));
        // At the initial data, before the start.
        assert_eq!(
            problem
                .solve_ivp(Scheme::Variational, 0.0, 1.0)
                .unwrap_err(),
            degenerate(Location::Step(0))
        );
        // From two given nodes: at Q_1, before step 2.
        assert_eq!(
            problem
                .solve_ivp_from_nodes(Scheme::Direct, 0.0, 0.1)
                .unwrap_err(),
            degenerate(Location::Step(1))
        );
        // At the first quadrature node of the straight-line guess (I_− starts at 1, I_+ at 0).
        let first = match side {
            Side::Backward => 1,
            Side::Forward => 0,
        };
        assert_eq!(
            problem
                .solve_bvp(Scheme::Variational, 0.0, 1.0)
                .unwrap_err(),
            degenerate(Location::Node(first))
        );
    }
}

/// `L = ½v² + ½x²`: regular (`L_vv = 1`), but the implicit direct σ = − step has the Jacobian
/// `L_vv/h − h L_xx = 1/h − h`, singular at `h = 1`.
#[test]
fn a_singular_step_of_a_regular_lagrangian_is_a_singular_jacobian() {
    let grid = Grid::new(0.0, 10.0, 10).unwrap();
    let problem = varembed_tests::problem(
        &Inverted,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    assert_eq!(
        problem.solve_ivp(Scheme::Direct, 1.0, 0.0).unwrap_err(),
        Error::SingularJacobian {
            at: Location::Step(2)
        }
    );
    // At h = 0.5 the same step is regular (1/h − h = 1.5) and the run returns.
    let fine = varembed_tests::problem(
        &Inverted,
        Grid::new(0.0, 5.0, 10).unwrap(),
        Embedding::finite_difference(Side::Backward),
    );
    assert!(fine.solve_ivp(Scheme::Direct, 1.0, 0.0).is_ok());
}

#[test]
fn newton_failure_reports_step_and_residual() {
    // A pendulum with a step far too large for the implicit direct scheme to converge in 2
    // iterations.
    let grid = Grid::new(0.0, 50.0, 50).unwrap();
    let pendulum = Pendulum { g: 9.81, l: 1.0 };
    let problem = varembed_tests::problem(
        &pendulum,
        grid,
        Embedding::finite_difference(Side::Backward),
    )
    .with_newton(NewtonOptions {
        tolerance: 1e-12,
        max_iterations: 2,
    });
    match problem.solve_ivp(Scheme::Direct, 2.5, 0.0) {
        Err(Error::NewtonDidNotConverge {
            at: Location::Step(n),
            iterations: 2,
            residual,
        }) => {
            assert!(
                n >= 1 && residual > 0.0 && residual.is_finite(),
                "step {n}, residual {residual}"
            );
        }
        other => panic!("expected a Newton failure, got {other:?}"),
    }
    let bvp = problem.solve_bvp(Scheme::Variational, 0.0, 3.0);
    assert!(
        matches!(
            bvp,
            Err(Error::NewtonDidNotConverge {
                at: Location::Newton(2),
                ..
            })
        ),
        "{bvp:?}"
    );
}

#[test]
fn unstable_explicit_scheme_is_reported_not_returned() {
    // Störmer–Verlet is stable for ωh < 2. At ωh = 2.01 its step map has the real eigenvalue
    // λ = −c − √(c² − 1), c = (ωh)²/2 − 1: reported at the first check (step 2), even on a run
    // far too short to overflow.
    let omega = 1.0;
    let c: f64 = 2.01f64.powi(2) / 2.0 - 1.0;
    let expected = -c - (c * c - 1.0).sqrt();
    let oscillator = Oscillator { omega };
    for n in [10, 5000] {
        let grid = Grid::new(0.0, 2.01 * n as f64, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let problem =
                varembed_tests::problem(&oscillator, grid, Embedding::finite_difference(side));
            match problem.solve_ivp(Scheme::Variational, 1.0, 0.0) {
                Err(
                    error @ Error::Unstable {
                        at: Location::Step(2),
                        re,
                        im,
                        largest_stable_step,
                    },
                ) => {
                    assert!(
                        (re - expected).abs() < 1e-6 && im == 0.0,
                        "λ = {re} + {im}i, expected {expected}"
                    );
                    // The remedy: Störmer–Verlet's exact limit h = 2/ω, named in the message.
                    let h = largest_stable_step.expect("a measured limit");
                    assert!((h - 2.0 / omega).abs() < 1e-8 * h, "{h}");
                    let text = error.to_string();
                    assert!(text.contains("use a step h ≤ 2.000e0"), "{text}");
                    assert!(text.contains("midpoint variational integrator"), "{text}");
                }
                other => panic!("expected Unstable, got {other:?}"),
            }
        }
    }
}

/// `L = ½v² + ½x²`: the inverted oscillator, `q = cosh t`, a *physical* instability.
struct Inverted;
impl Lagrangian<1> for Inverted {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * (v[0] * v[0] + x[0] * x[0])
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (*x, *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::identity(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

#[test]
fn physical_growth_is_not_flagged_but_overflow_is_reported() {
    // Eigenvalues ≈ e^{±h}, positive: no Unstable. cosh(t) overflows f64 near t = 710.
    let grid = Grid::new(0.0, 1000.0, 100_000).unwrap();
    let problem =
        varembed_tests::problem(&Inverted, grid, Embedding::finite_difference(Side::Forward));
    match problem.solve_ivp(Scheme::Variational, 1.0, 0.0) {
        Err(Error::NotFinite {
            at: Location::Step(n),
        }) => {
            let t = grid.t(n);
            assert!((700.0..720.0).contains(&t), "overflow at t = {t}");
        }
        other => panic!("expected NotFinite, got {other:?}"),
    }
    // On a short interval the same run is a normal, accurate solution.
    let short = varembed_tests::problem(
        &Inverted,
        Grid::new(0.0, 5.0, 5000).unwrap(),
        Embedding::finite_difference(Side::Forward),
    );
    let run = short.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
    assert!((run.last()[0] - 5f64.cosh()).abs() < 1e-2 * 5f64.cosh());
}

/// Kepler `L = ½|v|² + 1/|x|`, singular at the origin.
struct Kepler;
impl Lagrangian<2> for Kepler {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> f64 {
        0.5 * v.norm_squared() + 1.0 / x.norm()
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, _t: f64) -> (Vector<2>, Vector<2>) {
        (-x / x.norm().powi(3), *v)
    }
    fn hessian(&self, x: &Vector<2>, _v: &Vector<2>, _t: f64) -> Hessian<2> {
        let r = x.norm();
        Hessian {
            xx: (x * x.transpose() * 3.0 / r.powi(2) - Matrix::<2>::identity()) / r.powi(3),
            xv: Matrix::<2>::zeros(),
            vv: Matrix::<2>::identity(),
        }
    }
}

#[test]
fn lagrangian_blowing_up_is_located_at_its_node() {
    let grid = Grid::new(0.0, 1.0, 4).unwrap();
    let problem =
        varembed_tests::problem(&Kepler, grid, Embedding::finite_difference(Side::Backward));
    let mut q = vec![Vector::<2>::new(1.0, 0.0); 5];
    q[3] = Vector::<2>::zeros();
    assert_eq!(
        problem.residual(Scheme::Direct, &q),
        Err(Error::NotFinite {
            at: Location::Node(3)
        })
    );
    assert_eq!(
        problem.action(&q),
        Err(Error::NotFinite {
            at: Location::Node(3)
        })
    );
}

/// `L = ½(v₀ + v₁)² − ½(x₀² + x₁²)`: only the sum of the velocities has inertia.
#[varembed::lagrangian]
fn shared_inertia(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * (v[0] + v[1]) * (v[0] + v[1]) - 0.5 * (x[0] * x[0] + x[1] * x[1])
}

#[test]
fn a_degenerate_lagrangian_names_the_direction_without_inertia() {
    // ∂²L/∂v² = [[1, 1], [1, 1]]: it vanishes along (1, −1)/√2, and the error says so.
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = varembed_tests::problem(
        &SharedInertia,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    let error = problem
        .solve_ivp(Scheme::Variational, [0.1, 0.2], [0.0, 0.0])
        .unwrap_err();
    let Error::DegenerateLagrangian { directions, .. } = &error else {
        panic!("expected DegenerateLagrangian, got {error}");
    };
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert_eq!(directions.len(), 1, "{directions:?}");
    let [(i, a), (j, b)] = directions[0][..] else {
        panic!("{directions:?}");
    };
    assert_eq!((i, j), (0, 1));
    assert!((a - s).abs() < 1e-12 && (b + s).abs() < 1e-12, "{a}, {b}");
    assert!(
        error
            .to_string()
            .contains("vanishes along (v₀ 0.707, v₁ -0.707)"),
        "{error}"
    );
}
