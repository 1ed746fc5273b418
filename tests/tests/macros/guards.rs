//! Indices guarded by the condition of an `if`: a chain with fixed ends written with its
//! neighbours read in branches, `let left = if i > 0 { x[i - 1] } else { 0.0 };`, so that one
//! loop covers the boundary particles. Each model is written a second time as a plain generic
//! fn, differentiated by num-dual's hyper-dual numbers: at N = 1, 2 and 5 (named, literal and
//! run-time dimension) the generated value, gradient and Hessian agree with it to 1e-12
//! relative, the `DynLagrangian` impl of a named model with its `Lagrangian<N>` impl bit for
//! bit, every entry beyond the claimed bandwidth is exactly 0, and a run-time model's
//! `invalid_dimension()` finds nothing to report.

use num_dual::{DualNum, HyperDual64};
use varembed::{DynLagrangian, Lagrangian, SparseBlock, SparseHessian, Vector, lagrangian};
use varembed_tests::models::num_dual::{assert_matches_oracle, close, dual_derivatives};
use varembed_tests::rng::Rng;

/// The models at a named dimension `N = $n`, and at the literal `$n`.
macro_rules! models {
    ($module:ident, $n:literal) => {
        mod $module {
            use super::*;

            pub const N: usize = $n;

            /// A chain with fixed ends `x_{-1} = x_N = 0`: the neighbours read in branches,
            /// the left one with the condition negated, the right one in an iterator sum.
            #[lagrangian]
            pub fn fixed(x: [f64; N], v: [f64; N], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..N {
                    let left = if i == 0 { 0.0 } else { x[i - 1] };
                    l += 0.5 * v[i] * v[i]
                        - 0.5 * k * (x[i] - left).powi(2)
                        - 0.25 * (x[i] - left).powi(4);
                }
                let walls: f64 = (0..N)
                    .map(|j| {
                        let right = if j + 1 < N { x[j + 1] } else { 0.0 };
                        (right - x[j]).cosh() * (1.0 + v[j] * right)
                    })
                    .sum();
                l - walls
            }

            /// Both neighbours in one branch, `&&`, an `else if` and an index guarded by a
            /// condition on `N - 1 - i`: a discrete Laplacian coupled to the velocities.
            #[lagrangian]
            pub fn laplacian(x: [f64; N], v: [f64; N], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..N {
                    let lap = if i > 0 && i + 1 < N {
                        x[i - 1] - 2.0 * x[i] + x[i + 1]
                    } else if i > 0 {
                        x[i - 1] - x[i]
                    } else if N - 1 - i > 0 {
                        x[i + 1] - x[i]
                    } else {
                        0.0
                    };
                    l += 0.5 * v[i] * v[i] + k * lap * x[i] * (1.0 + 0.1 * v[i] * lap);
                }
                l
            }

            /// `fixed` at the literal dimension.
            #[lagrangian]
            pub fn fixed_literal(x: [f64; $n], v: [f64; $n], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..$n {
                    let left = if i == 0 { 0.0 } else { x[i - 1] };
                    l += 0.5 * v[i] * v[i]
                        - 0.5 * k * (x[i] - left).powi(2)
                        - 0.25 * (x[i] - left).powi(4);
                }
                let walls: f64 = (0..$n)
                    .map(|j| {
                        let right = if j + 1 < $n { x[j + 1] } else { 0.0 };
                        (right - x[j]).cosh() * (1.0 + v[j] * right)
                    })
                    .sum();
                l - walls
            }
        }
    };
}

/// A component guarded by a condition on a `usize` const other than the dimension: the
/// guard `i < M` keeps `x[i + 1]` below `N` when `M < N`, a check left to the compiler.
mod with_const {
    use super::*;

    pub const N: usize = 5;
    pub const M: usize = 3;

    #[lagrangian]
    pub fn first_bonds(x: [f64; N], v: [f64; N], k: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..N {
            let right = if i < M { x[i + 1] } else { x[i] };
            l += 0.5 * v[i] * v[i] - 0.5 * k * (right - x[i]).powi(2) * (1.0 + x[i] * x[i]);
        }
        l
    }
}

fn first_bonds_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64, m: usize) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        let right = if i < m { x[i + 1] } else { x[i] };
        l += v[i] * v[i] * 0.5 - (right - x[i]).powi(2) * (x[i] * x[i] + 1.0) * (0.5 * k);
    }
    l
}

#[test]
fn a_guard_on_another_const_matches_num_dual() {
    let mut rng = Rng(0xC0457);
    let k = 0.9;
    let lag = with_const::FirstBonds { k };
    let oracle = |w: &[HyperDual64]| first_bonds_dual(w, k, with_const::M);
    for _ in 0..10 {
        let (x, v) = (rng.vector::<5>(0.8), rng.vector::<5>(1.5));
        check_named("first bonds", &lag, &oracle, &x, &v);
    }
    let text = with_const::FirstBonds::DERIVATIVES;
    assert!(
        text.contains("for i in 0..N: if i < M: ∂L/∂x[i + 1] += "),
        "{text}"
    );
}

