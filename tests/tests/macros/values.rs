//! Values bound together: local arrays (`let a = [b * x[1], -b * x[0], 0.0];`, read at literal
//! indices and in loops over a literal range, which the macro unrolls) and helpers returning
//! tuples and arrays (`let (a, b) = polar(…);`, `let c = cross(…); c[2]`, `polar(…).0`). Each
//! model is written a second time as a plain generic fn, differentiated by num-dual's
//! hyper-dual numbers, and the generated value, gradient and Hessian must agree to 1e-12
//! relative.

#![allow(
    dead_code,
    reason = "the #[lagrangian] fns stay callable, but these tests use the generated structs"
)]

use num_dual::DualNum;
use varembed::{DynLagrangian, Lagrangian, Vector, lagrangian};
use varembed_tests::models::num_dual::assert_matches_oracle;
use varembed_tests::rng::Rng;

/// The point `(r cos θ, r sin θ)`.
#[lagrangian(helper)]
fn polar(r: f64, theta: f64) -> (f64, f64) {
    let (s, c) = theta.sin_cos();
    (r * c, r * s)
}

/// `a × b`.
#[lagrangian(helper)]
fn cross(a0: f64, a1: f64, a2: f64, b0: f64, b1: f64, b2: f64) -> [f64; 3] {
    [a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0]
}

/// `|a × b|²`, through the helper returning an array, read in an unrolled loop.
#[lagrangian(helper)]
fn cross_squared(a0: f64, a1: f64, a2: f64, b0: f64, b1: f64, b2: f64) -> f64 {
    let c = cross(a0, a1, a2, b0, b1, b2);
    let mut s = 0.0;
    for k in 0..3 {
        s += c[k] * c[k];
    }
    s
}

/// A helper returning a tuple through another: the polar point and its squared radius.
#[lagrangian(helper)]
fn polar_and_radius(r: f64, theta: f64) -> [f64; 3] {
    let p = polar(r, theta);
    [p.0, p.1, p.0 * p.0 + p.1 * p.1]
}

/// A particle in a frame spinning at rate `b` about the third axis: the frame velocity
/// `a = b ẑ × x` as a local array, the kinetic energy `½|v + a|²` as an unrolled loop, and
/// the helpers' tuples and arrays in the potential.
#[lagrangian]
fn spinning(x: [f64; 3], v: [f64; 3], b: f64, k: f64) -> f64 {
    let a = [-b * x[1], b * x[0], 0.0];
    let mut kinetic = 0.0;
    for i in 0..3 {
        let w = v[i] + a[i];
        kinetic += 0.5 * w * w;
    }
    let (px, py) = polar(x[2], x[0]);
    let [c0, _, c2] = cross(x[0], x[1], x[2], v[0], v[1], v[2]);
    let r = polar_and_radius(x[1], x[2]);
    let drag: f64 = (0..3).map(|i| a[i] * v[i]).sum();
    kinetic + drag
        - k * (px * py + c0 * c2 + r[2] * r[0])
        - 0.1 * cross_squared(x[0], x[1], x[2], 1.0, 0.5, 0.25)
        + polar(v[0], x[1]).1
}

