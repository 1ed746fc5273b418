//! Expressions of a `#[lagrangian]` body: numbers, the parameters, `x[…]`, arithmetic, the
//! `f64` functions, casts of indices, iterator sums and calls of helper fns (branches are in
//! `branch.rs`, tuples and arrays in `values.rs`).

use syn::{BinOp, Expr, Ident, Lit, UnOp};

use super::body::Parser;
use super::scope::{Binding, Env, Kind, Returns, State, Values, strip};
use super::signature::Length;
use crate::ir::{Cmp, Func, Id, Var, constant_value};

/// The `f64` functions a body may call, for the error on any other.
const METHODS: &str = "the f64 methods are sin cos tan asin acos atan atan2 sinh cosh tanh exp \
     exp_m1 ln ln_1p log10 sqrt cbrt recip abs signum powi powf hypot max min";

/// The functions of one argument besides the receiver.
/// Why the force of a `#[force]` with loops cannot be read.
const FORCE_NOT_READ: &str = "the force is only added to (`f[i] += …;`) and returned: its components are not read; bind what two of them share to a `let`";

const BINARY: [&str; 6] = ["powi", "powf", "hypot", "atan2", "max", "min"];

impl Parser {
    pub(super) fn expr(&mut self, e: &Expr, env: &Env) -> Id {
        match e {
            Expr::Paren(p) => self.expr(&p.expr, env),
            Expr::Group(g) => self.expr(&g.expr, env),
            Expr::Lit(l) => self.literal(&l.lit),
            Expr::Unary(u) => match u.op {
                UnOp::Neg(_) => {
                    let a = self.expr(&u.expr, env);
                    self.graph.neg(a)
                }
                _ => self.error(u.op, "only unary `-` is supported on numbers"),
            },
            Expr::Binary(b) => {
                let l = self.expr(&b.left, env);
                let r = self.expr(&b.right, env);
                match b.op {
                    BinOp::Add(_) => self.graph.add(l, r),
                    BinOp::Sub(_) => self.graph.sub(l, r),
                    BinOp::Mul(_) => self.graph.mul(l, r),
                    BinOp::Div(_) if self.holds_sum(r) => self.sum_inside(&b.right, "a divisor"),
                    BinOp::Div(_) => self.graph.div(l, r),
                    op => self.error(
                        op,
                        "this operator is not supported on numbers: use `+ - * /`",
                    ),
                }
            }
            Expr::Path(p) => self.path(p, env),
            Expr::Index(ix) => self.index(ix, env),
            Expr::MethodCall(mc) => self.method_call(mc, env),
            Expr::Call(call) => self.call(call, env),
            Expr::If(x) => self.conditional(x, env),
            Expr::Block(b) if b.label.is_none() => self.block(&b.block, &mut env.clone()),
            Expr::Cast(c) => {
                if !super::signature::is_f64(&c.ty) {
                    return self.error(&c.ty, "only casts `as f64` of an index are supported");
                }
                if self.is_int_cast(&c.expr, env) {
                    self.int_value(&c.expr, env)
                } else {
                    self.expr(&c.expr, env)
                }
            }
            Expr::ForLoop(x) => self.error(
                x.for_token,
                "a `for` loop is a statement: add to a `let mut` accumulator, then use it",
            ),
            Expr::Match(x) => self.error(
                x.match_token,
                "`match` is not supported: use `if c { a } else { b }`",
            ),
            Expr::While(x) => self.error(
                x.while_token,
                "`while` is not supported: loop over a range, `for i in 0..N`",
            ),
            Expr::Loop(x) => self.error(
                x.loop_token,
                "`loop` is not supported: loop over a range, `for i in 0..N`",
            ),
            Expr::Closure(x) => self.error(
                x,
                "a closure is supported only in `(a..b).map(|i| …).sum::<f64>()`",
            ),
            Expr::Macro(m) => {
                self.error(&m.mac, format!("a macro is not supported in a {} body", self.attr.name()))
            }
            Expr::Reference(r) => self.error(
                r.and_token,
                "a reference is not supported: the body works on `f64` values",
            ),
            Expr::Return(r) => self.error(
                r.return_token,
                "`return` is not supported: the body ends with the value of `L`",
            ),
            Expr::Assign(a) => self.error(a, "an assignment is a statement: end it with `;`"),
            Expr::Field(f) if self.values_kind(&f.base, env).is_some() => self.field(f, env),
            Expr::Field(f) if self.is_unknown(&f.base, env) => self.graph.num(0.0),
            Expr::Field(f) => self.error(
                f,
                "a field access is not supported: model constants are parameters of the fn",
            ),
            Expr::Tuple(t) => self.error(
                t,
                "a tuple is a value of its own: bind it, `let (a, b) = (…, …);` or `let r = (…, …);`, then read `a` or `r.0`",
            ),
            Expr::Array(_) | Expr::Repeat(_) => self.error(
                e,
                "an array is a value of its own: bind it, `let a = [e0, e1, e2];`, then read `a[1]`",
            ),
            other => self.error(
                other,
                format!("this expression is not supported in a {} body", self.attr.name()),
            ),
        }
    }

