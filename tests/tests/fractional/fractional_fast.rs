//! The fractional boundary-value fast path (FFT operators, Newton–Krylov) against the dense
//! reference.

use varembed::__private::fft_operator::FftOperator;
use varembed::__private::operator::Operator;
use varembed::{
    Embedding, Error, FractionalSolver, Grid, Hessian, Lagrangian, Matrix, Problem, Scheme, Side,
    Solution, Vector,
};
use varembed_tests::curve::{max_diff, max_norm};
use varembed_tests::models::hand::{Coupled, Oscillator, Pendulum};
use varembed_tests::rng::Rng;

fn relative_gap<const D: usize>(fast: &[Vector<D>], dense: &[Vector<D>]) -> f64 {
    max_diff(fast, dense) / max_norm(dense)
}

fn check_operator<const D: usize>(rng: &mut Rng, n: usize, side: Side, alpha: f64) {
    let grid = Grid::new(0.0, 1.3, n).unwrap();
    let op = Operator::grunwald_letnikov(side, alpha, &grid).unwrap();
    let mut fast = FftOperator::new(&op);
    let q = rng.curve::<D>(n, 1.0);
    let w: Vec<Vector<D>> = rng.curve::<D>(n - 1, 1.0);
    let dense = op.apply(&q).unwrap();
    let apply = relative_gap(&fast.apply(&q).unwrap(), &dense);
    // The difference form on a rough curve, where it is at its least accurate (FftOperator
    // docs): its FFT input is as large as the nodes and T' has weights summing to ~N^{1−α}.
    let by_differences = relative_gap(&fast.apply_by_differences(&q).unwrap(), &dense);
    let transpose = relative_gap(
        &fast.apply_transpose(&w).unwrap(),
        &op.apply_transpose(&w).unwrap(),
    );
    assert!(
        apply <= 1e-12 && by_differences <= 1e-12 && transpose <= 1e-12,
        "N = {n}, {side:?}, α = {alpha}, d = {D}: apply {apply:e}, by differences \
         {by_differences:e}, transpose {transpose:e}"
    );
}

/// FFT products equal the dense loops to 1e-12 relative.
#[test]
fn fft_products_equal_the_dense_loops() {
    let mut rng = Rng(11);
    for n in [1, 2, 7, 64, 100, 333, 1000] {
        for side in [Side::Backward, Side::Forward] {
            for alpha in [0.1, 0.3, 0.5, 0.7, 0.95, 1.0] {
                check_operator::<1>(&mut rng, n, side, alpha);
                check_operator::<2>(&mut rng, n, side, alpha);
                check_operator::<3>(&mut rng, n, side, alpha);
            }
        }
    }
}

#[test]
fn fft_products_check_lengths() {
    let grid = Grid::new(0.0, 1.0, 5).unwrap();
    let op = Operator::grunwald_letnikov(Side::Forward, 0.5, &grid).unwrap();
    let mut fast = FftOperator::new(&op);
    assert!(fast.apply(&[Vector::<1>::zeros(); 5]).is_err());
    assert!(
        fast.apply_by_differences(&[Vector::<1>::zeros(); 7])
            .is_err()
    );
    assert!(fast.apply_transpose(&[Vector::<1>::zeros(); 6]).is_err());
}

/// A coupled, non-separable, time-dependent Lagrangian in d = 2 with a convex potential part:
/// `L = ½(1 + 0.2x₁²)v₀² + ½v₁² + 0.2v₀v₁ + 0.3 cos(t) x₀v₁ + ½x₀² + ¼x₁⁴ + 0.2x₀x₁`.
struct Coupled2;

