//! Every supported function, through `#[lagrangian]`, against hand-written first and second
//! derivatives at `1e-12` relative.
//!
//! Each Lagrangian is `L = f(x)` (or `f(x, v)` for the two-argument functions), so
//! `∂L/∂x = f'(x)` and `∂²L/∂x² = f''(x)`.

#![allow(
    dead_code,
    reason = "the #[lagrangian] fns stay callable, but these tests only use the generated structs"
)]

use std::f64;

use varembed::{Lagrangian, Vector, lagrangian};

const TOL: f64 = 1e-12;

fn close(what: &str, got: f64, want: f64) {
    let err = (got - want).abs();
    assert!(
        err <= TOL * want.abs().max(f64::MIN_POSITIVE) || got == want,
        "{what}: got {got:e}, want {want:e} (relative error {:e})",
        err / want.abs()
    );
}

/// Checks value, `f'` and `f''` of a one-variable `L = f(x)` at each point; the velocity
/// derivatives must vanish.
fn check_unary(
    lag: &impl Lagrangian<1>,
    points: &[f64],
    f: impl Fn(f64) -> f64,
    d1: impl Fn(f64) -> f64,
    d2: impl Fn(f64) -> f64,
) {
    for &x in points {
        let (xv, vv) = (Vector::<1>::new(x), Vector::<1>::new(0.7));
        close(&format!("L({x})"), lag.value(&xv, &vv, 0.0), f(x));
        let (fx, fv) = lag.gradient(&xv, &vv, 0.0);
        close(&format!("L'({x})"), fx[0], d1(x));
        assert_eq!(fv[0], 0.0);
        let hs = lag.hessian(&xv, &vv, 0.0);
        close(&format!("L''({x})"), hs.xx[(0, 0)], d2(x));
        assert_eq!((hs.xv[(0, 0)], hs.vv[(0, 0)]), (0.0, 0.0));
    }
}

const POINTS: [f64; 4] = [-1.3, -0.4, 0.25, 0.9];
const POSITIVE: [f64; 4] = [0.05, 0.4, 1.7, 12.5];

#[lagrangian]
fn l_sin(x: f64, _v: f64) -> f64 {
    x.sin()
}
#[test]
fn sin() {
    check_unary(&LSin, &POINTS, f64::sin, f64::cos, |x| -x.sin());
}

#[lagrangian]
fn l_cos(x: f64, _v: f64) -> f64 {
    f64::cos(x)
}
#[test]
fn cos() {
    check_unary(&LCos, &POINTS, f64::cos, |x| -x.sin(), |x| -x.cos());
}

#[lagrangian]
fn l_tan(x: f64, _v: f64) -> f64 {
    x.tan()
}
#[test]
fn tan() {
    let sec2 = |x: f64| 1.0 / (x.cos() * x.cos());
    check_unary(&LTan, &POINTS, f64::tan, sec2, |x| 2.0 * sec2(x) * x.tan());
}

/// Points of `asin` and `acos` next to ±1, where `1 − x·x` loses the low bits of `x·x`: the
/// rule `1/√(1 − x·x)` is off by 1.8e-9, 2.5e-10, 7.5e-12, 2.8e-12 and 5.5e-12 relative there
/// (its second derivative by three times as much; Python against mpmath), where the macro's
/// `(1 − x)(1 + x)` is within a few ulps.
const NEAR_ONE: [f64; 5] = [
    1.0 - 7.4e-9,
    -(1.0 - 1e-9),
    1.0 - 3e-11,
    -(1.0 - 2e-6),
    0.999999,
];

/// `1 − x²` to a few ulps at every `|x| ≤ 1`: `δ(2 − δ)` with `δ = 1 − |x|`, which is exact
/// for `|x| ≥ ½` (Sterbenz), so that only the product's two roundings remain.
fn one_minus_square(x: f64) -> f64 {
    let delta = 1.0 - x.abs();
    delta * (2.0 - delta)
}

#[lagrangian]
fn l_asin(x: f64, _v: f64) -> f64 {
    x.asin()
}
#[test]
fn asin() {
    for pts in [&[-0.9, -0.4, 0.25, 0.7][..], &NEAR_ONE] {
        check_unary(
            &LAsin,
            pts,
            f64::asin,
            |x| 1.0 / one_minus_square(x).sqrt(),
            |x| x / one_minus_square(x).powf(1.5),
        );
    }
}

