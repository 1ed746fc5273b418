//! Integer expressions: the ranges of loops, the components `x[i + 1]`, `x[(i + 1) % N]`, and
//! integers used as numbers (`(N - i) as f64`, `i.max(j) as f64`).

use syn::{BinOp, Expr, Lit};

use super::body::Parser;
use super::branch::tighter;
use super::scope::{Binding, Env, Int, strip};
use crate::ir::{Affine, Bound, Cmp, Component, Guard, Id, Sym, Var, constant_value};

const INDEX_FORMS: &str = "index expressions are built from loop variables, the dimension, \
     `usize` consts, integer literals, `+ - *`, `/` of constants by a literal, `% N` and \
     `max`/`min`";

impl Parser {
    /// Whether `e` is an integer expression: it names a loop variable, an index `let` or `N`.
    pub(super) fn is_int(&self, e: &Expr, env: &Env) -> bool {
        self.int_like(e, env, false)
    }

    /// Whether `e` is an integer expression, counting the names of `usize` consts (`M`) and
    /// integer literals: in `… as f64`, where neither can be an `f64`.
    pub(super) fn is_int_cast(&self, e: &Expr, env: &Env) -> bool {
        self.int_like(e, env, true)
    }

    /// Whether `let name = e;` binds an index because of a `usize` const: `e` names one, and
    /// is made of integers only (`M / 2`, `M - 1`), so that `let a = K * 2.0;` is still read
    /// as a number.
    pub(super) fn is_const_index(&self, e: &Expr, env: &Env) -> bool {
        fn walk(e: &Expr, env: &Env, named: &mut bool) -> bool {
            match strip(e) {
                Expr::Path(p) => match p.path.get_ident().map(ToString::to_string) {
                    Some(name) => match env.get(&name) {
                        Some(b) => matches!(b, Binding::Index(_) | Binding::Dim | Binding::Int(_)),
                        None => {
                            *named |= is_const_name(&name);
                            is_const_name(&name)
                        }
                    },
                    None => false,
                },
                Expr::Binary(b) => {
                    matches!(
                        b.op,
                        BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Div(_)
                    ) && walk(&b.left, env, named)
                        && walk(&b.right, env, named)
                }
                Expr::Lit(l) => {
                    matches!(&l.lit, Lit::Int(i) if matches!(i.suffix(), "" | "usize"))
                }
                _ => false,
            }
        }
        let mut named = false;
        walk(e, env, &mut named) && named
    }

    fn int_like(&self, e: &Expr, env: &Env, consts: bool) -> bool {
        match strip(e) {
            Expr::Path(p) => match p.path.get_ident().map(ToString::to_string) {
                Some(name) => match env.get(&name) {
                    Some(b) => matches!(b, Binding::Index(_) | Binding::Dim | Binding::Int(_)),
                    None => consts && is_const_name(&name),
                },
                None => false,
            },
            Expr::Binary(b) => {
                matches!(
                    b.op,
                    BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Rem(_) | BinOp::Div(_)
                ) && (self.int_like(&b.left, env, consts) || self.int_like(&b.right, env, consts))
            }
            Expr::MethodCall(mc) if mc.method == "max" || mc.method == "min" => {
                self.int_like(&mc.receiver, env, consts)
            }
            // Under `as f64`, `(7 / 2)` is integer arithmetic, as in Rust.
            Expr::Lit(l) => {
                matches!(&l.lit, Lit::Int(i) if i.suffix() == "usize" || (consts && i.suffix().is_empty()))
            }
            _ => false,
        }
    }