models!(n1, 1);
models!(n2, 2);
models!(n5, 5);

/// `fixed` at a run-time dimension.
#[lagrangian]
pub fn fixed_runtime(x: &[f64], v: &[f64], n: usize, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let left = if i == 0 { 0.0 } else { x[i - 1] };
        l += 0.5 * v[i] * v[i] - 0.5 * k * (x[i] - left).powi(2) - 0.25 * (x[i] - left).powi(4);
    }
    let walls: f64 = (0..n)
        .map(|j| {
            let right = if j + 1 < n { x[j + 1] } else { 0.0 };
            (right - x[j]).cosh() * (1.0 + v[j] * right)
        })
        .sum();
    l - walls
}

/// `laplacian` at a run-time dimension.
#[lagrangian]
pub fn laplacian_runtime(x: &[f64], v: &[f64], n: usize, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let lap = if i > 0 && i + 1 < n {
            x[i - 1] - 2.0 * x[i] + x[i + 1]
        } else if i > 0 {
            x[i - 1] - x[i]
        } else if n - 1 - i > 0 {
            x[i + 1] - x[i]
        } else {
            0.0
        };
        l += 0.5 * v[i] * v[i] + k * lap * x[i] * (1.0 + 0.1 * v[i] * lap);
    }
    l
}

fn fixed_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        let left = if i == 0 { T::zero() } else { x[i - 1] };
        l += v[i] * v[i] * 0.5 - (x[i] - left).powi(2) * (0.5 * k) - (x[i] - left).powi(4) * 0.25;
    }
    for j in 0..n {
        let right = if j + 1 < n { x[j + 1] } else { T::zero() };
        l -= (right - x[j]).cosh() * (v[j] * right + 1.0);
    }
    l
}

fn laplacian_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        let lap = if i > 0 && i + 1 < n {
            x[i - 1] - x[i] * 2.0 + x[i + 1]
        } else if i > 0 {
            x[i - 1] - x[i]
        } else if i + 1 < n {
            x[i + 1] - x[i]
        } else {
            T::zero()
        };
        l += v[i] * v[i] * 0.5 + lap * x[i] * k * (v[i] * lap * 0.1 + 1.0);
    }
    l
}

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

/// The `DynLagrangian` of `lag` against the hyper-dual oracle at `(x, v)`, and every entry
/// of its blocks beyond its claimed bandwidth exactly 0.
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
    let (l, f, p, blocks) = evaluate(lag, x, v);
    close(&format!("{name} L"), l, value);
    let band = lag.hessian_bandwidth().expect("a banded model");
    for i in 0..d {
        close(&format!("{name} ∂L/∂x[{i}]"), f[i], grad[i]);
        close(&format!("{name} ∂L/∂v[{i}]"), p[i], grad[d + i]);
        for j in 0..d {
            let oracle = [hess[i][j], hess[i][d + j], hess[d + i][d + j]];
            for ((block, m), o) in ["xx", "xv", "vv"].iter().zip(&blocks).zip(oracle) {
                close(&format!("{name} {block}[({i}, {j})]"), m[i][j], o);
                if i.abs_diff(j) > band {
                    assert_eq!(m[i][j], 0.0, "{name}: {block}[({i}, {j})] beyond {band}");
                }
            }
        }
    }
}

/// The named model against the oracle through both impls, which agree bit for bit, and its
/// Hessian zero beyond the claimed bandwidth.
fn check_named<const D: usize, L: Lagrangian<D> + DynLagrangian>(
    name: &str,
    lag: &L,
    oracle: &dyn Fn(&[HyperDual64]) -> HyperDual64,
    x: &Vector<D>,
    v: &Vector<D>,
) {
    let h = assert_matches_oracle(name, lag, oracle, x, v);
    let band = Lagrangian::hessian_bandwidth(lag).expect("a banded model");
    for (block, m) in [("xx", &h.xx), ("xv", &h.xv), ("vv", &h.vv)] {
        for i in 0..D {
            for j in 0..D {
                if i.abs_diff(j) > band {
                    assert_eq!(m[(i, j)], 0.0, "{name}: {block}[({i}, {j})] beyond {band}");
                }
            }
        }
    }
    let (xs, vs) = (x.as_slice(), v.as_slice());
    assert_dyn_matches_oracle(name, lag, oracle, xs, vs);
    let (l, f, p, [xx, xv, vv]) = evaluate(lag, xs, vs);
    let (gf, gp, h) = lag.gradient_and_hessian(x, v, 0.0);
    assert_eq!(l, Lagrangian::value(lag, x, v, 0.0), "{name}: value");
    for i in 0..D {
        assert_eq!((f[i], p[i]), (gf[i], gp[i]), "{name}: gradient[{i}]");
        for j in 0..D {
            let dense = (h.xx[(i, j)], h.xv[(i, j)], h.vv[(i, j)]);
            assert_eq!((xx[i][j], xv[i][j], vv[i][j]), dense, "{name}: ({i}, {j})");
        }
    }
}

