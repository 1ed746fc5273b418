//! The Caputo form of Gauss-GLEσ against exact solutions with `q(a) ≠ 0`.
//!
//! On `[0, 1]`, σ = −: choose the momentum `p(t)` a polynomial with `p(1) = 0`; then
//! `q = q_a + I^α_− p` (left Riemann–Liouville integral, `I^α tᵏ = k!/Γ(k + 1 + α) t^{k+α}`) has
//! Caputo derivative `D^α_C q = D^α_− (q − q_a) = p`, and it solves the Euler–Lagrange equation
//! `∂_x L + D^α_+ (∂_v L) = 0` of `L = ½v² + c cos x − F(t) x` with
//! `F = D^α_+ p − c sin q`, where `D^α_+ p` is in closed form once `p` is written in powers of
//! `1 − t` (`D^α_+ (1 − t)^j = j!/Γ(j + 1 − α) (1 − t)^{j−α}`; `p(1) = 0` keeps it bounded).
//! σ = + is the mirror image: `q(1 − t)` solves the problem of `F(1 − t)` under the right
//! Caputo derivative, whose end is `b`.

use varembed::{Embedding, FractionalSolver, Grid, Scheme, Side, Vector, observed_orders};
use varembed_tests::curve::v1;
use varembed_tests::fractional::ExactSolution;

/// The max nodal error of the Caputo solution on `N` steps.
fn error(
    exact: &ExactSolution,
    side: Side,
    scheme: Scheme,
    solver: FractionalSolver,
    n: usize,
) -> f64 {
    let embedding = Embedding::caputo(side, exact.alpha).unwrap();
    let (solution, error) = exact.solve((embedding, scheme), solver, n);
    assert!(solution.warnings.is_empty(), "{:?}", solution.warnings);
    error
}

/// `p = 1 + t − 2t²` (`p(0) = 1`): `q − q_a ~ t^α/Γ(1 + α)` next to `a`, the generic
/// behaviour of a Caputo solution.
fn generic(alpha: f64) -> ExactSolution {
    ExactSolution {
        alpha,
        qa: 0.5,
        p: vec![1.0, 1.0, -2.0],
        c: 1.0,
    }
}

/// `p = t − t³` (`p(0) = 0`): `q − q_a ~ t^{1+α}` next to `a`.
fn flat_at_a(alpha: f64) -> ExactSolution {
    ExactSolution {
        alpha,
        qa: 0.5,
        p: vec![0.0, 1.0, 0.0, -1.0],
        c: 1.0,
    }
}

/// Errors on `ns` and the orders between them, every order in `orders` and the last error at
/// most 1.1 times `last` (the value measured when the test was written).
fn converges(
    exact: &ExactSolution,
    side: Side,
    (scheme, solver): (Scheme, FractionalSolver),
    ns: &[usize],
    orders: (f64, f64),
    last: f64,
) {
    let errors: Vec<(usize, f64)> = ns
        .iter()
        .map(|&n| (n, error(exact, side, scheme, solver, n)))
        .collect();
    let observed = observed_orders(&errors);
    let what = format!(
        "α = {} {side:?} {scheme} {solver:?}: {errors:?}, orders {observed:?}",
        exact.alpha
    );
    assert!(
        observed.iter().all(|o| (orders.0..=orders.1).contains(o)),
        "{what}"
    );
    assert!(errors.last().unwrap().1 <= 1.1 * last, "{what}");
}

const DENSE: (Scheme, FractionalSolver) = (Scheme::Variational, FractionalSolver::Dense);
const FAST: (Scheme, FractionalSolver) = (Scheme::Variational, FractionalSolver::Fast);

/// Generic data: order α, both sides (measured on `N = 50 … 400`: 0.608, 0.606, 0.604 at
/// α = 0.6; 0.794, 0.797, 0.799 at α = 0.8; the same for σ = +, the mirror image).
#[test]
fn generic_data_converge_at_order_alpha() {
    for (alpha, last) in [(0.6, 3.284e-3), (0.8, 6.101e-4)] {
        for side in [Side::Backward, Side::Forward] {
            let orders = (alpha - 0.03, alpha + 0.05);
            converges(
                &generic(alpha),
                side,
                DENSE,
                &[50, 100, 200, 400],
                orders,
                last,
            );
        }
    }
}

