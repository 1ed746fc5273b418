//! Whole solves of the fast path: its typed errors, its Krylov iteration counts, the
//! evaluations it makes.

use super::*;
use std::cell::Cell;

/// The pendulum `L = ½v² + cos x`, counting the calls of its `hessian`.
#[derive(Default)]
struct Pendulum {
    hessians: Cell<usize>,
}

impl Lagrangian<1> for Pendulum {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * v[0] * v[0] + x[0].cos()
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (Vector::<1>::new(-x[0].sin()), *v)
    }
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        self.hessians.set(self.hessians.get() + 1);
        Hessian {
            xx: Matrix::<1>::new(-x[0].cos()),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// `c (½v² + cos x)`: the pendulum times `c`.
struct ScaledPendulum(f64);

impl Lagrangian<1> for ScaledPendulum {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        self.0 * (0.5 * v[0] * v[0] + x[0].cos())
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (Vector::<1>::new(-self.0 * x[0].sin()), v * self.0)
    }
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-self.0 * x[0].cos()),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::new(self.0),
        }
    }
}

/// A Krylov budget too small for the system is a typed error, never a returned curve.
#[test]
fn an_exhausted_krylov_budget_is_a_typed_error() {
    let n = 200;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let embedding = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let disc = Discretisation::new(&Mixed, grid, embedding);
    let guess: Vec<Vector<2>> = (0..=n)
        .map(|k| Vector::<2>::new(k as f64 / n as f64, 0.0))
        .collect();
    let options = SolverOptions {
        krylov: KrylovBudget {
            minres_iterations: 1,
            gmres_iterations: 1,
            restart: 1,
        },
        ..SolverOptions::default()
    };
    let err = solve(&disc, &options, Scheme::Variational, guess).unwrap_err();
    // The message names the remedies.
    let message = err.to_string();
    assert!(
        message.contains("FractionalSolver::Dense") && message.contains("solve_bvp_from"),
        "{message}"
    );
    assert!(
        matches!(
            err,
            Error::KrylovDidNotConverge {
                at: Location::Newton(0),
                ..
            }
        ),
        "{err:?}"
    );
}

/// `L = ½v² − 72x²`: `J = DᵀD − 144` is indefinite. CG must report the breakdown, and the
/// Newton system is still solved (by MINRES) to the asked tolerance.
#[test]
fn cg_breaks_down_on_an_indefinite_jacobian_and_minres_solves_it() {
    struct Oscillator;
    impl Lagrangian<1> for Oscillator {
        fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
            0.5 * v[0] * v[0] - 72.0 * x[0] * x[0]
        }
        fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
            (Vector::<1>::new(-144.0 * x[0]), *v)
        }
        fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
            Hessian {
                xx: Matrix::<1>::new(-144.0),
                xv: Matrix::<1>::zeros(),
                vv: Matrix::<1>::identity(),
            }
        }
    }
    let n = 300;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::grunwald_letnikov(side, 0.7).unwrap();
        let disc = Discretisation::new(&Oscillator, grid, embedding);
        let q: Vec<Vector<1>> = (0..=n)
            .map(|k| Vector::<1>::new(0.3 - 1.3 * k as f64 / n as f64))
            .collect();
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, eval) = linearized(&disc, &mut fft, &q);
        let rhs = eval.r.clone();
        let mut delta = vec![0.0; n - 1];
        let options = KrylovOptions {
            tolerance: 1e-10,
            max_iterations: 300,
            restart: 30,
        };
        let cg = conjugate_gradient(&mut system, &rhs, &mut delta, &options);
        assert!(matches!(cg, Err(KrylovFailure::Breakdown { .. })), "{cg:?}");
        let at = Location::Newton(0);
        solve_newton_system(
            &mut system,
            &mut rhs.clone(),
            &mut delta,
            1e-10,
            &KrylovBudget::default(),
            at,
            &mut MinresWork::default(),
        )
        .unwrap();
        let residual = relative_residual(&mut system, &rhs, &delta);
        assert!(residual <= 1e-10, "{side:?}: {residual:e}");
    }
}

/// `‖b − J x‖₂ / ‖b‖₂`, with `J x` a fresh product.
fn relative_residual<const D: usize>(system: &mut FastSystem<'_, D>, b: &[f64], x: &[f64]) -> f64 {
    let mut jx = vec![0.0; b.len()];
    system.apply(x, &mut jx);
    let gap: f64 = b.iter().zip(&jx).map(|(b, jx)| (b - jx) * (b - jx)).sum();
    let norm: f64 = b.iter().map(|b| b * b).sum();
    (gap / norm).sqrt()
}

