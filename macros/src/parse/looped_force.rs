//! The body of a `#[force]` over a named dimension (`x: [f64; N]`) or slices (`x: &[f64]`,
//! `n: usize`): a zero force declared once, `let mut f = [0.0; N];` (`vec![0.0; n]`), its
//! components added to, `f[i] += …;` / `f[i + 1] -= …;` in straight-line code or in loops, and
//! `f` at the end.
//!
//! The force is read as its virtual work `W = Σ_k w_k f_k`: each `f[idx] += e` adds
//! `w[idx]·e` to an accumulator, the leaves `w` being [`Var::F`]/[`Var::FAt`]. `W` is then a
//! scalar with loops like a Lagrangian, linear in `w`, and `f_k = ∂W/∂w_k`,
//! `∂f_k/∂x_j = ∂²W/∂w_k∂x_j` come out of the loop path's term-by-term derivatives
//! (`assemble::assemble_force`). Only `+=` and `-=` are taken: with the force starting at
//! zero they are sums, where `f[i] = e` would overwrite what another statement added.

use syn::{Expr, ExprRepeat, Ident, Lit, Stmt};

use super::body::{Parser, is_compound};
use super::scope::{Binding, Env, strip};
use super::signature::{Shape, Signature};
use crate::ir::{Id, Var};

/// The name the virtual work is accumulated under (not an identifier, so no clash).
const WORK: &str = "virtual work";

impl Parser {
    /// The virtual work of a force with loops: the body's statements, with the force declared
    /// and added to as the module says, ending with the force's name.
    pub(super) fn looped_force_body(
        &mut self,
        block: &syn::Block,
        sig: &Signature,
        env: &mut Env,
    ) -> Id {
        let zero = self.graph.num(0.0);
        env.insert(WORK.into(), Binding::Mut { id: zero, depth: 0 });
        let n = block.stmts.len();
        for stmt in block.stmts.iter().take(n.saturating_sub(1)) {
            self.statement(stmt, env);
        }
        let declared = env.iter().find_map(|(name, b)| match b {
            Binding::Output => Some(name.clone()),
            _ => None,
        });
        let want = match sig.states.first().map(|s| s.1) {
            Some(Shape::Slice) => "`let mut f = vec![0.0; n];` (`n` the dimension)",
            _ => "`let mut f = [0.0; N];` (`N` the dimension)",
        };
        let last = match block.stmts.last() {
            Some(Stmt::Expr(e, None)) => Some(e),
            _ => None,
        };
        let ends_with = last.and_then(|e| match strip(e) {
            Expr::Path(p) => p.path.get_ident().map(Ident::to_string),
            _ => None,
        });
        match (declared, ends_with) {
            (Some(d), Some(e)) if d == e => {}
            (Some(d), _) => {
                let msg = format!("the body must end with the force, `{d}`");
                match last {
                    Some(e) => self.error(e, msg),
                    None => {
                        self.errors
                            .push(syn::Error::new(block.brace_token.span.close(), msg));
                        zero
                    }
                };
            }
            (None, _) => {
                let msg = format!(
                    "a force over a named or run-time dimension starts from zero, {want}, adds to its components (`f[i] += …;`) and ends with `f`"
                );
                match last {
                    Some(e) => {
                        self.error(e, msg);
                    }
                    None => self
                        .errors
                        .push(syn::Error::new(block.brace_token.span.join(), msg)),
                }
            }
        }
        match env.get(WORK) {
            Some(&Binding::Mut { id, .. }) => id,
            _ => zero,
        }
    }

