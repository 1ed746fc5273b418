//! Hard cases: degenerate Lagrangians, Newton failure, bad input, and randomized
//! input that must never panic.

use varembed::{Embedding, Error, Grid, Location, Scheme, Side, Vector, lagrangian};
use varembed_tests::models::generated::Pendulum;
use varembed_tests::rng::Rng;

/// `x₁` has no velocity term: `∂²L/∂v² = diag(1, 0)`, singular (a constraint coordinate).
#[lagrangian]
fn constrained(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * v[0] * v[0] + x[0].cos() - x[1] * x[1]
}

/// Relativistic oscillator: `L = −√(1 − v²) − ½k x²`, speeds below 1.
#[lagrangian]
fn relativistic(x: f64, v: f64, k: f64) -> f64 {
    -(1.0 - v * v).sqrt() - 0.5 * k * x * x
}

#[test]
fn degenerate_lagrangian_is_reported_at_the_initial_data() {
    let grid = Grid::new(0.0, 1.0, 100).unwrap();
    let (q0, v0) = (Vector::<2>::new(0.3, 0.0), Vector::<2>::new(0.1, 0.0));
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&Constrained, grid, Embedding::finite_difference(side));
        for scheme in [Scheme::Direct, Scheme::Variational] {
            // L_vv = diag(1, 0): pivots 1 and 0, the ratio 0, before the start is attempted;
            // the degenerate direction is v₁.
            let err = problem.solve_ivp(scheme, q0, v0).unwrap_err();
            assert_eq!(
                err,
                Error::DegenerateLagrangian {
                    at: Location::Step(0),
                    measure: 0.0,
                    directions: vec![vec![(1, 1.0)]],
                },
                "{side:?} {scheme}"
            );
            // From two given nodes: at Q_1, before the first step.
            let err = problem
                .solve_ivp_from_nodes(scheme, q0, q0 + v0 * grid.h())
                .unwrap_err();
            assert_eq!(
                err,
                Error::DegenerateLagrangian {
                    at: Location::Step(1),
                    measure: 0.0,
                    directions: vec![vec![(1, 1.0)]],
                },
                "{side:?} {scheme}"
            );
        }
    }
}

#[test]
fn newton_failure_with_a_step_far_too_large() {
    // k = 100, h = 0.5: one step changes the momentum by h·k·x ≈ 50, so the speed jumps from
    // 0 towards 1 and Newton's first update overshoots |v| = 1, where L is not defined.
    let lag = Relativistic { k: 100.0 };
    let grid = Grid::new(0.0, 50.0, 100).unwrap();
    let problem = varembed_tests::problem(&lag, grid, Embedding::finite_difference(Side::Backward));
    match problem.solve_ivp(Scheme::Variational, 1.0, 0.0) {
        Err(Error::NewtonDidNotConverge {
            at: Location::Step(n),
            iterations,
            residual,
        }) => {
            assert!(
                n >= 1 && iterations >= 1 && residual.is_finite() && residual > 0.0,
                "{n} {iterations} {residual}"
            );
        }
        other => panic!("expected a located Newton failure, got {other:?}"),
    }
    // The same problem with a resolved step runs, at speeds below 1.
    let fine = varembed_tests::problem(
        &lag,
        Grid::new(0.0, 1.0, 10_000).unwrap(),
        Embedding::finite_difference(Side::Backward),
    );
    let run = fine.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
    let vmax = run
        .q
        .windows(2)
        .map(|w| ((w[1][0] - w[0][0]) / 1e-4).abs())
        .fold(0.0, f64::max);
    assert!(vmax < 1.0 && vmax > 0.9, "max speed {vmax}");
}