/// A momentum vanishing at `a`: order about `1 + α` (measured on `N = 50 … 400`: 1.57, 1.59,
/// 1.60 at α = 0.6; 1.60, 1.66, 1.70 at α = 0.8, still rising).
#[test]
fn data_flat_at_the_start_converge_faster() {
    for (alpha, last) in [(0.6, 3.383e-6), (0.8, 1.289e-6)] {
        for side in [Side::Backward, Side::Forward] {
            converges(
                &flat_at_a(alpha),
                side,
                DENSE,
                &[50, 100, 200, 400],
                (1.5, 1.9),
                last,
            );
        }
    }
}

/// The fast path (its residual's velocity corrected by the rank-one end term) continues the
/// same orders to `N = 6400` (measured: generic 0.6012, 0.6006, 0.6003 at α = 0.6; flat at `a`
/// 1.741, 1.754, 1.764 at α = 0.8), and agrees with the dense solve where both run.
#[test]
fn the_fast_path_continues_the_orders() {
    let ns = [800, 1600, 3200, 6400];
    for side in [Side::Backward, Side::Forward] {
        converges(&generic(0.6), side, FAST, &ns, (0.58, 0.65), 6.203e-4);
        converges(&flat_at_a(0.8), side, FAST, &ns, (1.65, 1.9), 1.020e-8);
        for exact in [generic(0.8), flat_at_a(0.6)] {
            let dense = error(
                &exact,
                side,
                Scheme::Variational,
                FractionalSolver::Dense,
                300,
            );
            let fast = error(
                &exact,
                side,
                Scheme::Variational,
                FractionalSolver::Fast,
                300,
            );
            assert!(
                (dense - fast).abs() <= 1e-9 * dense,
                "{dense:e} vs {fast:e}"
            );
        }
    }
}

/// The direct scheme (the right Riemann–Liouville operator applied to the momenta) has the same
/// solutions: the embedding is coherent.
#[test]
fn the_direct_scheme_converges_the_same() {
    let direct = (Scheme::Direct, FractionalSolver::Dense);
    for side in [Side::Backward, Side::Forward] {
        converges(
            &generic(0.8),
            side,
            direct,
            &[100, 200],
            (0.77, 0.85),
            1.062e-3,
        );
        converges(
            &flat_at_a(0.6),
            side,
            direct,
            &[100, 200],
            (1.5, 1.9),
            1.024e-5,
        );
    }
}

/// The discrete velocity is the Grünwald–Letnikov sum of the shifted curve, computed here from
/// the weights' definition `α_r = (−1)^r C(α, r)` by a loop of its own.
#[test]
fn the_velocity_is_grunwald_letnikov_of_the_shifted_curve() {
    let (n, alpha) = (12, 0.7);
    let grid = Grid::new(0.0, 1.2, n).unwrap();
    let q: Vec<Vector<1>> = (0..=n).map(|k| v1(0.4 + (0.9 * k as f64).cos())).collect();
    let weight = |r: usize| (0..r).fold(1.0, |w, i| -w * (alpha - i as f64) / (i + 1) as f64);
    let h_alpha = grid.h().powf(-alpha);
    for side in [Side::Backward, Side::Forward] {
        let problem = varembed_tests::problem(&Free, grid, Embedding::caputo(side, alpha).unwrap());
        for (k, v) in problem.quadrature_velocities(&q).unwrap() {
            let want = match side {
                Side::Backward => (0..=k)
                    .map(|r| weight(r) * (q[k - r][0] - q[0][0]))
                    .sum::<f64>(),
                Side::Forward => -(0..=n - k)
                    .map(|r| weight(r) * (q[k + r][0] - q[n][0]))
                    .sum::<f64>(),
            } * h_alpha;
            assert!(
                (v[0] - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{side:?} k = {k}: {} vs {want}",
                v[0]
            );
        }
    }
}

/// `L = ½v²`.
#[varembed::lagrangian]
fn free(_x: f64, v: f64) -> f64 {
    0.5 * v * v
}
