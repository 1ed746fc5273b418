//! The direct embedding of `q̈ + q̇ + q = 0` is the paper's formula and converges at order 1 to
//! the exact solution, from exact start nodes and from the initial derivatives (the Taylor
//! start); so does a third-order operator; a wrong number of initial derivatives is a typed
//! error naming the expected count; an embedding is shared by threads.

use varembed::{DifferentialOperator, Ensemble, Error, Vector};
use varembed::{Grid, Side};
use varembed_tests::curve::v1;
use varembed_tests::rng::Rng;

/// Exact solution with `q(0) = 1`, `q̇(0) = 0`: `e^{−t/2}(cos ωt + sin(ωt)/(2ω))`, `ω = √3/2`.
fn exact(t: f64) -> f64 {
    let w = 3f64.sqrt() / 2.0;
    (-t / 2.0).exp() * ((w * t).cos() + (w * t).sin() / (2.0 * w))
}

fn friction() -> DifferentialOperator<'static, 1> {
    DifferentialOperator::new()
        .linear(2, 1.0)
        .linear(1, 1.0)
        .linear(0, 1.0)
}

#[test]
fn residual_is_the_papers_formula() {
    let grid = Grid::new(0.0, 2.0, 16).unwrap();
    let h = grid.h();
    let q = Rng(9).curve::<1>(16, 1.0);
    let op = friction();
    let backward = op.embed(Side::Backward, grid);
    assert_eq!(backward.rows(), 2..=16);
    for (i, k) in backward.rows().enumerate() {
        let expected = (q[k][0] - 2.0 * q[k - 1][0] + q[k - 2][0]) / (h * h)
            + (q[k][0] - q[k - 1][0]) / h
            + q[k][0];
        let got = backward.residual(&q).unwrap()[i][0];
        assert!(
            (got - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "row {k}"
        );
    }
    let forward = op.embed(Side::Forward, grid);
    assert_eq!(forward.rows(), 0..=14);
    for (i, k) in forward.rows().enumerate() {
        let expected = (q[k + 2][0] - 2.0 * q[k + 1][0] + q[k][0]) / (h * h)
            + (q[k + 1][0] - q[k][0]) / h
            + q[k][0];
        let got = forward.residual(&q).unwrap()[i][0];
        assert!(
            (got - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "row {k}"
        );
    }
}

#[test]
fn nonlinear_terms_are_embedded_as_written() {
    // d/dt ∘ sin versus cos(·) d/dt: equal operators, different embeddings (paper §1.2).
    let grid = Grid::new(0.0, 1.0, 8).unwrap();
    let h = grid.h();
    let q = Rng(4).curve::<1>(8, 1.0);
    let composed = DifferentialOperator::<1>::new().term(1, |_, _| 1.0, |x, _| v1(x[0].sin()));
    let chain = DifferentialOperator::<1>::new().term(1, |x, _| x[0].cos(), |x, _| *x);
    let a = composed.embed(Side::Backward, grid).residual(&q).unwrap();
    let b = chain.embed(Side::Backward, grid).residual(&q).unwrap();
    for (i, k) in (1..=8).enumerate() {
        assert!((a[i][0] - (q[k][0].sin() - q[k - 1][0].sin()) / h).abs() < 1e-12);
        assert!((b[i][0] - q[k][0].cos() * (q[k][0] - q[k - 1][0]) / h).abs() < 1e-12);
    }
    assert!((a[0][0] - b[0][0]).abs() > 1e-6);
}

/// `q⃛ + q̈ + q̇ + q = (d/dt + 1)(d²/dt² + 1) q = 0` from `q(0) = 2`, `q̇(0) = −1`, `q̈(0) = 0`:
/// `q = cos t + e^{−t}`.
fn third_order() -> DifferentialOperator<'static, 1> {
    DifferentialOperator::new()
        .linear(3, 1.0)
        .linear(2, 1.0)
        .linear(1, 1.0)
        .linear(0, 1.0)
}

fn exact_third(t: f64) -> f64 {
    t.cos() + (-t).exp()
}

/// The max error over the nodes of `solve(side, grid)` against `exact` on `[0, 5]`, at
/// `N = 200, 400, 800, 1600`, and the observed orders between successive sizes.
fn orders(
    side: Side,
    exact: fn(f64) -> f64,
    solve: impl Fn(Side, Grid) -> Vec<Vector<1>>,
) -> (Vec<f64>, Vec<f64>) {
    let errors: Vec<f64> = [200, 400, 800, 1600]
        .iter()
        .map(|&n| {
            let grid = Grid::new(0.0, 5.0, n).unwrap();
            let q = solve(side, grid);
            (0..=n)
                .map(|k| (q[k][0] - exact(grid.t(k))).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    let orders = errors.windows(2).map(|p| (p[0] / p[1]).log2()).collect();
    (errors, orders)
}

fn assert_first_order(what: &str, side: Side, (errors, orders): (Vec<f64>, Vec<f64>)) {
    for order in &orders {
        assert!(
            (order - 1.0).abs() < 0.1,
            "{what}, {side:?}: observed orders {orders:?} from {errors:?}"
        );
    }
}

#[test]
fn direct_embedding_converges_at_order_one_from_exact_start_nodes() {
    for side in [Side::Backward, Side::Forward] {
        let run = orders(side, exact, |side, grid| {
            let op = friction();
            let start = [v1(exact(0.0)), v1(exact(grid.h()))];
            op.embed(side, grid).solve_ivp_from_nodes(&start).unwrap()
        });
        assert_first_order("q̈ + q̇ + q, exact Q_0, Q_1", side, run);
    }
}

#[test]
fn direct_embedding_converges_at_order_one_from_the_initial_derivatives() {
    for side in [Side::Backward, Side::Forward] {
        let run = orders(side, exact, |side, grid| {
            let op = friction();
            op.embed(side, grid).solve_ivp(&[v1(1.0), v1(0.0)]).unwrap()
        });
        assert_first_order("q̈ + q̇ + q from q(0), q̇(0)", side, run);
    }
}

#[test]
fn a_third_order_operator_converges_at_order_one_from_the_initial_derivatives() {
    for side in [Side::Backward, Side::Forward] {
        let run = orders(side, exact_third, |side, grid| {
            let op = third_order();
            let derivatives = [v1(2.0), v1(-1.0), v1(0.0)];
            op.embed(side, grid).solve_ivp(&derivatives).unwrap()
        });
        assert_first_order("q⃛ + q̈ + q̇ + q from q(0), q̇(0), q̈(0)", side, run);
    }
}

#[test]
fn the_start_nodes_are_the_taylor_polynomial_of_the_derivatives() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let h = grid.h();
    let (q0, v0, a0) = (0.5, -2.0, 3.0);
    for side in [Side::Backward, Side::Forward] {
        let q = third_order()
            .embed(side, grid)
            .solve_ivp(&[v1(q0), v1(v0), v1(a0)])
            .unwrap();
        for j in 0..3 {
            let t = j as f64 * h;
            let taylor = q0 + t * v0 + 0.5 * t * t * a0;
            assert!((q[j][0] - taylor).abs() < 1e-15, "{side:?}, Q_{j}");
        }
        assert_eq!(q[0][0], q0);
    }
    // The same nodes handed over as start nodes give the same run, bit for bit.
    let scheme = friction();
    let scheme = scheme.embed(Side::Backward, grid);
    let from_derivatives = scheme.solve_ivp(&[v1(q0), v1(v0)]).unwrap();
    let from_nodes = scheme.solve_ivp_from_nodes(&from_derivatives[..2]).unwrap();
    assert_eq!(from_derivatives, from_nodes);
}

#[test]
fn a_wrong_number_of_derivatives_is_an_error_naming_the_order() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let op = third_order();
    let scheme = op.embed(Side::Backward, grid);
    for found in [0, 1, 2, 4] {
        let derivatives = vec![v1(1.0); found];
        let err = scheme.solve_ivp(&derivatives).unwrap_err();
        assert!(
            matches!(err, Error::WrongLength { expected: 3, found: f, .. } if f == found),
            "{err}"
        );
        assert!(err.to_string().contains("expected 3"), "{err}");
    }
    let err = scheme
        .solve_ivp(&[v1(1.0), v1(f64::NAN), v1(0.0)])
        .unwrap_err();
    assert!(matches!(err, Error::NonFiniteInput { .. }), "{err}");
    // Order 0: an algebraic equation, no derivative.
    let algebraic = DifferentialOperator::<1>::new().term(0, |_, _| 1.0, |q, _| q.map(|x| x - 2.0));
    let q = algebraic
        .embed(Side::Backward, grid)
        .solve_ivp(&[])
        .unwrap();
    assert!(q.iter().all(|x| (x[0] - 2.0).abs() < 1e-12));
}

#[test]
fn an_embedding_is_shared_by_the_threads_of_an_ensemble() {
    fn shared<T: Send + Sync>(_: &T) {}
    let op = friction();
    let grid = Grid::new(0.0, 5.0, 400).unwrap();
    let scheme = op.embed(Side::Backward, grid);
    shared(&op);
    shared(&scheme);
    let starts: Vec<[Vector<1>; 2]> = (0..8).map(|i| [v1(1.0), v1(0.1 * i as f64)]).collect();
    let parallel = Ensemble::new().map(&starts, |d| scheme.solve_ivp(d).unwrap());
    let serial = Ensemble::serial().map(&starts, |d| scheme.solve_ivp(d).unwrap());
    assert_eq!(parallel, serial);
    assert_eq!(parallel[3], scheme.solve_ivp(&starts[3]).unwrap());
}