    /// `let mut f = [0.0; N];` or `let mut f = vec![0.0; n];` in the body of a force with
    /// loops, `N` (`n`) the dimension: binds `f` as the force. `false` when `init` is not such
    /// a value.
    pub(super) fn declares_force(&mut self, pat: &syn::Pat, init: &Expr, env: &mut Env) -> bool {
        if !self.looped_force {
            return false;
        }
        let repeat = match strip(init) {
            Expr::Repeat(r) => Some(r.clone()),
            Expr::Macro(m) if m.mac.path.is_ident("vec") => {
                let tokens = &m.mac.tokens;
                syn::parse2::<ExprRepeat>(quote::quote!([#tokens])).ok()
            }
            _ => None,
        };
        let Some(repeat) = repeat else {
            return false;
        };
        let is_zero = matches!(strip(&repeat.expr), Expr::Lit(l) if match &l.lit {
            Lit::Float(f) => f.base10_parse::<f64>().is_ok_and(|z| z == 0.0),
            Lit::Int(i) => i.base10_parse::<u64>().is_ok_and(|z| z == 0),
            _ => false,
        });
        let is_dim = matches!(strip(&repeat.len), Expr::Path(p)
            if p.path.get_ident().is_some_and(|n| matches!(env.get(&n.to_string()), Some(Binding::Dim))));
        let name = match pat {
            syn::Pat::Ident(pi) if pi.mutability.is_some() && pi.subpat.is_none() => {
                Some(pi.ident.to_string())
            }
            _ => None,
        };
        if !is_zero || !is_dim {
            // Reported, and `f` still bound as the force so that its uses report nothing more.
            self.error(
                init,
                "the force starts from zero over the dimension: `[0.0; N]` (slices: `vec![0.0; n]`)",
            );
        }
        let Some(name) = name else {
            self.error(pat, "the force is a `let mut` name: `let mut f = …;`");
            return true;
        };
        if self.frames_open() {
            self.error(pat, "the force is declared outside every loop");
            return true;
        }
        if env.values().any(|b| matches!(b, Binding::Output)) {
            self.error(pat, "the force is declared once");
            return true;
        }
        env.insert(name, Binding::Output);
        true
    }

    /// `f[idx] += e;` or `f[idx] -= e;` on the force `f`: adds `±w[idx]·e` to the virtual
    /// work. `false` when `e` does not update the force (it is then read as any statement).
    pub(super) fn adds_to_force(&mut self, e: &Expr, env: &mut Env) -> bool {
        let (left, op, right) = match e {
            Expr::Assign(a) => (&*a.left, None, &*a.right),
            Expr::Binary(b) if is_compound(b.op) => (&*b.left, Some(b.op), &*b.right),
            _ => return false,
        };
        let target = match strip(left) {
            Expr::Index(ix) => Some((&*ix.expr, Some(&*ix.index))),
            other => Some((other, None)),
        };
        let Some((array, index)) = target else {
            return false;
        };
        let is_force = matches!(strip(array), Expr::Path(p)
            if p.path.get_ident().is_some_and(|n| matches!(env.get(&n.to_string()), Some(Binding::Output))));
        if !is_force {
            return false;
        }
        let Some(index) = index else {
            self.error(
                left,
                "the force is added to component by component: `f[i] += …;`",
            );
            return true;
        };
        let negative = match op {
            Some(syn::BinOp::AddAssign(_)) => false,
            Some(syn::BinOp::SubAssign(_)) => true,
            _ => {
                self.error(
                    e,
                    "a component of the force is added to (`f[i] += …;`) or subtracted from (`-=`): the force starts at zero and each statement adds its part, so an assignment or a product could undo another's",
                );
                return true;
            }
        };
        let weight = self.force_weight(index, env);
        let value = self.expr(right, env);
        let Some(weight) = weight else {
            return true;
        };
        let w = self.graph.var(weight);
        let mut work = self.graph.mul(w, value);
        if negative {
            work = self.graph.neg(work);
        }
        self.add_to(WORK, work, env);
        true
    }

    /// The weight leaf of the force component at `index` (checked like an index of `x`).
    fn force_weight(&mut self, index: &Expr, env: &Env) -> Option<Var> {
        if let Expr::Lit(syn::ExprLit {
            lit: Lit::Int(i), ..
        }) = strip(index)
        {
            return match i.base10_parse::<usize>() {
                Ok(i) => Some(Var::F(i)),
                Err(e) => {
                    self.errors.push(e);
                    None
                }
            };
        }
        let c = self.component(index, env)?;
        Some(match c.at.as_constant() {
            Some(k) if !c.wrap => Var::F(k as usize),
            _ => Var::FAt(c),
        })
    }
}
