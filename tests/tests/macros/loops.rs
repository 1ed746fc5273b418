//! Lagrangians with loops through `#[lagrangian]` against an independent computation: every
//! model is written a second time below as a plain generic fn, differentiated by num-dual's
//! hyper-dual numbers entry by entry (`∂/∂z_a` and `∂²/∂z_a∂z_b` exactly, no truncation), and
//! the generated value, gradient and Hessian must agree to 1e-12 relative at N = 4, 16, 64.
//! The forms of one model (a `for` loop, an iterator sum, a helper fn, hand-unrolled) must
//! agree with each other too.

use num_dual::{DualNum, HyperDual64};
use varembed::{Lagrangian, Matrix, Vector, lagrangian};
use varembed_tests::models::dual_chains::{
    fput_fixed_dual, fput_periodic_dual, n_link_dual, toda_dual,
};
use varembed_tests::models::num_dual::{assert_matches_oracle, close, dual_derivatives};
use varembed_tests::rng::Rng;

/// `V(d) = d²/2 + α d³/3 + β d⁴/4`, the FPUT spring.
#[lagrangian(helper)]
fn spring(d: f64, alpha: f64, beta: f64) -> f64 {
    0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4)
}

/// The models of this file at dimension `N`, in a module of their own.
macro_rules! models {
    ($module:ident, $n:expr) => {
        mod $module {
            use super::*;
            use std::f64::consts::PI;

            pub const N: usize = $n;

            /// FPUT chain with fixed ends `x_{-1} = x_N = 0`: a `for` loop.
            #[lagrangian]
            pub fn fput_fixed(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
                let mut kinetic = 0.0;
                for i in 0..N {
                    kinetic += 0.5 * v[i] * v[i];
                }
                let mut potential = 0.0;
                for i in 0..N - 1 {
                    let d = x[i + 1] - x[i];
                    potential += 0.5 * d * d + alpha / 3.0 * d.powi(3) + beta / 4.0 * d.powi(4);
                }
                let (first, last) = (x[0], -x[N - 1]);
                potential +=
                    0.5 * first * first + alpha / 3.0 * first.powi(3) + beta / 4.0 * first.powi(4);
                potential +=
                    0.5 * last * last + alpha / 3.0 * last.powi(3) + beta / 4.0 * last.powi(4);
                kinetic - potential
            }

            /// The same chain: iterator sums and a helper fn.
            #[lagrangian]
            pub fn fput_helper(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
                let kinetic = (0..N).map(|i| 0.5 * v[i] * v[i]).sum::<f64>();
                let bonds: f64 = (0..N - 1)
                    .map(|i| spring(x[i + 1] - x[i], alpha, beta))
                    .sum();
                kinetic - bonds - spring(x[0], alpha, beta) - spring(-x[N - 1], alpha, beta)
            }

            /// Periodic FPUT chain, `x_N = x_0`.
            #[lagrangian]
            pub fn fput_periodic(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
                (0..N)
                    .map(|i| {
                        let d = x[(i + 1) % N] - x[i];
                        0.5 * v[i] * v[i] - spring(d, alpha, beta)
                    })
                    .sum()
            }

            /// Toda lattice, periodic: `V(d) = (a/b) e^{−b d} + a d`.
            #[lagrangian]
            pub fn toda(x: [f64; N], v: [f64; N], a: f64, b: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..N {
                    let d = x[(i + 1) % N] - x[i];
                    l += 0.5 * v[i] * v[i] - (a / b * (-b * d).exp() + a * d);
                }
                l
            }

            /// An n-link pendulum of unit masses and lengths `l` (angles from the downward
            /// vertical): `T = ½ l² Σ_i Σ_j (N − max(i, j)) cos(x_i − x_j) v_i v_j`,
            /// `U = −g l Σ_i (N − i) cos x_i`, nested sums.
            #[lagrangian]
            pub fn n_link(x: [f64; N], v: [f64; N], g: f64, l: f64) -> f64 {
                let mut kinetic = 0.0;
                for i in 0..N {
                    for j in 0..N {
                        let mass_below = (N - i.max(j)) as f64;
                        kinetic += 0.5 * l * l * mass_below * (x[i] - x[j]).cos() * v[i] * v[j];
                    }
                }
                let potential: f64 = (0..N).map(|i| -g * l * (N - i) as f64 * x[i].cos()).sum();
                kinetic - potential
            }

            /// Particles on a line with a one-sided wall at 0 and a periodic pinning of
            /// period 1: a branch, `f64::max`, `signum` and `PI`.
            #[lagrangian]
            pub fn walled(x: [f64; N], v: [f64; N], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..N {
                    let wall = if x[i] < 0.0 { k * x[i] * x[i] } else { 0.0 };
                    let pin = (2.0 * PI * x[i]).cos() * f64::max(v[i].abs(), 0.5) * v[i].signum();
                    l += 0.5 * v[i] * v[i] - wall + 0.1 * pin;
                }
                l
            }
        }
    };
}

