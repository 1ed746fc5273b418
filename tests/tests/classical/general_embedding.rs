//! The direct embedding of `q̈ + q̇ + q = 0` is the paper's formula and converges
//! at order 1 to the exact solution.

use varembed::DifferentialOperator;
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

#[test]
fn direct_embedding_converges_at_order_one() {
    let t_end = 5.0;
    for side in [Side::Backward, Side::Forward] {
        let errors: Vec<f64> = [200, 400, 800, 1600]
            .iter()
            .map(|&n| {
                let grid = Grid::new(0.0, t_end, n).unwrap();
                let op = friction();
                let q = op
                    .embed(side, grid)
                    .solve_ivp(&[v1(exact(0.0)), v1(exact(grid.h()))])
                    .unwrap();
                (0..=n)
                    .map(|k| (q[k][0] - exact(grid.t(k))).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            assert!(
                (order - 1.0).abs() < 0.1,
                "{side:?}: observed order {order} from {errors:?}"
            );
        }
    }
}
