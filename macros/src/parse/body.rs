//! The body of a `#[lagrangian]` fn, walked into the expression DAG: statements, `let`
//! bindings, accumulators and `for` loops. Expressions are in `expr.rs`, integer index
//! expressions in `index.rs`.
//!
//! A loop is a sum: `let mut acc = 0.0; for i in a..b { acc += f(i); }` binds `acc` to
//! `acc + Σ_i f(i)`. Inside a loop an accumulator declared outside it may only be added to or
//! subtracted from (`+=`, `-=`), and not read: anything else would be a recurrence, not a sum.

use std::collections::{HashMap, HashSet};

use syn::{BinOp, Expr, Ident, Pat, Stmt};

use super::scope::{Binding, Env, Fact, Returns, strip};
use super::signature::{Signature, is_f64};
use crate::ir::{Affine, Attr, Graph, Id, IndexVar, Var};

/// One open loop: what it adds to the accumulators declared outside it.
struct Frame {
    var: IndexVar,
    /// `(accumulator, the sum of what one iteration adds to it)`, in first-update order.
    adds: Vec<(String, Id)>,
    /// Accumulators of outer scopes read in this loop.
    read: HashSet<String>,
}

/// Walks a body, building its nodes and collecting its errors.
pub struct Parser {
    pub(super) graph: Graph,
    pub(super) errors: Vec<syn::Error>,
    frames: Vec<Frame>,
    /// The helper fns the body may call, by name.
    pub(super) helpers: HashMap<String, syn::ItemFn>,
    /// Helpers being inlined (to reject recursion).
    pub(super) inlining: Vec<String>,
    /// The dimension, when it is a literal.
    pub(super) dim: Option<usize>,
    /// Checking a helper on its own: calls of other helpers are not resolved.
    pub(super) checking_helper: bool,
    /// A helper was found to call itself (through others) while inlining.
    pub(super) recursion: bool,
    /// The loop variables tested by the conditions of the `if`s being walked, for the hint of
    /// an index error in their branches.
    pub(super) branch_vars: Vec<IndexVar>,
    /// What the conditions of the branches being read say of the loop variables, outermost
    /// first (`branch.rs`).
    pub(super) facts: Vec<Fact>,
    /// The attribute the fn is expanded by (a vector-valued fn unrolls every loop over a
    /// literal range, and a constraint's body cannot read `v` or `t`).
    pub(super) attr: Attr,
    /// A `#[force]` over a named or run-time dimension: its body declares the force and adds
    /// to its components (`looped_force.rs`).
    pub(super) looped_force: bool,
}

impl Parser {
    /// A parser that appends to `errors` (those of the signature).
    pub fn new(errors: Vec<syn::Error>, helpers: Vec<syn::ItemFn>) -> Self {
        Self {
            graph: Graph::new(),
            errors,
            frames: Vec::new(),
            helpers: helpers
                .into_iter()
                .map(|h| (h.sig.ident.to_string(), h))
                .collect(),
            inlining: Vec::new(),
            dim: None,
            checking_helper: false,
            recursion: false,
            branch_vars: Vec::new(),
            facts: Vec::new(),
            attr: Attr::Lagrangian,
            looped_force: false,
        }
    }

    /// Checks the body of a helper fn with parameters `params`, returning what `returns` says
    /// (`None`: a return type in error, whose value is not checked).
    pub fn helper_body(
        &mut self,
        name: &Ident,
        block: &syn::Block,
        params: &[Ident],
        returns: Option<Returns>,
    ) {
        self.checking_helper = true;
        self.inlining.push(name.to_string());
        let mut env = Env::new();
        for (k, p) in params.iter().enumerate() {
            env.insert(
                p.to_string(),
                Binding::Scalar(self.graph.var(Var::Const(k))),
            );
        }
        match returns {
            Some(Returns::Scalar) => {
                self.block(block, &mut env);
            }
            Some(Returns::Values(kind, n)) => {
                let name = name.to_string();
                self.values_block(block, &mut env, Some((&name, kind, n)));
            }
            None => {
                let n = block.stmts.len();
                for stmt in block.stmts.iter().take(n.saturating_sub(1)) {
                    self.statement(stmt, &mut env);
                }
            }
        }
    }

