//! Values bound together: local arrays `let a = [b * x[1], -b * x[0], 0.0];`, tuples, and
//! what a helper returning `(f64, f64)` or `[f64; K]` returns. They are read at constant
//! indices (`a[1]`, `r.0`); a loop over a literal range that reads a local array at an index
//! that is not a literal (`for k in 0..3 { acc += a[k] * a[k]; }`) is unrolled here, its
//! variable a constant in each copy, since the IR has no array that a loop variable could
//! index.

use proc_macro2::{TokenStream, TokenTree};
use quote::ToTokens;
use syn::{Expr, ItemFn, Lit, Pat, Stmt};

use super::body::Parser;
use super::scope::{Binding, Env, Int, Kind, Returns, Values, returns, strip};
use crate::ir::{Affine, Id};

/// How a local array may be indexed, for the errors on any other index.
const LOCAL_INDEX: &str = "a local array or a helper's array is read at a literal index \
     (`a[1]`), or at the variable of a loop over a literal range (`for k in 0..3 { … a[k] … }`, \
     which is unrolled)";

/// `(a, b)`, `[a, b]`, `r.0`-style kinds written out, `(f64, f64)` / `[f64; 2]`.
fn written(kind: Kind, n: usize) -> String {
    match kind {
        Kind::Tuple => format!("({})", vec!["f64"; n].join(", ")),
        Kind::Array => format!("[f64; {n}]"),
    }
}

impl Parser {
    /// What a helper called `name` returns, if it is a helper the body may call.
    pub(super) fn helper_returns(&self, name: &str) -> Option<Returns> {
        self.helpers
            .get(name)
            .map(|h: &ItemFn| returns(&h.sig.output).unwrap_or(Returns::Scalar))
    }

    /// Whether `e` is the call of a fn that is not known while a helper is checked on its own
    /// (another helper, whose shape is not known there).
    pub(super) fn is_unknown_call(&self, e: &Expr) -> bool {
        self.checking_helper
            && match strip(e) {
                Expr::Call(call) => match &*call.func {
                    Expr::Path(p) => p
                        .path
                        .get_ident()
                        .is_some_and(|n| !self.helpers.contains_key(&n.to_string())),
                    _ => false,
                },
                _ => false,
            }
    }

    /// Whether `e` is a name bound to [`Binding::Unknown`].
    pub(super) fn is_unknown(&self, e: &Expr, env: &Env) -> bool {
        match strip(e) {
            Expr::Path(p) => p
                .path
                .get_ident()
                .is_some_and(|n| matches!(env.get(&n.to_string()), Some(Binding::Unknown))),
            Expr::Call(_) => self.is_unknown_call(e),
            _ => false,
        }
    }

    /// Whether `e` is values (a tuple or an array), and which: decided on its form, before
    /// anything is built.
    pub(super) fn values_kind(&self, e: &Expr, env: &Env) -> Option<Kind> {
        match e {
            Expr::Paren(p) => self.values_kind(&p.expr, env),
            Expr::Group(g) => self.values_kind(&g.expr, env),
            Expr::Tuple(t) if !t.elems.is_empty() => Some(Kind::Tuple),
            Expr::Array(_) | Expr::Repeat(_) => Some(Kind::Array),
            Expr::Path(p) => match p.path.get_ident().and_then(|n| env.get(&n.to_string())) {
                Some(Binding::Values(v)) => Some(v.kind),
                _ => None,
            },
            Expr::Call(call) => match &*call.func {
                Expr::Path(p) => match p
                    .path
                    .get_ident()
                    .and_then(|n| self.helper_returns(&n.to_string()))
                {
                    Some(Returns::Values(kind, _)) => Some(kind),
                    _ => None,
                },
                _ => None,
            },
            Expr::Block(b) if b.label.is_none() => match b.block.stmts.last() {
                Some(Stmt::Expr(last, None)) => self.values_kind(last, env),
                _ => None,
            },
            Expr::MethodCall(mc) if mc.method == "sin_cos" && mc.args.is_empty() => {
                Some(Kind::Tuple)
            }
            _ => None,
        }
    }