#[lagrangian]
fn l_acos(x: f64, _v: f64) -> f64 {
    x.acos()
}
#[test]
fn acos() {
    for pts in [&[-0.9, -0.4, 0.25, 0.7][..], &NEAR_ONE] {
        check_unary(
            &LAcos,
            pts,
            f64::acos,
            |x| -1.0 / one_minus_square(x).sqrt(),
            |x| -x / one_minus_square(x).powf(1.5),
        );
    }
}

#[lagrangian]
fn l_atan(x: f64, _v: f64) -> f64 {
    x.atan()
}
#[test]
fn atan() {
    check_unary(
        &LAtan,
        &POINTS,
        f64::atan,
        |x| 1.0 / (1.0 + x * x),
        |x| -2.0 * x / (1.0 + x * x).powi(2),
    );
}

#[lagrangian]
fn l_sinh(x: f64, _v: f64) -> f64 {
    x.sinh()
}
#[test]
fn sinh() {
    check_unary(&LSinh, &POINTS, f64::sinh, f64::cosh, f64::sinh);
}

#[lagrangian]
fn l_cosh(x: f64, _v: f64) -> f64 {
    x.cosh()
}
#[test]
fn cosh() {
    check_unary(&LCosh, &POINTS, f64::cosh, f64::sinh, f64::cosh);
}

#[lagrangian]
fn l_tanh(x: f64, _v: f64) -> f64 {
    x.tanh()
}
#[test]
fn tanh() {
    // `1/cosh²` is accurate while `cosh` does not overflow (`|x| < 710`, then 0 like `sech²`).
    // Far out, `1 − tanh²` would not be: a relative error `ε cosh² x` (3e-10 at 8), and 0
    // from `|x| ≈ 19` on, where `tanh` rounds to ±1.
    let sech2 = |x: f64| 1.0 / (x.cosh() * x.cosh());
    let far = [-30.0, -12.5, 8.0, 20.0, 400.0, 800.0];
    for points in [&POINTS[..], &far] {
        check_unary(&LTanh, points, f64::tanh, sech2, |x| {
            -2.0 * sech2(x) * x.tanh()
        });
    }
}

#[lagrangian]
fn l_exp(x: f64, _v: f64) -> f64 {
    x.exp()
}
#[test]
fn exp() {
    check_unary(&LExp, &POINTS, f64::exp, f64::exp, f64::exp);
}

#[lagrangian]
fn l_exp_m1(x: f64, _v: f64) -> f64 {
    x.exp_m1()
}
#[test]
fn exp_m1() {
    // Near 0 too, where `exp_m1` is what `exp(x) − 1` cannot be.
    let pts = [-1.3, -1e-9, 3e-12, 0.9];
    check_unary(&LExpM1, &pts, f64::exp_m1, f64::exp, f64::exp);
}

#[lagrangian]
fn l_ln(x: f64, _v: f64) -> f64 {
    x.ln()
}
#[test]
fn ln() {
    check_unary(&LLn, &POSITIVE, f64::ln, |x| 1.0 / x, |x| -1.0 / (x * x));
}

#[lagrangian]
fn l_ln_1p(x: f64, _v: f64) -> f64 {
    f64::ln_1p(x)
}
#[test]
fn ln_1p() {
    let pts = [-0.9, -1e-9, 3e-12, 12.5];
    check_unary(
        &LLn1p,
        &pts,
        f64::ln_1p,
        |x| 1.0 / (1.0 + x),
        |x| -1.0 / ((1.0 + x) * (1.0 + x)),
    );
}

#[lagrangian]
fn l_log10(x: f64, _v: f64) -> f64 {
    x.log10()
}
#[test]
fn log10() {
    let ln10 = std::f64::consts::LN_10;
    check_unary(
        &LLog10,
        &POSITIVE,
        f64::log10,
        |x| 1.0 / (x * ln10),
        |x| -1.0 / (x * x * ln10),
    );
}

#[lagrangian]
fn l_sqrt(x: f64, _v: f64) -> f64 {
    x.sqrt()
}
#[test]
fn sqrt() {
    check_unary(
        &LSqrt,
        &POSITIVE,
        f64::sqrt,
        |x| 0.5 / x.sqrt(),
        |x| -0.25 / (x * x.sqrt()),
    );
}