    fn literal(&mut self, lit: &Lit) -> Id {
        let parsed = match lit {
            Lit::Float(f) if matches!(f.suffix(), "" | "f64") => f.base10_parse::<f64>(),
            Lit::Int(i) if matches!(i.suffix(), "" | "f64") => i.base10_parse::<f64>(),
            other => {
                return self.error(
                    other,
                    "this literal is not supported: only `f64` numbers are",
                );
            }
        };
        match parsed {
            Ok(x) => self.graph.num(x),
            Err(e) => {
                self.errors.push(e);
                self.graph.num(0.0)
            }
        }
    }

    fn path(&mut self, p: &syn::ExprPath, env: &Env) -> Id {
        if p.qself.is_some() || p.path.segments.iter().any(|s| !s.arguments.is_none()) {
            return self.error(p, "this path is not supported");
        }
        let segs: Vec<String> = p
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect();
        if segs.len() == 1 && p.path.leading_colon.is_none() {
            let name = &segs[0];
            return match env.get(name).cloned() {
                Some(Binding::Scalar(id)) => id,
                Some(Binding::Mut { id, depth }) => {
                    let e = Expr::Path(p.clone());
                    if self.read_accumulator(name, depth, &e) {
                        id
                    } else {
                        self.graph.num(0.0)
                    }
                }
                Some(Binding::Array { .. }) => {
                    self.error(p, format!("`{name}` is an array: use its components `{name}[i]`"))
                }
                Some(Binding::Values(v)) => match v.kind {
                    Kind::Array => self.error(p, format!("`{name}` is an array: read its values, `{name}[0]`")),
                    Kind::Tuple => self.error(p, format!("`{name}` is a tuple: read its values, `{name}.0`, or bind them, `let (a, b) = {name};`")),
                },
                Some(Binding::Unknown) => self.graph.num(0.0),
                Some(Binding::Output) => self.error(p, FORCE_NOT_READ),
                Some(Binding::Index(_) | Binding::Dim) => {
                    self.error(p, format!("`{name}` is an index: use it as a number with `{name} as f64`"))
                }
                Some(Binding::Int(_)) => self.error(
                    p,
                    format!(
                        "`{name}` is an integer (an `UPPER_CASE` name is read as a `usize` const): use it as a number with `{name} as f64`; a real constant of the model is a parameter of the fn"
                    ),
                ),
                None => match constant_value(name) {
                    // `use std::f64::consts::PI;` at the top of the module.
                    Some(c) => self.graph.num(c),
                    None => {
                        let msg = self.not_a_state(name).unwrap_or_else(|| format!("unknown name `{name}`: the body may use the parameters, its own `let` bindings and `std::f64::consts`"));
                        self.error(p, msg)
                    }
                },
            };
        }
        let n = segs.len();
        let prefix: Vec<&str> = segs[..n - 1].iter().map(String::as_str).collect();
        let consts_path = matches!(
            prefix.as_slice(),
            ["std", "f64", "consts"] | ["core", "f64", "consts"] | ["f64", "consts"]
        );
        if consts_path && let Some(c) = constant_value(&segs[n - 1]) {
            return self.graph.num(c);
        }
        self.error(
            p,
            "unknown path: the body may name the constants of `std::f64::consts`",
        )
    }