macro_rules! check_at {
    ($test:ident, $module:ident) => {
        #[test]
        fn $test() {
            use $module::N;
            let mut rng = Rng(0x6A4D + N as u64);
            let k = 1.3;
            let fixed = |w: &[HyperDual64]| fixed_dual(w, k);
            let laplacian = |w: &[HyperDual64]| laplacian_dual(w, k);
            let runtime_fixed = FixedRuntime { n: N, k };
            let runtime_laplacian = LaplacianRuntime { n: N, k };
            assert_eq!(runtime_fixed.invalid_dimension(), None);
            assert_eq!(runtime_laplacian.invalid_dimension(), None);
            for _ in 0..10 {
                let (x, v) = (rng.vector::<N>(0.8), rng.vector::<N>(1.5));
                check_named("fixed", &$module::Fixed { k }, &fixed, &x, &v);
                check_named("literal", &$module::FixedLiteral { k }, &fixed, &x, &v);
                check_named("laplacian", &$module::Laplacian { k }, &laplacian, &x, &v);
                let (xs, vs) = (x.as_slice(), v.as_slice());
                assert_dyn_matches_oracle("run-time fixed", &runtime_fixed, &fixed, xs, vs);
                let lap = &runtime_laplacian;
                assert_dyn_matches_oracle("run-time laplacian", lap, &laplacian, xs, vs);
            }
        }
    };
}

check_at!(guarded_neighbours_match_num_dual_at_n1, n1);
check_at!(guarded_neighbours_match_num_dual_at_n2, n2);
check_at!(guarded_neighbours_match_num_dual_at_n5, n5);

/// The chain is tridiagonal; the Laplacian's square couples next-but-one neighbours. Claims
/// that the tests above check against the Hessian.
#[test]
fn guarded_chains_claim_their_bandwidth() {
    for band in [
        Lagrangian::hessian_bandwidth(&n5::Fixed { k: 1.0 }),
        Lagrangian::hessian_bandwidth(&n5::FixedLiteral { k: 1.0 }),
        DynLagrangian::hessian_bandwidth(&FixedRuntime { n: 5, k: 1.0 }),
    ] {
        assert_eq!(band, Some(1));
    }
    for band in [
        Lagrangian::hessian_bandwidth(&n5::Laplacian { k: 1.0 }),
        DynLagrangian::hessian_bandwidth(&LaplacianRuntime { n: 5, k: 1.0 }),
    ] {
        assert_eq!(band, Some(2));
    }
}

/// The derivatives with respect to a guarded component are added where the guard holds, and
/// the text says so; the fn itself is still there.
#[test]
fn derivatives_text_names_the_guards() {
    let text = n5::Fixed::DERIVATIVES;
    assert!(
        text.contains("for i in 0..N: if i >= 1: ∂L/∂x[i - 1] += "),
        "{text}"
    );
    assert!(
        text.contains("for j in 0..N: if j < N - 1: ∂L/∂x[j + 1] += "),
        "{text}"
    );
    assert!(
        text.contains("for i in 0..N: if i >= 1: ∂²L/∂x[i - 1]∂x[i] += "),
        "{text}"
    );
    let x = [0.1, 0.2, 0.3, 0.4, 0.5];
    let lag = n5::Fixed { k: 2.0 };
    let l = Lagrangian::value(&lag, &Vector::<5>::from(x), &Vector::<5>::zeros(), 0.0);
    assert!((n5::fixed(x, [0.0; 5], 2.0) - l).abs() < 1e-12);
}

/// A guard that keeps an index in range only for some dimensions: `x[i + 1]` read while
/// `i < 3` needs `n ≥ 4` (or `n = 0`, where no iteration reads it), which
/// `invalid_dimension()` checks over the iterations the guard lets through.
#[lagrangian]
pub fn near_start(x: &[f64], v: &[f64], n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let right = if i < 3 { x[i + 1] } else { 0.0 };
        l += 0.5 * v[i] * v[i] - right * x[i];
    }
    l
}

#[test]
fn invalid_dimension_follows_the_guard() {
    for (n, valid) in [
        (0, true),
        (1, false),
        (2, false),
        (3, false),
        (4, true),
        (9, true),
    ] {
        let report = NearStart { n }.invalid_dimension();
        assert_eq!(report.is_none(), valid, "n = {n}: {report:?}");
    }
    let report = NearStart { n: 3 }.invalid_dimension().expect("reads x[3]");
    assert!(report.contains("reads component 3"), "{report}");
}