    /// The values of `e`, for which [`Parser::values_kind`] is `Some`.
    pub(super) fn values(&mut self, e: &Expr, env: &Env) -> Values {
        match e {
            Expr::Paren(p) => self.values(&p.expr, env),
            Expr::Group(g) => self.values(&g.expr, env),
            Expr::Tuple(t) => Values {
                ids: t.elems.iter().map(|e| self.expr(e, env)).collect(),
                kind: Kind::Tuple,
            },
            Expr::Array(a) => Values {
                ids: a.elems.iter().map(|e| self.expr(e, env)).collect(),
                kind: Kind::Array,
            },
            Expr::Repeat(r) => {
                let value = self.expr(&r.expr, env);
                let n = match strip(&r.len) {
                    Expr::Lit(syn::ExprLit {
                        lit: Lit::Int(k), ..
                    }) => k.base10_parse::<usize>().ok(),
                    _ => None,
                };
                let n = n.unwrap_or_else(|| {
                    self.error(&r.len, "the length of `[value; K]` is an integer literal");
                    1
                });
                Values {
                    ids: vec![value; n],
                    kind: Kind::Array,
                }
            }
            Expr::Path(p) => match p.path.get_ident().and_then(|n| env.get(&n.to_string())) {
                Some(Binding::Values(v)) => v.clone(),
                _ => unreachable!("values_kind said values"),
            },
            Expr::Call(call) => {
                let name = match &*call.func {
                    Expr::Path(p) => p.path.get_ident().map(ToString::to_string),
                    _ => None,
                };
                let name = name.expect("values_kind said a helper");
                self.inline_values(&name, call, env)
            }
            Expr::Block(b) => self.values_block(&b.block, &mut env.clone(), None),
            Expr::MethodCall(mc) => {
                let a = self.expr(&mc.receiver, env);
                let s = self.graph.call(crate::ir::Func::Sin, a);
                let c = self.graph.call(crate::ir::Func::Cos, a);
                Values {
                    ids: vec![s, c],
                    kind: Kind::Tuple,
                }
            }
            _ => unreachable!("values_kind said values"),
        }
    }

    /// The values a block ends with (a helper's body, a `{ … }`), `want` what it must return
    /// (for a helper: its signature's shape, and its name).
    pub(super) fn values_block(
        &mut self,
        block: &syn::Block,
        env: &mut Env,
        want: Option<(&str, Kind, usize)>,
    ) -> Values {
        let n = block.stmts.len();
        for stmt in block.stmts.iter().take(n.saturating_sub(1)) {
            self.statement(stmt, env);
        }
        let placeholder = |p: &mut Self, kind: Kind, n: usize| Values {
            ids: vec![p.graph.num(0.0); n],
            kind,
        };
        let (kind, count) = want.map_or((Kind::Tuple, 1), |(_, k, n)| (k, n));
        let last = match block.stmts.last() {
            Some(Stmt::Expr(e, None)) => e,
            _ => {
                self.errors.push(syn::Error::new(
                    block.brace_token.span.join(),
                    "the body must end with its values (an expression without `;`)",
                ));
                return placeholder(self, kind, count);
            }
        };
        if self.values_kind(last, env).is_none() {
            if self.is_unknown(last, env) {
                return placeholder(self, kind, count);
            }
            let msg = match want {
                None => "the body must end with values, e.g. `(a, b)` or `[a, b]`".to_string(),
                Some((_, Kind::Tuple, n)) => {
                    format!(
                        "the body must end with `{}`, e.g. `(a, b)`",
                        written(Kind::Tuple, n)
                    )
                }
                Some((_, Kind::Array, n)) => {
                    format!(
                        "the body must end with `{}`, e.g. `[a, b]`",
                        written(Kind::Array, n)
                    )
                }
            };
            self.error(last, msg);
            return placeholder(self, kind, count);
        }
        let values = self.values(last, env);
        if let Some((name, kind, count)) = want
            && (values.kind != kind || values.ids.len() != count)
        {
            self.error(
                last,
                format!(
                    "`{name}` returns `{}`: its body ends with {} of {} values",
                    written(kind, count),
                    values.kind.noun(),
                    values.ids.len()
                ),
            );
            return placeholder(self, kind, count);
        }
        values
    }