impl Lagrangian<2> for Coupled2 {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> f64 {
        0.5 * (1.0 + 0.2 * x[1] * x[1]) * v[0] * v[0]
            + 0.5 * v[1] * v[1]
            + 0.2 * v[0] * v[1]
            + 0.3 * t.cos() * x[0] * v[1]
            + 0.5 * x[0] * x[0]
            + 0.25 * x[1].powi(4)
            + 0.2 * x[0] * x[1]
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> (Vector<2>, Vector<2>) {
        (
            Vector::<2>::new(
                0.3 * t.cos() * v[1] + x[0] + 0.2 * x[1],
                0.2 * x[1] * v[0] * v[0] + x[1].powi(3) + 0.2 * x[0],
            ),
            Vector::<2>::new(
                (1.0 + 0.2 * x[1] * x[1]) * v[0] + 0.2 * v[1],
                v[1] + 0.2 * v[0] + 0.3 * t.cos() * x[0],
            ),
        )
    }
    fn hessian(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> Hessian<2> {
        Hessian {
            xx: Matrix::<2>::new(1.0, 0.2, 0.2, 0.2 * v[0] * v[0] + 3.0 * x[1] * x[1]),
            xv: Matrix::<2>::new(0.0, 0.3 * t.cos(), 0.4 * x[1] * v[0], 0.0),
            vv: Matrix::<2>::new(1.0 + 0.2 * x[1] * x[1], 0.2, 0.2, 1.0),
        }
    }
}

const SCHEMES: [Scheme; 2] = [Scheme::Direct, Scheme::Variational];
const ALPHAS: [f64; 4] = [0.3, 0.7, 0.95, 1.0];

/// Whether `q` meets Newton's stopping rule for `scheme` (see `NewtonOptions`), recomputed on
/// the dense residual path: `max|r| ≤ tolerance·(max|f| + h^{−α} max|p|)` (`f` on the rows,
/// the interior nodes; `p` on the quadrature nodes), or `max|r|` at
/// the round-off floor `64 ε ‖J‖∞ ‖Q‖∞`. `‖J‖∞` is bounded from the Hessian blocks with
/// `‖D‖ ≤ 2h^{−α}` (the Grünwald–Letnikov weights have `Σ|α_r| ≤ 2`):
/// `‖J‖∞ ≤ max‖L_xx‖ + 4h^{−α} max‖L_xv‖ + 4h^{−2α} max‖L_vv‖`. Returns the relative residual
/// and whether the rule holds (with a factor 2 of slack for the recomputation).
fn newton_criterion<L: Lagrangian<D> + ?Sized, const D: usize>(
    problem: &Problem<'_, L, D>,
    scheme: Scheme,
    q: &[Vector<D>],
) -> (f64, bool) {
    let r = problem.residual(scheme, q).unwrap();
    let v = problem.quadrature_velocities(q).unwrap();
    let (mut f_max, mut p_max) = (0.0f64, 0.0f64);
    let (mut xx, mut xv, mut vv) = (0.0f64, 0.0f64, 0.0f64);
    let norm = |m: &Matrix<D>| {
        m.row_iter()
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    for (k, vk) in &v {
        let (k, vk) = (*k, vk);
        let t = problem.grid().t(k);
        let (f, p) = problem.lagrangian().gradient(&q[k], vk, t);
        let hs = problem.lagrangian().hessian(&q[k], vk, t);
        if (1..problem.grid().n()).contains(&k) {
            f_max = f_max.max(f.amax());
        }
        p_max = p_max.max(p.amax());
        (xx, xv, vv) = (
            xx.max(norm(&hs.xx)),
            xv.max(norm(&hs.xv)),
            vv.max(norm(&hs.vv)),
        );
    }
    let h_alpha = problem.grid().h().powf(-problem.embedding().alpha());
    let residual = max_norm(&r);
    let relative = residual / (f_max + h_alpha * p_max);
    let jacobian = xx + 4.0 * h_alpha * xv + 4.0 * h_alpha * h_alpha * vv;
    let floor = 64.0 * f64::EPSILON * jacobian * max_norm(q);
    let tolerance = problem.newton_options().tolerance;
    (
        relative,
        relative <= 2.0 * tolerance || residual <= 2.0 * floor,
    )
}

/// Solves with the fast and the dense path; checks both residuals and returns the gap.
fn fast_vs_dense<L: Lagrangian<D>, const D: usize>(
    lagrangian: &L,
    n: usize,
    side: Side,
    alpha: f64,
    scheme: Scheme,
    qa: Vector<D>,
    qb: Vector<D>,
) -> f64 {
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let embedding = Embedding::grunwald_letnikov(side, alpha).unwrap();
    let problem = Problem::new(lagrangian, grid, embedding);
    let solve = |solver| -> Solution<D> {
        Problem::new(lagrangian, grid, embedding)
            .with_fractional_solver(solver)
            .solve_bvp(scheme, qa, qb)
            .unwrap_or_else(|e| panic!("{solver:?}, N = {n}, {side:?}, α = {alpha}: {e}"))
    };
    let (fast, dense) = (
        solve(FractionalSolver::Fast),
        solve(FractionalSolver::Dense),
    );
    for (name, sol) in [("fast", &fast), ("dense", &dense)] {
        let (rel, holds) = newton_criterion(&problem, scheme, &sol.q);
        // The dense residual path recomputes what the FFT path converged on: round-off apart,
        // the Newton criterion holds for it too.
        assert!(
            holds,
            "{name}: N = {n}, {side:?}, α = {alpha}, {scheme}: relative residual {rel:e}"
        );
    }
    fast.max_distance(&dense.q).unwrap()
}

/// Fast and dense agree, d = 1: the pendulum `L = ½v² + cos x` with random boundary values.
#[test]
fn fast_and_dense_agree_on_the_pendulum() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let mut rng = Rng(21);
    let mut cases = Vec::new();
    for n in [50, 300] {
        for side in [Side::Backward, Side::Forward] {
            for alpha in ALPHAS {
                for scheme in SCHEMES {
                    cases.push((n, side, alpha, scheme));
                }
            }
        }
    }
    for (side, alpha, scheme) in [
        (Side::Backward, 0.3, Scheme::Variational),
        (Side::Forward, 0.95, Scheme::Direct),
    ] {
        cases.push((1000, side, alpha, scheme));
    }
    for (n, side, alpha, scheme) in cases {
        let qa = Vector::<1>::new(rng.uniform(-1.0, 1.0));
        let qb = Vector::<1>::new(rng.uniform(-2.0, 2.0));
        let gap = fast_vs_dense(&pendulum, n, side, alpha, scheme, qa, qb);
        assert!(
            gap <= 1e-10,
            "N = {n}, {side:?}, α = {alpha}, {scheme}: gap {gap:e}"
        );
    }
}

/// Fast and dense agree, d = 2, on the test models' `Coupled`, whose `L_vv` (entries `1 + x₀²`, `0.3 x₁`, 1)
/// moves with every Newton iterate: the preconditioner's Woodbury correction is recomputed at
/// each linearisation, where the pendulum's constant `L_vv` keeps it (both hold the fast path
/// to the dense solution).
#[test]
fn fast_and_dense_agree_when_the_kinetic_term_moves_with_the_iterate() {
    let mut rng = Rng(23);
    for n in [60, 320] {
        for side in [Side::Backward, Side::Forward] {
            for (alpha, scheme) in [(0.7, Scheme::Variational), (0.8, Scheme::Direct)] {
                // Boundary values of a few tenths: at α = 0.45, or with values near 1, Newton
                // from the straight line fails on the dense path too for some draws.
                let qa = Vector::<2>::new(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4));
                let qb = Vector::<2>::new(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6));
                let gap = fast_vs_dense(&Coupled, n, side, alpha, scheme, qa, qb);
                assert!(
                    gap <= 1e-10,
                    "N = {n}, {side:?}, α = {alpha}, {scheme}: gap {gap:e}"
                );
            }
        }
    }
}

