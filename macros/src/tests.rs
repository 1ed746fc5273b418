//! Unit tests of the pipeline: randomized derivatives against finite differences, the
//! expansion snapshot of the pendulum, and CSE on the double pendulum.

use std::collections::{HashMap, HashSet};

use proc_macro2::TokenStream;
use quote::quote;
use varembed_tests::rng::Rng;

use crate::codegen::{self, hessian_roots};
use crate::cse::Plan;
use crate::diff::Derivatives;
use crate::expand::expand;
use crate::expr::{Graph, Id, Node, Var};
use crate::parse::{self, Model};

/// Every operation the generator draws, to check that all are covered.
const OPS: [&str; 25] = [
    "+", "-", "*", "/", "neg", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh",
    "exp", "ln", "log10", "sqrt", "cbrt", "recip", "abs", "powi", "powf", "hypot", "const",
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
        "exp" | "sinh" | "cosh" => call(rng, op, format!("2.0 * ({a}).sin()")),
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
        let mut model = parse::parse(quote!(), item).unwrap_or_else(|e| panic!("{e}\n{src}"));
        let d = Derivatives::new(&mut model.graph, model.root, 2);
        let g = &model.graph;
        let point: [f64; 6] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let env_at = |w: Var, val: f64| {
            move |u: Var| {
                if u == w {
                    return val;
                }
                match u {
                    Var::X(i) => point[i],
                    Var::V(i) => point[2 + i],
                    Var::T => point[4],
                    _ => 1.0 + 0.5 * point[5],
                }
            }
        };
        let base = |u: Var| env_at(Var::H, 0.0)(u);
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
            let exact = g.eval(sym, &base);
            let scale = 1.0 + f(w0).abs() + f(w0 + h).abs() + exact.abs();
            if !fd.is_finite() || !exact.is_finite() || spread > 1e-2 * scale {
                skipped += 1;
                continue;
            }
            // Error budget: truncation h⁴·f⁽⁵⁾/… ≲ 1e-12·|f⁽⁵⁾| and rounding ≈ 3ε|f|/h ≈ 7e-13·|f|
            // for h = 1e-3; the derivatives of these bounded compositions stay within ~1e3 of
            // the scale, so 1e-7·scale leaves a wide margin while catching any wrong rule
            // (a wrong rule is off by O(1)·scale).
            assert!(
                (fd - exact).abs() <= 1e-7 * scale,
                "d/d{w:?}: symbolic {exact:e}, finite differences {fd:e}\n{src}"
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
    let mut model = parse::parse(quote!(), item).unwrap();
    let d = Derivatives::new(&mut model.graph, model.root, 1);
    let g = &model.graph;
    // L = v − 5k: ∂L/∂x = 0, ∂L/∂v = 1, every second derivative 0.
    assert!(g.is_num(d.fx[0], 0.0));
    assert!(g.is_num(d.fv[0], 1.0));
    for id in [d.xx[0], d.xv[0], d.vv[0]] {
        assert!(g.is_num(id, 0.0));
    }
    assert!(matches!(g.node(model.root), Node::Sub(_, b) if matches!(g.node(b), Node::Mul(..))));
    let text = codegen::derivatives_text(&model, &d);
    assert_eq!(text, "L = v - 5.0 * k\n∂L/∂x = 0.0\n∂L/∂v = 1.0");
}

fn pretty(ts: TokenStream) -> String {
    let file: syn::File = syn::parse2(ts).expect("the expansion is a valid file");
    prettyplease::unparse(&file)
}

fn pendulum_item() -> TokenStream {
    quote! {
        /// Planar pendulum of length `l` under gravity `g`.
        pub fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
            0.5 * l * l * v * v + g * l * x.cos()
        }
    }
}

/// Compares the pretty-printed expansion of `item` with `macros/tests/expand/<name>.expanded.rs`;
/// with `UPDATE_EXPAND=1` rewrites the file first (review the diff).
fn check_snapshot(name: &str, item: TokenStream) {
    let out = pretty(expand(quote!(), item).expect("the model expands"));
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/expand/{name}.expanded.rs"));
    if std::env::var_os("UPDATE_EXPAND").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &out).unwrap();
    }
    let expected = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with UPDATE_EXPAND=1", path.display()));
    assert!(
        out == expected,
        "the expansion of {name} changed; run with UPDATE_EXPAND=1 and review the diff.\n{out}"
    );
}

/// Must show 5: the pendulum's generated code, so a change to the emitted derivatives shows
/// in review.
#[test]
fn pendulum_expansion_snapshot() {
    check_snapshot("pendulum", pendulum_item());
}

/// The double pendulum's generated code (d = 2, shared temporaries, symmetric blocks).
#[test]
fn double_pendulum_expansion_snapshot() {
    check_snapshot("double_pendulum", double_pendulum_item());
}

/// Kepler's generated code: a constant `L_vv = I`, so the explicit update is `b + h π` with no
/// division and no linear solve.
#[test]
fn kepler_expansion_snapshot() {
    check_snapshot("kepler", kepler_item());
}