/// Less common forms in one Lagrangian of dimension 5: a triangular double loop over
/// `j in i + 1..N`, an inclusive range, an index `let`, mirrored indices `x[N - 1 - i]`, strided
/// `x[2 * i]`, `else if` with `&&`/`||` on indices, `sin_cos`, a product of two sums, a sum
/// times a velocity, a sum in a branch and a nested block.
mod forms {
    use super::*;

    pub const N: usize = 5;

    #[lagrangian]
    pub fn forms(x: [f64; N], v: [f64; N], t: f64, k: f64) -> f64 {
        let mut pairs = 0.0;
        for i in 0..N {
            for j in i + 1..N {
                let (s, c) = (x[i] - x[j]).sin_cos();
                pairs += k * s * c * v[j] + c / (j - i) as f64;
            }
        }
        let mut mirror = 0.0;
        for i in 0..=2 {
            let back = N - 1 - i;
            mirror += x[i] * x[back] * (back as f64 + 1.0);
        }
        let strided: f64 = (0..3).map(|i| x[2 * i] * x[2 * i].exp()).sum();
        let weighted: f64 = (0..N)
            .map(|i| {
                let w = if i == 0 || i == N - 1 {
                    0.5
                } else if i > 1 && i < 3 {
                    2.0
                } else {
                    1.0
                };
                w * v[i] * v[i]
            })
            .sum();
        let total_x: f64 = (0..N).map(|i| x[i]).sum();
        let total_v: f64 = (0..N).map(|i| v[i]).sum();
        let branch = if t > 0.5 { total_x * 0.25 } else { -total_x };
        pairs + mirror + strided + weighted + 0.1 * total_x * total_v + v[0] * total_x + branch + {
            let a = x[1] * v[2];
            a * a
        }
    }
}

fn forms_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], p: [f64; 2]) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let (k, t) = (p[0], p[1]);
    let mut l = T::zero();
    for i in 0..n {
        for j in i + 1..n {
            let d = x[i] - x[j];
            l += d.sin() * d.cos() * v[j] * k + d.cos() / (j - i) as f64;
        }
    }
    for i in 0..=2 {
        l += x[i] * x[n - 1 - i] * ((n - 1 - i) as f64 + 1.0);
    }
    for i in 0..3 {
        l += x[2 * i] * x[2 * i].exp();
    }
    for i in 0..n {
        let w = if i == 0 || i == n - 1 {
            0.5
        } else if i == 2 {
            2.0
        } else {
            1.0
        };
        l += v[i] * v[i] * w;
    }
    let total_x = x.iter().fold(T::zero(), |a, &b| a + b);
    let total_v = v.iter().fold(T::zero(), |a, &b| a + b);
    let branch = if t > 0.5 { total_x * 0.25 } else { -total_x };
    let a = x[1] * v[2];
    l + total_x * total_v * 0.1 + v[0] * total_x + branch + a * a
}

