//! Branches, `if c { a } else { b }`: their conditions, and the indices those conditions
//! guard, as in `for i in 0..N { let left = if i > 0 { x[i - 1] } else { 0.0 }; … }`.
//!
//! Both branches are differentiated, the condition is not (`Select` nodes). A condition on
//! constants alone (the variable of an unrolled loop) is decided when the fn is parsed.
//!
//! The condition of a branch tells which iterations read the branch, where it compares a loop
//! variable with a constant or `N` (a [`Fact`]: `i ≥ low`, `i < high`). An index that would
//! leave `0..N` somewhere in the range of its loop, but stays inside over the iterations its
//! branch is read in, becomes a component with a [`Guard`](crate::ir::Guard): the generated
//! code reads it, and adds its derivatives into their entries, only where the guard holds.
//! The branch's value and derivatives are `if c { … } else { … }` already, so the guard
//! changes no number; it keeps the other iterations from naming an entry that does not exist
//! (`fx[i - 1]` at `i = 0`). A guard is a side of the facts, never more than they say, so it
//! holds wherever the branch is taken.

use syn::{BinOp, Expr, UnOp};

use super::body::Parser;
use super::scope::{Binding, Env, Fact, strip};
use crate::ir::{Affine, Cmp, Id, IndexVar};

impl Parser {
    /// `if c { a } else { b }`: both branches are differentiated, the condition is not.
    pub(super) fn conditional(&mut self, x: &syn::ExprIf, env: &Env) -> Id {
        let Some((_, else_branch)) = &x.else_branch else {
            return self.error(
                x.if_token,
                "an `if` needs an `else`: `if c { a } else { b }`",
            );
        };
        // A condition on constants alone (the variable of an unrolled loop, a literal
        // dimension) is decided here, and only the branch it takes is read: the other may
        // name an index that does not exist there (`a[k - 1]` at `k = 0`).
        if let Some(taken) = self.constant_condition(&x.cond, env) {
            return if taken {
                self.block(&x.then_branch, &mut env.clone())
            } else {
                self.expr(else_branch, env)
            };
        }
        // What the condition says of the loop variables guards the indices of each branch
        // (below); the variables it tests are kept for the hint of an index error.
        let depth = self.branch_vars.len();
        tested_vars(&x.cond, env, &mut self.branch_vars);
        let open = self.facts.len();
        let (holds, fails) = (
            self.condition_facts(&x.cond, env, true),
            self.condition_facts(&x.cond, env, false),
        );
        self.facts.extend(holds);
        let then = self.block(&x.then_branch, &mut env.clone());
        self.facts.truncate(open);
        self.facts.extend(fails);
        let other = self.expr(else_branch, env);
        self.facts.truncate(open);
        self.branch_vars.truncate(depth);
        self.condition(&x.cond, env, then, other)
    }

    /// `if cond { then } else { other }` for a condition made of comparisons.
    fn condition(&mut self, cond: &Expr, env: &Env, then: Id, other: Id) -> Id {
        match strip(cond) {
            Expr::Binary(b) => {
                let op = match b.op {
                    BinOp::Lt(_) => Cmp::Lt,
                    BinOp::Le(_) => Cmp::Le,
                    BinOp::Gt(_) => Cmp::Gt,
                    BinOp::Ge(_) => Cmp::Ge,
                    BinOp::Eq(_) => Cmp::Eq,
                    BinOp::Ne(_) => Cmp::Ne,
                    BinOp::And(_) => {
                        let inner = self.condition(&b.right, env, then, other);
                        return self.condition(&b.left, env, inner, other);
                    }
                    BinOp::Or(_) => {
                        let inner = self.condition(&b.right, env, then, other);
                        return self.condition(&b.left, env, then, inner);
                    }
                    _ => return self.condition_error(cond),
                };
                let int = self.is_int(&b.left, env) || self.is_int(&b.right, env);
                let (l, r) = if int {
                    (self.int_value(&b.left, env), self.int_value(&b.right, env))
                } else {
                    (self.expr(&b.left, env), self.expr(&b.right, env))
                };
                if self.holds_sum(l) || self.holds_sum(r) {
                    return self.sum_inside(cond, "a condition");
                }
                self.graph.select(op, l, r, then, other)
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Not(_)) => {
                self.condition(&u.expr, env, other, then)
            }
            _ => self.condition_error(cond),
        }
    }