fn spinning_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], b: f64, k: f64) -> T {
    let (x, v) = z.split_at(3);
    let a = [x[1] * -b, x[0] * b, T::zero()];
    let mut kinetic = T::zero();
    for i in 0..3 {
        let w = v[i] + a[i];
        kinetic += w * w * 0.5;
    }
    let polar = |r: T, t: T| (r * t.cos(), r * t.sin());
    let cross = |a: [T; 3], b: [T; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let (px, py) = polar(x[2], x[0]);
    let c = cross([x[0], x[1], x[2]], [v[0], v[1], v[2]]);
    let p = polar(x[1], x[2]);
    let r = [p.0, p.1, p.0 * p.0 + p.1 * p.1];
    let drag = a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
    let one = T::one();
    let d = cross([x[0], x[1], x[2]], [one, one * 0.5, one * 0.25]);
    let cross_squared = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    kinetic + drag - (px * py + c[0] * c[2] + r[2] * r[0]) * k - cross_squared * 0.1
        + polar(v[0], x[1]).1
}

#[test]
fn local_arrays_and_helpers_returning_values_match_num_dual() {
    let mut rng = Rng(0xA77);
    let (b, k) = (0.8, 1.3);
    let lag = Spinning { b, k };
    for _ in 0..10 {
        let x = rng.vector::<3>(1.0);
        let v = rng.vector::<3>(1.5);
        assert_matches_oracle("spinning", &lag, &|z| spinning_dual(z, b, k), &x, &v);
    }
    // The loops over the local arrays are unrolled: no sum is left in the text.
    assert!(
        !Spinning::DERIVATIVES.contains('Σ'),
        "{}",
        Spinning::DERIVATIVES
    );
}

const N: usize = 5;

/// A pair of values from one particle: its displacement and velocity, scaled.
#[lagrangian(helper)]
fn scaled(q: f64, p: f64, s: f64) -> (f64, f64) {
    (s * q, s * p)
}

/// A chain whose bonds are local arrays in a loop over the particles (an unrolled loop
/// inside a kept one), whose kinetic terms come from a helper's tuple, with a product over a
/// local array (`*=` in an unrolled loop is a product: the loop is straight-line code), and
/// neighbours read through a constant condition in the unrolled loop (`k > 0` decides which
/// branch is read, so `w[k - 1]` at `k = 0` is never read).
#[lagrangian]
fn bonds(x: [f64; N], v: [f64; N], k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        let (q, p) = scaled(x[i], v[i], 0.5);
        l += p * p - 0.1 * q * q;
    }
    for i in 0..N - 1 {
        let d = [x[i + 1] - x[i], v[i + 1] - v[i]];
        for j in 0..2 {
            l -= 0.5 * k * d[j] * d[j];
        }
    }
    let w = [x[0], x[1], x[N - 1]];
    let mut product = 1.0;
    for j in 0..3 {
        let previous = if j > 0 { w[j - 1] } else { 1.0 };
        product *= 1.0 + previous * w[j] * w[j];
    }
    l - product.ln()
}

fn bonds_dual<T: DualNum<Primitive = f64> + Copy>(z: &[T], k: f64) -> T {
    let n = z.len() / 2;
    let (x, v) = z.split_at(n);
    let mut l = T::zero();
    for i in 0..n {
        let (q, p) = (x[i] * 0.5, v[i] * 0.5);
        l += p * p - q * q * 0.1;
    }
    for i in 0..n - 1 {
        let d = [x[i + 1] - x[i], v[i + 1] - v[i]];
        for dj in d {
            l -= dj * dj * (0.5 * k);
        }
    }
    let w = [x[0], x[1], x[n - 1]];
    let mut product = T::one();
    for j in 0..3 {
        let previous = if j > 0 { w[j - 1] } else { T::one() };
        product *= T::one() + previous * w[j] * w[j];
    }
    l - product.ln()
}

#[test]
fn arrays_in_chain_loops_match_num_dual() {
    let mut rng = Rng(0xB0D);
    let k = 0.7;
    let lag = Bonds { k };
    for _ in 0..10 {
        let x = rng.vector::<N>(0.8);
        let v = rng.vector::<N>(1.5);
        assert_matches_oracle("bonds", &lag, &|z| bonds_dual(z, k), &x, &v);
        // The run-time impl computes the same numbers.
        let (xs, vs) = (x.as_slice(), v.as_slice());
        assert_eq!(
            DynLagrangian::value(&lag, xs, vs, 0.0),
            Lagrangian::value(&lag, &x, &v, 0.0)
        );
    }
    // The loop over the particles stays a loop; the one over a bond's two values does not.
    let text = Bonds::DERIVATIVES;
    assert!(
        text.contains("for i in 0..N - 1: ∂L/∂x[i + 1] += "),
        "{text}"
    );
    assert!(!text.contains("for j in"), "{text}");
}

#[test]
fn helpers_returning_values_are_still_fns() {
    assert_eq!(polar(2.0, 0.0), (2.0, 0.0));
    assert_eq!(cross(1.0, 0.0, 0.0, 0.0, 1.0, 0.0), [0.0, 0.0, 1.0]);
    let lag = Spinning { b: 0.0, k: 0.0 };
    let zero = Vector::<3>::zeros();
    assert_eq!(lag.value(&zero, &zero, 0.0), 0.0);
}
