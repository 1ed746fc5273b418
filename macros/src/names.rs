//! How the loop path writes its integer side: loop variables, index expressions (positive
//! terms first, so that a valid index never underflows), the ranges, the constants the macro
//! does not know, and the `const` assertions that check the indices the macro could not.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote, quote_spanned};

use crate::assemble::Assembly;
use crate::ir::{Affine, Component, Graph, IndexVar, Model, Sym, Var};

/// How loop variables, indices and the dimension are written.
pub struct Names<'a> {
    g: &'a Graph,
    pub dim: TokenStream,
    pub vars: Vec<Ident>,
}

impl<'a> Names<'a> {
    /// The names of `model`'s loop variables: each as written, unless a loop nest of `a` holds
    /// two of that name (or it is a name the methods use), then with its number.
    pub fn new(model: &'a Model, a: &Assembly) -> Self {
        let g = &model.graph;
        let dim = match (&model.dim_name, &model.runtime_dim) {
            (Some(p), _) => quote!(#p),
            (None, Some(n)) => quote!(self.#n),
            (None, None) => {
                let d = Literal::usize_unsuffixed(model.dim);
                quote!(#d)
            }
        };
        let vars = g
            .ranges
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let clash = a.terms.iter().any(|t| {
                    t.loops
                        .iter()
                        .filter(|i| g.ranges[i.0 as usize].name == r.name)
                        .count()
                        > 1
                });
                let reserved = [
                    "x", "v", "t", "fx", "fv", "xx", "xv", "vv", "value", "out", "row", "col", "f",
                    "jx", "jv",
                ]
                .contains(&r.name.as_str())
                    || r.name.starts_with('e')
                    || r.name.starts_with("lifted")
                    || r.name.starts_with("adjoint");
                if clash || reserved {
                    format_ident!("{}_{}", r.name.trim_start_matches("r#"), k)
                } else {
                    Ident::new(&r.name, Span::call_site())
                }
            })
            .collect();
        Self { g, dim, vars }
    }

    /// `scale·i + n·N + k·s + c` as a `usize` expression (positive terms first, so that it
    /// does not underflow where its value is a valid index).
    pub fn affine(&self, a: Affine) -> TokenStream {
        let (mut pos, neg) = self.terms(a);
        if pos.is_empty() {
            pos.push(quote!(0));
        }
        quote!(#(#pos)+* #(- #neg)*)
    }

    /// `a < b` without a subtraction (`pos(a) + neg(b) < pos(b) + neg(a)`), so that it cannot
    /// underflow in `usize`.
    fn less(&self, a: Affine, b: Affine) -> TokenStream {
        let ((mut pa, na), (pb, nb)) = (self.terms(a), self.terms(b));
        pa.extend(nb);
        let mut right = pb;
        right.extend(na);
        for side in [&mut pa, &mut right] {
            if side.is_empty() {
                side.push(quote!(0));
            }
        }
        quote!((#(#pa)+* < #(#right)+*))
    }

    /// `a op b` (`op` a comparison) without a subtraction and without parentheses, as
    /// [`Names::less`] writes `<`: `pos(a) + neg(b) op pos(b) + neg(a)`.
    fn compare(&self, a: Affine, op: TokenStream, b: Affine) -> TokenStream {
        let ((mut pa, na), (pb, nb)) = (self.terms(a), self.terms(b));
        pa.extend(nb);
        let mut right = pb;
        right.extend(na);
        for side in [&mut pa, &mut right] {
            if side.is_empty() {
                side.push(quote!(0));
            }
        }
        quote!(#(#pa)+* #op #(#right)+*)
    }

    /// The condition under which every one of the components `vars` is read (`i >= 1` for
    /// `x[i - 1]` in `if i > 0 { … }`), `None` when they are read in every iteration.
    pub fn guard(&self, vars: &[Var]) -> Option<TokenStream> {
        let mut conds: Vec<TokenStream> = Vec::new();
        for &v in vars {
            let (Var::XAt(c) | Var::VAt(c) | Var::FAt(c)) = v else {
                continue;
            };
            let Some(i) = c.at.var else {
                continue;
            };
            let var = Affine::var(i);
            let sides = [
                c.guard.low.map(|low| self.compare(var, quote!(>=), low)),
                c.guard.high.map(|high| self.compare(var, quote!(<), high)),
            ];
            for cond in sides.into_iter().flatten() {
                if !conds.iter().any(|k| k.to_string() == cond.to_string()) {
                    conds.push(cond);
                }
            }
        }
        (!conds.is_empty()).then(|| quote!(#(#conds)&&*))
    }

    /// The positive terms of `a`, and the magnitudes of its negative ones.
    fn terms(&self, a: Affine) -> (Vec<TokenStream>, Vec<TokenStream>) {
        let mut pos = Vec::new();
        let mut neg = Vec::new();
        let mut term = |k: i64, what: TokenStream| {
            let mag = Literal::i64_unsuffixed(k.abs());
            let t = if k.abs() == 1 {
                what
            } else {
                quote!(#mag * #what)
            };
            if k > 0 {
                pos.push(t)
            } else if k < 0 {
                neg.push(t)
            }
        };
        if let Some(i) = a.var {
            let name = &self.vars[i.0 as usize];
            term(a.scale, quote!(#name));
        }
        let dim = &self.dim;
        term(a.n, quote!(#dim));
        if let Some(s) = a.sym {
            term(a.k, self.sym(s));
        }
        if a.c != 0 {
            let c = Literal::i64_unsuffixed(a.c.abs());
            if a.c > 0 {
                pos.push(quote!(#c))
            } else {
                neg.push(quote!(#c))
            }
        }
        (pos, neg)
    }

    /// A constant the macro does not know, as written (`M`) or as a division (`(N / 2)`).
    fn sym(&self, s: crate::ir::SymId) -> TokenStream {
        match &self.g.syms[s.0 as usize] {
            Sym::Named(name) => quote!(#name),
            Sym::Div(a, d) => {
                let (pos, neg) = self.terms(*a);
                let single = pos.len() + neg.len() == 1 && neg.is_empty();
                let a = self.affine(*a);
                let d = Literal::i64_unsuffixed(*d);
                if single {
                    quote!((#a / #d))
                } else {
                    quote!(((#a) / #d))
                }
            }
        }
    }

    /// The index checks left to the compiler (see [`crate::ir::Bound`]), as `const`
    /// assertions spanned on the index they check.
    pub fn bounds(&self, model: &Model) -> TokenStream {
        let fn_name = &model.item.sig.ident;
        let attr = model.attr.name();
        let checks = self.g.bounds.iter().map(|b| {
            let holds = self.less(b.lhs, b.rhs);
            let cond = match b.guard {
                Some((start, end)) => {
                    let nonempty = self.less(start, end);
                    quote!(!#nonempty || #holds)
                }
                None => holds,
            };
            let msg = format!("{attr} fn `{fn_name}`: {}", b.what);
            quote_spanned!(b.span=> const _: () = ::core::assert!(#cond, #msg);)
        });
        quote!(#(#checks)*)
    }

    fn component(&self, c: Component) -> TokenStream {
        let at = self.affine(c.at);
        let dim = &self.dim;
        if c.wrap { quote!((#at) % #dim) } else { at }
    }

    /// The index of a state component.
    pub fn position(&self, v: Var) -> TokenStream {
        match v {
            Var::X(k) | Var::V(k) | Var::F(k) => {
                let k = Literal::usize_unsuffixed(k);
                quote!(#k)
            }
            Var::XAt(c) | Var::VAt(c) | Var::FAt(c) => self.component(c),
            _ => unreachable!("only state and force components are differentiated"),
        }
    }

    /// The tokens of a leaf. A guarded component is read only where its guard holds (0
    /// elsewhere): a temporary that holds it may be computed in every iteration, and is used
    /// only in the branch that the guard protects.
    pub fn leaf(&self, consts: &[Ident], v: Var) -> TokenStream {
        match v {
            Var::X(_) | Var::XAt(_) | Var::V(_) | Var::VAt(_) => {
                let i = self.position(v);
                let read = match v {
                    Var::X(_) | Var::XAt(_) => quote!(x[#i]),
                    _ => quote!(v[#i]),
                };
                match self.guard(&[v]) {
                    Some(g) => quote!((if #g { #read } else { 0.0 })),
                    None => read,
                }
            }
            Var::T => quote!(t),
            Var::Const(k) => {
                let c = &consts[k];
                quote!(self.#c)
            }
            Var::Index(i) => {
                let name = &self.vars[i.0 as usize];
                quote!((#name as f64))
            }
            Var::Dim => {
                let dim = &self.dim;
                quote!((#dim as f64))
            }
            Var::Sym(s) => {
                let s = self.sym(s);
                quote!((#s as f64))
            }
            Var::Lifted(k) => lifted(k),
            Var::Adjoint(k) => adjoint(k),
            Var::F(_) | Var::FAt(_) => {
                unreachable!("the weights of a force's virtual work are differentiated away")
            }
        }
    }

    pub fn range(&self, i: IndexVar) -> TokenStream {
        let r = &self.g.ranges[i.0 as usize];
        let (start, end) = (self.affine(r.start), self.affine(r.end));
        quote!(#start..#end)
    }
}

/// The local holding the value of lifted sum `k`.
pub fn lifted(k: usize) -> TokenStream {
    let name = quote::format_ident!("lifted_{}", k);
    quote!(#name)
}

/// The local holding the adjoint `∂L/∂s_k` of lifted sum `k`.
pub fn adjoint(k: usize) -> TokenStream {
    let name = quote::format_ident!("adjoint_{}", k);
    quote!(#name)
}
