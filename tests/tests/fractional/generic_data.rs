//! Gauss-GLE− on generic data, against exact solutions: the momentum `p = ∂L/∂v` not vanishing
//! at `b`, where the right derivative of the Euler–Lagrange equation starts, or at `a`.
//!
//! On `[0, 1]`: choose `p(t)` a polynomial; `q = I^α_− p` (left Riemann–Liouville integral,
//! `I^α tᵏ = k!/Γ(k + 1 + α) t^{k+α}`) has `D^α_− q = p` and `q(0) = 0`, and it solves the
//! Euler–Lagrange equation `∂_x L + D^α_+ (∂_v L) = 0` of `L = ½v² + cos x − F(t) x` with
//! `F = D^α_+ p − sin q`. With `p = Σ_j ρ_j uʲ`, `u = 1 − t`,
//! `D^α_+ p = Σ_j ρ_j j!/Γ(j + 1 − α) u^{j−α}`: when `p(1) = ρ_0 ≠ 0` the forcing is singular
//! like `(1 − t)^{−α}` at `b` (read by no row: the rows are the interior nodes). These tests
//! pin the orders `core/docs/schemes.md` states for such data, on the dense and the fast solver,
//! both sides.

use varembed::{Embedding, FractionalSolver, Grid, Scheme, Side, observed_orders};
use varembed_tests::fractional::ExactSolution;
use varembed_tests::special::gamma;

/// `q = I^α p` for the momentum `p = Σ_k p[k] tᵏ`, under `L = ½v² + cos x − F(t) x`.
fn exact(alpha: f64, p: Vec<f64>) -> ExactSolution {
    ExactSolution {
        alpha,
        qa: 0.0,
        p,
        c: 1.0,
    }
}

/// The max nodal errors of the paper's scheme (σ = −) on `ns` steps.
fn errors(exact: &ExactSolution, solver: FractionalSolver, ns: &[usize]) -> Vec<(usize, f64)> {
    ns.iter()
        .map(|&n| (n, error(exact, Side::Backward, solver, n)))
        .collect()
}

/// The max nodal error on `n` steps of Gauss-GLEσ; σ = + solves the mirror image.
fn error(exact: &ExactSolution, side: Side, solver: FractionalSolver, n: usize) -> f64 {
    let gle = Embedding::grunwald_letnikov(side, exact.alpha).unwrap();
    exact.solve((gle, Scheme::Variational), solver, n).1
}

