//! For `L = ½v² − U(x)` the variational scheme is Störmer–Verlet for both σ, and the direct
//! schemes are the textbook two-step formulas (implicit for σ = −, explicit for σ = +; see
//! `core/docs/schemes.md`).

use varembed::{Embedding, Grid, Scheme, Side, Vector};
use varembed_tests::models::hand::Anharmonic;
use varembed_tests::rng::Rng;

fn second_difference(q: &[Vector<1>], k: usize, h: f64) -> f64 {
    (q[k + 1][0] - 2.0 * q[k][0] + q[k - 1][0]) / (h * h)
}

#[test]
fn residuals_are_the_textbook_formulas() {
    let grid = Grid::new(0.0, 3.0, 30).unwrap();
    let h = grid.h();
    let mut rng = Rng(11);
    let q = rng.curve::<1>(grid.n(), 1.5);
    let force = |k: usize| Anharmonic::force(q[k][0]);
    // Row k of every scheme is −(second difference + U'), i.e. second difference − force.
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + b.abs());
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&Anharmonic, grid, Embedding::finite_difference(side));
        let variational = problem.residual(Scheme::Variational, &q).unwrap();
        for (i, k) in problem.residual_rows(Scheme::Variational).enumerate() {
            let verlet = -(second_difference(&q, k, h) - force(k));
            assert!(
                close(variational[i][0], verlet),
                "{side:?} variational row {k}"
            );
        }
        let direct = problem.residual(Scheme::Direct, &q).unwrap();
        for (i, k) in problem.residual_rows(Scheme::Direct).enumerate() {
            let expected = match side {
                // (Q_k − 2Q_{k−1} + Q_{k−2})/h² = −U'(Q_k)
                Side::Backward => -(second_difference(&q, k - 1, h) - force(k)),
                // (Q_{k+2} − 2Q_{k+1} + Q_k)/h² = −U'(Q_k)
                Side::Forward => -(second_difference(&q, k + 1, h) - force(k)),
            };
            assert!(close(direct[i][0], expected), "{side:?} direct row {k}");
        }
    }
}

#[test]
fn variational_runs_follow_the_stormer_verlet_recurrence() {
    let grid = Grid::new(0.0, 20.0, 2000).unwrap();
    let h = grid.h();
    for side in [Side::Backward, Side::Forward] {
        let problem =
            varembed_tests::problem(&Anharmonic, grid, Embedding::finite_difference(side));
        let run = problem.solve_ivp(Scheme::Variational, 1.2, 0.3).unwrap();
        for k in 1..grid.n() {
            let next = 2.0 * run.q[k][0] - run.q[k - 1][0] + h * h * Anharmonic::force(run.q[k][0]);
            assert!(
                (run.q[k + 1][0] - next).abs() <= 1e-13 * (1.0 + next.abs()),
                "{side:?} node {}",
                k + 1
            );
        }
        // The direct σ = − run obeys the implicit recurrence, the σ = + run the explicit one.
        let direct = problem.solve_ivp(Scheme::Direct, 1.2, 0.3).unwrap();
        assert_eq!(
            direct.q[..2],
            run.q[..2],
            "both schemes start from the same Q_0, Q_1"
        );
        for k in 2..=grid.n() {
            let (lhs, rhs) = match side {
                Side::Backward => (
                    second_difference(&direct.q, k - 1, h),
                    Anharmonic::force(direct.q[k][0]),
                ),
                Side::Forward => (
                    second_difference(&direct.q, k - 1, h),
                    Anharmonic::force(direct.q[k - 2][0]),
                ),
            };
            assert!(
                (lhs - rhs).abs() <= 1e-8 * (1.0 + rhs.abs()),
                "{side:?} direct node {k}: {lhs} vs {rhs}"
            );
        }
    }
}
