//! Derivatives against finite differences on random expression trees, and simplification.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use super::{OPS, Rng, gen_fn, model};
use crate::ir::{Id, Node, Var};
use crate::text;

/// Central difference with one Richardson step: `(4 D(h/2) − D(h)) / 3`, truncation error
/// `O(h⁴ f⁽⁵⁾)`, rounding error about `3 ε |f| / h`. Also returns `|D(h) − D(h/2)|`, which is
/// `≈ ¼ h² |f'''|` for a smooth `f` and large where `f` is not smooth on `[w − h, w + h]`
/// (`abs` near 0).
fn richardson(f: &dyn Fn(f64) -> f64, w: f64, h: f64) -> (f64, f64) {
    let d = |h: f64| (f(w + h) - f(w - h)) / (2.0 * h);
    let (d1, d2) = (d(h), d(h / 2.0));
    ((4.0 * d2 - d1) / 3.0, (d1 - d2).abs())
}

#[test]
fn random_trees_match_finite_differences() {
    let mut rng = Rng(0x5EED);
    let mut used = HashMap::new();
    let vars = [Var::X(0), Var::X(1), Var::V(0), Var::V(1)];
    let (mut checked, mut skipped) = (0usize, 0usize);
    let trees = 1200;
    for _ in 0..trees {
        let src = gen_fn(&mut rng, &mut used);
        let item: TokenStream = src.parse().expect("generated source tokenizes");
        let (model, d) = model(item);
        let g = &model.graph;
        let point: [f64; 6] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let base = |u: Var| match u {
            Var::X(i) => point[i],
            Var::V(i) => point[2 + i],
            Var::T => point[4],
            Var::Const(_) => 1.0 + 0.5 * point[5],
            _ => unreachable!("the random trees have no loops"),
        };
        // The point with `w` moved to `val`.
        let env_at = |w: Var, val: f64| move |u: Var| if u == w { val } else { base(u) };
        let value = g.eval(model.root, &base);
        if !value.is_finite() {
            skipped += 1;
            continue;
        }
        // First derivatives against differences of L; second derivatives against differences
        // of the (just checked) first derivatives.
        let mut cases: Vec<(Id, Id, Var)> = Vec::new();
        for (i, &w) in vars.iter().enumerate() {
            let first = if i < 2 { d.fx[i] } else { d.fv[i - 2] };
            cases.push((first, model.root, w));
            for (j, &u) in vars.iter().enumerate() {
                let second = match (i < 2, j < 2) {
                    (true, true) => d.xx[i * 2 + j],
                    (true, false) => d.xv[i * 2 + j - 2],
                    (false, true) => d.xv[j * 2 + i - 2],
                    (false, false) => d.vv[(i - 2) * 2 + j - 2],
                };
                cases.push((second, first, u));
            }
        }
        for (sym, of, w) in cases {
            let w0 = base(w);
            let h = 1e-3 * w0.abs().max(1.0);
            let f = |val: f64| g.eval(of, &env_at(w, val));
            let (fd, spread) = richardson(&f, w0, h);
            // The estimate with half the step: a kink closer to `w0` than the step (`abs`
            // near 0) can leave `D(h)` and `D(h/2)` close, but not both estimates.
            let (fd_half, _) = richardson(&f, w0, h / 2.0);
            let exact = g.eval(sym, &base);
            let scale = 1.0 + f(w0).abs() + f(w0 + h).abs() + exact.abs();
            let rough = spread > 1e-2 * scale || (fd - fd_half).abs() > 1e-8 * scale;
            if !fd.is_finite() || !exact.is_finite() || rough {
                skipped += 1;
                continue;
            }
            // Error budget: truncation h⁴·f⁽⁵⁾/… ≲ 1e-12·|f⁽⁵⁾| and rounding ≈ 3ε|f|/h ≈ 7e-13·|f|
            // for h = 1e-3; the derivatives of these bounded compositions stay within ~1e3 of
            // the scale, so 1e-7·scale leaves a wide margin while catching any wrong rule
            // (a wrong rule is off by O(1)·scale).
            assert!(
                (fd - exact).abs() <= 1e-7 * scale,
                "d/d{w:?} at {w0:e}: symbolic {exact:e}, finite differences {fd:e}\n{src}"
            );
            checked += 1;
        }
    }
    for op in OPS {
        assert!(
            used.get(op).copied().unwrap_or(0) >= 20,
            "operation {op} drawn too rarely"
        );
    }
    // Points where L is not finite or not smooth at the FD scale are rare.
    eprintln!("checked {checked}, skipped {skipped}");
    assert!(skipped * 100 < checked, "skipped {skipped} of {checked}");
    assert!(checked >= trees * 15, "checked {checked}");
}

#[test]
fn simplification_folds_and_drops_zeros() {
    let item = quote! {
        fn f(x: f64, v: f64, k: f64) -> f64 {
            let z = 0.0 * x + 1.0 * v - (2.0 + 3.0) * k;
            z * 1.0 + (v - v) * x.sin() + std::f64::consts::PI * 0.0
        }
    };
    let (model, d) = model(item);
    let g = &model.graph;
    // L = v − 5k: ∂L/∂x = 0, ∂L/∂v = 1, every second derivative 0.
    assert!(g.is_num(d.fx[0], 0.0));
    assert!(g.is_num(d.fv[0], 1.0));
    for id in [d.xx[0], d.xv[0], d.vv[0]] {
        assert!(g.is_num(id, 0.0));
    }
    assert!(matches!(g.node(model.root), Node::Sub(_, b) if matches!(g.node(b), Node::Mul(..))));
    let text = text::derivatives_text(&model, &d);
    assert_eq!(text, "L = v - 5.0 * k\n∂L/∂x = 0.0\n∂L/∂v = 1.0");
}

#[test]
fn atan2_exp_m1_ln_1p_fold_and_print() {
    let item = quote! {
        fn f(x: f64, v: f64) -> f64 {
            1.0f64.atan2(2.0) * x + f64::exp_m1(0.5) * v.ln_1p() + f64::atan2(x, v) + 0.0f64.ln_1p()
        }
    };
    let (model, d) = model(item);
    let text = text::derivatives_text(&model, &d);
    // The text's normal form rounds coefficients to 12 digits for reading.
    let (a, b) = (
        crate::readable::number(1.0f64.atan2(2.0)),
        crate::readable::number(0.5f64.exp_m1()),
    );
    let expected = [
        format!("L = {a} * x + {b} * v.ln_1p() + x.atan2(v)"),
        format!("∂L/∂x = {a} + v / v.hypot(x).powi(2)"),
        format!("∂L/∂v = {b} / (1.0 + v) - x / v.hypot(x).powi(2)"),
    ];
    for line in expected {
        assert!(text.contains(&line), "{line}\n{text}");
    }
}