    /// `e` as an integer expression; `None` after reporting an error.
    pub(super) fn int_expr(&mut self, e: &Expr, env: &Env) -> Option<Int> {
        let affine = |a: Affine, value: Id| Int {
            affine: Some(a),
            wrap: false,
            value: Some(value),
        };
        match strip(e) {
            Expr::Lit(l) => match &l.lit {
                Lit::Int(i) if matches!(i.suffix(), "" | "usize") => {
                    match i.base10_parse::<i64>() {
                        Ok(n) => Some(affine(Affine::constant(n), self.graph.num(n as f64))),
                        Err(err) => {
                            self.errors.push(err);
                            None
                        }
                    }
                }
                other => {
                    self.error(other, format!("not an integer: {INDEX_FORMS}"));
                    None
                }
            },
            Expr::Path(p) => {
                let name = p
                    .path
                    .get_ident()
                    .map(ToString::to_string)
                    .unwrap_or_default();
                match env.get(&name) {
                    Some(&Binding::Index(i)) => {
                        Some(affine(Affine::var(i), self.graph.var(Var::Index(i))))
                    }
                    Some(Binding::Dim) => {
                        let value = self.dim_value();
                        Some(affine(Affine::dim(), value))
                    }
                    Some(&Binding::Int(v)) => Some(v),
                    Some(_) => {
                        self.error(
                            p,
                            format!("`{name}` is a number, not an index: a loop range or an index cannot depend on `x`, `v`, `t` or a model constant; {INDEX_FORMS}"),
                        );
                        None
                    }
                    None if is_const_name(&name) => {
                        // A `usize` const item: the generated code names it (an unknown name
                        // is then rustc's error, on these tokens).
                        let ident = p.path.get_ident().cloned()?;
                        let s = self.graph.sym(Sym::Named(ident));
                        let value = self.graph.var(Var::Sym(s));
                        Some(affine(Affine::sym(s), value))
                    }
                    None => {
                        self.error(p, format!("unknown index `{name}`: {INDEX_FORMS}"));
                        None
                    }
                }
            }
            Expr::Binary(b) => self.int_binary(b, env),
            Expr::MethodCall(mc)
                if (mc.method == "max" || mc.method == "min") && mc.args.len() == 1 =>
            {
                let a = self.int_expr(&mc.receiver, env)?;
                let b = self.int_expr(&mc.args[0], env)?;
                let (Some(va), Some(vb)) = (a.value, b.value) else {
                    self.error(
                        mc,
                        "`max`/`min` of a wrapped index (`% N`) is not supported",
                    );
                    return None;
                };
                let op = if mc.method == "max" { Cmp::Ge } else { Cmp::Le };
                let value = self.graph.select(op, va, vb, va, vb);
                Some(Int {
                    affine: None,
                    wrap: false,
                    value: Some(value),
                })
            }
            Expr::Cast(c) if is_usize(&c.ty) => self.int_expr(&c.expr, env),
            Expr::Index(ix) => {
                self.error(ix, "`x[…]` and `v[…]` are numbers: a loop range or an index cannot depend on `x` or `v`");
                None
            }
            other => {
                self.error(other, format!("not an index expression: {INDEX_FORMS}"));
                None
            }
        }
    }

    fn int_binary(&mut self, b: &syn::ExprBinary, env: &Env) -> Option<Int> {
        let l = self.int_expr(&b.left, env)?;
        let r = self.int_expr(&b.right, env)?;
        if let BinOp::Div(_) = b.op {
            return self.int_division(b, l, r);
        }
        if let BinOp::Rem(_) = b.op {
            let is_dim = r.affine.is_some_and(|a| {
                a == Affine::dim() || Some(a) == self.dim.map(|d| Affine::constant(d as i64))
            });
            let unrolled = self.attr != crate::ir::Attr::Lagrangian;
            return match (l.affine, is_dim, l.wrap) {
                // A force's or constraint's loops are unrolled: a constant index wraps now.
                (Some(a), true, false) if unrolled && a.as_constant().is_some() => {
                    let (k, d) = (a.as_constant()?, self.dim? as i64);
                    Some(self.constant(k.rem_euclid(d)))
                }
                (Some(a), true, false) => Some(Int {
                    affine: Some(a),
                    wrap: true,
                    value: None,
                }),
                _ => {
                    self.error(b, "`%` is supported as `(a·i + b) % N`, a periodic index, with `N` the dimension");
                    None
                }
            };
        }
        if l.wrap || r.wrap {
            self.error(
                b,
                "an index taken `% N` cannot be combined further: apply `% N` last",
            );
            return None;
        }
        let affine = match (b.op, l.affine, r.affine) {
            (BinOp::Add(_), Some(a), Some(c)) => a.add_scaled(c, 1),
            (BinOp::Sub(_), Some(a), Some(c)) => a.add_scaled(c, -1),
            (BinOp::Mul(_), Some(a), Some(c)) => match (a.as_constant(), c.as_constant()) {
                (Some(k), _) => Some(c.scaled(k)),
                (_, Some(k)) => Some(a.scaled(k)),
                _ => None,
            },
            _ => None,
        };
        let value = match (l.value, r.value) {
            (Some(x), Some(y)) => Some(match b.op {
                BinOp::Add(_) => self.graph.add(x, y),
                BinOp::Sub(_) => self.graph.sub(x, y),
                BinOp::Mul(_) => self.graph.mul(x, y),
                _ => {
                    self.error(
                        b.op,
                        format!("this operator is not supported on indices: {INDEX_FORMS}"),
                    );
                    return None;
                }
            }),
            _ => None,
        };
        Some(Int {
            affine,
            wrap: false,
            value,
        })
    }