/// Fast and dense agree, d = 2: a coupled, non-separable, time-dependent Lagrangian.
#[test]
fn fast_and_dense_agree_on_a_coupled_two_dimensional_lagrangian() {
    let mut rng = Rng(22);
    for n in [40, 250] {
        for side in [Side::Backward, Side::Forward] {
            for (i, alpha) in ALPHAS.into_iter().enumerate() {
                let scheme = SCHEMES[i % 2];
                let qa = Vector::<2>::new(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
                let qb = Vector::<2>::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
                let gap = fast_vs_dense(&Coupled2, n, side, alpha, scheme, qa, qb);
                assert!(
                    gap <= 1e-10,
                    "N = {n}, {side:?}, α = {alpha}, {scheme}: gap {gap:e}"
                );
            }
        }
    }
}

/// `L = ½v² − 72x²` makes `J = DᵀD − 144` indefinite (conjugate gradients would break down);
/// MINRES solves it and the fast path returns the dense path's solution.
#[test]
fn an_indefinite_jacobian_is_solved_by_minres_and_stays_correct() {
    let oscillator = Oscillator { omega: 12.0 };
    for side in [Side::Backward, Side::Forward] {
        for alpha in [0.7, 1.0] {
            let gap = fast_vs_dense(
                &oscillator,
                600,
                side,
                alpha,
                Scheme::Variational,
                Vector::<1>::new(0.3),
                Vector::<1>::new(-1.0),
            );
            assert!(gap <= 1e-10, "{side:?}, α = {alpha}: gap {gap:e}");
        }
    }
}

/// A strong pendulum `L = ½v² + 50 cos x` pulled through many turns
/// (`Q_N = 30`): whatever the solver does, an `Ok` meets the Newton tolerance on the dense
/// residual and an `Err` is one of the typed failures.
#[test]
fn a_hard_nonconvex_problem_gives_a_correct_answer_or_a_typed_error() {
    let pendulum = Pendulum { g: 50.0, l: 1.0 };
    let n = 500;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let mut outcomes = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        for alpha in [0.3, 0.7] {
            let embedding = Embedding::grunwald_letnikov(side, alpha).unwrap();
            for solver in [FractionalSolver::Fast, FractionalSolver::Auto] {
                let problem = varembed_tests::problem(&pendulum, grid, embedding)
                    .with_fractional_solver(solver);
                match problem.solve_bvp(Scheme::Variational, 0.0, 30.0) {
                    Ok(sol) => {
                        let (rel, holds) = newton_criterion(&problem, Scheme::Variational, &sol.q);
                        assert!(holds, "{solver:?}: residual {rel:e}");
                        outcomes.push("ok");
                    }
                    Err(
                        Error::NewtonDidNotConverge { .. }
                        | Error::KrylovDidNotConverge { .. }
                        | Error::SingularJacobian { .. }
                        | Error::NotFinite { .. },
                    ) => outcomes.push("typed error"),
                    Err(other) => panic!("unexpected error {other:?}"),
                }
            }
        }
    }
    eprintln!("outcomes: {outcomes:?}");
}

