//! The two starts of an initial value run (`core/docs/solvers.md`), against an independent RK4
//! reference: on the pendulum the variational positions are first order from the discrete
//! Legendre start and second order from the second-order start, with the error figures at
//! t = 10 stated below to 15 %.

use varembed::{Embedding, Grid, Scheme, Side, Start};
use varembed_tests::models::hand::Pendulum;

/// Classical RK4 on `q̈ = −(g/l) sin q` with `steps` steps: an independent reference, fourth
/// order, so 2·10⁵ steps over [0, 10] are accurate to ~1e-15.
fn rk4_pendulum(g_over_l: f64, q0: f64, v0: f64, t_end: f64, steps: usize) -> f64 {
    let h = t_end / steps as f64;
    let f = |q: f64, v: f64| (v, -g_over_l * q.sin());
    let (mut q, mut v) = (q0, v0);
    for _ in 0..steps {
        let k1 = f(q, v);
        let k2 = f(q + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
        let k3 = f(q + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
        let k4 = f(q + h * k3.0, v + h * k3.1);
        q += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
    }
    q
}

#[test]
fn legendre_start_is_first_order_and_second_order_start_is_second_order() {
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let reference = rk4_pendulum(1.0, 1.0, 0.0, 10.0, 200_000);
    for side in [Side::Backward, Side::Forward] {
        for (start, expected, order) in [
            (Start::Legendre, [2.1e-4, 1.05e-4, 5.3e-5], 1.0),
            (Start::SecondOrder, [1.5e-6, 3.8e-7, 9.6e-8], 2.0),
        ] {
            let errors: Vec<f64> = [1000, 2000, 4000]
                .iter()
                .map(|&n| {
                    let problem = varembed_tests::problem(
                        &pendulum,
                        Grid::new(0.0, 10.0, n).unwrap(),
                        Embedding::finite_difference(side),
                    );
                    let run = problem
                        .solve_ivp_with(Scheme::Variational, 1.0, 0.0, start)
                        .unwrap();
                    (run.last()[0] - reference).abs()
                })
                .collect();
            println!("{side:?} {start:?}: {errors:?}");
            for (e, d) in errors.iter().zip(expected) {
                assert!(
                    (e / d - 1.0).abs() < 0.15,
                    "{side:?} {start:?}: error {e:e}, expected {d:e}"
                );
            }
            for pair in errors.windows(2) {
                let observed = (pair[0] / pair[1]).log2();
                assert!(
                    (observed - order).abs() < 0.1,
                    "{side:?} {start:?}: order {observed}"
                );
            }
        }
    }
}
