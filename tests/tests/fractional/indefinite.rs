//! Indefinite Jacobians on the fast path: `L = ½v² − ½k x² + c x` with `k` above the lowest
//! eigenvalues of the kinetic part, so that `J = DᵀD − k` has negative eigenvalues (71 of 199
//! at `α = 0.3`, `k = 25`, `N = 200`). GMRES(30) stagnated there at a relative residual of 0.83
//! (`Error::KrylovDidNotConverge` at every `N` from 200 to 4000, both sides); MINRES solves it.

use varembed::{Embedding, FractionalSolver, Grid, Scheme, Side, Solution};
use varembed_tests::curve::max_norm;
use varembed_tests::models::generated::ForcedSpring;
use varembed_tests::rng::Rng;

fn solve(
    model: &ForcedSpring,
    side: Side,
    alpha: f64,
    n: usize,
    scheme: Scheme,
    (qa, qb): (f64, f64),
    solver: FractionalSolver,
) -> Solution<1> {
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let gle = Embedding::grunwald_letnikov(side, alpha).unwrap();
    varembed_tests::problem(model, grid, gle)
        .with_fractional_solver(solver)
        .solve_bvp(scheme, qa, qb)
        .unwrap_or_else(|e| panic!("{solver:?}, {side:?}, α = {alpha}, N = {n}, {scheme}: {e}"))
}

/// The fast solution's distance to the dense one, relative to `max|Q|` of the dense one.
fn gap(fast: &Solution<1>, dense: &Solution<1>) -> f64 {
    fast.max_distance(&dense.q).unwrap() / max_norm(&dense.q)
}

const SPRING: ForcedSpring = ForcedSpring { k: 25.0, c: 1.0 };

/// `α = 0.3`, `Q_0 = 0`, `Q_N = 1`, both sides, at `N = 200` (both schemes) and `1000`: the fast
/// path matches the dense one to 1e-9 of `max|Q|`, and at `N = 200` the midpoint matches an
/// independent solve of the same linear system (numpy, `np.linalg.solve` on the assembled
/// `DᵀD − 25`: `Q(1/2)` = 0.9302748160218386 for σ = −, 0.10807000388460547 for σ = +).
#[test]
fn the_indefinite_spring_is_solved_on_the_fast_path() {
    for n in [200, 1000] {
        for side in [Side::Backward, Side::Forward] {
            // Coherent: both schemes are the same equations; the direct one at N = 200 only.
            let schemes = if n == 200 {
                vec![Scheme::Variational, Scheme::Direct]
            } else {
                vec![Scheme::Variational]
            };
            for scheme in schemes {
                let run = |solver| solve(&SPRING, side, 0.3, n, scheme, (0.0, 1.0), solver);
                let (fast, dense) = (run(FractionalSolver::Fast), run(FractionalSolver::Dense));
                let gap = gap(&fast, &dense);
                assert!(gap <= 1e-9, "{side:?}, N = {n}, {scheme}: gap {gap:e}");
                if n == 200 {
                    let expected = match side {
                        Side::Backward => 0.9302748160218386,
                        Side::Forward => 0.10807000388460547,
                    };
                    let size = max_norm(&dense.q);
                    let error = (fast.q[n / 2][0] - expected).abs() / size;
                    assert!(error <= 1e-9, "{side:?}, {scheme}: Q(1/2) off by {error:e}");
                }
            }
        }
    }
}

/// `N = 4000`: solved on the fast path, its residual (by `Problem::residual`, on the FFT route
/// the solver shares nothing of beyond the operators) within the stopping rule.
#[test]
fn the_indefinite_spring_at_n_4000() {
    let n = 4000;
    for side in [Side::Backward, Side::Forward] {
        let fast = solve(
            &SPRING,
            side,
            0.3,
            n,
            Scheme::Variational,
            (0.0, 1.0),
            FractionalSolver::Fast,
        );
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let gle = Embedding::grunwald_letnikov(side, 0.3).unwrap();
        let problem = varembed_tests::problem(&SPRING, grid, gle);
        let r = max_norm(&problem.residual(Scheme::Variational, &fast.q).unwrap());
        // The rows balance 25|Q| + 1 against h^{−α} |p|, both about 10² here.
        assert!(r <= 1e-9, "{side:?}: residual {r:e}");
    }
}

/// Generated indefinite cases against the dense solve: α drawn in `(0, 1/2]` and in
/// `(1/2, 1)`, `k` between 15 and 150 (above the lowest kinetic eigenvalue, about 1.3 at
/// `α = 0.3` and 10 at `α = 1`), random force, end values, side and scheme, `N` 200 to 400.
#[test]
fn generated_indefinite_cases_match_the_dense_solve() {
    let mut rng = Rng(0x1def_1417e);
    for case in 0..16 {
        let alpha = if case % 2 == 0 {
            rng.uniform(0.05, 0.5)
        } else {
            rng.uniform(0.5, 1.0)
        };
        let model = ForcedSpring {
            k: rng.uniform(15.0, 150.0),
            c: rng.uniform(-3.0, 3.0),
        };
        let side = [Side::Backward, Side::Forward][rng.below(2)];
        let scheme = [Scheme::Variational, Scheme::Direct][rng.below(2)];
        let ends = (rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
        let n = 200 + rng.below(201);
        let run = |solver| solve(&model, side, alpha, n, scheme, ends, solver);
        let gap = gap(&run(FractionalSolver::Fast), &run(FractionalSolver::Dense));
        assert!(
            gap <= 1e-9,
            "case {case}: k = {}, α = {alpha}, {side:?}, N = {n}: gap {gap:e}",
            model.k
        );
    }
}
