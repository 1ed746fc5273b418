//! Hard cases: the fractional boundary value problem across α.
//!
//! Pendulum `L = ½v² + cos x`, Gauss-GLE−, `[0, 1]`, `Q_0 = 0`, `Q_N = 1`. Every α is solved
//! (or would be a typed error); the solution changes continuously in α and tends to the classical
//! one as α → 1; for α ≤ 1/2 the discrete solutions do not converge to a curve through both
//! boundary values: the jump `Q_N − Q_{N−1}` at `t = b` does not vanish as `h → 0` (see the docs
//! of `EmbeddingKind::GrunwaldLetnikov`).

use varembed::{Embedding, Grid, Scheme, Side, Solution};
use varembed_tests::models::generated::UnitPendulum;

fn solve(alpha: f64, n: usize) -> Solution<1> {
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    let problem = varembed_tests::problem(
        &UnitPendulum,
        grid,
        Embedding::grunwald_letnikov(Side::Backward, alpha).unwrap(),
    );
    let sol = problem
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap_or_else(|e| panic!("α = {alpha}, N = {n}: {e}"));
    // Whatever α, a returned solution solves both schemes' rows (coherent embedding), checked
    // through `Problem::residual` (by FFT at these N, so affordable at every size).
    for scheme in [Scheme::Direct, Scheme::Variational] {
        let r = problem.residual(scheme, &sol.q).unwrap();
        let max = r.iter().map(|x| x.amax()).fold(0.0, f64::max);
        assert!(
            max < 1e-8 * (n as f64).powf(alpha),
            "α = {alpha}, N = {n}: {scheme} residual {max:e}"
        );
    }
    sol
}

fn end_jump(sol: &Solution<1>) -> f64 {
    let n = sol.q.len() - 1;
    sol.q[n][0] - sol.q[n - 1][0]
}

fn max_gap(a: &Solution<1>, b: &Solution<1>) -> f64 {
    a.max_distance(&b.q).unwrap()
}

#[test]
fn every_alpha_is_solved_and_the_boundary_layer_appears_at_one_half() {
    let sizes = [100, 200, 400];
    for alpha in [0.05, 0.3, 0.5, 0.7, 0.99, 1.0] {
        let jumps: Vec<f64> = sizes.iter().map(|&n| end_jump(&solve(alpha, n))).collect();
        if alpha < 0.5 {
            // Measured: 0.80, 0.84, 0.86 (α = 0.05); 0.44, 0.47, 0.49 (α = 0.3): growing.
            assert!(
                jumps[0] > 0.4 && jumps[2] >= jumps[0],
                "α = {alpha}: jumps {jumps:?}"
            );
        } else if alpha > 0.5 {
            // Measured: 0.036, 0.028, 0.021 (α = 0.7), ratio ≈ 2^{2(α − 1/2)} per doubling.
            for pair in jumps.windows(2) {
                assert!(pair[0] / pair[1] > 1.2, "α = {alpha}: jumps {jumps:?}");
            }
        } else {
            // α = 1/2, the borderline: 0.156, 0.150, 0.144: decaying like a tiny power of h.
            assert!(
                jumps[2] > 0.1 && jumps[2] < jumps[0],
                "α = 1/2: jumps {jumps:?}"
            );
        }
    }
}

#[test]
fn solution_is_continuous_in_alpha_and_tends_to_the_classical_one() {
    let n = 200;
    let classical = {
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        varembed_tests::problem(
            &UnitPendulum,
            grid,
            Embedding::finite_difference(Side::Backward),
        )
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .unwrap()
    };
    let exactly_one = solve(1.0, n);
    assert!(max_gap(&exactly_one, &classical) < 1e-12);
    // Distance to the classical solution shrinks linearly as α → 1 (≈ C (1 − α)).
    let gaps: Vec<f64> = [0.9, 0.99, 0.999]
        .iter()
        .map(|&a| max_gap(&solve(a, n), &classical))
        .collect();
    for pair in gaps.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!((5.0..20.0).contains(&ratio), "gaps {gaps:?}: ratio {ratio}");
    }
    assert!(gaps[2] < 1e-3, "gaps {gaps:?}");
    // Continuity across the whole range: a step of 0.01 in α moves the solution by < 0.05.
    let mut previous = solve(0.3, n);
    for k in 31..=100 {
        let current = solve(k as f64 / 100.0, n);
        let gap = max_gap(&previous, &current);
        assert!(
            gap < 0.05,
            "α = {}: jump of {gap} in the solution",
            k as f64 / 100.0
        );
        previous = current;
    }
}

/// Every α at N = 10⁴ (the fast path: `FractionalSolver::Auto` picks Newton–Krylov above 400
/// unknowns): every α is solved, the solution's midpoint moves continuously with α, and the
/// boundary layer persists for α ≤ 1/2 while it is small for α > 1/2.
#[test]
fn ten_thousand_nodes_every_alpha() {
    let n = 10_000;
    let mut midpoints = Vec::new();
    for alpha in [0.05, 0.3, 0.5, 0.7, 0.99, 1.0] {
        let sol = solve(alpha, n);
        let jump = end_jump(&sol);
        if alpha < 0.5 {
            assert!(jump > 0.4, "α = {alpha}: jump {jump}");
        } else if alpha > 0.5 {
            assert!(jump < 0.01, "α = {alpha}: jump {jump}");
        }
        midpoints.push(sol.q[n / 2][0]);
    }
    // α = 0.99 and α = 1 within O(1 − α) of each other (0.5665 against 0.5643 at N = 800).
    assert!(
        (midpoints[4] - midpoints[5]).abs() < 5e-3,
        "midpoints {midpoints:?}"
    );
}

/// N = 10⁵, one α on each side of 1/2.
#[test]
fn hundred_thousand_nodes() {
    let n = 100_000;
    let below = end_jump(&solve(0.3, n));
    let above = end_jump(&solve(0.7, n));
    // Measured at N = 100…400: 0.44–0.49 (growing) and 0.036–0.021 (≈ h^{0.4}); at 10⁵ the
    // layer below 1/2 is still there and the jump above has kept shrinking.
    assert!(below > 0.4, "α = 0.3: jump {below}");
    assert!(above < 0.01, "α = 0.7: jump {above}");
}
