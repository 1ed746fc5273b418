//! The order of the variational Gauss-GLE− boundary value scheme depends on the data, as
//! `core/docs/schemes.md` states: second order on smooth compatible data, first order when the
//! momentum vanishes identically, about `2α − 1` on generic Dirichlet data. One test per regime,
//! each with the library's `observed_order` over doubling `N`.
//!
//! The first two regimes have a closed form at `α = ½`: with `w(t) = t²(1 − t)³`,
//! `q = I^½ w` (left Riemann–Liouville integral) solves both `L = ½v² − x D^½_+ w(t)` (whose
//! momentum is `p = D^½_− q = w`) and `L = ½(v − w(t))²` (whose momentum `v − w` vanishes), with
//! `q(0) = 0` and `q(1) = I^½ w (1)`. At `α = ½` both end values cannot be imposed on generic data
//! (the solutions carry `Warning::IllPosedFractional`); these data are compatible, and the
//! solutions converge.

use varembed::{
    Embedding, Grid, Hessian, Lagrangian, Matrix, Problem, Scheme, Side, Vector, lagrangian,
    max_error, observed_orders,
};

/// `Γ(n + ½) = √π Π_{j<n} (j + ½)`.
fn gamma_half(n: usize) -> f64 {
    std::f64::consts::PI.sqrt() * (0..n).map(|j| j as f64 + 0.5).product::<f64>()
}
/// `Γ(n + 1) = n!`.
fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// `w(t) = t²(1 − t)³ = t² − 3t³ + 3t⁴ − t⁵`.
fn w(t: f64) -> f64 {
    t * t * (1.0 - t).powi(3)
}

/// `q = I^½ w` (left Riemann–Liouville integral, `I^α tᵏ = k!/Γ(k + 1 + α) t^{k+α}`).
fn q_exact(t: f64) -> f64 {
    [(2, 1.0), (3, -3.0), (4, 3.0), (5, -1.0)]
        .iter()
        .map(|&(k, d)| d * factorial(k) / gamma_half(k + 1) * t.powf(k as f64 + 0.5))
        .sum()
}

/// `D^½_+ w` (right Riemann–Liouville derivative): with `u = 1 − t`, `w = u³ − 2u⁴ + u⁵` and
/// `D^α uᵏ = k!/Γ(k + 1 − α) u^{k−α}`.
fn right_derivative_w(t: f64) -> f64 {
    [(3, 1.0), (4, -2.0), (5, 1.0)]
        .iter()
        .map(|&(k, c)| c * factorial(k) / gamma_half(k) * (1.0 - t).powf(k as f64 - 0.5))
        .sum()
}

/// `L = ½v² − x D^½_+ w(t)`: its fractional Euler–Lagrange equation `∂L/∂x + D^α_+ ∂L/∂v = 0`
/// is solved by `p = D^½_− q = w`, `q = I^½ w`.
struct Forced;
impl Lagrangian<1> for Forced {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * v[0] * v[0] - x[0] * right_derivative_w(t)
    }
    fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (Vector::<1>::new(-right_derivative_w(t)), *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::zeros(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// `L = ½(v − w(t))²`: solved by `p = 0`, `D^½_− q = w`, the same `q = I^½ w`.
struct Tracking;
impl Lagrangian<1> for Tracking {
    fn value(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * (v[0] - w(t)).powi(2)
    }
    fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (Vector::<1>::zeros(), Vector::<1>::new(v[0] - w(t)))
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::zeros(),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

#[lagrangian]
fn pendulum(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.cos()
}

fn errors<L: Lagrangian<1>>(model: &L, sizes: &[usize]) -> Vec<(usize, f64)> {
    let gle = Embedding::grunwald_letnikov(Side::Backward, 0.5).unwrap();
    sizes
        .iter()
        .map(|&n| {
            let problem = Problem::new(model, Grid::new(0.0, 1.0, n).unwrap(), gle);
            let run = problem
                .solve_bvp(Scheme::Variational, 0.0, q_exact(1.0))
                .unwrap();
            (
                n,
                max_error(&run.grid, &run.q, |t| Vector::<1>::new(q_exact(t))),
            )
        })
        .collect()
}

/// `I^½ w(1) = (1/Γ(½)) ∫_0^1 (1 − s)^{−½} w(s) ds = (2/√π) ∫_0^1 w(1 − u²) du`, by composite
/// Simpson on the smooth right-hand integral: the closed form of `q` checked independently.
#[test]
fn the_closed_form_is_the_half_integral() {
    let m = 2000;
    let f = |u: f64| w(1.0 - u * u);
    let simpson: f64 = (0..=m)
        .map(|i| {
            let weight = if i == 0 || i == m {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            weight * f(i as f64 / m as f64)
        })
        .sum::<f64>()
        / (3.0 * m as f64);
    let quadrature = 2.0 / std::f64::consts::PI.sqrt() * simpson;
    assert!(
        (quadrature - q_exact(1.0)).abs() < 1e-13,
        "{quadrature} vs {}",
        q_exact(1.0)
    );
}

/// Smooth compatible data, the momentum `p = w` not zero: second order (max error 3.7e-9 at
/// N = 2048), from the errors of the left and the right Grünwald–Letnikov operators cancelling
/// as those of `Δ_−` and `Δ_+` do in the classical centred second difference.
#[test]
fn smooth_compatible_data_are_second_order() {
    let e = errors(&Forced, &[256, 512, 1024, 2048]);
    let orders = observed_orders(&e);
    assert!(
        orders.iter().all(|o| (o - 2.0).abs() < 0.05),
        "{e:?} {orders:?}"
    );
    assert!(e[3].1 < 4e-9, "{e:?}");
}

/// The momentum vanishing identically: only the consistency of the left operator `Δ^α_−`,
/// first order, is left (max error 7.9e-6 at N = 2048).
#[test]
fn vanishing_momentum_is_first_order() {
    let e = errors(&Tracking, &[256, 512, 1024, 2048]);
    let orders = observed_orders(&e);
    assert!(
        orders.iter().all(|o| (o - 1.0).abs() < 0.05),
        "{e:?} {orders:?}"
    );
}

/// Generic Dirichlet data (the tour's fractional scene, the pendulum, `q(0) = 0`, `q(1) = 1`)
/// at α = 0.8: the solution behaves like `(1 − t)^{2α−1}` at `t = 1`, and the order is about
/// `2α − 1 = 0.6` (self-convergence: 0.56, 0.58, 0.58 from N = 128).
#[test]
fn generic_dirichlet_data_are_of_order_two_alpha_minus_one() {
    let alpha = 0.8;
    let gle = Embedding::grunwald_letnikov(Side::Backward, alpha).unwrap();
    let problem = varembed_tests::problem(&Pendulum, Grid::new(0.0, 1.0, 128).unwrap(), gle);
    let run = problem.convergence_bvp(Scheme::Variational, 0.0, 1.0, &Default::default(), 5);
    assert!(run.failures.is_empty(), "{:?}", run.failures);
    let orders = run.orders();
    assert_eq!(orders.len(), 3);
    let expected = 2.0 * alpha - 1.0;
    assert!(
        orders.iter().all(|o| (o - expected).abs() < 0.1),
        "{orders:?}"
    );
}