    /// `L` as a node of the graph: the value of `block` with the parameters of `sig` bound.
    pub fn body(&mut self, block: &syn::Block, sig: &Signature) -> Id {
        let mut env = self.signature_env(sig);
        self.block(block, &mut env)
    }

    /// Whether a loop that is a sum is open (not an unrolled one).
    pub(super) fn frames_open(&self) -> bool {
        !self.frames.is_empty()
    }

    /// The graph built and the errors collected.
    pub fn finish(self) -> (crate::ir::Graph, Vec<syn::Error>) {
        (self.graph, self.errors)
    }

    pub(super) fn error(
        &mut self,
        tokens: impl quote::ToTokens,
        msg: impl std::fmt::Display,
    ) -> Id {
        self.errors.push(syn::Error::new_spanned(tokens, msg));
        // A placeholder so that the walk goes on and reports the next error too.
        self.graph.num(0.0)
    }

    /// The value of a block that ends in an expression (a fn body, a closure's block).
    pub(super) fn block(&mut self, block: &syn::Block, env: &mut Env) -> Id {
        let n = block.stmts.len();
        for stmt in block.stmts.iter().take(n.saturating_sub(1)) {
            self.statement(stmt, env);
        }
        match block.stmts.last() {
            Some(Stmt::Expr(e, None)) if !matches!(e, Expr::ForLoop(_)) => self.expr(e, env),
            Some(last) => {
                self.statement(last, env);
                self.errors.push(syn::Error::new(
                    block.brace_token.span.close(),
                    "the body must end with the value of `L` (an expression without `;`)",
                ));
                self.graph.num(0.0)
            }
            None => {
                self.errors.push(syn::Error::new(
                    block.brace_token.span.join(),
                    "the body must end with the value of `L` (an expression without `;`)",
                ));
                self.graph.num(0.0)
            }
        }
    }

    pub(super) fn statement(&mut self, stmt: &Stmt, env: &mut Env) {
        match stmt {
            Stmt::Local(local) => {
                let Some(init) = &local.init else {
                    self.error(local, "a `let` needs a value: `let name = expression;`");
                    return;
                };
                if let Some((_, diverge)) = &init.diverge {
                    self.error(
                        diverge,
                        "`let … else` is not supported: write `let name = expression;`",
                    );
                }
                if !self.declares_force(&local.pat, &init.expr, env) {
                    self.let_binding(&local.pat, &init.expr, env);
                }
            }
            Stmt::Expr(Expr::ForLoop(f), _) => self.for_loop(f, env),
            Stmt::Expr(e, Some(_)) if self.adds_to_force(e, env) => {}
            Stmt::Expr(e, Some(_)) if self.sets_element(e, env) => {}
            Stmt::Expr(Expr::Binary(b), Some(_)) if is_compound(b.op) => {
                self.compound(&b.left, b.op, &b.right, env)
            }
            Stmt::Expr(Expr::Assign(a), Some(_)) => self.assign(a, env),
            Stmt::Expr(e @ (Expr::While(_) | Expr::Loop(_)), _) => {
                self.expr(e, env);
            }
            Stmt::Expr(e, _) => {
                self.error(
                    e,
                    "a statement here is not supported: a body is `let`s, `for` loops adding to a `let mut` accumulator, and the value of `L` at the end",
                );
            }
            Stmt::Item(syn::Item::Use(u)) if is_consts_use(&u.tree) => {}
            Stmt::Item(syn::Item::Fn(f)) => {
                self.error(
                    &f.sig.ident,
                    "a fn inside the body is not supported: define it next to the Lagrangian with `#[lagrangian(helper)]`",
                );
            }
            Stmt::Item(item) => {
                self.error(item, "an item inside the body is not supported");
            }
            Stmt::Macro(m) => {
                self.error(
                    &m.mac,
                    format!("a macro is not supported in a {} body", self.attr.name()),
                );
            }
        }
    }