    /// `a / d`: of constants (`N / 2`, `M / 2`, `7 / 2`) by a positive literal `d`. The floor
    /// of a loop variable's multiple is not an index (`x[i / 2]` names each component twice,
    /// which an affine index cannot say), so it is rejected with the loop that says it.
    fn int_division(&mut self, b: &syn::ExprBinary, l: Int, r: Int) -> Option<Int> {
        let d = match r.affine.and_then(Affine::as_constant) {
            Some(d) if d > 0 && !r.wrap => d,
            _ => {
                self.error(
                    &b.right,
                    "an index may be divided only by a positive integer literal, e.g. `N / 2`",
                );
                return None;
            }
        };
        let a = match l.affine {
            Some(a) if !l.wrap => a.at_dim(self.dim),
            _ => {
                self.error(b, format!("not an index expression: {INDEX_FORMS}"));
                return None;
            }
        };
        if a.var.is_some() {
            self.error(
                b,
                "`/` of a loop variable is not an index: split the loop instead, e.g. `for j in 0..N / 2 { … x[2 * j] … x[2 * j + 1] … }`",
            );
            return None;
        }
        let affine = match a.as_constant() {
            Some(c) if c >= 0 => Affine::constant(c / d),
            Some(_) => {
                self.error(b, "this division is of a negative index");
                return None;
            }
            None if d == 1 => a,
            None => Affine::sym(self.graph.sym(Sym::Div(a, d))),
        };
        let value = match (affine.as_constant(), affine.sym) {
            (Some(c), _) => self.graph.num(c as f64),
            (None, Some(s)) if affine == Affine::sym(s) => self.graph.var(Var::Sym(s)),
            _ => l.value?,
        };
        Some(Int {
            affine: Some(affine),
            wrap: false,
            value: Some(value),
        })
    }

    /// `N` as a number.
    fn dim_value(&mut self) -> Id {
        match self.dim {
            Some(d) => self.graph.num(d as f64),
            None => self.graph.var(Var::Dim),
        }
    }

    /// An integer expression as a number (`(N - i) as f64`).
    pub(super) fn int_value(&mut self, e: &Expr, env: &Env) -> Id {
        match self.int_expr(e, env) {
            Some(Int { value: Some(v), .. }) => v,
            Some(_) => self.error(e, "an index taken `% N` cannot be used as a number"),
            None => self.graph.num(0.0),
        }
    }

    /// One end of a loop range.
    pub(super) fn range_end(&mut self, e: &Expr, env: &Env) -> Option<Affine> {
        let v = self.int_expr(e, env)?;
        match v.affine {
            Some(a) if !v.wrap => Some(a.at_dim(self.dim)),
            _ => {
                self.error(e, "a loop range must be `a·i + b` in an outer loop variable `i`, the dimension and integer literals");
                None
            }
        }
    }