/// The forms above against num-dual, on both sides of the branch in `t`.
#[test]
fn less_common_forms_match_num_dual() {
    let mut rng = Rng(0xF02);
    for t in [0.2, 0.9] {
        let lag = forms::Forms { k: 0.7 };
        for _ in 0..20 {
            let x = rng.vector::<5>(0.8);
            let v = rng.vector::<5>(1.5);
            let z: Vec<f64> = x.iter().chain(v.iter()).copied().collect();
            let (value, grad, hess) = dual_derivatives(&|w| forms_dual(w, [0.7, t]), &z);
            close("forms L", lag.value(&x, &v, t), value);
            let (f, q, h) = lag.gradient_and_hessian(&x, &v, t);
            for i in 0..5 {
                close("forms f", f[i], grad[i]);
                close("forms p", q[i], grad[5 + i]);
                for j in 0..5 {
                    close(&format!("forms xx[({i}, {j})]"), h.xx[(i, j)], hess[i][j]);
                    close(
                        &format!("forms xv[({i}, {j})]"),
                        h.xv[(i, j)],
                        hess[i][5 + j],
                    );
                    close(
                        &format!("forms vv[({i}, {j})]"),
                        h.vv[(i, j)],
                        hess[5 + i][5 + j],
                    );
                }
            }
        }
    }
}

models!(n4, 4);
models!(n16, 16);
models!(n64, 64);

/// The oracles: the same Lagrangians as plain generic fns of `z = (x, v)` (the chains are in
/// `varembed_tests::models::dual_chains`).
fn walled_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], p: [f64; 2]) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        let wall = if x[i].re() < 0.0 {
            x[i] * x[i] * p[0]
        } else {
            T::zero()
        };
        let speed = if v[i].abs().re() >= 0.5 {
            v[i].abs()
        } else {
            T::zero() + 0.5
        };
        let pin = (x[i] * (2.0 * std::f64::consts::PI)).cos() * speed * v[i].re().signum();
        l += v[i] * v[i] * 0.5 - wall + pin * 0.1;
    }
    l
}

/// The generated value and derivatives (every method) against the oracle's at random points,
/// and the claimed bandwidth against the Hessian.
fn check<const D: usize>(
    name: &str,
    lag: &impl Lagrangian<D>,
    oracle: fn(&[HyperDual64], [f64; 2]) -> HyperDual64,
    p: [f64; 2],
    rng: &mut Rng,
    points: usize,
) {
    for _ in 0..points {
        let x = rng.vector::<D>(0.8);
        let v = rng.vector::<D>(1.5);
        let h = assert_matches_oracle(name, lag, &|w| oracle(w, p), &x, &v);
        outside_band_is_zero(name, lag, &h);
    }
}

/// Every entry of the three blocks with `|i − j|` beyond the claimed bandwidth is exactly 0:
/// the claim checked against the Hessian itself, not against the macro's reasoning.
fn outside_band_is_zero<const D: usize>(
    name: &str,
    lag: &impl Lagrangian<D>,
    h: &varembed::Hessian<D>,
) {
    let Some(band) = lag.hessian_bandwidth() else {
        return;
    };
    for (block, m) in [("xx", &h.xx), ("xv", &h.xv), ("vv", &h.vv)] {
        for i in 0..D {
            for j in 0..D {
                if i.abs_diff(j) > band {
                    assert_eq!(
                        m[(i, j)],
                        0.0,
                        "{name}: {block}[({i}, {j})] outside the band {band}"
                    );
                }
            }
        }
    }
}

macro_rules! check_all {
    ($test:ident, $module:ident, $points:expr) => {
        #[test]
        fn $test() {
            use $module::*;
            let mut rng = Rng(0x100B5 + N as u64);
            let (alpha, beta) = (0.25, 0.7);
            check(
                "fput_fixed",
                &FputFixed { alpha, beta },
                fput_fixed_dual,
                [alpha, beta],
                &mut rng,
                $points,
            );
            check(
                "fput_helper",
                &FputHelper { alpha, beta },
                fput_fixed_dual,
                [alpha, beta],
                &mut rng,
                $points,
            );
            check(
                "fput_periodic",
                &FputPeriodic { alpha, beta },
                fput_periodic_dual,
                [alpha, beta],
                &mut rng,
                $points,
            );
            check(
                "toda",
                &Toda { a: 1.3, b: 0.8 },
                toda_dual,
                [1.3, 0.8],
                &mut rng,
                $points,
            );
            check(
                "n_link",
                &NLink { g: 9.81, l: 0.5 },
                n_link_dual,
                [9.81, 0.5],
                &mut rng,
                $points,
            );
            check(
                "walled",
                &Walled { k: 3.0 },
                walled_dual,
                [3.0, 0.0],
                &mut rng,
                $points,
            );
        }
    };
}

