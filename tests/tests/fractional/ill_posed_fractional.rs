//! Fractional boundary value problems of order `α ≤ 1/2` with both end values imposed: the
//! discrete solutions do not settle as `N` grows, and every solution says so with
//! `Warning::IllPosedFractional`; at `α > 1/2` they converge and carry no warning.

use varembed::{Embedding, FractionalSolver, Grid, Scheme, Side, Solution, Warning};
use varembed_tests::models::generated::UnitPendulum;

/// The pendulum `L = ½v² + cos x` under Gauss-GLE−, `Q_0 = 0`, `Q_N = 1` on `[0, 1]`.
fn solve(alpha: f64, n: usize, solver: FractionalSolver) -> Solution<1> {
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let gle = Embedding::grunwald_letnikov(Side::Backward, alpha).unwrap();
    varembed_tests::problem(&UnitPendulum, grid, gle)
        .with_fractional_solver(solver)
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap()
}

/// `Q(1/2)` on `N = 250, 1000, 4000` (each a quadrupling).
fn midpoints(alpha: f64) -> [f64; 3] {
    [250, 1000, 4000].map(|n| {
        let sol = solve(alpha, n, FractionalSolver::Auto);
        let expected = if alpha <= 0.5 {
            vec![Warning::IllPosedFractional { alpha }]
        } else {
            vec![]
        };
        assert_eq!(sol.warnings, expected, "α = {alpha}, N = {n}");
        sol.q[n / 2][0]
    })
}

#[test]
fn at_one_half_the_midpoint_drifts_and_the_solution_is_flagged() {
    let [a, b, c] = midpoints(0.5);
    // Measured: 0.4656, 0.4258, 0.3922 (and 0.332 at N = 10⁵): a drift of 0.03–0.04 per
    // quadrupling that hardly slows down.
    assert!(
        (a - 0.4656).abs() < 1e-3 && (c - 0.3922).abs() < 1e-3,
        "{a} {b} {c}"
    );
    let ratio = (b - c) / (a - b);
    assert!(
        ratio > 0.7,
        "successive changes {} {} barely shrink",
        a - b,
        b - c
    );
}

#[test]
fn above_one_half_the_midpoint_converges_and_nothing_is_flagged() {
    let [a, b, c] = midpoints(0.7);
    // The error behaves like h^{2α−1} = h^{0.4}: each quadrupling divides the change by
    // 4^{0.4} ≈ 1.74.
    let ratio = (b - c) / (a - b);
    assert!((ratio - 4f64.powf(-0.4)).abs() < 0.1, "ratio {ratio}");
}

#[test]
fn every_solver_and_scheme_flags_the_ill_posed_problem() {
    for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
        for alpha in [0.05, 0.3, 0.5] {
            let sol = solve(alpha, 64, solver);
            assert_eq!(sol.warnings, [Warning::IllPosedFractional { alpha }]);
        }
        assert!(solve(0.51, 64, solver).warnings.is_empty());
    }
    let grid = Grid::new(0.0, 1.0, 32).unwrap();
    let gle = Embedding::grunwald_letnikov(Side::Forward, 0.4).unwrap();
    let direct = varembed_tests::problem(&UnitPendulum, grid, gle)
        .solve_bvp(Scheme::Direct, 0.0, 1.0)
        .unwrap();
    assert_eq!(
        direct.warnings,
        [Warning::IllPosedFractional { alpha: 0.4 }]
    );
    let message = direct.warnings[0].to_string();
    assert!(
        message.contains("α = 0.4") && message.contains("need not converge"),
        "{message}"
    );
    // The classical embeddings, and α = 1, are well-posed.
    let fde = Embedding::finite_difference(Side::Backward);
    let classical = varembed_tests::problem(&UnitPendulum, grid, fde)
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap();
    assert!(classical.warnings.is_empty());
    assert!(solve(1.0, 32, FractionalSolver::Auto).warnings.is_empty());
}

/// `Q(1/2)` of `L = ½v² − ½k x²` under Gauss-GLE− at `α = 0.74` on `[0, 1]`, `Q_0 = 0`,
/// `Q_N = 1`, dense solver, with its warnings. Exactly at a resonance of the discrete problem the
/// solve fails with `SingularJacobian`.
fn fractional_oscillator(k: f64, n: usize) -> varembed::Result<(f64, Vec<Warning>)> {
    oscillator_with(k, n, FractionalSolver::Dense)
}