    /// `let pattern = init;` where `init` is values: a name binds them together, `(a, b)` and
    /// `[a, b]` bind each.
    pub(super) fn bind_values(&mut self, pat: &Pat, values: Values, env: &mut Env) {
        match pat {
            Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                env.insert(pi.ident.to_string(), Binding::Values(values));
            }
            Pat::Type(pt) => self.bind_values(&pt.pat, values, env),
            Pat::Wild(_) => {}
            Pat::Tuple(pt) => self.bind_each(pat, &pt.elems, Kind::Tuple, values, env),
            Pat::Slice(ps) => self.bind_each(pat, &ps.elems, Kind::Array, values, env),
            other => {
                self.error(
                    other,
                    "values are bound to a name, `let a = [x[0], x[1]];`, or to one name each, `let (a, b) = …;`",
                );
            }
        }
    }

    fn bind_each(
        &mut self,
        pat: &Pat,
        elems: &syn::punctuated::Punctuated<Pat, syn::Token![,]>,
        kind: Kind,
        values: Values,
        env: &mut Env,
    ) {
        if values.kind != kind || values.ids.len() != elems.len() {
            self.error(
                pat,
                format!(
                    "this pattern takes {} of {} values, and the value is {} of {}",
                    kind.noun(),
                    elems.len(),
                    values.kind.noun(),
                    values.ids.len()
                ),
            );
            let zero = self.graph.num(0.0);
            for p in elems {
                self.bind(p, zero, env);
            }
            return;
        }
        for (p, id) in elems.iter().zip(values.ids) {
            self.bind(p, id, env);
        }
    }

    /// `base[index]` where `base` is values.
    pub(super) fn element(&mut self, ix: &syn::ExprIndex, env: &Env) -> Id {
        let values = self.values(&ix.expr, env);
        let name = written_base(&ix.expr);
        if values.kind == Kind::Tuple {
            return self.error(
                ix,
                format!("{name} is a tuple: read its fields, `{name}.0`"),
            );
        }
        let Some(k) = self.constant_index(&ix.index, env) else {
            return self.graph.num(0.0);
        };
        self.pick(&values, k, &ix.index, &name)
    }

    /// `base.k` where `base` is values.
    pub(super) fn field(&mut self, f: &syn::ExprField, env: &Env) -> Id {
        let values = self.values(&f.base, env);
        let name = written_base(&f.base);
        let syn::Member::Unnamed(k) = &f.member else {
            return self.error(&f.member, format!("{name} has no named fields"));
        };
        if values.kind == Kind::Array {
            return self.error(
                f,
                format!("{name} is an array: read it at an index, `{name}[0]`"),
            );
        }
        self.pick(&values, k.index as i64, &f.member, &name)
    }

    fn pick(&mut self, values: &Values, k: i64, at: &dyn quote::ToTokens, name: &str) -> Id {
        match usize::try_from(k) {
            Ok(k) if k < values.ids.len() => values.ids[k],
            _ => self.error(
                at,
                format!(
                    "index {k} is out of bounds: {name} has {} values",
                    values.ids.len()
                ),
            ),
        }
    }

    /// The value of an index of values: a literal, or an index expression of constants (the
    /// variable of an unrolled loop); `None` after reporting an error.
    pub(super) fn constant_index(&mut self, e: &Expr, env: &Env) -> Option<i64> {
        if let Expr::Lit(syn::ExprLit {
            lit: Lit::Int(i), ..
        }) = strip(e)
        {
            return match i.base10_parse::<i64>() {
                Ok(k) => Some(k),
                Err(err) => {
                    self.errors.push(err);
                    None
                }
            };
        }
        if self.is_int(e, env) || self.is_const_index(e, env) {
            let v = self.int_expr(e, env)?;
            if let Some(k) = v.affine.and_then(Affine::as_constant).filter(|_| !v.wrap) {
                return Some(k);
            }
        }
        self.error(e, LOCAL_INDEX);
        None
    }

    /// `let pattern = init;` when `init` calls a helper not known while checking one on its
    /// own: every name is bound to [`Binding::Unknown`] (a `let mut` to a number, which only
    /// an `f64` can be).
    pub(super) fn bind_unknown(&mut self, pat: &Pat, env: &mut Env) {
        match pat {
            Pat::Ident(pi) if pi.mutability.is_some() => {
                let zero = self.graph.num(0.0);
                self.bind(pat, zero, env);
            }
            Pat::Ident(pi) => {
                env.insert(pi.ident.to_string(), Binding::Unknown);
            }
            Pat::Type(pt) => self.bind_unknown(&pt.pat, env),
            Pat::Tuple(pt) => pt.elems.iter().for_each(|p| self.bind_unknown(p, env)),
            Pat::Slice(ps) => ps.elems.iter().for_each(|p| self.bind_unknown(p, env)),
            _ => {}
        }
    }

    /// The values of `init` as an `n`-tuple: `(a, b)`, `a.sin_cos()`, a tuple bound earlier or
    /// returned by a helper.
    pub(super) fn tuple_values(&mut self, init: &Expr, n: usize, env: &mut Env) -> Vec<Id> {
        match init {
            Expr::Tuple(t) if t.elems.len() == n => {
                t.elems.iter().map(|e| self.expr(e, env)).collect()
            }
            Expr::Paren(p) => self.tuple_values(&p.expr, n, env),
            _ if self.is_unknown(init, env) => vec![self.graph.num(0.0); n],
            _ if self.values_kind(init, env) == Some(Kind::Tuple) => {
                let values = self.values(init, env);
                if values.ids.len() == n {
                    return values.ids;
                }
                let e = self.error(
                    init,
                    format!(
                        "this is a tuple of {} values, bound to {n} names",
                        values.ids.len()
                    ),
                );
                vec![e; n]
            }
            other => {
                let e = self.error(
                    other,
                    format!("a tuple `let` needs a tuple of {n} values, e.g. `let (a, b) = (x[0], x[1]);`, or `a.sin_cos()`"),
                );
                vec![e; n]
            }
        }
    }

    /// The range to unroll a loop over, for a loop over `ends` with the body `body`: a
    /// literal range, and a body that reads values (not `x`, `v`) at an index that is not a
    /// literal.
    pub(super) fn unrolls(
        &self,
        ends: Option<(Affine, Affine)>,
        body: &dyn ToTokens,
        env: &Env,
    ) -> Option<(i64, i64)> {
        let (start, end) = ends?;
        let range = (start.as_constant()?, end.as_constant()?);
        // A force or constraint is differentiated entry by entry: every such loop unrolls.
        let vector = self.attr != crate::ir::Attr::Lagrangian;
        (vector || reads_values_at_variable(body.to_token_stream(), env)).then_some(range)
    }

    /// `Σ body` over `start..end`, the sum unrolled as a `for` loop is ([`Parser::unrolled`]).
    pub(super) fn unrolled_sum(
        &mut self,
        body: &Expr,
        name: &str,
        (start, end): (i64, i64),
        env: &Env,
    ) -> Id {
        let mut sum = self.graph.num(0.0);
        for k in start..end {
            let mut inner = env.clone();
            inner.insert(name.to_string(), Binding::Int(self.constant(k)));
            let value = self.expr(body, &inner);
            sum = self.graph.add(sum, value);
        }
        sum
    }

    /// The body of a loop over `start..end` with its variable `name` a constant in each copy:
    /// the statements are read as straight-line code, so an accumulator declared outside
    /// receives each copy's updates in turn (a `let` of the body that shadows it ends that).
    pub(super) fn unrolled(
        &mut self,
        body: &syn::Block,
        name: &str,
        (start, end): (i64, i64),
        env: &mut Env,
    ) {
        for k in start..end {
            let mut inner = env.clone();
            inner.insert(name.to_string(), Binding::Int(self.constant(k)));
            let mut shadowed = std::collections::HashSet::new();
            for stmt in &body.stmts {
                if let Stmt::Local(local) = stmt {
                    // The outer accumulator named again: what it received so far is its value.
                    for declared in pattern_names(&local.pat) {
                        if env.get(&declared).is_some_and(carried)
                            && shadowed.insert(declared.clone())
                            && let Some(b) = inner.get(&declared).filter(|b| carried(b))
                        {
                            env.insert(declared, b.clone());
                        }
                    }
                }
                match stmt {
                    Stmt::Expr(e, None) if !matches!(e, Expr::ForLoop(_)) => {
                        self.error(e, "a loop body is statements (`acc += …;`), not a value");
                    }
                    s => self.statement(s, &mut inner),
                }
            }
            let outer: Vec<String> = env
                .iter()
                .filter(|(n, b)| carried(b) && !shadowed.contains(*n))
                .map(|(n, _)| n.clone())
                .collect();
            for n in outer {
                if let Some(b) = inner.get(&n).filter(|b| carried(b)) {
                    env.insert(n, b.clone());
                }
            }
        }
    }

    /// The constant `k` as an index.
    pub(super) fn constant(&mut self, k: i64) -> Int {
        Int {
            affine: Some(Affine::constant(k)),
            wrap: false,
            value: Some(self.graph.num(k as f64)),
        }
    }
}

