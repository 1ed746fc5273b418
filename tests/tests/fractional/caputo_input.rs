//! What the Caputo form cannot serve gets a typed error naming it: an order outside `(0, 1]`,
//! an initial value problem (every node couples to every other), node values (the fractional
//! velocity has no value at the end outside `I_σ`), a curve of the wrong length, and a model
//! of run-time dimension (whose solvers are the banded ones of the classical embeddings).

use varembed::{DynProblem, Embedding, Error, Grid, Scheme, Side, Vector, lagrangian};
use varembed_tests::models::chain::FputChain;

#[lagrangian]
fn pendulum(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.cos()
}

#[test]
fn an_order_outside_zero_to_one_is_refused_by_value() {
    for alpha in [0.0, -0.5, 1.0 + 1e-12, 1.5, f64::INFINITY] {
        for side in [Side::Backward, Side::Forward] {
            assert_eq!(
                Embedding::caputo(side, alpha),
                Err(Error::AlphaOutOfRange { alpha })
            );
        }
    }
    match Embedding::caputo(Side::Backward, f64::NAN) {
        Err(Error::AlphaOutOfRange { alpha }) => assert!(alpha.is_nan()),
        other => panic!("{other:?}"),
    }
    let message = Embedding::caputo(Side::Forward, 1.5)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("α = 1.5") && message.contains("(0, 1]"),
        "{message}"
    );
}

#[test]
fn initial_value_problems_and_node_values_are_unsupported_and_name_the_embedding() {
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let caputo = Embedding::caputo(side, 0.7).unwrap();
        let name = caputo.to_string();
        let problem = varembed_tests::problem(&Pendulum, grid, caputo);
        for scheme in [Scheme::Direct, Scheme::Variational] {
            match problem.solve_ivp(scheme, 0.3, 0.0) {
                Err(Error::Unsupported {
                    operation,
                    embedding,
                }) => {
                    assert_eq!(embedding, name);
                    assert!(operation.contains("initial value"), "{operation}");
                }
                other => panic!("{name} {scheme}: {other:?}"),
            }
        }
        for scheme in [Scheme::Direct, Scheme::Variational] {
            assert!(matches!(
                problem.solve_ivp_from_nodes(scheme, 0.3, 0.31),
                Err(Error::Unsupported { embedding, .. }) if embedding == name
            ));
        }
        assert!(matches!(
            problem.compare_ivp(0.3, 0.0),
            Err(Error::Unsupported { embedding, .. }) if embedding == name
        ));
        // No three-point recurrence, so no discrete Legendre start of one either.
        assert!(matches!(
            problem.legendre_start(0.3, 0.0),
            Err(Error::Unsupported { embedding, .. }) if embedding == name
        ));
        let solution = problem.solve_bvp(Scheme::Variational, 0.3, 1.0).unwrap();
        assert!(matches!(
            solution.node_values(&Pendulum),
            Err(Error::Unsupported { embedding, .. }) if embedding == name
        ));
    }
}

#[test]
fn a_curve_of_the_wrong_length_is_refused_with_both_lengths() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = varembed_tests::problem(
        &Pendulum,
        grid,
        Embedding::caputo(Side::Forward, 0.6).unwrap(),
    );
    let short = vec![Vector::<1>::new(0.2); 10];
    for scheme in [Scheme::Direct, Scheme::Variational] {
        assert!(matches!(
            problem.residual(scheme, &short),
            Err(Error::WrongLength {
                expected: 11,
                found: 10,
                ..
            })
        ));
        assert!(matches!(
            problem.solve_bvp_from(scheme, &short),
            Err(Error::WrongLength {
                expected: 11,
                found: 10,
                ..
            })
        ));
    }
    assert!(matches!(
        problem.action(&short),
        Err(Error::WrongLength {
            expected: 11,
            found: 10,
            ..
        })
    ));
}

/// A model of run-time dimension, with end values of its dimension or not: the Caputo form
/// is refused before the data are read, by name.
#[test]
fn a_run_time_dimension_model_is_unsupported_whatever_its_data() {
    let chain = FputChain {
        n: 4,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let grid = Grid::new(0.0, 1.0, 16).unwrap();
    let caputo = Embedding::caputo(Side::Backward, 0.8).unwrap();
    let problem = DynProblem::new(&chain, grid, caputo);
    for (qa, qb) in [(vec![0.1; 4], vec![0.0; 4]), (vec![0.1; 3], vec![0.0; 5])] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            match problem.solve_bvp(scheme, &qa, &qb) {
                Err(Error::Unsupported { embedding, .. }) => {
                    assert_eq!(embedding, "Caputo Gauss-GLE− (α = 0.8)")
                }
                other => panic!("{other:?}"),
            }
        }
    }
}