fn kepler_item() -> TokenStream {
    quote! {
        /// Kepler problem, `μ = 1`.
        fn kepler(x: [f64; 2], v: [f64; 2]) -> f64 {
            0.5 * (v[0] * v[0] + v[1] * v[1]) + 1.0 / (x[0] * x[0] + x[1] * x[1]).sqrt()
        }
    }
}

/// Whether a division is reachable from `roots`.
fn has_division(g: &Graph, roots: &[Id]) -> bool {
    g.reachable(roots)
        .into_iter()
        .any(|id| matches!(g.node(id), Node::Div(..)))
}

#[test]
fn explicit_update_inverts_a_constant_matrix_at_compile_time() {
    use codegen::{Explicit, Kind};
    let kind = |k: Kind| Kind::ALL.iter().position(|&x| x == k).unwrap();
    let vb = kind(Kind::VariationalBackward);

    // L_vv = I: dy = h·(−π), division-free; the direct backward step is not affine.
    let mut model = parse::parse(quote!(), kepler_item()).unwrap();
    let low = codegen::lower(&mut model);
    let Some(Explicit::ClosedForm { dy, check: false }) = &low.explicit[vb] else {
        panic!("Kepler: a closed form without a run-time check expected");
    };
    assert!(!has_division(&model.graph, dy));
    let env = |v: Var| match v {
        Var::H => 0.25,
        Var::M(i) => [3.0, -5.0][i],
        _ => f64::NAN,
    };
    assert_eq!(model.graph.eval_many(dy, &env), vec![-0.75, 1.25]);
    assert!(low.explicit[kind(Kind::DirectBackward)].is_none());

    // L_vv = [[2, 1], [1, 2]]: dy = h M⁻¹ (−π) with M⁻¹ folded to numbers.
    let item = quote! {
        fn coupled(x: [f64; 2], v: [f64; 2]) -> f64 {
            v[0] * v[0] + v[0] * v[1] + v[1] * v[1] - x[0].cos() * x[1]
        }
    };
    let mut model = parse::parse(quote!(), item).unwrap();
    let low = codegen::lower(&mut model);
    let Some(Explicit::ClosedForm { dy, .. }) = &low.explicit[vb] else {
        panic!("coupled: a closed form expected");
    };
    assert!(!has_division(&model.graph, dy));
    let got = model.graph.eval_many(dy, &env);
    // −h M⁻¹ π with M⁻¹ = [[2, −1], [−1, 2]]/3.
    let want = [-0.25 * (2.0 * 3.0 + 5.0) / 3.0, -0.25 * (-3.0 - 10.0) / 3.0];
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= 1e-15 * w.abs(), "{got:?} vs {want:?}");
    }

    // L_vv = diag(1, 0), singular: no closed form (Newton reports the singular Jacobian).
    let item = quote! {
        fn constrained(x: [f64; 2], v: [f64; 2]) -> f64 {
            0.5 * v[0] * v[0] + x[0].cos() - x[1] * x[1]
        }
    };
    let mut model = parse::parse(quote!(), item).unwrap();
    let low = codegen::lower(&mut model);
    assert!(matches!(low.explicit[vb], Some(Explicit::Singular)));

    // A model constant in L_vv (d = 1): h/m, a loop-invariant quotient, times the residual.
    let mut model = parse::parse(quote!(), pendulum_item()).unwrap();
    let low = codegen::lower(&mut model);
    assert!(matches!(
        low.explicit[vb],
        Some(Explicit::ClosedForm { check: true, .. })
    ));
}

