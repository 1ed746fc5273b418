//! Hard cases (issue 6): degenerate Lagrangians, Newton failure, bad input, and randomized
//! input that must never panic.

use varembed::{Embedding, Error, Grid, Location, Problem, Scheme, Side, Vector, lagrangian};

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
fn degenerate_lagrangian_is_a_singular_jacobian_with_step_index() {
    let grid = Grid::new(0.0, 1.0, 100).unwrap();
    let (q0, v0) = (Vector::<2>::new(0.3, 0.0), Vector::<2>::new(0.1, 0.0));
    for side in [Side::Backward, Side::Forward] {
        let problem = Problem::new(&Constrained, grid, Embedding::finite_difference(side));
        for scheme in [Scheme::Direct, Scheme::Variational] {
            // The discrete Legendre start needs L_vv (σ = +: L_vv/h − L_xv) invertible.
            let err = problem.solve_ivp(scheme, q0, v0).unwrap_err();
            assert_eq!(
                err,
                Error::SingularJacobian {
                    at: Location::Step(1)
                },
                "{side:?} {scheme}"
            );
        }
        // From two given nodes the explicit schemes (Jacobian L_vv/h) are singular at step 2.
        let kind_singular = match side {
            Side::Backward => Scheme::Variational, // L_vx + L_vv/h
            Side::Forward => Scheme::Direct,       // L_vv/h
        };
        let err = problem
            .solve_ivp_from_nodes(kind_singular, q0, q0 + v0 * grid.h())
            .unwrap_err();
        assert_eq!(
            err,
            Error::SingularJacobian {
                at: Location::Step(2)
            },
            "{side:?} {kind_singular}"
        );
    }
}

#[test]
fn newton_failure_with_a_step_far_too_large() {
    // k = 100, h = 0.5: one step changes the momentum by h·k·x ≈ 50, so the speed jumps from
    // 0 towards 1 and Newton's first update overshoots |v| = 1, where L is not defined.
    let lag = Relativistic { k: 100.0 };
    let grid = Grid::new(0.0, 50.0, 100).unwrap();
    let problem = Problem::new(&lag, grid, Embedding::finite_difference(Side::Backward));
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
    let fine = Problem::new(
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