#[lagrangian]
fn l_cbrt(x: f64, _v: f64) -> f64 {
    x.cbrt()
}
#[test]
fn cbrt() {
    // Negative points too: cbrt is real there.
    let pts = [-2.5, -0.3, 0.4, 8.0];
    check_unary(
        &LCbrt,
        &pts,
        f64::cbrt,
        |x| 1.0 / (3.0 * x.cbrt().powi(2)),
        |x| -2.0 / (9.0 * x.cbrt().powi(5)),
    );
}

#[lagrangian]
fn l_recip(x: f64, _v: f64) -> f64 {
    x.recip()
}
#[test]
fn recip() {
    let pts = [-2.5, -0.3, 0.4, 8.0];
    check_unary(
        &LRecip,
        &pts,
        f64::recip,
        |x| -1.0 / (x * x),
        |x| 2.0 / (x * x * x),
    );
}

#[lagrangian]
fn l_abs(x: f64, _v: f64) -> f64 {
    x.abs()
}
#[test]
fn abs() {
    let sign = |x: f64| if x > 0.0 { 1.0 } else { -1.0 };
    check_unary(&LAbs, &[-2.0, -0.5, 0.5, 3.0], f64::abs, sign, |_| 0.0);
    // At 0 the derivative used is sign(0) = 0.
    let (fx, _) = LAbs.gradient(&Vector::<1>::new(0.0), &Vector::<1>::new(1.0), 0.0);
    assert_eq!(fx[0], 0.0);
}

#[lagrangian]
fn l_powi(x: f64, _v: f64) -> f64 {
    x.powi(3) + 2.0 * f64::powi(x, -2)
}
#[test]
fn powi() {
    let pts = [-2.5, -0.3, 0.4, 8.0];
    check_unary(
        &LPowi,
        &pts,
        |x| x.powi(3) + 2.0 * x.powi(-2),
        |x| 3.0 * x * x - 4.0 / x.powi(3),
        |x| 6.0 * x + 12.0 / x.powi(4),
    );
}

#[lagrangian]
fn l_consts(x: f64, _v: f64) -> f64 {
    std::f64::consts::PI * x * x + core::f64::consts::E * x - f64::consts::SQRT_2 / x
}
#[test]
fn consts_and_arithmetic() {
    use std::f64::consts::{E, PI, SQRT_2};
    check_unary(
        &LConsts,
        &[-2.0, -0.5, 0.5, 3.0],
        |x| PI * x * x + E * x - SQRT_2 / x,
        |x| 2.0 * PI * x + E + SQRT_2 / (x * x),
        |x| 2.0 * PI - 2.0 * SQRT_2 / (x * x * x),
    );
}

/// Checks the full first and second derivatives of a two-argument `L(x, v)`.
#[allow(
    clippy::too_many_arguments,
    reason = "one closure per derivative keeps the tests flat"
)]
fn check_binary(
    lag: &impl Lagrangian<1>,
    points: &[(f64, f64)],
    f: impl Fn(f64, f64) -> f64,
    fx: impl Fn(f64, f64) -> f64,
    fv: impl Fn(f64, f64) -> f64,
    fxx: impl Fn(f64, f64) -> f64,
    fxv: impl Fn(f64, f64) -> f64,
    fvv: impl Fn(f64, f64) -> f64,
) {
    for &(x, v) in points {
        let (xs, vs) = (Vector::<1>::new(x), Vector::<1>::new(v));
        close("L", lag.value(&xs, &vs, 0.0), f(x, v));
        let (gx, gv) = lag.gradient(&xs, &vs, 0.0);
        close("L_x", gx[0], fx(x, v));
        close("L_v", gv[0], fv(x, v));
        let hs = lag.hessian(&xs, &vs, 0.0);
        close("L_xx", hs.xx[(0, 0)], fxx(x, v));
        close("L_xv", hs.xv[(0, 0)], fxv(x, v));
        close("L_vv", hs.vv[(0, 0)], fvv(x, v));
    }
}

#[lagrangian]
fn l_powf(x: f64, v: f64) -> f64 {
    x.powf(v)
}
#[test]
fn powf() {
    // Base > 0: the exponent derivative x^v·ln x needs it.
    let pts = [(0.3, -1.2), (1.7, 0.5), (4.0, 2.5)];
    check_binary(
        &LPowf,
        &pts,
        f64::powf,
        |x, v| v * x.powf(v - 1.0),
        |x, v| x.powf(v) * x.ln(),
        |x, v| v * (v - 1.0) * x.powf(v - 2.0),
        |x, v| x.powf(v - 1.0) * (1.0 + v * x.ln()),
        |x, v| x.powf(v) * x.ln() * x.ln(),
    );
}

