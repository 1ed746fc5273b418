//! The index checks of a model whose dimension is a run-time value (`x: &[f64]` with a
//! `usize` model constant `n`), made by its `invalid_dimension()`: what the compiler checks
//! for a named dimension `[f64; N]` (`const` assertions, overflow of `N - 1`), checked once
//! the value of `n` is known, before the solver's first step.
//!
//! Each loop variable's range is bounded by its least and greatest value over the ranges of
//! the loops around it, in `i64`; every range end must be at least 0 (`0..n - 1` needs
//! `n ≥ 1`), every component read in a loop that runs must lie in `0..n`, a periodic index
//! needs `n ≥ 1`, and a division `(a) / d` an `a ≥ 0`. A loop whose range depends on an
//! outer loop variable is bounded over the whole outer range, as the macro's own checks do.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::ir::{Affine, Component, Graph, Guard, Model, Node, Sym, Var};
use crate::names::Names;

/// `fn invalid_dimension(&self) -> Option<String>` of a run-time dimension model.
pub fn invalid_dimension(model: &Model, names: &Names<'_>) -> TokenStream {
    let checks = index_checks(model, names);
    quote! {
        #[inline]
        fn invalid_dimension(&self) -> ::core::option::Option<::std::string::String> {
            #checks
        }
    }
}

