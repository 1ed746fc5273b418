//! Chain Lagrangians in forms beyond the affine indices of `macro_loops.rs`: a named `usize`
//! const other than the dimension in ranges, indices, numbers and index `let`s (`for i in
//! 0..M`, `M as f64`, `let half = N / 2;`), and integer division of constants by a literal
//! (`0..N / 2`, `x[N / 2]`, `(N - 1) / 2`). Each model is written a second time as a plain
//! generic fn, differentiated by num-dual's hyper-dual numbers, and the generated value,
//! gradient and Hessian must agree to 1e-12 relative, at an even and an odd dimension, named
//! and literal.

use num_dual::{DualNum, HyperDual64};
use varembed::{Lagrangian, lagrangian};
use varembed_tests::models::num_dual::assert_matches_oracle;
use varembed_tests::rng::Rng;

/// The models of this file at dimension `N` (named, and the literal `$n`) with `M` dimers.
macro_rules! models {
    ($module:ident, $n:literal, $m:literal) => {
        mod $module {
            use super::*;

            pub const N: usize = $n;
            pub const M: usize = $m;

            /// `M` dimers `(x[2i], x[2i + 1])`, each a spring of stiffness growing with its
            /// number, with a pinning of the first particle after the dimers: `M` is a
            /// `usize` const other than the dimension, in a range, an index and a number.
            #[lagrangian]
            pub fn dimers(x: [f64; N], v: [f64; N], k: f64) -> f64 {
                let mut l = 0.0;
                let dimers = M;
                for i in 0..dimers {
                    let (a, b) = (x[2 * i], x[2 * i + 1]);
                    let stiffness = k * (M - i) as f64 / M as f64;
                    l += 0.5 * (v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1])
                        - stiffness * (b - a).powi(2)
                        - 0.25 * (b - a).powi(4);
                }
                l - x[2 * M].cos() * v[N - 1]
            }

            /// The same dimers with a literal dimension: `M` is checked against it by the
            /// compiler.
            #[lagrangian]
            pub fn dimers_literal(x: [f64; $n], v: [f64; $n], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..M {
                    let (a, b) = (x[2 * i], x[2 * i + 1]);
                    let stiffness = k * (M - i) as f64 / M as f64;
                    l += 0.5 * (v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1])
                        - stiffness * (b - a).powi(2)
                        - 0.25 * (b - a).powi(4);
                }
                l - x[2 * M].cos() * v[$n - 1]
            }

            /// A diatomic chain: the pairs `0..N / 2` bound inside, the `(N - 1) / 2` bonds
            /// between pairs, the middle particle `x[N / 2]` pinned with weight `N / 2`.
            #[lagrangian]
            pub fn diatomic(x: [f64; N], v: [f64; N], k: f64) -> f64 {
                let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
                let mut potential = 0.0;
                for i in 0..N / 2 {
                    let d = x[2 * i + 1] - x[2 * i];
                    potential += k * d * d + (d * v[2 * i]).sin();
                }
                let half = N / 2;
                for j in 0..(N - 1) / 2 {
                    potential += 0.5 * (x[2 * j + 2] - x[2 * j + 1]).powi(4);
                }
                kinetic - potential - half as f64 * 0.1 * x[half].powi(2)
            }

            /// No loop: a literal dimension and a component named by `M` alone.
            #[lagrangian]
            pub fn pinned(x: [f64; $n], v: [f64; $n]) -> f64 {
                let left = M - 1;
                0.5 * v[M] * v[M] - (M as f64) * x[M].powi(2) * x[left]
            }

            /// The diatomic chain with a literal dimension (the divisions fold to numbers).
            #[lagrangian]
            pub fn diatomic_literal(x: [f64; $n], v: [f64; $n], k: f64) -> f64 {
                let kinetic: f64 = (0..$n).map(|i| 0.5 * v[i] * v[i]).sum();
                let mut potential = 0.0;
                for i in 0..$n / 2 {
                    let d = x[2 * i + 1] - x[2 * i];
                    potential += k * d * d + (d * v[2 * i]).sin();
                }
                for j in 0..($n - 1) / 2 {
                    potential += 0.5 * (x[2 * j + 2] - x[2 * j + 1]).powi(4);
                }
                kinetic - potential - ($n / 2) as f64 * 0.1 * x[$n / 2].powi(2)
            }
        }
    };
}