    fn index(&mut self, ix: &syn::ExprIndex, env: &Env) -> Id {
        if self.values_kind(&ix.expr, env).is_some() {
            return self.element(ix, env);
        }
        if self.is_unknown(&ix.expr, env) {
            return self.graph.num(0.0);
        }
        let name = match &*ix.expr {
            Expr::Path(p) if p.qself.is_none() => p.path.get_ident().map(Ident::to_string),
            _ => None,
        };
        let (state, len) = match name.as_ref().and_then(|n| env.get(n)) {
            Some(&Binding::Array { state, len }) => (state, len),
            Some(Binding::Output) => return self.error(ix, FORCE_NOT_READ),
            Some(Binding::Scalar(_)) => {
                let n = name.unwrap_or_default();
                return self.error(
                    &ix.expr,
                    format!(
                        "`{n}` is a scalar: only `x` and `v` declared as `[f64; D]` can be indexed"
                    ),
                );
            }
            _ => {
                let msg = name.as_deref().and_then(|n| self.not_a_state(n));
                let msg = msg.unwrap_or_else(|| {
                    "only `x`, `v` and arrays of values (`let a = [e0, e1];`) can be indexed".into()
                });
                return self.error(&ix.expr, msg);
            }
        };
        if let Expr::Lit(syn::ExprLit {
            lit: Lit::Int(i), ..
        }) = strip(&ix.index)
        {
            return match (i.base10_parse::<usize>(), len) {
                (Ok(i), Length::Known(dim)) if i >= dim => self.error(
                    &ix.index,
                    format!("index {i} is out of bounds: the dimension is {dim}"),
                ),
                (Ok(i), _) => self.graph.var(state.component(i)),
                (Err(e), _) => {
                    self.errors.push(e);
                    self.graph.num(0.0)
                }
            };
        }
        match self.component(&ix.index, env) {
            Some(c) => match c.at.as_constant() {
                Some(k) if !c.wrap => self.graph.var(state.component(k as usize)),
                _ => self.graph.var(match state {
                    State::Position => Var::XAt(c),
                    State::Velocity => Var::VAt(c),
                }),
            },
            None => self.graph.num(0.0),
        }
    }

    fn method_call(&mut self, mc: &syn::ExprMethodCall, env: &Env) -> Id {
        let name = mc.method.to_string();
        if name == "sum" {
            return self.sum_call(mc, env);
        }
        if [
            "iter",
            "into_iter",
            "zip",
            "windows",
            "map",
            "enumerate",
            "fold",
            "dot",
        ]
        .contains(&name.as_str())
        {
            return self.iteration_error(&Expr::MethodCall(mc.clone()));
        }
        if let Some(tf) = &mc.turbofish {
            return self.error(tf, "a turbofish is supported only on `sum::<f64>()`");
        }
        if self.is_int(&mc.receiver, env) {
            return self.int_value(&Expr::MethodCall(mc.clone()), env);
        }
        let recv = self.expr(&mc.receiver, env);
        let args: Vec<&Expr> = mc.args.iter().collect();
        self.function(&mc.method, recv, &args, &mc.args, env)
    }

    /// `(a..b).map(|i| …).sum::<f64>()`.
    fn sum_call(&mut self, mc: &syn::ExprMethodCall, env: &Env) -> Id {
        if let Some(tf) = &mc.turbofish {
            let f64_only = tf.args.len() == 1
                && matches!(&tf.args[0], syn::GenericArgument::Type(t) if super::signature::is_f64(t));
            if !f64_only {
                return self.error(tf, "a sum is `sum::<f64>()` or `sum()`");
            }
        }
        if let Expr::MethodCall(map) = strip(&mc.receiver)
            && map.method == "map"
            && map.args.len() == 1
            && let Expr::Closure(closure) = strip(&map.args[0])
            && matches!(strip(&map.receiver), Expr::Range(_))
        {
            return self.iterator_sum(&map.receiver, closure, env);
        }
        self.iteration_error(&mc.receiver)
    }

    /// The error for iterating anything but a range, with the index form to write instead.
    pub(super) fn iteration_error(&mut self, e: &Expr) -> Id {
        let text = quote::ToTokens::to_token_stream(e).to_string();
        let hint = if text.contains("windows") {
            "write neighbours with an index: `(0..N - 1).map(|i| f(x[i], x[i + 1])).sum::<f64>()`"
        } else if text.contains("zip") {
            "write pairs with an index: `(0..N).map(|i| f(x[i], v[i])).sum::<f64>()`"
        } else if text.contains("dot") {
            "write the dot product as a sum: `(0..N).map(|i| v[i] * v[i]).sum::<f64>()`"
        } else {
            "iterate over indices: `(0..N).map(|i| … x[i] …).sum::<f64>()` or `for i in 0..N`"
        };
        self.error(e, format!("only ranges of indices can be iterated: {hint}"))
    }