#[test]
fn bad_input_is_a_typed_error() {
    for (a, b, n) in [
        (0.0, 1.0, 0),
        (1.0, 1.0, 10),
        (1.0, 0.0, 10),
        (f64::NAN, 1.0, 10),
        (0.0, f64::INFINITY, 10),
    ] {
        assert!(matches!(Grid::new(a, b, n), Err(Error::InvalidGrid { .. })));
    }
    for alpha in [0.0, -1.0, 1.5, f64::NAN] {
        assert!(matches!(
            Embedding::grunwald_letnikov(Side::Forward, alpha),
            Err(Error::AlphaOutOfRange { .. })
        ));
    }
    let lag = Pendulum { g: 9.81, l: 1.0 };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = varembed_tests::problem(&lag, grid, Embedding::finite_difference(Side::Backward));
    for (q0, v0) in [
        (f64::NAN, 0.0),
        (0.0, f64::INFINITY),
        (f64::NEG_INFINITY, 1.0),
    ] {
        assert!(matches!(
            problem.solve_ivp(Scheme::Variational, q0, v0),
            Err(Error::NonFiniteInput { .. })
        ));
        assert!(matches!(
            problem.solve_bvp(Scheme::Direct, q0, v0),
            Err(Error::NonFiniteInput { .. })
        ));
    }
    let wrong = vec![Vector::<1>::zeros(); 12];
    assert!(matches!(
        problem.residual(Scheme::Direct, &wrong),
        Err(Error::WrongLength {
            expected: 11,
            found: 12,
            ..
        })
    ));
    assert!(matches!(
        problem.action(&wrong[..3]),
        Err(Error::WrongLength { .. })
    ));
    assert!(matches!(
        problem.solve_bvp_from(Scheme::Variational, &wrong),
        Err(Error::WrongLength { .. })
    ));
    assert!(matches!(
        varembed::curve_from_flat::<2>(&[1.0; 5]),
        Err(Error::WrongDimension { .. })
    ));
}

fn finite<const D: usize>(q: &[Vector<D>]) -> bool {
    q.iter().all(|x| x.iter().all(|c| c.is_finite()))
}

/// Random grids, α, constants and data: every call returns a finite result or a typed error,
/// and never panics (a panic fails this test).
#[test]
fn randomized_input_never_panics() {
    let mut rng = Rng(2026);
    let (mut solved, mut errors) = (0, 0);
    for case in 0..400 {
        let a = rng.wild();
        let b = if rng.next_f64() < 0.8 {
            a + rng.next_f64() * 5.0
        } else {
            rng.wild()
        };
        let n = [0, 1, 2, 3, 7, 40, 200][(rng.next_f64() * 7.0) as usize];
        let Ok(grid) = Grid::new(a, b, n) else {
            errors += 1;
            continue;
        };
        let side = if rng.next_f64() < 0.5 {
            Side::Backward
        } else {
            Side::Forward
        };
        let embedding = match (rng.next_f64() * 3.0) as u32 {
            0 => Embedding::finite_difference(side),
            1 => Embedding::asymmetric(side),
            _ => match Embedding::grunwald_letnikov(side, rng.wild().abs().min(2.0)) {
                Ok(e) => e,
                Err(Error::AlphaOutOfRange { .. }) => {
                    errors += 1;
                    continue;
                }
                Err(other) => panic!("case {case}: {other:?}"),
            },
        };
        let lag = Pendulum {
            g: rng.wild(),
            l: rng.wild(),
        };
        let problem = varembed_tests::problem(&lag, grid, embedding);
        let scheme = if rng.next_f64() < 0.5 {
            Scheme::Direct
        } else {
            Scheme::Variational
        };
        let (x0, x1) = (rng.wild(), rng.wild());
        let outcomes = [
            problem.solve_ivp(scheme, x0, x1),
            problem.solve_bvp(scheme, x0, x1),
        ];
        for outcome in outcomes {
            match outcome {
                Ok(sol) => {
                    assert!(
                        finite(&sol.q),
                        "case {case}: a returned solution must be finite"
                    );
                    assert_eq!(sol.q.len(), grid.n() + 1);
                    solved += 1;
                }
                Err(e) => {
                    assert!(!e.to_string().is_empty());
                    errors += 1;
                }
            }
        }
        let q: Vec<Vector<1>> = (0..=grid.n())
            .map(|_| Vector::<1>::new(rng.wild()))
            .collect();
        match problem.residual(scheme, &q) {
            Ok(r) => assert!(
                finite(&r),
                "case {case}: residual must be finite or an error"
            ),
            Err(_) => errors += 1,
        }
        if let Ok(s) = problem.action(&q) {
            assert!(s.is_finite(), "case {case}");
        }
    }
    // Both outcomes occur: the generator reaches solvable and unsolvable cases alike.
    assert!(
        solved > 50 && errors > 50,
        "solved {solved}, errors {errors}"
    );
}