#[test]
fn invert_matches_solve_small_criterion() {
    let inv = codegen::invert(&[2.0, 1.0, 1.0, 2.0], 2).unwrap();
    let want = [2.0 / 3.0, -1.0 / 3.0, -1.0 / 3.0, 2.0 / 3.0];
    for (g, w) in inv.iter().zip(want) {
        assert!((g - w).abs() <= 1e-15, "{inv:?}");
    }
    // Partial pivoting: a zero leading entry is fine.
    assert_eq!(
        codegen::invert(&[0.0, 2.0, 4.0, 0.0], 2).unwrap(),
        vec![0.0, 0.25, 0.5, 0.0]
    );
    assert_eq!(codegen::invert(&[4.0], 1).unwrap(), vec![0.25]);
    // Singular to the relative threshold 1e-14, not finite, zero.
    assert!(codegen::invert(&[1.0, 1.0, 1.0, 1.0 + 1e-15], 2).is_none());
    assert!(codegen::invert(&[1.0, f64::INFINITY, 0.0, 1.0], 2).is_none());
    assert!(codegen::invert(&[1.0, f64::NAN, 0.0, 1.0], 2).is_none());
    assert!(codegen::invert(&[0.0], 1).is_none());
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

fn double_pendulum() -> Model {
    parse::parse(quote!(), double_pendulum_item()).expect("the double pendulum parses")
}

/// Walks what a plan emits — each temporary's definition and each root — and returns the
/// operations evaluated, each as the full expansion of its subtree (independent of node ids),
/// and the expansions of the temporaries' definitions.
fn evaluated_subtrees(g: &Graph, plan: &Plan, roots: &[Id]) -> (Vec<String>, Vec<String>) {
    fn key(g: &Graph, id: Id, memo: &mut HashMap<Id, String>) -> String {
        if let Some(k) = memo.get(&id) {
            return k.clone();
        }
        let node = g.node(id);
        let children: Vec<String> = node.children().iter().map(|&c| key(g, c, memo)).collect();
        let head = match node {
            Node::Num(bits) => format!("{:?}", f64::from_bits(bits)),
            Node::Var(v) => format!("{v:?}"),
            Node::Add(..) => "+".into(),
            Node::Sub(..) => "-".into(),
            Node::Mul(..) => "*".into(),
            Node::Div(..) => "/".into(),
            Node::Neg(_) => "neg".into(),
            Node::Call(f, _) => f.name().into(),
            Node::Powi(_, n) => format!("powi{n}"),
            Node::Powf(..) => "powf".into(),
            Node::Hypot(..) => "hypot".into(),
        };
        let k = format!("{head}({})", children.join(","));
        memo.insert(id, k.clone());
        k
    }
    fn walk(g: &Graph, plan: &Plan, id: Id, top: bool, out: &mut Vec<Id>) {
        if g.node(id).is_leaf() || (!top && plan.temp(id).is_some()) {
            return; // a leaf or a read of a temporary: nothing evaluated
        }
        out.push(id);
        for c in g.node(id).children() {
            walk(g, plan, c, false, out);
        }
    }
    let mut evaluated = Vec::new();
    for &t in &plan.temps {
        walk(g, plan, t, true, &mut evaluated);
    }
    for &r in roots {
        if plan.temp(r).is_none() {
            walk(g, plan, r, true, &mut evaluated);
        }
    }
    let mut memo = HashMap::new();
    let all = evaluated.iter().map(|&id| key(g, id, &mut memo)).collect();
    let defs = plan.temps.iter().map(|&id| key(g, id, &mut memo)).collect();
    (all, defs)
}

fn duplicates(keys: &[String]) -> Vec<&String> {
    let mut seen = HashSet::new();
    keys.iter().filter(|k| !seen.insert(*k)).collect()
}

#[test]
fn double_pendulum_hessian_evaluates_each_subexpression_once() {
    let mut model = double_pendulum();
    let low = codegen::lower(&mut model);
    let g = &model.graph;
    let roots = hessian_roots(g, &low.d);
    let plan = Plan::new(g, &roots);
    let (keys, defs) = evaluated_subtrees(g, &plan, &roots);
    assert!(
        keys.len() > 10,
        "the hessian evaluates {} operations",
        keys.len()
    );
    assert!(
        duplicates(&keys).is_empty(),
        "evaluated twice: {:?}",
        duplicates(&keys)
    );
    // Every temporary's defining expression is distinct.
    assert!(!defs.is_empty());
    assert!(
        duplicates(&defs).is_empty(),
        "temporaries repeat: {:?}",
        duplicates(&defs)
    );

    // The same holds for every other emitted method.
    let mut methods: Vec<Vec<Id>> = vec![
        vec![model.root],
        low.d.fx.iter().chain(&low.d.fv).copied().collect(),
    ];
    methods.extend(low.momentum.iter().cloned());
    methods.extend(low.residual.iter().cloned());
    for roots in &methods {
        let plan = Plan::new(g, roots);
        let (keys, _) = evaluated_subtrees(g, &plan, roots);
        assert!(
            duplicates(&keys).is_empty(),
            "evaluated twice: {:?}",
            duplicates(&keys)
        );
    }

    // Negative control: without temporaries the hessian does repeat work, so the check above
    // is able to fail.
    let inline = Plan::without_temps(g);
    let (keys, _) = evaluated_subtrees(g, &inline, &roots);
    assert!(!duplicates(&keys).is_empty());
}

/// The emitted code means what the IR means: the generated `let`s and expressions of
/// gradient + hessian, printed as Rust and read back by the parser, evaluate to the same
/// numbers (this checks operator precedence, parentheses, negative literals, named constants).
/// `abs` is left out of these trees: its derivative `sign` is emitted as an `if`, which the
/// parser rejects by design; `tests/tests/macro_functions.rs` covers it through the macro.
#[test]
fn emitted_code_round_trips_through_the_parser() {
    let mut rng = Rng(0xC0DE);
    let mut used = HashMap::new();
    let mut trees = 0;
    while trees < 300 {
        let src = gen_fn(&mut rng, &mut used);
        if src.contains("abs") {
            continue;
        }
        trees += 1;
        let item: TokenStream = src.parse().expect("generated source tokenizes");
        let mut model = parse::parse(quote!(), item).unwrap_or_else(|e| panic!("{e}\n{src}"));
        let d = Derivatives::new(&mut model.graph, model.root, 2);
        let g = &model.graph;
        let mut roots: Vec<Id> = d.fx.iter().chain(&d.fv).copied().collect();
        roots.extend(hessian_roots(g, &d));
        let plan = Plan::new(g, &roots);
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
        let render = codegen::Render::new(g, &plan, &leaf);
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
}
