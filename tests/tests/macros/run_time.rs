//! `DynLagrangian` from `#[lagrangian]`: every model with loops implements it, and a model of
//! slices `x: &[f64]` whose length is a `usize` model constant implements only it.
//!
//! The FPUT chain (fixed ends, α and β), the periodic Toda lattice and the n-link pendulum are
//! written twice, with a named dimension `N` and with a run-time `n`. At N = 4, 16, 64 and
//! random points, the `DynLagrangian` value, force, momentum and Hessian (its entries summed
//! into dense blocks) of both agree with num-dual's hyper-dual oracle to 1e-12 relative, and
//! the named model's `DynLagrangian` impl with its own `Lagrangian<N>` impl, bit for bit. The
//! run-time models state the same bandwidth and dependences, and `invalid_dimension()` finds
//! the dimensions at which a run-time model reads beyond its components.

use num_dual::HyperDual64;
use varembed::{DynLagrangian, Lagrangian, SparseBlock, SparseHessian, Vector, lagrangian};
use varembed_tests::models::dual_chains::{fput_fixed_dual, n_link_dual, toda_dual};
// The FPUT chain of run-time length, shared with the solver's tests and benches.
use varembed_tests::models::generated::{FputChain as Fput, fput_chain as fput};
use varembed_tests::models::num_dual::{close, dual_derivatives};
use varembed_tests::rng::Rng;

/// Toda lattice, periodic: `V(d) = (a/b) e^{−b d} + a d`, iterator sum and `% n`.
#[lagrangian]
pub fn toda(x: &[f64], v: &[f64], a: f64, b: f64, n: usize) -> f64 {
    (0..n)
        .map(|i| {
            let d = x[(i + 1) % n] - x[i];
            0.5 * v[i] * v[i] - (a / b * (-b * d).exp() + a * d)
        })
        .sum()
}

/// An n-link pendulum of unit masses and lengths `l`: nested sums, `n` as a number.
#[lagrangian]
pub fn n_link(x: &[f64], v: &[f64], n: usize, g: f64, l: f64) -> f64 {
    let mut kinetic = 0.0;
    for i in 0..n {
        for j in 0..n {
            let mass_below = (n - i.max(j)) as f64;
            kinetic += 0.5 * l * l * mass_below * (x[i] - x[j]).cos() * v[i] * v[j];
        }
    }
    let potential: f64 = (0..n).map(|i| -g * l * (n - i) as f64 * x[i].cos()).sum();
    kinetic - potential
}

/// Reads `x[2]` whatever `n`: valid from `n = 3`.
#[lagrangian]
pub fn third(x: &[f64], v: &[f64], n: usize) -> f64 {
    let kinetic: f64 = (0..n).map(|i| 0.5 * v[i] * v[i]).sum();
    kinetic - x[2].powi(2)
}

/// Pairs `x[2i], x[2i + 1]` over `0..n / 2` and neighbours `x[i + 2]` over `0..n - 2`.
#[lagrangian]
pub fn pairs(x: &[f64], v: &[f64], n: usize, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n / 2 {
        l += 0.5 * v[2 * i] * v[2 * i + 1] - k * (x[2 * i + 1] - x[2 * i]).powi(2);
    }
    for i in 0..n - 2 {
        l -= x[i] * x[i + 2];
    }
    l
}