    /// The component an index expression names, checked against the dimension where the
    /// check can be decided at compile time. An index that leaves `0..N` somewhere in its
    /// loop but not where the `if`s around it let the loop through is guarded by them
    /// (`branch.rs`).
    pub(super) fn component(&mut self, e: &Expr, env: &Env) -> Option<Component> {
        let v = self.int_expr(e, env)?;
        let Some(at) = v.affine else {
            self.error(e, "an index must be `a·i + b` (optionally `% N`) in a loop variable `i`, the dimension and integer literals");
            return None;
        };
        let at = at.at_dim(self.dim);
        let range = at.var.map(|i| {
            let r = &self.graph.ranges[i.0 as usize];
            (r.start, r.end)
        });
        let Some(plain) = self.sides(at, range, v.wrap) else {
            self.error(e, "this index and the range of its loop name two different consts (or divisions): the bound check follows one; write both in the same const, or in `N`");
            return None;
        };
        let mut chosen = (Guard::NONE, range, plain);
        if let (true, Some(i), Some((start, end))) = (plain.fails(), at.var, range) {
            // The least guard that keeps the index in range: one side, then both.
            let (low, high) = self.fact_bounds(i);
            let mut candidates = Vec::new();
            if low.is_some() {
                candidates.push((low, None));
            }
            if high.is_some() {
                candidates.push((None, high));
            }
            if low.is_some() && high.is_some() {
                candidates.push((low, high));
            }
            for (gl, gh) in candidates {
                let narrowed = (
                    gl.map_or(start, |l| tighter(start, l, true)),
                    gh.map_or(end, |h| tighter(end, h, false)),
                );
                if let Some(sides) = self.sides(at, Some(narrowed), v.wrap)
                    && !sides.fails()
                {
                    chosen = (Guard { low: gl, high: gh }, Some(narrowed), sides);
                    break;
                }
            }
        }
        let (guard, range, (low, high)) = chosen;
        // `low`, `high`: whether the least and greatest value over the iterations that read
        // the index are in range; where they name a const the macro does not know, the
        // compiler checks.
        let text = quote::ToTokens::to_token_stream(e).to_string();
        let protected = at.var.is_some_and(|i| self.has_facts(i));
        match low {
            Side::Deferred(lhs, rhs) => {
                let what = match guard.low {
                    Some(_) => format!(
                        "the index `{text}` is negative at the first iteration that the `if` around it lets through"
                    ),
                    None => format!("the index `{text}` is negative at the start of its loop"),
                };
                self.defer_bound(e, range, (lhs, rhs), what);
            }
            Side::Fails if protected => {
                let hint = match (at.scale, at.n, at.sym, at.var) {
                    (1, 0, None, Some(i)) => format!(
                        " (`if {} >= {}` would)",
                        self.graph.ranges[i.0 as usize].name, -at.c
                    ),
                    _ => String::new(),
                };
                self.error(e, format!("the `if` around the index `{text}` does not protect it: the index is negative at the first iteration that its condition lets through{hint}"));
                return None;
            }
            Side::Fails => {
                let msg = if v.wrap {
                    "this index is negative at the start of its loop, and `%` of a negative index underflows: add `N`, e.g. `(i + N - 1) % N`".to_string()
                } else {
                    format!(
                        "this index is negative at the start of its loop{}",
                        self.branch_hint(at, "start")
                    )
                };
                self.error(e, msg);
                return None;
            }
            Side::Ok => {}
        }
        let bound = match self.dim {
            Some(d) => format!("{d}"),
            None => "`N`".into(),
        };
        match high {
            Side::Deferred(lhs, rhs) => {
                let what = match guard.high {
                    Some(_) => format!(
                        "the index `{text}` reaches the dimension or beyond at the last iteration that the `if` around it lets through"
                    ),
                    None => format!(
                        "the index `{text}` reaches the dimension or beyond at the end of its loop"
                    ),
                };
                self.defer_bound(e, range, (lhs, rhs), what);
            }
            Side::Fails if protected => {
                let n = match self.dim {
                    Some(d) => format!("{d}"),
                    None => "N".into(),
                };
                self.error(e, format!("the `if` around the index `{text}` does not protect it: the index reaches {bound} or beyond at the last iteration that its condition lets through (`if {text} < {n}` would)"));
                return None;
            }
            Side::Fails => {
                let hint = self.branch_hint(at, "end");
                self.error(e, format!("this index reaches {bound} or beyond at the end of its loop: the components are `0..N`{hint}"));
                return None;
            }
            Side::Ok => {}
        }
        Some(Component {
            at,
            wrap: v.wrap,
            guard,
        })
    }

    /// Whether `at` stays in `0..N` at the start and at the end of `range` (the range of its
    /// loop variable, or a part of it; `None` for an index without one); `None` when that
    /// needs two different [`Sym`]s. A periodic index (`wrap`) only needs its start.
    fn sides(
        &self,
        at: Affine,
        range: Option<(Affine, Affine)>,
        wrap: bool,
    ) -> Option<(Side, Side)> {
        // The least and greatest value over the range, as `n·N + c`.
        let (low, high) = match range {
            Some((start, end)) => self.extent_over(at, start, end)?,
            None => (at, at),
        };
        let surely_natural = low.n >= 0 && low.k >= 0 && low.c >= 0;
        let low_side = if low.sym.is_some() && !surely_natural {
            Side::Deferred(Affine::constant(-1), low)
        } else if low.n < 0 || (low.n == 0 && low.c < 0) {
            Side::Fails
        } else {
            Side::Ok
        };
        if wrap {
            return Some((low_side, Side::Ok));
        }
        let high_side = if high.sym.is_some() {
            Side::Deferred(high, Affine::dim().at_dim(self.dim))
        } else {
            let above = match self.dim {
                Some(d) => high.n == 0 && high.c >= d as i64,
                None => high.n > 1 || (high.n == 1 && high.c >= 0),
            };
            if above { Side::Fails } else { Side::Ok }
        };
        Some((low_side, high_side))
    }