    fn call(&mut self, call: &syn::ExprCall, env: &Env) -> Id {
        let Expr::Path(fp) = &*call.func else {
            return self.error(&call.func, "calling this is not supported");
        };
        let segs: Vec<String> = fp
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect();
        if segs.len() == 1 && fp.qself.is_none() {
            return self.helper_call(&segs[0], call, env);
        }
        let generic = fp.path.segments.iter().any(|s| !s.arguments.is_none());
        if fp.qself.is_some()
            || generic
            || segs.len() != 2
            || segs[0] != "f64"
            || call.args.is_empty()
        {
            return self.error(
                &call.func,
                "only the `f64::` functions and helper fns can be called",
            );
        }
        let method = &fp.path.segments[1].ident;
        if Func::from_name(&segs[1]).is_none() && !BINARY.contains(&segs[1].as_str()) {
            return self.error(
                method,
                format!("`f64::{method}` is not supported; {METHODS}"),
            );
        }
        let recv = self.expr(&call.args[0], env);
        let args: Vec<&Expr> = call.args.iter().skip(1).collect();
        self.function(method, recv, &args, &call.args, env)
    }

    /// A call of a `#[lagrangian(helper)]` fn returning `f64`: its body, with its parameters
    /// bound to the arguments.
    fn helper_call(&mut self, name: &str, call: &syn::ExprCall, env: &Env) -> Id {
        if let Some(Returns::Values(kind, n)) = self.helper_returns(name) {
            return self.error(
                call,
                format!("`{name}` returns {} of {n} values: bind them, `let (a, b) = {name}(…);` or `let r = {name}(…);`, then read one", kind.noun()),
            );
        }
        self.inline(name, call, env, |p, block, inner| p.block(block, inner))
            .unwrap_or_else(|zero| zero)
    }

    /// A call of a helper returning a tuple or an array: the values of its body.
    pub(super) fn inline_values(&mut self, name: &str, call: &syn::ExprCall, env: &Env) -> Values {
        let Some(Returns::Values(kind, n)) = self.helper_returns(name) else {
            unreachable!("values_kind said a helper returning values");
        };
        self.inline(name, call, env, |p, block, inner| {
            p.values_block(block, inner, Some((name, kind, n)))
        })
        .unwrap_or_else(|zero| Values {
            ids: vec![zero; n],
            kind,
        })
    }

    /// The body of helper `name` read by `read`, its parameters bound to the arguments of
    /// `call`; `Err` with a placeholder after an error. Errors inside the helper are reported
    /// at its definition, not here.
    fn inline<R>(
        &mut self,
        name: &str,
        call: &syn::ExprCall,
        env: &Env,
        read: impl FnOnce(&mut Self, &syn::Block, &mut Env) -> R,
    ) -> Result<R, Id> {
        if self.inlining.iter().any(|h| h == name) {
            self.recursion = true;
            return Err(self.error(
                &call.func,
                format!("`{name}` calls itself: a helper cannot be recursive"),
            ));
        }
        let Some(helper) = self.helpers.get(name).cloned() else {
            if self.checking_helper {
                return Err(self.graph.num(0.0));
            }
            return Err(self.error(
                &call.func,
                format!("`{name}` is not a helper: mark it `#[lagrangian(helper)]`, or use an `f64` method"),
            ));
        };
        let params: Vec<String> = helper
            .sig
            .inputs
            .iter()
            .filter_map(|a| match a {
                syn::FnArg::Typed(pt) => match &*pt.pat {
                    syn::Pat::Ident(pi) => Some(pi.ident.to_string()),
                    _ => None,
                },
                syn::FnArg::Receiver(_) => None,
            })
            .collect();
        if params.len() != call.args.len() {
            return Err(self.error(
                &call.args,
                format!("`{name}` takes {} argument(s)", params.len()),
            ));
        }
        let mut inner = Env::new();
        for (p, a) in params.into_iter().zip(&call.args) {
            let value = self.expr(a, env);
            inner.insert(p, Binding::Scalar(value));
        }
        let errors = self.errors.len();
        self.inlining.push(name.to_string());
        let value = read(self, &helper.block, &mut inner);
        self.inlining.pop();
        // The helper's own errors are reported at its definition; a recursion through other
        // helpers is only seen here, and is reported at the outermost call.
        self.errors.truncate(errors);
        if self.inlining.is_empty() && std::mem::take(&mut self.recursion) {
            return Err(self.error(&call.func, format!("`{name}` is recursive (it calls itself, directly or through other helpers): a helper cannot be")));
        }
        Ok(value)
    }