#[lagrangian]
fn l_hypot(x: f64, v: f64) -> f64 {
    f64::hypot(x, v)
}
#[test]
fn hypot() {
    let pts = [(0.3, -1.2), (-1.7, 0.5), (4.0, 2.5)];
    let r = |x: f64, v: f64| x.hypot(v);
    check_binary(
        &LHypot,
        &pts,
        f64::hypot,
        |x, v| x / r(x, v),
        |x, v| v / r(x, v),
        |x, v| v * v / r(x, v).powi(3),
        |x, v| -x * v / r(x, v).powi(3),
        |x, v| x * x / r(x, v).powi(3),
    );
}

#[lagrangian]
fn l_atan2(x: f64, v: f64) -> f64 {
    x.atan2(v)
}
#[lagrangian]
fn l_atan2_path(x: f64, v: f64) -> f64 {
    f64::atan2(x, v)
}
#[test]
fn atan2() {
    // L = atan2(x, v), the angle of the point (v, x): ∂/∂x = v/r², ∂/∂v = −x/r²; all four
    // quadrants, both sides of the cut along the negative `v` axis, and points so far from
    // and so near the origin that `x² + v²` overflows (past about 1e154) or underflows
    // (below about 1e-154) while the first derivatives, about `1/r`, are normal numbers (the
    // second, about `1/r²`, are subnormal or overflow there, so only the first are tested
    // there in earnest). The references scale by `r = hypot(x, v)` (`x/r`, `v/r` at most 1).
    let pts = [
        (0.3, 1.2),
        (1.7, -0.5),
        (-0.4, -2.5),
        (-1.1, 0.8),
        (1e-3, -1.0),
        (-1e-3, -1.0),
        (3e160, -4e160),
        (-2e155, 7e154),
        (5e-160, 1.2e-159),
        (-3e-170, -4e-170),
    ];
    let (c, s) = (
        |x: f64, v: f64| v / x.hypot(v),
        |x: f64, v: f64| x / x.hypot(v),
    );
    // 1/r², as 1/r twice: 1/r² itself overflows below about 1e-154.
    let over_r2 = |x: f64, v: f64, a: f64| a / x.hypot(v) / x.hypot(v);
    macro_rules! check {
        ($lag:expr) => {
            check_binary(
                &$lag,
                &pts,
                f64::atan2,
                |x, v| over_r2(x, v, c(x, v) * x.hypot(v)),
                |x, v| over_r2(x, v, -s(x, v) * x.hypot(v)),
                |x, v| over_r2(x, v, -2.0 * s(x, v) * c(x, v)),
                |x, v| over_r2(x, v, s(x, v) * s(x, v) - c(x, v) * c(x, v)),
                |x, v| over_r2(x, v, 2.0 * s(x, v) * c(x, v)),
            )
        };
    }
    check!(LAtan2);
    check!(LAtan2Path);
    // The angle jumps by 2π across the cut, its derivatives do not.
    let at = |x: f64| LAtan2.value(&Vector::<1>::new(x), &Vector::<1>::new(-1.0), 0.0);
    assert!((at(1e-3) - at(-1e-3) - 2.0 * std::f64::consts::PI).abs() < 1e-2);
}

#[lagrangian]
fn l_let_chain(x: f64, v: f64) -> f64 {
    let u = x * v;
    let w = -u / (1.0 + v * v);
    w - u
}
#[test]
fn let_bindings_and_quotient() {
    // L = −xv/(1 + v²) − xv.
    let q = |v: f64| 1.0 + v * v;
    let pts = [(0.3, -1.2), (-1.7, 0.5), (4.0, 2.5)];
    check_binary(
        &LLetChain,
        &pts,
        |x, v| -x * v / q(v) - x * v,
        |_, v| -v / q(v) - v,
        |x, v| -x * (1.0 - v * v) / q(v).powi(2) - x,
        |_, _| 0.0,
        |_, v| -(1.0 - v * v) / q(v).powi(2) - 1.0,
        |x, v| -x * (2.0 * v * v * v - 6.0 * v) / q(v).powi(3),
    );
}
