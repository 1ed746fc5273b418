//! What is emitted: its meaning (read back by the parser), its paths into core, its methods,
//! and the dependence of the Hessian blocks.

use std::collections::HashMap;

use proc_macro2::{TokenStream, TokenTree};
use quote::quote;

use super::{Rng, double_pendulum_item, gen_fn, kepler_item, model, pendulum_item};
use crate::cse;
use crate::expand::expand;
use crate::ir::{Dependence, Var};
use crate::parse;
use crate::render::Render;

/// The emitted code means what the IR means: the generated `let`s and expressions of
/// `gradient_and_hessian`, printed as Rust and read back by the parser, evaluate to the same
/// numbers (this checks operator precedence, parentheses, negative literals, named constants).
/// `abs` is left out of these trees: its derivative, `sign`, is emitted as an `if`, which the
/// parser rejects by design. `tanh`'s derivative is emitted as a call of core's
/// `__private::sech2`, which the parser does not know: it is read back as `1/cosh²`
/// ([`sech2_as_cosh`]). `tests/tests/macros/functions.rs` covers both through the macro.
#[test]
fn emitted_code_round_trips_through_the_parser() {
    let mut rng = Rng(0xC0DE);
    let mut used = HashMap::new();
    let mut trees = 0;
    let mut with_sech2 = 0;
    while trees < 300 {
        let src = gen_fn(&mut rng, &mut used);
        if src.contains("abs") {
            continue;
        }
        trees += 1;
        let item: TokenStream = src.parse().expect("generated source tokenizes");
        let (model, d) = model(item);
        let g = &model.graph;
        let mut roots = cse::gradient_roots(&d);
        roots.extend(cse::hessian_roots(g, &d));
        let plan = cse::plan(g, model.root, &d).gradient_and_hessian;
        let leaf = |v: Var| match v {
            Var::X(i) => {
                let i = proc_macro2::Literal::usize_unsuffixed(i);
                quote!(x[#i])
            }
            Var::V(i) => {
                let i = proc_macro2::Literal::usize_unsuffixed(i);
                quote!(v[#i])
            }
            Var::T => quote!(t),
            _ => quote!(c),
        };
        let render = Render::new(g, &plan, &leaf);
        let temps = render.temps();
        let point: [f64; 6] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let env = |u: Var| match u {
            Var::X(i) => point[i],
            Var::V(i) => point[2 + i],
            Var::T => point[4],
            _ => point[5],
        };
        for &root in &roots {
            let expr = render.root(root);
            let emitted = quote! {
                fn emitted(x: [f64; 2], v: [f64; 2], t: f64, c: f64) -> f64 { #temps #expr }
            };
            let (emitted, calls) = sech2_as_cosh(emitted);
            with_sech2 += usize::from(calls > 0);
            let back = parse::parse(quote!(), emitted.clone())
                .unwrap_or_else(|e| panic!("{e}\n{emitted}"));
            let (a, b) = (g.eval(root, &env), back.graph.eval(back.root, &env));
            if a.is_finite() {
                assert!(
                    (a - b).abs() <= 1e-14 * a.abs().max(1.0),
                    "IR {a:e}, emitted {b:e}\n{emitted}"
                );
            }
        }
    }
    // The trees hold `tanh` (every `asin`, `acos`, `tan` and `ln_1p` argument is bounded by
    // one): its derivative's call must have been read back, not skipped.
    assert!(with_sech2 > 20, "{with_sech2} roots read sech2 back");
}

/// `ts` with every call `::varembed::__private::sech2(a)` replaced by `(1.0 / (a.cosh() *
/// a.cosh()))`, which the parser reads (the same value to a few ulps while `cosh a` does not
/// overflow), and the number of calls replaced.
fn sech2_as_cosh(ts: TokenStream) -> (TokenStream, usize) {
    let path = ["varembed", "__private", "sech2"];
    let tokens: Vec<TokenTree> = ts.into_iter().collect();
    let (mut out, mut calls, mut i) = (Vec::new(), 0, 0);
    while i < tokens.len() {
        // `::` `varembed` `::` `__private` `::` `sech2` `(..)`: six punctuations and idents
        // (each `::` is two `:`), then the argument group.
        let ident = |k: usize, name: &str| matches!(tokens.get(k), Some(TokenTree::Ident(id)) if id == name);
        let colons = |k: usize| {
            (k..k + 2)
                .all(|j| matches!(tokens.get(j), Some(TokenTree::Punct(p)) if p.as_char() == ':'))
        };
        let is_call = (0..3).all(|n| colons(i + 3 * n) && ident(i + 3 * n + 2, path[n]));
        if let (true, Some(TokenTree::Group(arg))) = (is_call, tokens.get(i + 9)) {
            let (a, inner) = sech2_as_cosh(arg.stream());
            calls += 1 + inner;
            out.extend(quote!((1.0 / ((#a).cosh() * (#a).cosh()))));
            i += 10;
            continue;
        }
        match &tokens[i] {
            TokenTree::Group(g) => {
                let (inner, n) = sech2_as_cosh(g.stream());
                calls += n;
                let mut group = proc_macro2::Group::new(g.delimiter(), inner);
                group.set_span(g.span());
                out.push(TokenTree::Group(group));
            }
            other => out.push(other.clone()),
        }
        i += 1;
    }
    (out.into_iter().collect(), calls)
}

/// Every path into `varembed` in `ts`, as written, that is not `::varembed::__private::…`.
fn paths_outside_private(ts: TokenStream) -> Vec<String> {
    let tokens: Vec<TokenTree> = ts.into_iter().collect();
    let mut bad = Vec::new();
    let punct =
        |k: usize, c: char| matches!(tokens.get(k), Some(TokenTree::Punct(p)) if p.as_char() == c);
    for (k, tt) in tokens.iter().enumerate() {
        match tt {
            TokenTree::Group(g) => bad.extend(paths_outside_private(g.stream())),
            TokenTree::Ident(i) if i == "varembed" => {
                let rooted = k >= 2 && punct(k - 2, ':') && punct(k - 1, ':');
                let private = punct(k + 1, ':')
                    && punct(k + 2, ':')
                    && matches!(tokens.get(k + 3), Some(TokenTree::Ident(n)) if n == "__private");
                if !(rooted && private) {
                    let around = tokens[k.saturating_sub(2)..(k + 4).min(tokens.len())].iter();
                    bad.push(around.map(ToString::to_string).collect());
                }
            }
            _ => {}
        }
    }
    bad
}

/// Generated code reaches core only through `::varembed::__private`, so core's public API can
/// change without breaking it.
#[test]
fn expansion_names_core_only_through_private() {
    // The check can fail: a public path, a relative path.
    assert_eq!(
        paths_outside_private(quote!(impl ::varembed::Lagrangian<1> for A {})).len(),
        1
    );
    assert_eq!(
        paths_outside_private(quote!(let h: varembed::__private::Hessian<1>;)).len(),
        1
    );
    assert!(paths_outside_private(quote!(::varembed::__private::Vector::<2>::zeros())).is_empty());

    let mut items = vec![
        pendulum_item(),
        kepler_item(),
        double_pendulum_item(),
        quote!(
            fn driven(x: f64, v: f64, t: f64, k: f64) -> f64 {
                0.5 * v * v - k * x * t.cos()
            }
        ),
    ];
    let mut rng = Rng(0xFA7E);
    let mut used = HashMap::new();
    items.extend((0..40).map(|_| gen_fn(&mut rng, &mut used).parse().unwrap()));
    for item in items {
        let out = expand(quote!(), item)
            .expect("the model expands")
            .to_string();
        let ts: TokenStream = out.parse().unwrap();
        assert!(out.contains("varembed :: __private"), "{out}");
        let bad = paths_outside_private(ts);
        assert!(bad.is_empty(), "paths outside `__private`: {bad:?}\n{out}");
    }
}

/// The impl has exactly the agreed methods, each `#[inline]` (so a caller that reads one output
/// of `gradient_and_hessian` does not pay for the others).
#[test]
fn the_impl_has_the_agreed_methods_all_inline() {
    for item in [pendulum_item(), kepler_item(), double_pendulum_item()] {
        let out = expand(quote!(), item).expect("the model expands");
        let file: syn::File = syn::parse2(out).unwrap();
        let imp = file
            .items
            .iter()
            .find_map(|i| match i {
                syn::Item::Impl(imp) if imp.trait_.is_some() => Some(imp),
                _ => None,
            })
            .expect("the Lagrangian impl");
        let mut names = Vec::new();
        for item in &imp.items {
            let syn::ImplItem::Fn(f) = item else {
                panic!("only methods expected in the impl");
            };
            assert!(
                f.attrs.iter().any(|a| a.path().is_ident("inline")),
                "{} is not #[inline]",
                f.sig.ident
            );
            names.push(f.sig.ident.to_string());
        }
        assert_eq!(
            names,
            [
                "value",
                "gradient",
                "value_and_gradient",
                "hessian",
                "gradient_and_hessian",
                "hessian_dependence",
                "hessian_bandwidth",
                "dependence",
                "constants"
            ]
        );
    }
}

const NONE: Dependence = Dependence::NONE;
const X: Dependence = Dependence {
    x: true,
    v: false,
    t: false,
};

/// `dependence` is what `L` itself depends on: the time only where `t` appears in the value
/// (not through a model constant), the velocity and position likewise.
#[test]
fn dependence_of_l_tells_autonomous_from_time_dependent() {
    let of = |item: TokenStream| model(item).1.dependence;
    let pendulum = of(quote! {
        fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 { 0.5 * l * l * v * v + g * l * x.cos() }
    });
    assert_eq!(
        pendulum,
        Dependence {
            x: true,
            v: true,
            t: false
        }
    );
    let parametric = of(quote! {
        fn parametric(x: f64, v: f64, t: f64, eps: f64) -> f64 {
            0.5 * v * v - 0.5 * (1.0 + eps * t.cos()) * x * x
        }
    });
    assert_eq!(
        parametric,
        Dependence {
            x: true,
            v: true,
            t: true
        }
    );
    let free = of(quote! { fn free(x: f64, v: f64) -> f64 { 0.5 * v * v } });
    assert_eq!(
        free,
        Dependence {
            x: false,
            v: true,
            t: false
        }
    );
    // `t` in the signature but not in the value: still autonomous.
    let unused = of(quote! { fn c(x: f64, v: f64, t: f64) -> f64 { 0.5 * v * v - x * x } });
    assert!(!unused.t);
}

/// What the blocks `[xx, xv, vv]` of the model `item` depend on.
fn dependence_of(item: TokenStream) -> [Dependence; 3] {
    let (_, d) = model(item);
    let dep = d.hessian_dependence;
    [dep.xx, dep.xv, dep.vv]
}

/// `hessian_dependence` is read off the symbolic blocks: model constants do not count, an
/// all-zero block depends on nothing, and `x`, `v`, `t` are told apart.
#[test]
fn hessian_dependence_is_read_off_the_blocks() {
    // `L = ½ vᵀMv − U(x)`, with `M` from model constants (pendulum), the identity (Kepler) or
    // a coupled constant matrix: only `xx` depends on anything.
    assert_eq!(dependence_of(pendulum_item()), [X, NONE, NONE]);
    assert_eq!(dependence_of(kepler_item()), [X, NONE, NONE]);
    let coupled = quote! {
        fn coupled(x: [f64; 2], v: [f64; 2]) -> f64 {
            v[0] * v[0] + v[0] * v[1] + v[1] * v[1] - x[0].cos() * x[1]
        }
    };
    assert_eq!(dependence_of(coupled), [X, NONE, NONE]);

    // The double pendulum's mass matrix depends on the angle difference; the coupling term
    // `v[0] v[1] cos(x[0] − x[1])` puts x and v in `xx` and `xv`.
    let xv = Dependence {
        x: true,
        v: true,
        t: false,
    };
    assert_eq!(dependence_of(double_pendulum_item()), [xv, xv, X]);

    // Time, and blocks that vanish: `L = ½ e^t v² − k t x²` has `xv = 0`; `L = t x v` has
    // only `xv = t`; a free particle has constant `vv` and nothing else.
    let t = Dependence {
        x: false,
        v: false,
        t: true,
    };
    let damped = quote!(
        fn damped(x: f64, v: f64, t: f64, k: f64) -> f64 {
            0.5 * t.exp() * v * v - k * t * x * x
        }
    );
    assert_eq!(dependence_of(damped), [t, NONE, t]);
    let gyro = quote!(
        fn gyro(x: f64, v: f64, t: f64) -> f64 {
            t * x * v
        }
    );
    assert_eq!(dependence_of(gyro), [NONE, t, NONE]);
    let free = quote!(
        fn free(_x: f64, v: f64) -> f64 {
            0.5 * v * v
        }
    );
    assert_eq!(dependence_of(free), [NONE, NONE, NONE]);

    // `v` in `vv` (a relativistic particle) and in `xv`.
    let relativistic = quote! {
        fn relativistic(x: f64, v: f64, k: f64) -> f64 { -(1.0 - v * v).sqrt() - k * x * x }
    };
    let v = Dependence {
        x: false,
        v: true,
        t: false,
    };
    assert_eq!(dependence_of(relativistic), [NONE, NONE, v]);
    let drag = quote!(
        fn drag(x: f64, v: f64) -> f64 {
            x * v * v * v
        }
    );
    assert_eq!(dependence_of(drag), [NONE, v, xv]);
}

/// The emitted `hessian_dependence` states the analysis field for field.
#[test]
fn hessian_dependence_is_emitted_as_analysed() {
    let out = expand(quote!(), double_pendulum_item()).unwrap();
    let file: syn::File = syn::parse2(out).unwrap();
    let text = prettyplease::unparse(&file);
    let body = &text[text.find("fn hessian_dependence").expect("emitted")..];
    let body = body.replace(char::is_whitespace, "").replace(",}", "}");
    let dependence = "::varembed::__private::Dependence";
    for (block, (x, v, t)) in [
        ("xx", (true, true, false)),
        ("xv", (true, true, false)),
        ("vv", (true, false, false)),
    ] {
        let want = format!("{block}: {dependence} {{ x: {x}, v: {v}, t: {t} }}");
        assert!(
            body.contains(&want.replace(' ', "")),
            "{want} not in\n{body}"
        );
    }
}