check_all!(loop_models_match_num_dual_at_n4, n4, 20);
check_all!(loop_models_match_num_dual_at_n16, n16, 4);
check_all!(loop_models_match_num_dual_at_n64, n64, 1);

/// The FPUT chain at N = 4 unrolled by hand, as the macro accepted it before loops.
#[lagrangian]
fn fput_unrolled(x: [f64; 4], v: [f64; 4], alpha: f64, beta: f64) -> f64 {
    let kinetic = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    let d0 = x[0];
    let d1 = x[1] - x[0];
    let d2 = x[2] - x[1];
    let d3 = x[3] - x[2];
    let d4 = -x[3];
    kinetic
        - (0.5 * d0 * d0 + alpha / 3.0 * d0.powi(3) + beta / 4.0 * d0.powi(4))
        - (0.5 * d1 * d1 + alpha / 3.0 * d1.powi(3) + beta / 4.0 * d1.powi(4))
        - (0.5 * d2 * d2 + alpha / 3.0 * d2.powi(3) + beta / 4.0 * d2.powi(4))
        - (0.5 * d3 * d3 + alpha / 3.0 * d3.powi(3) + beta / 4.0 * d3.powi(4))
        - (0.5 * d4 * d4 + alpha / 3.0 * d4.powi(3) + beta / 4.0 * d4.powi(4))
}

/// The `for` loop, iterator-sum + helper and hand-unrolled forms of one chain agree.
#[test]
fn loop_sum_helper_and_unrolled_forms_agree() {
    let mut rng = Rng(0xF0);
    let (alpha, beta) = (0.25, 0.7);
    let forms: [&dyn Lagrangian<4>; 3] = [
        &n4::FputFixed { alpha, beta },
        &n4::FputHelper { alpha, beta },
        &FputUnrolled { alpha, beta },
    ];
    for _ in 0..50 {
        let (x, v) = (rng.vector::<4>(1.0), rng.vector::<4>(1.0));
        let reference = forms[2].gradient_and_hessian(&x, &v, 0.0);
        for form in &forms[..2] {
            close("L", form.value(&x, &v, 0.0), forms[2].value(&x, &v, 0.0));
            let (f, p, h) = form.gradient_and_hessian(&x, &v, 0.0);
            let (l, vf, vp) = form.value_and_gradient(&x, &v, 0.0);
            close("fused L", l, forms[2].value(&x, &v, 0.0));
            for i in 0..4 {
                close("f", f[i], reference.0[i]);
                close("p", p[i], reference.1[i]);
                close("fused f", vf[i], reference.0[i]);
                close("fused p", vp[i], reference.1[i]);
            }
            for (a, b) in [
                (h.xx, reference.2.xx),
                (h.xv, reference.2.xv),
                (h.vv, reference.2.vv),
            ] {
                assert!((a - b).amax() <= 1e-12 * b.amax().max(1.0), "{a} {b}");
            }
        }
    }
}