/// The preconditioner keeps the Krylov iterations per Newton step flat as `N` grows, for the
/// paper's scheme (MINRES) and for the corrected form's direct scheme (GMRES, the paper's
/// preconditioner without the starting columns): on the pendulum `L = ½v² + cos x`, α = 0.7,
/// `0 → 1`, the most iterations of any Newton step at `N = 2·10⁴` is at most one more than at
/// `N = 200`, and never above 8 (measured at `N = 200, 2000, 20 000`: paper's 6, 6, 5;
/// corrected 6, 4, 5).
#[test]
fn krylov_iterations_stay_flat_as_n_grows() {
    let most = |n: usize, embedding: Embedding, scheme: Scheme| {
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let pendulum = Pendulum::default();
        let disc = Discretisation::new(&pendulum, grid, embedding);
        let guess: Vec<Vector<1>> = (0..=n)
            .map(|k| Vector::<1>::new(k as f64 / n as f64))
            .collect();
        let options = SolverOptions::default();
        let (solution, iterations) = disc
            .with_velocity_fft(|fft| {
                solve_with(&disc, fft, &options, scheme, (guess, ETA_MAX), CHECK_STEPS)
            })
            .unwrap();
        assert_eq!(iterations.len(), solution.newton_iterations);
        iterations.into_iter().max().unwrap()
    };
    let paper = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let corrected = Embedding::corrected_grunwald_letnikov(Side::Backward, 0.7).unwrap();
    for (embedding, scheme) in [(paper, Scheme::Variational), (corrected, Scheme::Direct)] {
        let counts: Vec<usize> = [200, 2_000, 20_000]
            .into_iter()
            .map(|n| most(n, embedding, scheme))
            .collect();
        assert!(
            counts[2] <= counts[0] + 1 && counts.iter().all(|&c| (1..=8).contains(&c)),
            "{embedding} {scheme:?}: {counts:?}"
        );
    }
}

/// A solve evaluates the Hessians once a row for the guess's check, once for each Newton
/// step but the first (whose linearisation reads the check's, at the same iterate), and once
/// for the solution's check: counted on a pendulum whose `hessian` counts its calls.
#[test]
fn a_solve_evaluates_the_guess_hessians_once() {
    let n = 300;
    let lagrangian = Pendulum::default();
    for side in [Side::Backward, Side::Forward] {
        lagrangian.hessians.set(0);
        let embedding = Embedding::grunwald_letnikov(side, 0.7).unwrap();
        let problem = crate::Problem::new(&lagrangian, Grid::new(0.0, 1.0, n).unwrap(), embedding)
            .with_fractional_solver(crate::FractionalSolver::Fast)
            .with_posedness_check(false);
        let solution = problem.solve_bvp(Scheme::Variational, 0.0, 1.0).unwrap();
        assert!(solution.newton_iterations >= 2, "{side:?}");
        assert_eq!(
            lagrangian.hessians.get(),
            n * (solution.newton_iterations + 1),
            "{side:?}: {} Newton steps",
            solution.newton_iterations
        );
    }
}

/// GMRES on the corrected direct scheme's Newton system (whose products take `D z` from the
/// preconditioner's images): a solve it reports converged has the residual a fresh product
/// `J x` measures within the tolerance, and reports that residual. The images round
/// differently from a fresh product; the residual it stops on must be the fresh one.
#[test]
fn gmres_reports_the_residual_a_fresh_product_measures() {
    fn check<L: Lagrangian<2>>(l: &L, embedding: Embedding, n: usize) {
        let grid = Grid::new(0.2, 1.5, n).unwrap();
        let disc = Discretisation::new(l, grid, embedding);
        let q: Vec<Vector<2>> = (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                Vector::<2>::new((3.0 * t).sin(), 0.5 * (5.0 * t).cos())
            })
            .collect();
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, _) = linearized_for(&disc, Scheme::Direct, &mut fft, &q);
        assert!(!system.symmetric(), "{embedding}: GMRES's system");
        let b: Vec<f64> = (0..(n - 1) * 2).map(|i| ((i * 7) as f64).sin()).collect();
        let options = KrylovOptions {
            tolerance: 1e-11,
            max_iterations: 400,
            restart: 3,
        };
        let mut x = vec![0.0; b.len()];
        let stats = crate::solve::krylov::gmres(&mut system, &b, &mut x, &options).unwrap();
        let fresh = relative_residual(&mut system, &b, &x);
        assert!(
            fresh <= options.tolerance && (stats.relative_residual - fresh).abs() <= 1e-3 * fresh,
            "{embedding}: reported {:e}, fresh {fresh:e}",
            stats.relative_residual
        );
    }
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::corrected_grunwald_letnikov(side, 0.95).unwrap();
        check(&Mixed, embedding, 40_000);
        check(&Unmixed, embedding, 40_000);
    }
}