/// The statements of [`invalid_dimension`], ending with `None` when every check passes.
pub fn index_checks(model: &Model, names: &Names<'_>) -> TokenStream {
    let g = &model.graph;
    let mut checker = Checker {
        g,
        fn_name: model.item.sig.ident.to_string(),
        dim_name: model
            .runtime_dim
            .as_ref()
            .map_or_else(|| "n".to_string(), ToString::to_string),
        extents: Vec::new(),
        stmts: Vec::new(),
    };
    let dim = &names.dim;
    checker.stmts.push(quote!(let dim = #dim as i64;));

    // The ranges: the least and greatest value of each loop variable, where its loop runs.
    for (k, r) in g.ranges.iter().enumerate() {
        let outer = [r.start.var, r.end.var].into_iter().flatten().next();
        let reached = outer.and_then(|j| checker.extents[j.0 as usize].live.clone());
        let range = format!("{}..{}", checker.text(r.start), checker.text(r.end));
        let last = r.end.add_scaled(Affine::constant(1), -1).unwrap_or(r.end);
        for (which, end) in [("start", r.start), ("end", r.end)] {
            let (min, _) = checker.extremes(end);
            let msg = checker.message(&format!(
                "loops over `{range}`, whose {which} {} is {{}} at its dimension",
                checker.text(end)
            ));
            checker.check(reached.clone(), &min, Test::Negative, &msg);
        }
        let extent = match outer {
            None => {
                let live = (!always_nonneg(
                    r.end
                        .add_scaled(r.start, -1)
                        .map(|d| d.add_scaled(Affine::constant(1), -1).unwrap_or(d)),
                ))
                .then(|| {
                    let (a, b) = (checker.eval(r.start), checker.eval(last));
                    quote!((#a <= #b))
                });
                Extent {
                    lo: Value::Known(r.start),
                    hi: Value::Known(last),
                    live,
                }
            }
            Some(_) => {
                let (lo_k, hi_k, live_k) = (lo(k), hi(k), live(k));
                let (min, _) = checker.extremes(r.start);
                let (_, max) = checker.extremes(last);
                let (min, max) = (checker.tokens(&min), checker.tokens(&max));
                let reached = reached.clone().unwrap_or_else(|| quote!(true));
                checker.stmts.push(quote! {
                    let #lo_k = #min;
                    let #hi_k = #max;
                    let #live_k = #reached && #lo_k <= #hi_k;
                });
                Extent {
                    lo: Value::Dynamic(quote!(#lo_k)),
                    hi: Value::Dynamic(quote!(#hi_k)),
                    live: Some(quote!(#live_k)),
                }
            }
        };
        checker.extents.push(extent);
    }

    // Divisions `(a) / d` of the dimension: `a` is computed in `usize`.
    for s in &g.syms {
        if let Sym::Div(a, _) = s {
            let msg = checker.message(&format!(
                "divides {} = {{}} at its dimension",
                checker.text(*a)
            ));
            checker.check(None, &Value::Known(*a), Test::Negative, &msg);
        }
    }

    // Literal components: the largest one read.
    let literal = (0..g.len())
        .filter_map(|id| match g.node(id) {
            Node::Var(Var::X(k) | Var::V(k) | Var::F(k)) => Some(k),
            _ => None,
        })
        .max();
    if let Some(k) = literal {
        let msg = checker.message("reads component {} but its dimension");
        let k = Affine::constant(k as i64);
        checker.check(None, &Value::Known(k), Test::AtLeastDim, &msg);
    }

    // Components at index expressions.
    let mut seen = std::collections::HashSet::new();
    for id in 0..g.len() {
        let (state, c) = match g.node(id) {
            Node::Var(Var::XAt(c)) => ("x", c),
            Node::Var(Var::VAt(c)) => ("v", c),
            Node::Var(Var::FAt(c)) => ("f", c),
            _ => continue,
        };
        if seen.insert((state, c)) {
            checker.component(state, c);
        }
    }

    let stmts = &checker.stmts;
    quote! {
        #(#stmts)*
        ::core::option::Option::None
    }
}

fn lo(k: usize) -> Ident {
    format_ident!("lo{}", k)
}

fn hi(k: usize) -> Ident {
    format_ident!("hi{}", k)
}

fn live(k: usize) -> Ident {
    format_ident!("live{}", k)
}

/// Whether `a ≥ 0` at every dimension `n ≥ 0` (`None`: not an expression of `n` alone).
fn always_nonneg(a: Option<Affine>) -> bool {
    a.is_some_and(|a| a.var.is_none() && a.sym.is_none() && a.n >= 0 && a.c >= 0)
}

/// A value of the checks: an index expression of the dimension (and of the `usize` consts), or
/// `i64` tokens.
#[derive(Clone)]
enum Value {
    Known(Affine),
    Dynamic(TokenStream),
}

/// The least and greatest value of a loop variable, and whether its loop runs (`None`:
/// whenever the loops around it run).
struct Extent {
    lo: Value,
    hi: Value,
    live: Option<TokenStream>,
}

/// What a check rejects.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Test {
    /// `value < 0`.
    Negative,
    /// `value ≥ n`.
    AtLeastDim,
    /// `n = 0` (the value is not read).
    ZeroDim,
}

struct Checker<'a> {
    g: &'a Graph,
    fn_name: String,
    dim_name: String,
    /// The extents of the loop variables seen so far.
    extents: Vec<Extent>,
    stmts: Vec<TokenStream>,
}

impl Checker<'_> {
    /// The format string of a message `{fn} {what} {n} = {}` (one placeholder in `what`
    /// before the dimension's).
    fn message(&self, what: &str) -> String {
        format!("`{}` {what} {} = {{}}", self.fn_name, self.dim_name)
    }

    /// Adds the check that `value` passes `test` where `reached`, unless it passes at every
    /// dimension; `msg` has a placeholder for the value (except for [`Test::ZeroDim`]) and
    /// one for the dimension.
    fn check(&mut self, reached: Option<TokenStream>, value: &Value, test: Test, msg: &str) {
        if let Value::Known(a) = value {
            let passes = match test {
                Test::Negative => always_nonneg(Some(*a)),
                Test::AtLeastDim => {
                    // `a < n` at every `n ≥ 0`: `n − 1 − a ≥ 0`.
                    always_nonneg(
                        Affine::dim()
                            .add_scaled(*a, -1)
                            .map(|d| Affine { c: d.c - 1, ..d }),
                    )
                }
                Test::ZeroDim => false,
            };
            if passes {
                return;
            }
        }
        let v = self.tokens(value);
        let fails = match test {
            Test::Negative => quote!(#v < 0),
            Test::AtLeastDim => quote!(#v >= dim),
            Test::ZeroDim => quote!(dim == 0),
        };
        let cond = match reached {
            Some(r) => quote!(#r && #fails),
            None => fails,
        };
        let args = if test == Test::ZeroDim {
            quote!(dim)
        } else {
            quote!(#v, dim)
        };
        self.stmts.push(quote! {
            if #cond {
                return ::core::option::Option::Some(::std::format!(#msg, #args));
            }
        });
    }

    fn tokens(&self, v: &Value) -> TokenStream {
        match v {
            Value::Known(a) => self.eval(*a),
            Value::Dynamic(t) => t.clone(),
        }
    }

    /// `a` (free of loop variables) as an `i64` expression.
    fn eval(&self, a: Affine) -> TokenStream {
        self.eval_with(a, None)
    }

    /// `a` as an `i64` expression, its loop variable (if any) replaced by `var`.
    fn eval_with(&self, a: Affine, var: Option<&TokenStream>) -> TokenStream {
        let mut terms: Vec<(i64, TokenStream)> = Vec::new();
        if let (Some(_), Some(var)) = (a.var, var) {
            terms.push((a.scale, quote!(#var)));
        }
        terms.push((a.n, quote!(dim)));
        if let Some(s) = a.sym {
            terms.push((a.k, self.sym(s)));
        }
        let mut out = TokenStream::new();
        for (k, what) in terms.into_iter().filter(|t| t.0 != 0) {
            let mag = k.unsigned_abs() as i64;
            let term = if mag == 1 { what } else { quote!(#mag * #what) };
            out = match (out.is_empty(), k < 0) {
                (true, false) => term,
                (true, true) => quote!(-#term),
                (false, false) => quote!(#out + #term),
                (false, true) => quote!(#out - #term),
            };
        }
        let c = a.c;
        let mag = c.unsigned_abs() as i64;
        match (out.is_empty(), c) {
            (true, _) => quote!(#c),
            (false, 0) => quote!((#out)),
            (false, c) if c > 0 => quote!((#out + #mag)),
            (false, _) => quote!((#out - #mag)),
        }
    }

    /// The value of a constant the macro does not know, in `i64`.
    fn sym(&self, s: crate::ir::SymId) -> TokenStream {
        match &self.g.syms[s.0 as usize] {
            Sym::Named(name) => quote!((#name as i64)),
            Sym::Div(a, d) => {
                let a = self.eval(*a);
                quote!((#a / #d))
            }
        }
    }

    /// The least and greatest value of `a` over the extent of its loop variable.
    fn extremes(&self, a: Affine) -> (Value, Value) {
        match a.var {
            Some(i) => self.extremes_over(a, &self.extents[i.0 as usize]),
            None => (Value::Known(a), Value::Known(a)),
        }
    }

    /// The extent of the loop variable of `c` over the iterations its guard lets through
    /// (`max(lo, low)..=min(hi, high − 1)`, read where that is not empty); `None` for a
    /// component without a guard.
    fn guarded(&self, c: Component) -> Option<Extent> {
        let i = c.at.var.filter(|_| c.guard != Guard::NONE)?;
        let e = &self.extents[i.0 as usize];
        let lo = match c.guard.low {
            Some(low) => {
                let (a, b) = (self.tokens(&e.lo), self.eval(low));
                quote!(::core::cmp::max(#a, #b))
            }
            None => self.tokens(&e.lo),
        };
        let hi = match c.guard.high {
            Some(high) => {
                let last = high.add_scaled(Affine::constant(1), -1).unwrap_or(high);
                let (a, b) = (self.tokens(&e.hi), self.eval(last));
                quote!(::core::cmp::min(#a, #b))
            }
            None => self.tokens(&e.hi),
        };
        let live = match &e.live {
            Some(l) => quote!(#l && #lo <= #hi),
            None => quote!(#lo <= #hi),
        };
        Some(Extent {
            lo: Value::Dynamic(lo),
            hi: Value::Dynamic(hi),
            live: Some(live),
        })
    }

    /// The least and greatest value of `a` over the extent `e` of its loop variable.
    fn extremes_over(&self, a: Affine, e: &Extent) -> (Value, Value) {
        let rest = Affine {
            var: None,
            scale: 0,
            ..a
        };
        let at = |end: &Value| match end {
            Value::Known(b) => match rest.add_scaled(*b, a.scale) {
                Some(v) => Value::Known(v),
                None => {
                    let b = self.eval(*b);
                    Value::Dynamic(self.eval_with(a, Some(&b)))
                }
            },
            Value::Dynamic(t) => Value::Dynamic(self.eval_with(a, Some(t))),
        };
        let (at_lo, at_hi) = (at(&e.lo), at(&e.hi));
        if a.scale >= 0 {
            (at_lo, at_hi)
        } else {
            (at_hi, at_lo)
        }
    }

    /// The checks of one component read at `c`.
    fn component(&mut self, state: &str, c: Component) {
        let at = self.text(c.at);
        let written = if c.wrap {
            format!("{state}[({at}) % {}]", self.dim_name)
        } else {
            format!("{state}[{at}]")
        };
        let guarded = self.guarded(c);
        let (min, max) = match &guarded {
            Some(e) => self.extremes_over(c.at, e),
            None => self.extremes(c.at),
        };
        let reached = match guarded {
            Some(e) => e.live,
            None => {
                c.at.var
                    .and_then(|i| self.extents[i.0 as usize].live.clone())
            }
        };
        let where_ = |end: &str| match c.at.var {
            Some(_) => format!(" (`{written}` at the {end} of its loop)"),
            None => format!(" (`{written}`)"),
        };
        let text = |v: &Value| match v {
            Value::Known(a) if a.as_constant().is_none() => format!("{} = ", self.text(*a)),
            _ => String::new(),
        };
        let below = self.message(&format!(
            "reads component {}{{}}{}, below 0, at its dimension",
            text(&min),
            where_("start")
        ));
        let above = self.message(&format!(
            "reads component {}{{}}{} but its dimension",
            text(&max),
            where_("end")
        ));
        let zero = self.message(&format!("reads `{written}` at its dimension"));
        self.check(reached.clone(), &min, Test::Negative, &below);
        if c.wrap {
            self.check(reached, &min, Test::ZeroDim, &zero);
        } else {
            self.check(reached, &max, Test::AtLeastDim, &above);
        }
    }

    /// An index as written, `2 * i + n - 1`.
    fn text(&self, a: Affine) -> String {
        let mut parts: Vec<(i64, String)> = Vec::new();
        if let Some(i) = a.var {
            parts.push((a.scale, self.g.ranges[i.0 as usize].name.clone()));
        }
        parts.push((a.n, self.dim_name.clone()));
        if let Some(s) = a.sym {
            parts.push((a.k, self.sym_text(s)));
        }
        parts.push((a.c, String::new()));
        let mut out = String::new();
        for (k, what) in parts.into_iter().filter(|p| p.0 != 0) {
            let mag = k.unsigned_abs();
            let term = match (what.is_empty(), mag) {
                (true, _) => mag.to_string(),
                (false, 1) => what,
                (false, _) => format!("{mag} * {what}"),
            };
            if out.is_empty() {
                out = if k < 0 { format!("-{term}") } else { term };
            } else {
                out.push_str(if k < 0 { " - " } else { " + " });
                out.push_str(&term);
            }
        }
        if out.is_empty() { "0".into() } else { out }
    }

    fn sym_text(&self, s: crate::ir::SymId) -> String {
        match &self.g.syms[s.0 as usize] {
            Sym::Named(name) => name.to_string(),
            Sym::Div(a, d) => {
                let a = self.text(*a);
                if a.contains(' ') {
                    format!("(({a}) / {d})")
                } else {
                    format!("({a} / {d})")
                }
            }
        }
    }
}