/// Whether an unrolled copy of a loop body hands a binding on to the next copy and to the
/// code after the loop: an accumulator, and values (a local array set element by element).
fn carried(b: &Binding) -> bool {
    matches!(b, Binding::Mut { .. } | Binding::Values(_))
}

/// `a` for a name, `the value` for anything else: how an error names the values it reads.
fn written_base(e: &Expr) -> String {
    match strip(e) {
        Expr::Path(p) => match p.path.get_ident() {
            Some(n) => format!("`{n}`"),
            None => "the value".into(),
        },
        _ => "the value".into(),
    }
}

/// The names a `let` pattern binds.
fn pattern_names(pat: &Pat) -> Vec<String> {
    match pat {
        Pat::Ident(pi) => vec![pi.ident.to_string()],
        Pat::Type(pt) => pattern_names(&pt.pat),
        Pat::Tuple(pt) => pt.elems.iter().flat_map(pattern_names).collect(),
        Pat::Slice(ps) => ps.elems.iter().flat_map(pattern_names).collect(),
        _ => Vec::new(),
    }
}

/// Whether a loop body reads values that are not `x` or `v` at an index that is not a literal
/// (`a[k]`, `rot(q)[k + 1]`, `a[m]` with `let m = j - k;`): a loop over a literal range with
/// such a body is unrolled (an index that is still not a constant then is an error). Read
/// off the tokens: a bracket group that follows a name other than `x`/`v` (or a closing
/// group) and holds more than one integer literal.
fn reads_values_at_variable(tokens: TokenStream, env: &Env) -> bool {
    let tokens: Vec<TokenTree> = tokens.into_iter().collect();
    tokens.iter().enumerate().any(|(k, tt)| {
        let TokenTree::Group(g) = tt else {
            return false;
        };
        let indexed = g.delimiter() == proc_macro2::Delimiter::Bracket
            && match k.checked_sub(1).map(|j| &tokens[j]) {
                Some(TokenTree::Ident(name)) => {
                    !matches!(env.get(&name.to_string()), Some(Binding::Array { .. }))
                }
                Some(TokenTree::Group(_)) => true,
                _ => false,
            };
        let literal = {
            let mut inner = g.stream().into_iter();
            matches!(
                (inner.next(), inner.next()),
                (Some(TokenTree::Literal(_)), None)
            )
        };
        (indexed && !literal) || reads_values_at_variable(g.stream(), env)
    })
}
