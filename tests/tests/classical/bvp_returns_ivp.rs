//! The classical boundary value problem, given the endpoints of an initial value
//! run, returns that run (for every classical scheme, both sides).

use varembed::{Embedding, Grid, Scheme, Side, Vector};
use varembed_tests::curve::max_diff;
use varembed_tests::models::hand::{Coupled, Pendulum};

#[test]
fn bvp_through_the_ends_of_an_ivp_run_is_that_run() {
    let grid = Grid::new(0.0, 1.5, 300).unwrap();
    let pendulum = Pendulum { g: 9.81, l: 1.0 };
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::finite_difference(side),
            Embedding::asymmetric(side),
        ] {
            let problem = varembed_tests::problem(&pendulum, grid, embedding);
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let run = problem.solve_ivp(scheme, 0.8, -0.5).unwrap();
                let bvp = problem.solve_bvp(scheme, run.q[0], run.last()).unwrap();
                let gap = max_diff(&bvp.q, &run.q);
                assert!(gap < 1e-10, "{embedding} {scheme}: {gap:e}");
                assert!(
                    bvp.newton_iterations >= 2,
                    "the straight line is not the answer"
                );
            }
        }
    }
}

#[test]
fn bvp_returns_the_run_in_two_dimensions_with_a_time_dependent_lagrangian() {
    let grid = Grid::new(0.0, 1.0, 200).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let problem = varembed_tests::problem(&Coupled, grid, Embedding::finite_difference(side));
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let run = problem
                .solve_ivp(scheme, Vector::<2>::new(0.5, -0.2), [0.3, 0.4])
                .unwrap();
            let bvp = problem.solve_bvp(scheme, run.q[0], run.last()).unwrap();
            let gap = max_diff(&bvp.q, &run.q);
            assert!(gap < 1e-10, "{side:?} {scheme}: {gap:e}");
        }
    }
}