/// The same models with a named dimension, at `N = $n`.
macro_rules! named {
    ($module:ident, $n:expr) => {
        mod $module {
            use super::*;

            pub const N: usize = $n;

            #[lagrangian]
            pub fn fput(x: [f64; N], v: [f64; N], alpha: f64, beta: f64) -> f64 {
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

            #[lagrangian]
            pub fn toda(x: [f64; N], v: [f64; N], a: f64, b: f64) -> f64 {
                (0..N)
                    .map(|i| {
                        let d = x[(i + 1) % N] - x[i];
                        0.5 * v[i] * v[i] - (a / b * (-b * d).exp() + a * d)
                    })
                    .sum()
            }

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
        }
    };
}

named!(n4, 4);
named!(n16, 16);
named!(n64, 64);

/// A block's entries summed into a dense `d × d` matrix (row-major).
fn dense(block: &SparseBlock) -> Vec<Vec<f64>> {
    let d = block.dimension();
    let mut m = vec![vec![0.0; d]; d];
    for &(i, j, value) in block.entries() {
        m[i][j] += value;
    }
    m
}

/// Value, force, momentum and the three blocks of a `DynLagrangian` at `(x, v, 0)`.
type Evaluation = (f64, Vec<f64>, Vec<f64>, [Vec<Vec<f64>>; 3]);

fn evaluate(lag: &dyn DynLagrangian, x: &[f64], v: &[f64]) -> Evaluation {
    let d = lag.dimension();
    let (mut f, mut p) = (vec![f64::NAN; d], vec![f64::NAN; d]);
    lag.force(x, v, 0.0, &mut f);
    lag.momentum(x, v, 0.0, &mut p);
    let mut h = SparseHessian::new(d);
    lag.hessian(x, v, 0.0, &mut h);
    let blocks = [dense(&h.xx), dense(&h.xv), dense(&h.vv)];
    (lag.value(x, v, 0.0), f, p, blocks)
}

/// The `DynLagrangian` of `lag` against the hyper-dual oracle at `(x, v)`.
fn assert_dyn_matches_oracle(
    name: &str,
    lag: &dyn DynLagrangian,
    oracle: &dyn Fn(&[HyperDual64]) -> HyperDual64,
    x: &[f64],
    v: &[f64],
) {
    let d = lag.dimension();
    let z: Vec<f64> = x.iter().chain(v).copied().collect();
    let (value, grad, hess) = dual_derivatives(oracle, &z);
    let (l, f, p, [xx, xv, vv]) = evaluate(lag, x, v);
    close(&format!("{name} L"), l, value);
    for i in 0..d {
        close(&format!("{name} ∂L/∂x[{i}]"), f[i], grad[i]);
        close(&format!("{name} ∂L/∂v[{i}]"), p[i], grad[d + i]);
        for j in 0..d {
            close(&format!("{name} xx[({i}, {j})]"), xx[i][j], hess[i][j]);
            close(&format!("{name} xv[({i}, {j})]"), xv[i][j], hess[i][d + j]);
            close(
                &format!("{name} vv[({i}, {j})]"),
                vv[i][j],
                hess[d + i][d + j],
            );
        }
    }
}

/// The named model's two impls agree bit for bit: the same loops, in the same order.
fn assert_impls_agree<const D: usize, L: Lagrangian<D> + DynLagrangian>(
    name: &str,
    lag: &L,
    x: &Vector<D>,
    v: &Vector<D>,
) {
    assert_eq!(DynLagrangian::dimension(lag), D);
    let (l, f, p, [xx, xv, vv]) = evaluate(lag, x.as_slice(), v.as_slice());
    let (gf, gp, h) = lag.gradient_and_hessian(x, v, 0.0);
    assert_eq!(l, Lagrangian::value(lag, x, v, 0.0), "{name}: value");
    for i in 0..D {
        assert_eq!((f[i], p[i]), (gf[i], gp[i]), "{name}: gradient[{i}]");
        for j in 0..D {
            let dense = (h.xx[(i, j)], h.xv[(i, j)], h.vv[(i, j)]);
            assert_eq!((xx[i][j], xv[i][j], vv[i][j]), dense, "{name}: ({i}, {j})");
        }
    }
    assert_eq!(
        DynLagrangian::hessian_dependence(lag),
        Lagrangian::hessian_dependence(lag)
    );
    assert_eq!(
        DynLagrangian::hessian_bandwidth(lag),
        Lagrangian::hessian_bandwidth(lag)
    );
    assert_eq!(DynLagrangian::dependence(lag), Lagrangian::dependence(lag));
    assert_eq!(DynLagrangian::constants(lag), Lagrangian::constants(lag));
    assert_eq!(lag.invalid_dimension(), None);
}

/// The run-time model states what the named one does.
fn assert_same_properties(named: &dyn DynLagrangian, runtime: &dyn DynLagrangian) {
    assert_eq!(named.dimension(), runtime.dimension());
    assert_eq!(named.hessian_bandwidth(), runtime.hessian_bandwidth());
    assert_eq!(named.hessian_dependence(), runtime.hessian_dependence());
    assert_eq!(named.dependence(), runtime.dependence());
    assert_eq!(named.constants(), runtime.constants());
    assert_eq!(runtime.invalid_dimension(), None);
}

macro_rules! check_at {
    ($test:ident, $module:ident, $points:expr) => {
        #[test]
        fn $test() {
            use $module::N;
            let mut rng = Rng(0xD1A + N as u64);
            for (alpha, beta) in [(0.25, 0.0), (0.0, 0.7), (0.25, 0.7)] {
                let named = $module::Fput { alpha, beta };
                let runtime = Fput { n: N, alpha, beta };
                let oracle = move |w: &[HyperDual64]| fput_fixed_dual(w, [alpha, beta]);
                assert_same_properties(&named, &runtime);
                for _ in 0..$points {
                    let (x, v) = (rng.vector::<N>(0.8), rng.vector::<N>(1.5));
                    assert_impls_agree("fput", &named, &x, &v);
                    for lag in [&named as &dyn DynLagrangian, &runtime] {
                        assert_dyn_matches_oracle("fput", lag, &oracle, x.as_slice(), v.as_slice());
                    }
                }
            }
            let (a, b) = (1.3, 0.8);
            let named = $module::Toda { a, b };
            let runtime = Toda { n: N, a, b };
            assert_same_properties(&named, &runtime);
            let (g, l) = (9.81, 0.5);
            let named_link = $module::NLink { g, l };
            let runtime_link = NLink { n: N, g, l };
            assert_same_properties(&named_link, &runtime_link);
            for _ in 0..$points {
                let (x, v) = (rng.vector::<N>(0.8), rng.vector::<N>(1.5));
                assert_impls_agree("toda", &named, &x, &v);
                assert_impls_agree("n_link", &named_link, &x, &v);
                let (xs, vs) = (x.as_slice(), v.as_slice());
                for lag in [&named as &dyn DynLagrangian, &runtime] {
                    assert_dyn_matches_oracle("toda", lag, &|w| toda_dual(w, [a, b]), xs, vs);
                }
                for lag in [&named_link as &dyn DynLagrangian, &runtime_link] {
                    assert_dyn_matches_oracle("n_link", lag, &|w| n_link_dual(w, [g, l]), xs, vs);
                }
            }
        }
    };
}

check_at!(dyn_models_match_num_dual_at_n4, n4, 10);
check_at!(dyn_models_match_num_dual_at_n16, n16, 3);
check_at!(dyn_models_match_num_dual_at_n64, n64, 1);

/// One run-time model serves every dimension, the fn it came from included.
#[test]
fn one_runtime_model_any_dimension() {
    let mut rng = Rng(0x5EED);
    for n in [1, 2, 3, 7, 100] {
        let lag = Fput {
            n,
            alpha: 0.25,
            beta: 0.7,
        };
        assert_eq!(lag.invalid_dimension(), None, "n = {n}");
        let x: Vec<f64> = (0..n).map(|_| rng.uniform(-0.5, 0.5)).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let oracle = |w: &[HyperDual64]| fput_fixed_dual(w, [0.25, 0.7]);
        assert_dyn_matches_oracle("fput", &lag, &oracle, &x, &v);
        close("the fn", lag.value(&x, &v, 0.0), fput(&x, &v, n, 0.25, 0.7));
    }
    // The chain is tridiagonal at every `n`, as claimed.
    assert_eq!(Fput::default().hessian_bandwidth(), Some(1));
    assert_eq!(Toda::default().hessian_bandwidth(), None);
    assert_eq!(NLink::default().hessian_bandwidth(), None);
    assert_eq!(
        Fput::default().constants(),
        vec![("alpha", 0.0), ("beta", 0.0)]
    );
    assert!(Fput::DERIVATIVES.contains("for i in 0..n - 1: ∂L/∂x[i + 1] += "));
    assert!(NLink::DERIVATIVES.contains("for i in 0..n: for j in 0..n: "));
}

/// `invalid_dimension()` names the model, the dimension and what needs more components; it
/// finds nothing where every read is in range.
#[test]
fn invalid_dimension_reports_reads_beyond_n() {
    let fput = |n| Fput {
        n,
        alpha: 0.0,
        beta: 0.0,
    };
    let msg = fput(0).invalid_dimension().expect("0..n - 1 at n = 0");
    assert!(
        msg.contains("`fput_chain`") && msg.contains("0..n - 1"),
        "{msg}"
    );
    assert!(msg.contains("n = 0"), "{msg}");
    assert_eq!(fput(1).invalid_dimension(), None);

    let msg = Third { n: 2 }.invalid_dimension().expect("x[2] at n = 2");
    assert!(msg.contains("`third` reads component 2"), "{msg}");
    assert!(msg.contains("n = 2"), "{msg}");
    assert_eq!(Third { n: 3 }.invalid_dimension(), None);

    // `0..n - 2` needs n ≥ 2; `x[2 * i + 1]` over `0..n / 2` stays below n at every n.
    let msg = Pairs { n: 1, k: 1.0 }
        .invalid_dimension()
        .expect("0..n - 2 at n = 1");
    assert!(msg.contains("0..n - 2") && msg.contains("n = 1"), "{msg}");
    for n in [2, 3, 4, 9] {
        assert_eq!(Pairs { n, k: 1.0 }.invalid_dimension(), None, "n = {n}");
    }
    // A periodic lattice of no particles reads nothing.
    assert_eq!(
        Toda {
            n: 0,
            a: 1.0,
            b: 1.0
        }
        .invalid_dimension(),
        None
    );
}

/// A sum that a constant condition folds out of `L` (`v[1] - v[1]` is zero): the model was
/// written with a loop, so it implements `DynLagrangian` as every such model does, equal bit
/// for bit to its `Lagrangian<2>` (the differential fuzzer's seed 11 found it missing).
#[lagrangian]
#[allow(
    clippy::eq_op,
    reason = "the constant condition is the case under test"
)]
pub fn folded_sum(x: [f64; 2], v: [f64; 2], k: f64) -> f64 {
    let s: f64 = (0..2).map(|i| (x[(i + 1) % 2] - v[0]).sin()).sum();
    let kept = if v[1] - v[1] >= 0.1 {
        1.25 * s
    } else {
        0.5 * v[1] * v[1]
    };
    kept + k * x[1].cos()
}