/// A solve from the straight line on a grid of at least `nested_from` steps starts Newton from
/// the solution on a grid 32 times coarser (solved from its own straight line), interpolated
/// linearly; the solve from there meets its stopping rule in fewer Newton steps than from the
/// line, with nodes as close to the discrete solution (solved to the round-off floor) as the
/// solve from the line, and the same nodes for `c L` (`c = 10^{±12}`). A guess that is not the
/// straight line is taken as given, and a coarse solve that fails leaves the straight line.
#[test]
fn a_straight_line_guess_starts_from_a_coarser_grid_solution() {
    let n = 8192;
    let pendulum = Pendulum::default();
    let paper = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let corrected = Embedding::corrected_grunwald_letnikov(Side::Forward, 0.6).unwrap();
    let (qa, qb) = (Vector::<1>::new(0.0), Vector::<1>::new(1.0));
    for (embedding, scheme) in [(paper, Scheme::Variational), (corrected, Scheme::Direct)] {
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let disc = Discretisation::new(&pendulum, grid, embedding);
        let line = straight_line(qa, qb, n).unwrap();
        let options = SolverOptions::default();

        // The first iterate: the coarse grid's solution, solved here on its own.
        let coarse_grid = Grid::new(0.0, 1.0, n / 32).unwrap();
        let coarse = Discretisation::new(&pendulum, coarse_grid, embedding);
        let coarse_line = straight_line(qa, qb, n / 32).unwrap();
        let coarse_options = SolverOptions {
            posedness_check: false,
            ..options
        };
        let (coarse_solution, _) = coarse
            .with_velocity_fft(|fft| {
                solve_with(
                    &coarse,
                    fft,
                    &coarse_options,
                    scheme,
                    (coarse_line, ETA_MAX),
                    1 << 18,
                )
            })
            .unwrap();
        let (first, nested) = nested_guess(&disc, &options, scheme, line.clone(), n).unwrap();
        assert!(
            nested && first == posedness::interpolate(&coarse_solution.q, n),
            "{embedding}: the interpolated coarse solution"
        );

        let nested = solve_nested(&disc, &options, scheme, line.clone(), n).unwrap();
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (_, evaluation) = linearized_for(&disc, scheme, &mut fft, &nested.q);
        let (residual, tolerance) = (evaluation.norms().0, options.newton.tolerance);
        assert!(
            residual <= tolerance * evaluation.scale,
            "{embedding}: max|r| {residual:e} against {:e}",
            tolerance * evaluation.scale
        );
        let floor = SolverOptions {
            newton: crate::NewtonOptions {
                tolerance: 1e-16,
                ..options.newton
            },
            ..options
        };
        let solve_plain = |options: &SolverOptions| {
            solve_nested(&disc, options, scheme, line.clone(), usize::MAX).unwrap()
        };
        let (plain, reference) = (solve_plain(&options), solve_plain(&floor));
        assert!(
            nested.newton_iterations < plain.newton_iterations,
            "{embedding}: {} Newton steps from the coarser grid, {} from the line",
            nested.newton_iterations,
            plain.newton_iterations
        );
        let gap = |q: &[Vector<1>]| {
            q.iter()
                .zip(&reference.q)
                .map(|(a, b)| (a - b).amax())
                .fold(0.0, f64::max)
        };
        // As close to the floor's solution as the solve from the line, to 1e-13.
        let (from_line, from_coarse) = (gap(&plain.q), gap(&nested.q));
        assert!(
            from_coarse <= from_line.max(1e-13),
            "{embedding}: {from_coarse:e} from the coarser grid, {from_line:e} from the line"
        );

        // `c L` gives the nodes of `L` (its Euler–Lagrange equations are those of `L`).
        for c in [1e-12, 1e12] {
            let scaled = ScaledPendulum(c);
            let disc = Discretisation::new(&scaled, grid, embedding);
            let q = solve_nested(&disc, &options, scheme, line.clone(), n)
                .unwrap()
                .q;
            let moved = q
                .iter()
                .zip(&nested.q)
                .map(|(a, b)| (a - b).amax())
                .fold(0.0, f64::max);
            assert!(
                moved <= 1e-9,
                "{embedding}: c = {c:e}, nodes moved by {moved:e}"
            );
        }

        let mut bent = line.clone();
        bent[1][0] += 1e-3;
        let kept = nested_guess(&disc, &options, scheme, bent.clone(), 0).unwrap();
        assert!(
            kept == (bent, false),
            "{embedding}: a guess not the line is kept"
        );
        let failing = SolverOptions {
            newton: crate::NewtonOptions {
                max_iterations: 0,
                ..options.newton
            },
            ..options
        };
        let fallback = nested_guess(&disc, &failing, scheme, line.clone(), 0).unwrap();
        assert!(
            fallback == (line.clone(), false),
            "{embedding}: the line where the coarse solve fails"
        );
    }
}