models!(n8, 8, 3);
models!(n7, 7, 2);

/// The oracle of `dimers` at dimension `n` with `m` dimers.
fn dimers_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64, m: usize) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..m {
        let (a, b) = (x[2 * i], x[2 * i + 1]);
        let stiffness = k * (m - i) as f64 / m as f64;
        l += (v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1]) * 0.5
            - (b - a).powi(2) * stiffness
            - (b - a).powi(4) * 0.25;
    }
    l - x[2 * m].cos() * v[n - 1]
}

/// The oracle of `pinned` with `M = m`.
fn pinned_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], m: usize) -> T {
    let (x, v) = z.split_at(z.len() / 2);
    v[m] * v[m] * 0.5 - x[m].powi(2) * x[m - 1] * m as f64
}

/// The oracle of `diatomic` at dimension `n`.
fn diatomic_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let kinetic = v.iter().fold(T::zero(), |s, &w| s + w * w * 0.5);
    let mut potential = T::zero();
    for i in 0..n / 2 {
        let d = x[2 * i + 1] - x[2 * i];
        potential += d * d * k + (d * v[2 * i]).sin();
    }
    for j in 0..(n - 1) / 2 {
        potential += (x[2 * j + 2] - x[2 * j + 1]).powi(4) * 0.5;
    }
    kinetic - potential - x[n / 2].powi(2) * ((n / 2) as f64 * 0.1)
}

/// The generated value and derivatives (every method) against the oracle's at random points.
fn check<const D: usize>(
    name: &str,
    lag: &impl Lagrangian<D>,
    oracle: &dyn Fn(&[HyperDual64]) -> HyperDual64,
    rng: &mut Rng,
) {
    for _ in 0..10 {
        let x = rng.vector::<D>(0.8);
        let v = rng.vector::<D>(1.5);
        assert_matches_oracle(name, lag, oracle, &x, &v);
    }
}

#[test]
fn a_named_usize_const_in_ranges_indices_and_numbers_matches_num_dual() {
    let mut rng = Rng(0xD1);
    let k = 1.3;
    check(
        "dimers 8",
        &n8::Dimers { k },
        &|z| dimers_dual(z, k, 3),
        &mut rng,
    );
    check(
        "dimers 7",
        &n7::Dimers { k },
        &|z| dimers_dual(z, k, 2),
        &mut rng,
    );
    let d = |z: &[HyperDual64]| dimers_dual(z, k, 3);
    check("dimers literal 8", &n8::DimersLiteral { k }, &d, &mut rng);
    let d = |z: &[HyperDual64]| dimers_dual(z, k, 2);
    check("dimers literal 7", &n7::DimersLiteral { k }, &d, &mut rng);
    check("pinned 8", &n8::Pinned, &|z| pinned_dual(z, 3), &mut rng);
    check("pinned 7", &n7::Pinned, &|z| pinned_dual(z, 2), &mut rng);
}

#[test]
fn division_of_constants_in_ranges_and_indices_matches_num_dual() {
    let mut rng = Rng(0xD2);
    let k = 0.7;
    let d = |z: &[HyperDual64]| diatomic_dual(z, k);
    check("diatomic 8", &n8::Diatomic { k }, &d, &mut rng);
    check("diatomic 7", &n7::Diatomic { k }, &d, &mut rng);
    check(
        "diatomic literal 8",
        &n8::DiatomicLiteral { k },
        &d,
        &mut rng,
    );
    check(
        "diatomic literal 7",
        &n7::DiatomicLiteral { k },
        &d,
        &mut rng,
    );
}

/// The loops stay loops over the consts as written: the text names `M` and `N / 2`.
#[test]
fn derivatives_text_keeps_the_named_ranges() {
    let text = n8::Dimers::DERIVATIVES;
    assert!(
        text.contains("for i in 0..M: ∂L/∂x[2 * i + 1] += "),
        "{text}"
    );
    let text = n8::Diatomic::DERIVATIVES;
    assert!(
        text.contains("for i in 0..(N / 2): ∂L/∂x[2 * i + 1] += "),
        "{text}"
    );
    assert!(
        text.contains("for j in 0..((N - 1) / 2): ∂L/∂x[2 * j + 2] += "),
        "{text}"
    );
    assert!(text.contains("x[(N / 2)]"), "{text}");
    assert!(text.lines().count() < 40, "{text}");
}