/// The chain's Hessian is tridiagonal and its pattern is what `hessian_dependence` says.
#[test]
fn chain_hessian_is_tridiagonal() {
    let lag = n16::FputFixed {
        alpha: 0.25,
        beta: 0.7,
    };
    let mut rng = Rng(7);
    let (x, v) = (rng.vector::<16>(1.0), rng.vector::<16>(1.0));
    let h = lag.hessian(&x, &v, 0.0);
    for i in 0..16 {
        for j in 0..16 {
            assert_eq!(h.xx[(i, j)] != 0.0, i.abs_diff(j) <= 1, "xx[({i}, {j})]");
        }
    }
    assert_eq!(h.xv, Matrix::<16>::zeros());
    assert_eq!(h.vv, Matrix::<16>::identity());
    let dep = lag.hessian_dependence();
    assert!(dep.xx.x && !dep.xx.v && !dep.xx.t);
    assert!(!dep.xv.x && !dep.xv.v && !dep.vv.x && !dep.vv.v);
    // The text lists the derivatives of one bond, not of every entry.
    let text = n16::FputFixed::DERIVATIVES;
    assert!(
        text.contains("for i in 0..N - 1: ∂L/∂x[i + 1] += "),
        "{text}"
    );
    assert!(text.lines().count() < 20, "{text}");
    let _ = Vector::<16>::zeros();
}

/// `hessian_dependence` of models with loops, read off the loop bodies: the n-link pendulum's
/// mass matrix depends on the angles, its `xx` and `xv` on angles and rates.
#[test]
fn dependence_of_loop_models() {
    use varembed::Dependence;
    let on = |x: bool, v: bool| Dependence { x, v, t: false };
    let dep = n4::NLink { g: 1.0, l: 1.0 }.hessian_dependence();
    assert_eq!(
        (dep.xx, dep.xv, dep.vv),
        (on(true, true), on(true, true), on(true, false))
    );
    let dep = n4::FputPeriodic {
        alpha: 0.1,
        beta: 0.1,
    }
    .hessian_dependence();
    assert_eq!(
        (dep.xx, dep.xv, dep.vv),
        (on(true, false), on(false, false), on(false, false))
    );
    // `(x[1] v[2])²` makes `xv` depend on both; the sums' products keep `vv` constant.
    let dep = forms::Forms { k: 1.0 }.hessian_dependence();
    assert_eq!((dep.xv, dep.vv), (on(true, true), on(true, false)));
    assert!(forms::Forms { k: 1.0 }.dependence().t);
}

/// The structural bandwidth each model claims: a fixed-end chain is tridiagonal, a periodic
/// wrap or a double sum cannot be bounded, an unrolled model's is read off its entries. At
/// random points the claim holds (every entry outside the band is exactly 0, in `check` above
/// and here for the unrolled models).
#[test]
fn hessian_bandwidth_of_the_models() {
    use varembed_tests::models::generated::{DoublePendulum, Pendulum};
    let (alpha, beta) = (0.25, 0.7);
    assert_eq!(n64::FputFixed { alpha, beta }.hessian_bandwidth(), Some(1));
    assert_eq!(n64::FputHelper { alpha, beta }.hessian_bandwidth(), Some(1));
    assert_eq!(n64::FputPeriodic { alpha, beta }.hessian_bandwidth(), None);
    assert_eq!(n64::Toda { a: 1.0, b: 1.0 }.hessian_bandwidth(), None);
    assert_eq!(n64::NLink { g: 1.0, l: 1.0 }.hessian_bandwidth(), None);
    assert_eq!(n64::Walled { k: 1.0 }.hessian_bandwidth(), Some(0));
    assert_eq!(forms::Forms { k: 1.0 }.hessian_bandwidth(), None);
    assert_eq!(FputUnrolled { alpha, beta }.hessian_bandwidth(), Some(1));
    let double = DoublePendulum {
        m1: 1.0,
        m2: 2.0,
        l1: 1.0,
        l2: 0.5,
        g: 9.81,
    };
    assert_eq!(double.hessian_bandwidth(), Some(1));
    assert_eq!(Pendulum { g: 9.81, l: 1.0 }.hessian_bandwidth(), Some(0));
    // Through the blanket impl for references, as the solvers see a model.
    let by_ref = <&DoublePendulum as Lagrangian<2>>::hessian_bandwidth(&&double);
    assert_eq!(by_ref, Some(1));
    let mut rng = Rng(0xBA4D);
    for _ in 0..20 {
        let (x, v) = (rng.vector::<4>(1.0), rng.vector::<4>(1.0));
        let lag = FputUnrolled { alpha, beta };
        outside_band_is_zero("fput_unrolled", &lag, &lag.hessian(&x, &v, 0.0));
    }
}