fn oscillator_with(
    k: f64,
    n: usize,
    solver: FractionalSolver,
) -> varembed::Result<(f64, Vec<Warning>)> {
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.74).unwrap();
    let model = varembed_tests::models::hand::Oscillator { omega: k.sqrt() };
    let run = varembed_tests::problem(&model, grid, gle)
        .with_fractional_solver(solver)
        .solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    Ok((run.q[n / 2][0], run.warnings))
}

/// The measure of the `IllPosed` warning, if any.
fn ill_posed(warnings: &[Warning]) -> Option<f64> {
    warnings.iter().find_map(|w| match *w {
        Warning::IllPosed { measure } => Some(measure),
        _ => None,
    })
}

/// The first resonance `k*` of the oscillator at `N` steps: `Q(1/2)` grows without bound as
/// `k → k*` from below and changes sign across it (a singular system counts as past it). Found
/// by a scan, then bisection on the sign, with the dense solver.
fn first_resonance(n: usize) -> f64 {
    let below = |k: f64| fractional_oscillator(k, n).is_ok_and(|(q, _)| q > 0.0);
    let mut lo = 0.0;
    let mut hi = lo;
    while below(hi) {
        lo = hi;
        hi += 0.5;
        assert!(hi < 100.0, "no resonance below k = 100 at N = {n}");
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn a_fractional_problem_next_to_a_resonance_is_flagged_and_a_far_one_is_not() {
    for n in [50, 100, 200] {
        let resonance = first_resonance(n);
        // Within 0.1 % of it: Q(1/2) is in the hundreds, and the solution is flagged.
        let (q_near, near) = fractional_oscillator(resonance * 0.999, n).unwrap();
        let measure = ill_posed(&near);
        assert!(
            q_near.abs() > 100.0 && measure.is_some_and(|m| m < 1e-2),
            "N = {n}, k* = {resonance}: Q(1/2) = {q_near}, {near:?}"
        );
        // Half-way to it, and with no stiffness at all: no warning.
        for k in [0.0, 0.5 * resonance] {
            let (_, far) = fractional_oscillator(k, n).unwrap();
            assert!(far.is_empty(), "N = {n}, k = {k}: {far:?}");
        }
    }
}

/// The fast path flags the same near-resonant problems, and both solvers measure the distance
/// to the resonance: on `J = DᵀD − k` the measure (the smallest eigenvalue of `J` against its
/// kinetic part `DᵀD`) is `1 − k/k*` exactly, so 1e-3 at 0.999 k* and 3e-3 at 0.997 k*. Both
/// within 2 % of it (measured: within 0.01 %), and so within a few per cent of each other.
#[test]
fn the_fast_path_flags_the_near_resonance_with_the_dense_measure() {
    for n in [50, 100, 200] {
        let resonance = first_resonance(n);
        for fraction in [0.999, 0.997] {
            let exact = 1.0 - fraction;
            let k = resonance * fraction;
            let mut measures = Vec::new();
            for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
                let (_, warnings) = oscillator_with(k, n, solver).unwrap();
                let measure = ill_posed(&warnings)
                    .unwrap_or_else(|| panic!("{solver:?}, N = {n}, k = {k}: not flagged"));
                assert!(
                    (measure - exact).abs() <= 0.02 * exact,
                    "{solver:?}, N = {n}, k = {fraction} k*: measure {measure:e}, exact {exact:e}"
                );
                measures.push(measure);
            }
            eprintln!(
                "N = {n}, k = {fraction} k*: dense {:e}, fast {:e}",
                measures[0], measures[1]
            );
        }
        for k in [0.0, 0.5 * resonance] {
            let (_, far) = oscillator_with(k, n, FractionalSolver::Fast).unwrap();
            assert!(far.is_empty(), "fast, N = {n}, k = {k}: {far:?}");
        }
    }
}

/// The fast path's check can be turned off like the dense one's.
#[test]
fn the_fast_path_check_can_be_turned_off() {
    let n = 100;
    let k = first_resonance(n) * 0.999;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.74).unwrap();
    let model = varembed_tests::models::hand::Oscillator { omega: k.sqrt() };
    let quiet = varembed_tests::problem(&model, grid, gle)
        .with_fractional_solver(FractionalSolver::Fast)
        .with_posedness_check(false)
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap();
    assert!(quiet.warnings.is_empty(), "{:?}", quiet.warnings);
}