    /// The value of a condition that compares integer constants only (`k > 0` with `k` the
    /// variable of an unrolled loop), combined with `&&`, `||`, `!`; `None` for any other.
    fn constant_condition(&mut self, cond: &Expr, env: &Env) -> Option<bool> {
        match strip(cond) {
            Expr::Binary(b) => {
                let op = match b.op {
                    BinOp::And(_) => {
                        let l = self.constant_condition(&b.left, env)?;
                        let r = self.constant_condition(&b.right, env)?;
                        return Some(l && r);
                    }
                    BinOp::Or(_) => {
                        let l = self.constant_condition(&b.left, env)?;
                        let r = self.constant_condition(&b.right, env)?;
                        return Some(l || r);
                    }
                    BinOp::Lt(_) => Cmp::Lt,
                    BinOp::Le(_) => Cmp::Le,
                    BinOp::Gt(_) => Cmp::Gt,
                    BinOp::Ge(_) => Cmp::Ge,
                    BinOp::Eq(_) => Cmp::Eq,
                    BinOp::Ne(_) => Cmp::Ne,
                    _ => return None,
                };
                if !(self.is_int(&b.left, env) || self.is_int(&b.right, env)) {
                    return None;
                }
                // Read without a trace: a condition that is not constant is read again, with
                // its errors, as a condition.
                let (errors, syms) = (self.errors.len(), self.graph.syms.len());
                let l = self.int_expr(&b.left, env);
                let r = self.int_expr(&b.right, env);
                self.errors.truncate(errors);
                self.graph.syms.truncate(syms);
                let constant =
                    |v: Option<super::scope::Int>| v.filter(|v| !v.wrap)?.affine?.as_constant();
                let (l, r) = (constant(l)?, constant(r)?);
                Some(op.eval(l as f64, r as f64))
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Not(_)) => {
                self.constant_condition(&u.expr, env).map(|c| !c)
            }
            _ => None,
        }
    }

    fn condition_error(&mut self, cond: &Expr) -> Id {
        self.error(cond, "a condition is a comparison of numbers (`<`, `<=`, `>`, `>=`, `==`, `!=`), possibly combined with `&&`, `||`, `!`")
    }

    /// What `cond` says of the loop variables where it holds (`holds`) or where it does not.
    /// Comparisons of a loop variable (scale ±1: `i`, `i + 1`, `N - 1 - i`) with an index free
    /// of loop variables count, combined by `&&` where it holds, by `||` where it does not;
    /// anything else says nothing.
    pub(super) fn condition_facts(&mut self, cond: &Expr, env: &Env, holds: bool) -> Vec<Fact> {
        match strip(cond) {
            Expr::Binary(b) => match b.op {
                BinOp::And(_) | BinOp::Or(_) => {
                    // `a && b` holds: both hold; `a || b` does not: neither holds.
                    let both = matches!(b.op, BinOp::And(_)) == holds;
                    if !both {
                        return Vec::new();
                    }
                    let mut out = self.condition_facts(&b.left, env, holds);
                    out.extend(self.condition_facts(&b.right, env, holds));
                    out
                }
                op => self
                    .comparison_fact(b, op, env, holds)
                    .into_iter()
                    .collect(),
            },
            Expr::Unary(u) if matches!(u.op, UnOp::Not(_)) => {
                self.condition_facts(&u.expr, env, !holds)
            }
            _ => Vec::new(),
        }
    }

