//! Unit tests of the pipeline, one file per concern: derivatives against finite differences
//! and simplification ([`derivatives`]), CSE ([`cse`]), what is emitted and what it means
//! ([`emit`]), and the expansion snapshots ([`snapshots`]).

mod cse;
mod derivatives;
mod emit;
mod loops;
mod snapshots;
mod values;

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use crate::diff;
use crate::ir::{Derivatives, Model};
use crate::parse;

/// The seeded generator (SplitMix64) of the test-support crate, included by its file: a
/// dependency on that crate would build the whole library a second time, for the host.
#[path = "../../../tests/src/rng/splitmix.rs"]
mod splitmix;

use splitmix::Rng;

/// Every operation the generator draws, to check that all are covered.
const OPS: [&str; 28] = [
    "+", "-", "*", "/", "neg", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh",
    "exp", "exp_m1", "ln", "ln_1p", "log10", "sqrt", "cbrt", "recip", "abs", "powi", "powf",
    "hypot", "atan2", "const",
];

/// Random expression source over `x[0..2]`, `v[0..2]`, `t`, `c` and the `let` names in scope.
/// Arguments of functions with a restricted domain are wrapped so the domain holds
/// (`1.0 + e·e > 0` for ln/sqrt/…, `0.8·tanh e ∈ (−1, 1)` for asin/acos, bounded arguments for
/// exp/sinh/cosh/tan so values stay moderate).
fn gen_expr(
    rng: &mut Rng,
    depth: usize,
    names: &[String],
    used: &mut HashMap<&'static str, usize>,
) -> String {
    if depth == 0 || rng.below(5) == 0 {
        return match rng.below(6) {
            0 => format!("x[{}]", rng.below(2)),
            1 => format!("v[{}]", rng.below(2)),
            2 => ["t", "c"][rng.below(2)].to_string(),
            3 if !names.is_empty() => names[rng.below(names.len())].clone(),
            4 => {
                let c = rng.uniform(0.1, 2.0);
                if rng.below(2) == 0 {
                    format!("{c:?}")
                } else {
                    format!("(-{c:?})")
                }
            }
            _ => format!("{}", 1 + rng.below(3)),
        };
    }
    let op = OPS[rng.below(OPS.len())];
    *used.entry(op).or_default() += 1;
    let mut sub = |rng: &mut Rng| gen_expr(rng, depth - 1, names, used);
    let a = sub(rng);
    let pos = |e: &str| format!("(1.0 + ({e}) * ({e}))");
    let call = |rng: &mut Rng, f: &str, arg: String| {
        if rng.below(2) == 0 {
            format!("({arg}).{f}()")
        } else {
            format!("f64::{f}({arg})")
        }
    };
    match op {
        "+" | "-" | "*" => format!("({a}) {op} ({})", sub(rng)),
        "/" => format!("({a}) / {}", pos(&sub(rng))),
        "neg" => format!("-({a})"),
        "sin" | "cos" | "atan" | "tanh" | "abs" => call(rng, op, a),
        "tan" => call(rng, op, format!("0.7 * ({a}).tanh()")),
        "asin" | "acos" => call(rng, op, format!("0.8 * ({a}).tanh()")),
        "exp" | "exp_m1" | "sinh" | "cosh" => call(rng, op, format!("2.0 * ({a}).sin()")),
        "ln_1p" => call(rng, op, format!("0.9 * ({a}).tanh()")),
        "ln" | "log10" | "sqrt" | "cbrt" | "recip" => call(rng, op, pos(&a)),
        "powi" => {
            let n = rng.below(7) as i32 - 3;
            let base = if n < 0 {
                pos(&a)
            } else {
                format!("({a}).tanh()")
            };
            format!("{base}.powi({n})")
        }
        "powf" => format!("{}.powf(0.5 * ({}).sin())", pos(&a), sub(rng)),
        "hypot" => format!("({a}).hypot({})", pos(&sub(rng))),
        // Both signs of both arguments: every quadrant, the cut along the negative `x` axis
        // included (a point within the step of it is skipped as not smooth).
        "atan2" if rng.below(2) == 0 => format!("({a}).atan2({})", sub(rng)),
        "atan2" => format!("f64::atan2({a}, {})", sub(rng)),
        _ => format!("std::f64::consts::PI * ({a})"),
    }
}

/// A random `#[lagrangian]` fn: 0–3 `let`s (each may use the earlier ones), then L.
fn gen_fn(rng: &mut Rng, used: &mut HashMap<&'static str, usize>) -> String {
    let mut names = Vec::new();
    let mut body = String::new();
    for k in 0..rng.below(4) {
        let e = gen_expr(rng, 3, &names, used);
        body.push_str(&format!("let a{k} = {e};\n"));
        names.push(format!("a{k}"));
    }
    let e = gen_expr(rng, 3, &names, used);
    body.push_str(&e);
    format!("fn random(x: [f64; 2], v: [f64; 2], t: f64, c: f64) -> f64 {{\n{body}\n}}")
}

/// Parses `item` and differentiates it.
fn model(item: TokenStream) -> (Model, Derivatives) {
    let mut model = parse::parse(quote!(), item.clone()).unwrap_or_else(|e| panic!("{e}\n{item}"));
    let d = diff::differentiate(&mut model.graph, model.root, model.dim);
    (model, d)
}

fn pendulum_item() -> TokenStream {
    quote! {
        /// Planar pendulum of length `l` under gravity `g`.
        pub fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
            0.5 * l * l * v * v + g * l * x.cos()
        }
    }
}

fn kepler_item() -> TokenStream {
    quote! {
        /// Kepler problem, `μ = 1`.
        fn kepler(x: [f64; 2], v: [f64; 2]) -> f64 {
            0.5 * (v[0] * v[0] + v[1] * v[1]) + 1.0 / (x[0] * x[0] + x[1] * x[1]).sqrt()
        }
    }
}

fn double_pendulum_item() -> TokenStream {
    quote! {
        /// Double pendulum.
        fn double_pendulum(x: [f64; 2], v: [f64; 2], m1: f64, m2: f64, l1: f64, l2: f64, g: f64) -> f64 {
            let kinetic = 0.5 * (m1 + m2) * l1 * l1 * v[0] * v[0]
                + 0.5 * m2 * l2 * l2 * v[1] * v[1]
                + m2 * l1 * l2 * v[0] * v[1] * (x[0] - x[1]).cos();
            let potential = -(m1 + m2) * g * l1 * x[0].cos() - m2 * g * l2 * x[1].cos();
            kinetic - potential
        }
    }
}