#[test]
fn a_loop_folded_away_still_gives_a_dyn_lagrangian() {
    fn as_dyn(lag: &dyn DynLagrangian) -> &dyn DynLagrangian {
        lag
    }
    let model = FoldedSum { k: 0.7 };
    let (x, v) = ([0.3, -0.4], [0.2, 0.9]);
    let (xs, vs) = (Vector::<2>::from(x), Vector::<2>::from(v));
    let dynamic = as_dyn(&model);
    assert_eq!(dynamic.dimension(), 2);
    let want = 0.5 * 0.9 * 0.9 + 0.7 * (-0.4f64).cos();
    assert!((Lagrangian::value(&model, &xs, &vs, 0.0) - want).abs() < 1e-15);
    assert_eq!(
        dynamic.value(&x, &v, 0.0),
        Lagrangian::value(&model, &xs, &vs, 0.0)
    );
    let (mut f, mut p) = ([0.0; 2], [0.0; 2]);
    dynamic.force(&x, &v, 0.0, &mut f);
    dynamic.momentum(&x, &v, 0.0, &mut p);
    let (fs, ps) = Lagrangian::gradient(&model, &xs, &vs, 0.0);
    assert_eq!((f, p), (fs.into(), ps.into()));
    assert_eq!(p, [0.0, 0.9]);
    assert_eq!(f, [0.0, -0.7 * (-0.4f64).sin()]);
}