    fn comparison_fact(
        &mut self,
        b: &syn::ExprBinary,
        op: BinOp,
        env: &Env,
        holds: bool,
    ) -> Option<Fact> {
        let op = match op {
            BinOp::Lt(_) => Cmp::Lt,
            BinOp::Le(_) => Cmp::Le,
            BinOp::Gt(_) => Cmp::Gt,
            BinOp::Ge(_) => Cmp::Ge,
            BinOp::Eq(_) => Cmp::Eq,
            BinOp::Ne(_) => Cmp::Ne,
            _ => return None,
        };
        if !(self.is_int(&b.left, env) || self.is_int(&b.right, env)) {
            return None;
        }
        // Read without a trace: the condition is read, with its errors, as a condition.
        let (errors, syms) = (self.errors.len(), self.graph.syms.len());
        let sides = (self.int_expr(&b.left, env), self.int_expr(&b.right, env));
        self.errors.truncate(errors);
        let affine = |v: Option<super::scope::Int>| {
            let v = v.filter(|v| !v.wrap)?;
            Some(v.affine?.at_dim(self.dim))
        };
        let (Some(l), Some(r)) = (affine(sides.0), affine(sides.1)) else {
            self.graph.syms.truncate(syms);
            return None;
        };
        // `l op r` as `s·i + rest op 0`.
        let Some(d) = l.add_scaled(r, -1) else {
            self.graph.syms.truncate(syms);
            return None;
        };
        let (Some(var), 1 | -1) = (d.var, d.scale) else {
            self.graph.syms.truncate(syms);
            return None;
        };
        let rest = Affine {
            var: None,
            scale: 0,
            ..d
        };
        let op = if holds { op } else { negated(op) };
        // `i + rest op 0` is `i op −rest`; `−i + rest op 0` is `i op' rest`, `op'` mirrored.
        let (op, c) = if d.scale == 1 {
            (op, rest.scaled(-1))
        } else {
            (mirrored(op), rest)
        };
        let plus = |a: Affine, k: i64| a.add_scaled(Affine::constant(k), 1).unwrap_or(a);
        let (low, high) = match op {
            Cmp::Lt => (None, Some(c)),
            Cmp::Le => (None, Some(plus(c, 1))),
            Cmp::Gt => (Some(plus(c, 1)), None),
            Cmp::Ge => (Some(c), None),
            Cmp::Eq => (Some(c), Some(plus(c, 1))),
            Cmp::Ne => {
                // `i != c` excludes one end of the range, when `c` is that end.
                let r = &self.graph.ranges[var.0 as usize];
                if r.start == c {
                    (Some(plus(c, 1)), None)
                } else if plus(r.end, -1) == c {
                    (None, Some(c))
                } else {
                    return None;
                }
            }
        };
        Some(Fact { var, low, high })
    }

    /// The sides the open facts put on `var`, each the tightest where two can be compared (the
    /// inner one where they cannot).
    pub(super) fn fact_bounds(&self, var: IndexVar) -> (Option<Affine>, Option<Affine>) {
        let (mut low, mut high) = (None, None);
        for f in self.facts.iter().filter(|f| f.var == var) {
            if let Some(l) = f.low {
                low = Some(low.map_or(l, |old| tighter(old, l, true)));
            }
            if let Some(h) = f.high {
                high = Some(high.map_or(h, |old| tighter(old, h, false)));
            }
        }
        (low, high)
    }

    /// Whether any open fact names `var`.
    pub(super) fn has_facts(&self, var: IndexVar) -> bool {
        self.facts.iter().any(|f| f.var == var)
    }
}

/// Of two bounds `old` and `new` (`new` the inner one): the larger (`max`) or the smaller where
/// they differ by a constant, `new` where they cannot be compared.
pub fn tighter(old: Affine, new: Affine, max: bool) -> Affine {
    match new.add_scaled(old, -1).and_then(Affine::as_constant) {
        Some(d) if (d < 0) == max => old,
        _ => new,
    }
}

/// `¬(a op b)` as `a op' b`.
fn negated(op: Cmp) -> Cmp {
    match op {
        Cmp::Lt => Cmp::Ge,
        Cmp::Le => Cmp::Gt,
        Cmp::Gt => Cmp::Le,
        Cmp::Ge => Cmp::Lt,
        Cmp::Eq => Cmp::Ne,
        Cmp::Ne => Cmp::Eq,
    }
}

/// `a op b` as `b op' a`.
fn mirrored(op: Cmp) -> Cmp {
    match op {
        Cmp::Lt => Cmp::Gt,
        Cmp::Le => Cmp::Ge,
        Cmp::Gt => Cmp::Lt,
        Cmp::Ge => Cmp::Le,
        Cmp::Eq | Cmp::Ne => op,
    }
}

/// The loop variables a condition names, into `out`.
fn tested_vars(e: &Expr, env: &Env, out: &mut Vec<crate::ir::IndexVar>) {
    match strip(e) {
        Expr::Path(p) => {
            if let Some(Binding::Index(i)) =
                p.path.get_ident().and_then(|n| env.get(&n.to_string()))
            {
                out.push(*i);
            }
        }
        Expr::Binary(b) => {
            tested_vars(&b.left, env, out);
            tested_vars(&b.right, env, out);
        }
        Expr::Unary(u) => tested_vars(&u.expr, env, out),
        Expr::Cast(c) => tested_vars(&c.expr, env, out),
        Expr::MethodCall(mc) => {
            tested_vars(&mc.receiver, env, out);
            for a in &mc.args {
                tested_vars(a, env, out);
            }
        }
        _ => {}
    }
}