    /// `let pattern = init;`: a name, `mut` name (an accumulator), typed name or tuple.
    pub(super) fn let_binding(&mut self, pat: &Pat, init: &Expr, env: &mut Env) {
        match pat {
            Pat::Tuple(pt) => {
                let values = self.tuple_values(init, pt.elems.len(), env);
                for (p, value) in pt.elems.iter().zip(values) {
                    self.bind(p, value, env);
                }
            }
            Pat::Type(pt) if matches!(&*pt.pat, Pat::Tuple(_) | Pat::Slice(_)) => {
                self.let_binding(&pt.pat, init, env)
            }
            Pat::Slice(_) if self.values_kind(init, env).is_some() => {
                let values = self.values(init, env);
                self.bind_values(pat, values, env);
            }
            _ if self.is_unknown(init, env) => self.bind_unknown(pat, env),
            _ if self.values_kind(init, env).is_some() => {
                let values = self.values(init, env);
                self.bind_values(pat, values, env);
            }
            _ => {
                if self.is_int(init, env) || self.is_const_index(init, env) {
                    return self.bind_int(pat, init, env);
                }
                let value = self.expr(init, env);
                self.bind(pat, value, env);
            }
        }
    }

    /// Binds one name (or `_`) of a `let` to `value`.
    pub(super) fn bind(&mut self, pat: &Pat, value: Id, env: &mut Env) {
        match pat {
            Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                let binding = if pi.mutability.is_some() {
                    Binding::Mut {
                        id: value,
                        depth: self.frames.len(),
                    }
                } else {
                    Binding::Scalar(value)
                };
                env.insert(pi.ident.to_string(), binding);
            }
            Pat::Wild(_) => {}
            Pat::Type(pt) => {
                if !is_f64(&pt.ty) {
                    self.error(&pt.ty, "a `let` binding must be an `f64` (or an index)");
                }
                self.bind(&pt.pat, value, env)
            }
            other => {
                self.error(
                    other,
                    "a `let` binding must be a plain name or a tuple of names, e.g. `let r2 = x * x;`",
                );
            }
        }
    }

    /// `let k = i + 1;`: an integer binding, usable where a loop variable is.
    fn bind_int(&mut self, pat: &Pat, init: &Expr, env: &mut Env) {
        match pat {
            Pat::Ident(pi) if pi.mutability.is_none() && pi.subpat.is_none() => {
                if let Some(value) = self.int_expr(init, env) {
                    env.insert(pi.ident.to_string(), Binding::Int(value));
                }
            }
            Pat::Type(pt) => self.bind_int(&pt.pat, init, env),
            other => {
                self.error(other, "an index `let` must be a plain immutable name");
            }
        }
    }

    /// `acc += e`, `acc -= e`, `acc *= e`, `acc /= e`.
    fn compound(&mut self, left: &Expr, op: BinOp, right: &Expr, env: &mut Env) {
        let Some((name, id, depth)) = self.accumulator(left, env) else {
            return;
        };
        let value = self.expr(right, env);
        let inner = depth < self.frames.len();
        match op {
            BinOp::AddAssign(_) | BinOp::SubAssign(_) if inner => {
                let value = match op {
                    BinOp::SubAssign(_) => self.graph.neg(value),
                    _ => value,
                };
                if self.frames[depth..].iter().any(|f| f.read.contains(&name)) {
                    self.error(
                        left,
                        format!("`{name}` is read and updated in the same loop: a loop may only add to an accumulator (`{name} += …`)"),
                    );
                    return;
                }
                self.add_to(&name, value, env);
            }
            _ if inner => {
                self.error(
                    op,
                    format!("inside a loop, `{name}` can only be added to (`+=`) or subtracted from (`-=`): a loop is a sum"),
                );
            }
            _ => {
                let new = match op {
                    BinOp::AddAssign(_) => self.graph.add(id, value),
                    BinOp::SubAssign(_) => self.graph.sub(id, value),
                    BinOp::MulAssign(_) => self.graph.mul(id, value),
                    _ => self.graph.div(id, value),
                };
                env.insert(name, Binding::Mut { id: new, depth });
            }
        }
    }

    /// `acc = e`, outside any loop that did not declare `acc`.
    fn assign(&mut self, a: &syn::ExprAssign, env: &mut Env) {
        let Some((name, _, depth)) = self.accumulator(&a.left, env) else {
            return;
        };
        if depth < self.frames.len() {
            self.error(
                a,
                format!(
                    "inside a loop, `{name}` can only be added to (`{name} += …`): a loop is a sum"
                ),
            );
            return;
        }
        let value = self.expr(&a.right, env);
        env.insert(name, Binding::Mut { id: value, depth });
    }

    /// The accumulator named by `left`: its name, value and depth.
    fn accumulator(&mut self, left: &Expr, env: &Env) -> Option<(String, Id, usize)> {
        if let Expr::Index(ix) = strip(left) {
            let msg = if self.values_kind(&ix.expr, env).is_some() {
                "an array of values cannot be changed: build it with its values, `let a = [e0, e1];`"
            } else {
                "`x` and `v` cannot be changed: they are the point the Lagrangian is evaluated at"
            };
            self.error(ix, msg);
            return None;
        }
        let name = match left {
            Expr::Path(p) => p.path.get_ident().map(Ident::to_string),
            _ => None,
        };
        match name.as_ref().and_then(|n| env.get(n)) {
            Some(&Binding::Mut { id, depth }) => Some((name.unwrap_or_default(), id, depth)),
            Some(Binding::Array { .. }) => {
                self.error(left, "`x` and `v` cannot be changed: they are the point the Lagrangian is evaluated at");
                None
            }
            Some(_) => {
                self.error(left, "only a `let mut` accumulator can be updated");
                None
            }
            None => {
                self.error(
                    left,
                    "only a `let mut` accumulator declared in the body can be updated",
                );
                None
            }
        }
    }

    /// Records `name += value`: in the binding itself when `name` was declared at the current
    /// loop depth (an accumulator declared inside this loop's body, or outside every loop),
    /// otherwise in the innermost loop, which sums it over its index when it closes.
    pub(super) fn add_to(&mut self, name: &str, value: Id, env: &mut Env) {
        let declared_here = match env.get(name) {
            Some(&Binding::Mut { depth, .. }) => depth >= self.frames.len(),
            _ => return,
        };
        if declared_here {
            if let Some(Binding::Mut { id, depth }) = env.get(name).cloned() {
                let new = self.graph.add(id, value);
                env.insert(name.to_string(), Binding::Mut { id: new, depth });
            }
            return;
        }
        let frame = self
            .frames
            .last_mut()
            .expect("an accumulator of an outer loop depth");
        match frame.adds.iter_mut().find(|(n, _)| n == name) {
            Some((_, acc)) => *acc = self.graph.add(*acc, value),
            None => frame.adds.push((name.to_string(), value)),
        }
    }

    /// Notes that an outer accumulator is read in the open loops (see [`Parser::compound`]).
    pub(super) fn read_accumulator(&mut self, name: &str, depth: usize, at: &Expr) -> bool {
        let updated = self.frames[depth.min(self.frames.len())..]
            .iter()
            .any(|f| f.adds.iter().any(|(n, _)| n == name));
        if updated {
            self.error(
                at,
                format!("`{name}` is read and updated in the same loop: a loop may only add to an accumulator (`{name} += …`)"),
            );
            return false;
        }
        let from = depth.min(self.frames.len());
        for f in &mut self.frames[from..] {
            f.read.insert(name.to_string());
        }
        true
    }

    /// `for i in a..b { … }`: each accumulator it adds to gets `Σ_i` of what one iteration adds.
    fn for_loop(&mut self, f: &syn::ExprForLoop, env: &mut Env) {
        if let Some(label) = &f.label {
            self.error(label, "a loop label is not supported");
        }
        let Some(var_name) = self.loop_pattern(&f.pat) else {
            return;
        };
        let ends = self.range_ends(strip(&f.expr), env);
        if let Some(ends) = self.unrolls(ends, &f.body, env) {
            return self.unrolled(&f.body, &var_name, ends, env);
        }
        let var = self.new_var(ends, &var_name);
        let mut inner = env.clone();
        inner.insert(var_name, Binding::Index(var));
        self.frames.push(Frame {
            var,
            adds: Vec::new(),
            read: HashSet::new(),
        });
        for stmt in &f.body.stmts {
            match stmt {
                Stmt::Expr(e, None) if !matches!(e, Expr::ForLoop(_)) => {
                    self.error(e, "a loop body is statements (`acc += …;`), not a value");
                }
                s => self.statement(s, &mut inner),
            }
        }
        let frame = self.frames.pop().expect("pushed above");
        for (name, body) in frame.adds {
            let sum = self.graph.sum(frame.var, body);
            self.add_to(&name, sum, env);
        }
    }

    /// `(a..b).map(|i| body).sum()`, with the receiver of `sum` and the closure given.
    pub(super) fn iterator_sum(
        &mut self,
        range: &Expr,
        closure: &syn::ExprClosure,
        env: &Env,
    ) -> Id {
        if closure.inputs.len() != 1 {
            return self.error(
                &closure.inputs,
                "the closure of a sum takes one index, e.g. `|i| x[i] * x[i]`",
            );
        }
        let Some(name) = self.loop_pattern(&closure.inputs[0]) else {
            return self.graph.num(0.0);
        };
        let ends = self.range_ends(strip(range), env);
        if let Some(ends) = self.unrolls(ends, &closure.body, env) {
            return self.unrolled_sum(&closure.body, &name, ends, env);
        }
        let var = self.new_var(ends, &name);
        let mut inner = env.clone();
        inner.insert(name, Binding::Index(var));
        self.frames.push(Frame {
            var,
            adds: Vec::new(),
            read: HashSet::new(),
        });
        let body = self.expr(&closure.body, &inner);
        let frame = self.frames.pop().expect("pushed above");
        if let Some((name, _)) = frame.adds.first() {
            return self.error(
                &closure.body,
                format!("a closure cannot update `{name}`: write a `for` loop"),
            );
        }
        self.graph.sum(var, body)
    }

    /// The loop variable's name: a plain identifier.
    fn loop_pattern(&mut self, pat: &Pat) -> Option<String> {
        match pat {
            Pat::Ident(pi)
                if pi.by_ref.is_none() && pi.subpat.is_none() && pi.mutability.is_none() =>
            {
                Some(pi.ident.to_string())
            }
            Pat::Type(pt) => self.loop_pattern(&pt.pat),
            Pat::Wild(w) => {
                self.error(w, "name the loop index, e.g. `for i in 0..N`");
                None
            }
            other => {
                self.error(
                    other,
                    "loop over indices, e.g. `for i in 0..N { … x[i] … }`, not over tuples of values",
                );
                None
            }
        }
    }

    /// A new loop variable over the range `ends` (of `a..b` or `a..=b`). A range in error
    /// (`None`, reported) is replaced by an empty one, so that the loop's body is still
    /// checked, with its variable bound (no "unknown index" follows).
    fn new_var(&mut self, ends: Option<(Affine, Affine)>, name: &str) -> IndexVar {
        let (start, end) = ends.unwrap_or((Affine::constant(0), Affine::constant(0)));
        let var = IndexVar(self.graph.ranges.len() as u32);
        self.graph.ranges.push(crate::ir::Range {
            name: name.to_string(),
            start,
            end,
        });
        var
    }

    /// The ends of `a..b` (`a..=b` is `a..b + 1`), or `None` after reporting an error.
    pub(super) fn range_ends(&mut self, e: &Expr, env: &Env) -> Option<(Affine, Affine)> {
        let Expr::Range(r) = e else {
            self.iteration_error(e);
            return None;
        };
        let (Some(start), Some(end)) = (&r.start, &r.end) else {
            self.error(r, "a loop range needs both ends, e.g. `0..N`");
            return None;
        };
        let start = self.range_end(start, env);
        let mut end = self.range_end(end, env)?;
        if matches!(r.limits, syn::RangeLimits::Closed(_)) {
            end.c += 1;
        }
        Some((start?, end))
    }
}

/// `+=`, `-=`, `*=`, `/=`.
pub(super) fn is_compound(op: BinOp) -> bool {
    matches!(
        op,
        BinOp::AddAssign(_) | BinOp::SubAssign(_) | BinOp::MulAssign(_) | BinOp::DivAssign(_)
    )
}

/// `use std::f64::consts::PI;` (or `{PI, E}`, `*`): harmless, the body names them anyway.
fn is_consts_use(tree: &syn::UseTree) -> bool {
    let mut t = tree;
    let mut path = Vec::new();
    while let syn::UseTree::Path(p) = t {
        path.push(p.ident.to_string());
        t = &p.tree;
    }
    matches!(
        path.iter()
            .map(String::as_str)
            .collect::<Vec<_>>()
            .as_slice(),
        ["std", "f64", "consts"] | ["core", "f64", "consts"]
    )
}