/// The forcing's closed form against the definition: `D^α_+ p = (−d/dt) I^{1−α}_+ p`, the
/// right integral by Simpson's rule after the substitution `s = t + (1 − t)u^{1/(1−α)}`
/// (which removes the kernel's singularity), the derivative by a central difference.
#[test]
fn the_forcing_is_the_right_derivative_of_the_momentum() {
    let exact = exact(0.6, vec![0.5, -1.0, 2.0]);
    let a = exact.alpha;
    let p = |t: f64| exact.p.iter().rev().fold(0.0, |s, c| s * t + c);
    // I^{1−α}_+ p (t) = 1/Γ(1−α) ∫_t^1 (s − t)^{−α} p(s) ds; with s − t = (1 − t) u^{1/(1−α)},
    // (s − t)^{−α} ds = (1 − t)^{1−α}/(1 − α) du: a smooth integrand on [0, 1], Simpson.
    let integral = |t: f64| {
        let m = 4000;
        let e = 1.0 / (1.0 - a);
        let f = |u: f64| p(t + (1.0 - t) * u.powf(e));
        let sum: f64 = (0..=m)
            .map(|i| {
                let w = if i == 0 || i == m {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * f(i as f64 / m as f64)
            })
            .sum::<f64>()
            / (3.0 * m as f64);
        (1.0 - t).powf(1.0 - a) / (1.0 - a) * sum / gamma(1.0 - a)
    };
    for t in [0.1, 0.5, 0.9] {
        let dt = 1e-4;
        let derivative = -(integral(t + dt) - integral(t - dt)) / (2.0 * dt);
        let closed = exact.right_derivative_of_p(t);
        assert!(
            (derivative - closed).abs() < 1e-6 * closed.abs().max(1.0),
            "t = {t}: {derivative} vs {closed}"
        );
    }
}

/// `p = t²`: `p(0) = 0` (so `q ~ t^{2+α}`, smooth enough at `a`) and `p(1) = 1`. The order is
/// far below 2 and grows slowly (measured, fast solver, `N = 256 … 2048`: 0.566, 0.570, 0.573
/// at α = 0.6, max error 1.29e-3 at N = 2048; 0.729, 0.745, 0.756 at α = 0.8, 1.21e-4). The
/// dense solver on `N = 64 … 512` gives the same errors where the sizes meet (0.549, 0.560,
/// 0.566 and 0.674, 0.707, 0.729 before).
#[test]
fn a_momentum_not_vanishing_at_b_loses_the_order() {
    for (alpha, (low, high), last) in [(0.6, (0.56, 0.58), 1.295e-3), (0.8, (0.72, 0.77), 1.207e-4)]
    {
        let exact = exact(alpha, vec![0.0, 0.0, 1.0]);
        let fast = errors(&exact, FractionalSolver::Fast, &[256, 512, 1024, 2048]);
        let orders = observed_orders(&fast);
        let what = format!("α = {alpha}: {fast:?}, orders {orders:?}");
        assert!(orders.iter().all(|o| (low..=high).contains(o)), "{what}");
        assert!((fast[3].1 / last - 1.0).abs() < 0.01, "{what}");
        let dense = errors(&exact, FractionalSolver::Dense, &[64, 128, 256, 512]);
        let orders = observed_orders(&dense);
        assert!(
            orders.iter().all(|o| (0.5..high).contains(o)),
            "{dense:?} {orders:?}"
        );
        for (d, f) in dense[2..].iter().zip(&fast) {
            assert!((d.1 / f.1 - 1.0).abs() < 1e-9, "{dense:?} {fast:?}");
        }
        // σ = +, whose forcing is infinite at `a`: the mirror image, the same errors.
        for solver in [FractionalSolver::Dense, FractionalSolver::Fast] {
            let mirrored = error(&exact, Side::Forward, solver, 256);
            assert!(
                (mirrored / fast[0].1 - 1.0).abs() < 1e-9,
                "{mirrored} {fast:?}"
            );
        }
    }
}

/// `p = (1 − t)²`: `p(1) = 0` but `p(0) = 1`, so `q ~ t^α/Γ(1 + α)` at `a`; the Grünwald–Letnikov
/// integral of a momentum not vanishing at `a` is off by `O(h^α)` at the first nodes (at node
/// 1 it is `h^α p(0)` against `h^α p(0)/Γ(1 + α)`): order α in the maximum norm (measured:
/// 0.60 at α = 0.6, max error 1.23e-3 at N = 2048; 0.80 at α = 0.8, 1.65e-4).
#[test]
fn a_momentum_not_vanishing_at_a_gives_order_alpha() {
    let ns = [256, 512, 1024, 2048];
    for (alpha, last) in [(0.6, 1.230e-3), (0.8, 1.653e-4)] {
        let exact = exact(alpha, vec![1.0, -2.0, 1.0]);
        let e = errors(&exact, FractionalSolver::Fast, &ns);
        let orders = observed_orders(&e);
        let what = format!("α = {alpha}: {e:?}, orders {orders:?}");
        assert!(orders.iter().all(|o| (o - alpha).abs() < 0.03), "{what}");
        assert!((e[3].1 / last - 1.0).abs() < 0.01, "{what}");
    }
}

/// At the end node whose force no row reads, an infinite force is accepted but a NaN one is
/// still outside the Lagrangian's domain: `L = ½v² − x · 0/(1 − t)` is `0/0` at `t = 1`.
#[test]
fn a_nan_force_at_the_unread_end_is_outside_the_domain() {
    struct NanAtB;
    impl varembed::Lagrangian<1> for NanAtB {
        fn value(&self, x: &varembed::Vector<1>, v: &varembed::Vector<1>, t: f64) -> f64 {
            0.5 * v[0] * v[0] - x[0] * (0.0 * t) / (1.0 - t)
        }
        fn gradient(
            &self,
            _x: &varembed::Vector<1>,
            v: &varembed::Vector<1>,
            t: f64,
        ) -> (varembed::Vector<1>, varembed::Vector<1>) {
            (varembed_tests::curve::v1(-(0.0 * t) / (1.0 - t)), *v)
        }
        fn hessian(
            &self,
            _x: &varembed::Vector<1>,
            _v: &varembed::Vector<1>,
            _t: f64,
        ) -> varembed::Hessian<1> {
            varembed::Hessian {
                xx: varembed::Matrix::<1>::zeros(),
                xv: varembed::Matrix::<1>::zeros(),
                vv: varembed::Matrix::<1>::identity(),
            }
        }
    }
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    match varembed_tests::problem(&NanAtB, grid, gle).solve_bvp(Scheme::Variational, 0.0, 1.0) {
        Err(varembed::Error::OutsideDomain { what }) => {
            assert!(what.contains("Q_20") && what.contains("at b"), "{what}")
        }
        other => panic!("{other:?}"),
    }
}