    /// Whether `id` holds a sum that reads the variable of a loop around it: such a sum is one
    /// value per iteration, which may enter `L` polynomially but not inside a function, a
    /// divisor or a condition (a sum of the whole body is lifted there: `assemble.rs`).
    pub(super) fn holds_sum(&self, id: Id) -> bool {
        let g = &self.graph;
        let mut stack = vec![id];
        let mut outer = Vec::new();
        let mut seen = std::collections::HashSet::new();
        while let Some(n) = stack.pop() {
            if !seen.insert(n) {
                continue;
            }
            match g.node(n) {
                crate::ir::Node::Sum(..) => outer.push(n),
                node => stack.extend(node.children()),
            }
        }
        if outer.is_empty() {
            return false;
        }
        let free = crate::rewrite::free_vars(g);
        outer.iter().any(|&s| !free[s].is_empty())
    }

    /// The error for a per-iteration sum used where only a value of the whole body can be.
    pub(super) fn sum_inside(&mut self, at: &dyn quote::ToTokens, what: &str) -> Id {
        self.error(
            at,
            format!("a sum that reads the variable of a loop around it cannot be inside {what}: it may be added, multiplied or raised to a power up to 4 (`powi`); or compute it as a sum of its own outside that loop"),
        )
    }

    /// A method `recv.name(args)` or the function `f64::name(recv, args)`.
    fn function(
        &mut self,
        name: &Ident,
        recv: Id,
        args: &[&Expr],
        all_args: &dyn quote::ToTokens,
        env: &Env,
    ) -> Id {
        let s = name.to_string();
        let small_power =
            s == "powi" && args.len() == 1 && matches!(int_literal(args[0]), Some(Ok(1..=4)));
        if !small_power && self.holds_sum(recv) {
            return self.sum_inside(name, &format!("`{s}`"));
        }
        let arity = usize::from(BINARY.contains(&s.as_str()));
        if Func::from_name(&s).is_none() && arity == 0 {
            return self.error(
                name,
                format!("the method `{s}` is not supported; {METHODS}"),
            );
        }
        if args.len() != arity {
            let msg = format!("`{s}` takes {arity} argument(s) besides the receiver");
            return if args.is_empty() {
                self.error(name, msg)
            } else {
                self.error(all_args, msg)
            };
        }
        match s.as_str() {
            "powi" => match int_literal(args[0]) {
                Some(Ok(n)) if n != i64::from(i32::MIN) && i32::try_from(n).is_ok() => self.graph.powi(recv, n as i32),
                Some(Ok(_)) | Some(Err(_)) => self.error(args[0], "the `powi` exponent is out of range for `i32`"),
                None => self.error(
                    args[0],
                    "the `powi` exponent must be an integer literal (use `powf` for a general exponent)",
                ),
            },
            "powf" | "hypot" | "atan2" | "max" | "min" => {
                let b = self.expr(args[0], env);
                if self.holds_sum(b) {
                    return self.sum_inside(args[0], &format!("`{s}`"));
                }
                match s.as_str() {
                    "powf" => self.graph.powf(recv, b),
                    "hypot" => self.graph.hypot(recv, b),
                    "atan2" => self.graph.atan2(recv, b),
                    "max" => self.graph.select(Cmp::Ge, recv, b, recv, b),
                    _ => self.graph.select(Cmp::Le, recv, b, recv, b),
                }
            }
            _ => match Func::from_name(&s) {
                Some(f) => self.graph.call(f, recv),
                None => self.error(name, format!("the method `{s}` is not supported")),
            },
        }
    }
}

/// An integer literal, possibly negated (`-2`), possibly parenthesised.
fn int_literal(e: &Expr) -> Option<syn::Result<i64>> {
    match e {
        Expr::Lit(syn::ExprLit {
            lit: Lit::Int(i), ..
        }) if matches!(i.suffix(), "" | "i32") => Some(i.base10_parse::<i64>()),
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
            int_literal(&u.expr).map(|r| r.map(|n| -n))
        }
        Expr::Paren(p) => int_literal(&p.expr),
        Expr::Group(g) => int_literal(&g.expr),
        _ => None,
    }
}