    /// For an index out of range in a branch of an `if` on its loop variable whose condition
    /// does not say which iterations read it: the conditions that do, and the way without one.
    fn branch_hint(&self, at: Affine, end: &'static str) -> String {
        match at.var {
            Some(i) if self.branch_vars.contains(&i) => {
                let n = &self.graph.ranges[i.0 as usize].name;
                // `x[i − c]` is valid from `i = c`, `x[i + c]` up to `N − c`; other forms get
                // the advice without the bound.
                let plain = at.scale == 1 && at.n == 0 && at.sym.is_none();
                let range = match (end == "start", plain) {
                    (true, true) => {
                        format!("from where it is valid (start its range at `{}`)", -at.c)
                    }
                    (false, true) => {
                        format!("up to where it is valid (end its range at `N - {}`)", at.c)
                    }
                    (true, false) => "from where it is valid".to_string(),
                    (false, false) => "up to where it is valid".to_string(),
                };
                format!(
                    ", and the `if` on `{n}` around it does not say which iterations read it: write its condition as a comparison of `{n}` with a constant or `N` (`{n} > 0`, `{n} + 1 < N`), or run the loop {range} and write the boundary term outside it"
                )
            }
            _ => String::new(),
        }
    }

    /// A check of `component` as a `const` assertion in the generated code, `lhs < rhs`
    /// where the loop range `guard` is not empty: for an index whose extent names a [`Sym`].
    fn defer_bound(
        &mut self,
        e: &Expr,
        guard: Option<(Affine, Affine)>,
        (lhs, rhs): (Affine, Affine),
        what: String,
    ) {
        let bounds = &mut self.graph.bounds;
        // One assertion per check: `x[2 * i]` read twice fails once.
        if !bounds
            .iter()
            .any(|b| (b.guard, b.lhs, b.rhs) == (guard, lhs, rhs))
        {
            bounds.push(Bound {
                guard,
                lhs,
                rhs,
                what,
                span: syn::spanned::Spanned::span(e),
            });
        }
    }

    /// The least and greatest value of `at` over `start..end` (the range of its loop variable,
    /// or a part of it), as affine expressions in `N` and a [`Sym`] (`n: 0, c: 0` bounds that
    /// are not decidable are reported as in range); `None` when that needs two different
    /// [`Sym`]s.
    fn extent_over(&self, at: Affine, start: Affine, end: Affine) -> Option<(Affine, Affine)> {
        let last = end.add_scaled(Affine::constant(1), -1).unwrap_or(end);
        if start.var.is_some() || last.var.is_some() {
            // A range that depends on an outer loop variable: not decided here.
            return Some((Affine::constant(0), Affine::constant(0)));
        }
        let rest = Affine {
            var: None,
            scale: 0,
            ..at
        };
        let at_start = rest.add_scaled(start, at.scale)?;
        let at_last = rest.add_scaled(last, at.scale)?;
        Some(if at.scale > 0 {
            (at_start, at_last)
        } else {
            (at_last, at_start)
        })
    }
}

/// Whether one end of an index's values is in `0..N`.
#[derive(Clone, Copy)]
enum Side {
    Ok,
    Fails,
    /// Decided by the compiler: `lhs < rhs`, a `const` assertion.
    Deferred(Affine, Affine),
}

impl Side {
    fn fails(self) -> bool {
        matches!(self, Side::Fails)
    }
}

trait Fails {
    fn fails(&self) -> bool;
}

impl Fails for (Side, Side) {
    fn fails(&self) -> bool {
        self.0.fails() || self.1.fails()
    }
}

/// Whether an unbound `name` is taken for a `usize` const item: written in `UPPER_CASE`, and
/// not one of `std::f64::consts`.
fn is_const_name(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_uppercase())
        && name
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
        && constant_value(name).is_none()
}

/// Whether `ty` is `usize`.
fn is_usize(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Path(tp) if tp.path.is_ident("usize"))
}