/// Fast and dense agree at N = 1000 (dense LU of a 999² system at every Newton iteration:
/// 1.3 s in the test profile).
#[test]
fn n1000_fast_and_dense_agree() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    for (side, alpha) in [(Side::Backward, 0.7), (Side::Forward, 0.3)] {
        let gap = fast_vs_dense(
            &pendulum,
            1000,
            side,
            alpha,
            Scheme::Variational,
            Vector::<1>::new(0.0),
            Vector::<1>::new(1.0),
        );
        eprintln!("N = 1000, {side:?}, α = {alpha}: gap {gap:e}");
        assert!(gap <= 1e-10, "{side:?}, α = {alpha}: gap {gap:e}");
    }
}

/// The fast path at N = 10⁶ (d = 1) in O(N) memory. Run alone, in release, so
/// that the process's peak resident set (`VmHWM`) is this solve's:
/// `cargo test -p varembed-tests --release --test fractional -- --ignored million --nocapture`.
#[test]
#[ignore = "N = 10⁶: run alone in release to measure the peak memory"]
fn million_nodes_in_linear_memory() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let n = 1_000_000;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let embedding = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let problem = varembed_tests::problem(&pendulum, grid, embedding);
    let sol = problem.solve_bvp(Scheme::Variational, 0.0, 1.0).unwrap();
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let peak_kib: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .expect("VmHWM in /proc/self/status");
    let peak_mib = peak_kib / 1024.0;
    eprintln!(
        "N = {n}: {} Newton iterations, peak RSS {peak_mib:.0} MiB",
        sol.newton_iterations
    );
    // A dense Jacobian would need 8 TB; O(N) storage is a few hundred bytes per node (345 MiB
    // measured in release, BENCHMARKS.md).
    assert!(peak_mib < 400.0, "peak RSS {peak_mib:.0} MiB");
    assert!(sol.q.iter().all(|x| x[0].is_finite()));
}

/// `L = ½ m(x) v²` with `m(x) = x − 0.5` (degenerate at `x = ½`, negative below) and a
/// Hessian that is NaN where `x > 1.5` (outside the domain).
struct MassByPosition;
impl Lagrangian<1> for MassByPosition {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * (x[0] - 0.5) * v[0] * v[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        let m = x[0] - 0.5;
        (
            Vector::<1>::new(0.5 * v[0] * v[0]),
            Vector::<1>::new(m * v[0]),
        )
    }
    fn hessian(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> Hessian<1> {
        let nan = if x[0] > 1.5 { f64::NAN } else { 0.0 };
        Hessian {
            xx: Matrix::<1>::new(nan),
            xv: Matrix::<1>::new(v[0]),
            vv: Matrix::<1>::new(x[0] - 0.5),
        }
    }
}

/// The fast path checks the guess's nodes with the velocities of its first evaluation: the
/// same errors as the dense path, at the same node (a degenerate `∂²L/∂v²` where the straight
/// line crosses `x = ½`, a node outside the domain where it passes `x = 1.5`; the velocity the
/// message quotes is the FFT product's there, equal to the dense loops' to rounding).
#[test]
fn the_fast_path_checks_the_guess_as_the_dense_path_does() {
    let n = 40;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    for (qa, qb, outside) in [(0.0, 1.0, false), (1.0, 2.0, true)] {
        let errors: Vec<Error> = [FractionalSolver::Dense, FractionalSolver::Fast]
            .into_iter()
            .map(|solver| {
                varembed_tests::problem(&MassByPosition, grid, gle)
                    .with_fractional_solver(solver)
                    .solve_bvp(Scheme::Variational, qa, qb)
                    .unwrap_err()
            })
            .collect();
        let node = |e: &Error| e.to_string().split(" (velocity").next().map(str::to_owned);
        assert_eq!(node(&errors[0]), node(&errors[1]));
        match &errors[1] {
            Error::OutsideDomain { what } if outside => {
                assert!(what.contains("node Q_21 = [1.525]"), "{what}")
            }
            Error::DegenerateLagrangian { .. } if !outside => {}
            other => panic!("{qa} → {qb}: {other}"),
        }
    }
}
