//! At α = 1 the Gauss-GLE± residual and boundary value solution equal the
//! classical variational ones to 1e-12.

use varembed::{Embedding, Grid, Scheme, Side};
use varembed_tests::curve::{max_diff, max_norm};
use varembed_tests::models::hand::{Coupled, Pendulum};
use varembed_tests::rng::Rng;

#[test]
fn alpha_one_residual_is_the_classical_variational_residual() {
    let grid = Grid::new(0.0, 1.5, 25).unwrap();
    let mut rng = Rng(17);
    for side in [Side::Backward, Side::Forward] {
        let classical = varembed_tests::problem(&Coupled, grid, Embedding::finite_difference(side));
        let gle = varembed_tests::problem(
            &Coupled,
            grid,
            Embedding::grunwald_letnikov(side, 1.0).unwrap(),
        );
        let q = rng.curve::<2>(grid.n(), 1.0);
        let reference = classical.residual(Scheme::Variational, &q).unwrap();
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let r = gle.residual(scheme, &q).unwrap();
            assert!(
                max_diff(&r, &reference) <= 1e-12 * max_norm(&reference),
                "{side:?} {scheme}"
            );
        }
    }
}

#[test]
fn alpha_one_bvp_is_the_classical_variational_bvp() {
    let grid = Grid::new(0.0, 2.0, 60).unwrap();
    let pendulum = Pendulum { g: 9.81, l: 1.0 };
    for side in [Side::Backward, Side::Forward] {
        let classical =
            varembed_tests::problem(&pendulum, grid, Embedding::finite_difference(side))
                .solve_bvp(Scheme::Variational, 0.3, -0.4)
                .unwrap();
        let gle = varembed_tests::problem(
            &pendulum,
            grid,
            Embedding::grunwald_letnikov(side, 1.0).unwrap(),
        );
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let sol = gle.solve_bvp(scheme, 0.3, -0.4).unwrap();
            let gap = max_diff(&sol.q, &classical.q);
            assert!(gap < 1e-12, "{side:?} {scheme}: {gap:e}");
        }
    }
}
