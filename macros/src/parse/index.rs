//! Integer expressions: the ranges of loops, the components `x[i + 1]`, `x[(i + 1) % N]`, and
//! integers used as numbers (`(N - i) as f64`, `i.max(j) as f64`).

use syn::{BinOp, Expr, Lit};

use super::body::Parser;
use super::scope::{Binding, Env, Int, strip};
use crate::ir::{Affine, Cmp, Component, Id, Var};

const INDEX_FORMS: &str = "index expressions are built from loop variables, the dimension, \
     integer literals, `+ - *`, `% N` and `max`/`min`";

impl Parser {
    /// Whether `e` is an integer expression: it names a loop variable, an index `let` or `N`.
    pub(super) fn is_int(&self, e: &Expr, env: &Env) -> bool {
        match strip(e) {
            Expr::Path(p) => matches!(
                p.path.get_ident().and_then(|i| env.get(&i.to_string())),
                Some(Binding::Index(_) | Binding::Dim | Binding::Int(_))
            ),
            Expr::Binary(b) => {
                matches!(
                    b.op,
                    BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Rem(_) | BinOp::Div(_)
                ) && (self.is_int(&b.left, env) || self.is_int(&b.right, env))
            }
            Expr::MethodCall(mc) if mc.method == "max" || mc.method == "min" => {
                self.is_int(&mc.receiver, env)
            }
            Expr::Lit(l) => matches!(&l.lit, Lit::Int(i) if i.suffix() == "usize"),
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
        if let BinOp::Div(_) = b.op {
            self.error(b.op, "integer division is not supported in an index");
            return None;
        }
        let l = self.int_expr(&b.left, env)?;
        let r = self.int_expr(&b.right, env)?;
        if let BinOp::Rem(_) = b.op {
            let is_dim = r.affine.is_some_and(|a| {
                a == Affine::dim() || Some(a) == self.dim.map(|d| Affine::constant(d as i64))
            });
            return match (l.affine, is_dim, l.wrap) {
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
    /// check can be decided at compile time.
    pub(super) fn component(&mut self, e: &Expr, env: &Env) -> Option<Component> {
        let v = self.int_expr(e, env)?;
        let Some(at) = v.affine else {
            self.error(e, "an index must be `a·i + b` (optionally `% N`) in a loop variable `i`, the dimension and integer literals");
            return None;
        };
        let at = at.at_dim(self.dim);
        let c = Component { at, wrap: v.wrap };
        let (low, high) = self.extent(at);
        // `low`, `high`: the least and greatest value over the loop's range, as `n·N + c`.
        let below = low.n < 0 || (low.n == 0 && low.c < 0);
        if below {
            let msg = if v.wrap {
                "this index is negative at the start of its loop, and `%` of a negative index underflows: add `N`, e.g. `(i + N - 1) % N`"
            } else {
                "this index is negative at the start of its loop"
            };
            self.error(e, msg);
            return None;
        }
        let above = match self.dim {
            Some(d) => high.n == 0 && high.c >= d as i64,
            None => high.n > 1 || (high.n == 1 && high.c >= 0),
        };
        if above && !v.wrap {
            let bound = match self.dim {
                Some(d) => format!("{d}"),
                None => "`N`".into(),
            };
            self.error(e, format!("this index reaches {bound} or beyond at the end of its loop: the components are `0..N`"));
            return None;
        }
        Some(c)
    }

    /// The least and greatest value of `at` over the range of its loop variable, as affine
    /// expressions in `N` alone (`n: 0, c: 0` bounds that are not decidable are reported as
    /// in range).
    fn extent(&self, at: Affine) -> (Affine, Affine) {
        let Some(i) = at.var else {
            return (at, at);
        };
        let r = &self.graph.ranges[i.0 as usize];
        let (start, last) = (
            r.start,
            r.end.add_scaled(Affine::constant(1), -1).unwrap_or(r.end),
        );
        if start.var.is_some() || last.var.is_some() {
            // A range that depends on an outer loop variable: not decided here.
            return (Affine::constant(0), Affine::constant(0));
        }
        let rest = Affine {
            var: None,
            scale: 0,
            ..at
        };
        let at_start = rest.add_scaled(start, at.scale).unwrap_or(rest);
        let at_last = rest.add_scaled(last, at.scale).unwrap_or(rest);
        if at.scale > 0 {
            (at_start, at_last)
        } else {
            (at_last, at_start)
        }
    }
}

/// Whether `ty` is `usize`.
fn is_usize(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Path(tp) if tp.path.is_ident("usize"))
}
