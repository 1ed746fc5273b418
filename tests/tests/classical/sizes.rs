//! Problems too large for the machine or the solver are typed errors before any work, and
//! Newton's acceptance does not take a residual that is large against the equation.

use varembed::{DynProblem, Embedding, Error, FractionalSolver, Grid, Scheme, Side, lagrangian};
use varembed_tests::models::chain::FputChain;
use varembed_tests::models::generated::UnitPendulum;

#[test]
fn a_grid_too_fine_to_index_or_resolve_is_invalid() {
    for n in [usize::MAX, Grid::MAX_STEPS + 1] {
        assert!(
            matches!(Grid::new(0.0, 1.0, n), Err(Error::InvalidGrid { .. })),
            "N = {n}"
        );
    }
    // h = 1e-17 (N = 10¹⁷ < MAX_STEPS) moves 0 but not 1: the nodes near b would coincide.
    let n = 100_000_000_000_000_000;
    assert!(n < Grid::MAX_STEPS);
    let error = Grid::new(0.0, 1.0, n).unwrap_err();
    assert!(
        error.to_string().contains("too small to resolve"),
        "{error}"
    );
}

#[test]
fn nodes_that_cannot_fit_in_memory_are_a_typed_error_before_any_step() {
    // 10¹² steps: 8 TB of nodes for a scalar model, more than any machine this runs on.
    let grid = Grid::new(0.0, 1e6, 1_000_000_000_000).unwrap();
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::midpoint(),
        Embedding::gauss_legendre(2).unwrap(),
    ] {
        let problem = varembed_tests::problem(&UnitPendulum, grid, embedding);
        let ivp = problem.solve_ivp(Scheme::Variational, 0.1, 0.0);
        assert!(
            matches!(&ivp, Err(Error::TooLarge { .. })),
            "{embedding}: {ivp:?}"
        );
        if !matches!(
            embedding.kind(),
            varembed::EmbeddingKind::GaussLegendre { .. }
        ) {
            let bvp = problem.solve_bvp(Scheme::Variational, 0.0, 0.1);
            assert!(
                matches!(&bvp, Err(Error::TooLarge { .. })),
                "{embedding}: {bvp:?}"
            );
        }
    }
    let chain = FputChain {
        n: 4,
        alpha: 0.0,
        beta: 0.0,
        periodic: false,
    };
    let dynamic = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Forward));
    let run = dynamic.solve_ivp(Scheme::Variational, &[0.1; 4], &[0.0; 4]);
    assert!(matches!(&run, Err(Error::TooLarge { .. })), "{run:?}");
    let bvp = dynamic.solve_bvp(Scheme::Variational, &[0.0; 4], &[0.1; 4]);
    assert!(
        matches!(&bvp, Err(Error::TooLarge { what }) if what.contains("smaller N")),
        "{bvp:?}"
    );
}

#[test]
fn a_dense_fractional_solve_of_hours_is_refused_up_front() {
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.6).unwrap();
    let n = FractionalSolver::DENSE_MAX + 2;
    let problem = varembed_tests::problem(&UnitPendulum, Grid::new(0.0, 1.0, n).unwrap(), gle)
        .with_fractional_solver(FractionalSolver::Dense);
    let error = problem
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap_err();
    assert!(
        matches!(&error, Error::TooLarge { what } if what.contains("FractionalSolver::Fast")),
        "{error}"
    );
}

/// `L = ½v² + 1/|x|`: a repulsive singularity at `x = 0`, which the straight line from 1 to −1
/// crosses.
#[lagrangian]
fn repelled(x: f64, v: f64) -> f64 {
    0.5 * v * v + 1.0 / x.abs()
}

#[test]
fn newton_does_not_accept_a_residual_that_is_large_against_its_rows() {
    // The midpoint direct solve from the straight line through the singularity: whatever it
    // returns, an Ok must solve its rows to the tolerance of each row's own terms.
    let grid = Grid::new(0.0, 3.0, 11).unwrap();
    let problem = varembed_tests::problem(&Repelled, grid, Embedding::midpoint());
    match problem.solve_bvp(Scheme::Direct, 1.0, -1.0) {
        Ok(solution) => {
            let residual = problem.residual(Scheme::Direct, &solution.q).unwrap();
            let worst = residual.iter().map(|r| r[0].abs()).fold(0.0, f64::max);
            assert!(
                worst < 1e-6,
                "Ok with a residual of {worst:e}: {:?}",
                solution.q
            );
        }
        Err(error) => assert!(
            matches!(
                error,
                Error::NewtonDidNotConverge { .. }
                    | Error::NotFinite { .. }
                    | Error::OutsideDomain { .. }
                    | Error::SingularJacobian { .. }
            ),
            "{error}"
        ),
    }
}
