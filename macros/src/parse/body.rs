//! The body of a `#[lagrangian]` fn, walked into the expression DAG.

use std::collections::HashMap;

use syn::{BinOp, Expr, Ident, Lit, Pat, Stmt, UnOp};

use super::signature::{Length, Shape, Signature, is_f64};
use crate::ir::{Func, Graph, Id, Var, constant_value};

/// What the body of a `#[lagrangian]` fn may contain (appended to every body error).
const SUPPORTED: &str = "supported in a #[lagrangian] body: `let` bindings, `+ - * /`, \
     unary `-`, float and integer literals, parentheses, `x[i]`/`v[i]` with a literal index, \
     the parameters, the f64 methods (or `f64::` functions) sin cos tan asin acos atan sinh \
     cosh tanh exp ln log10 sqrt cbrt recip abs powi powf hypot, and `std::f64::consts::*`";

/// The usable names in the body.
#[derive(Clone, Copy)]
enum Binding {
    /// A value: a scalar parameter or a `let`.
    Scalar(Id),
    /// `x` or `v` declared as an array: only its components can be used.
    Array { state: State, len: Length },
}

/// Which of the two state parameters an array is.
#[derive(Clone, Copy, PartialEq, Eq)]
enum State {
    Position,
    Velocity,
}

impl State {
    /// The variable of component `i`.
    fn component(self, i: usize) -> Var {
        match self {
            State::Position => Var::X(i),
            State::Velocity => Var::V(i),
        }
    }
}

/// Walks a body, building its nodes and collecting its errors.
pub struct Parser {
    graph: Graph,
    errors: Vec<syn::Error>,
}

impl Parser {
    /// A parser that appends to `errors` (those of the signature).
    pub fn new(errors: Vec<syn::Error>) -> Self {
        Self {
            graph: Graph::new(),
            errors,
        }
    }

    /// `L` as a node of the graph: the value of `block` with the parameters of `sig` bound.
    pub fn body(&mut self, block: &syn::Block, sig: &Signature) -> Id {
        let mut env: HashMap<String, Binding> = HashMap::new();
        let states = [State::Position, State::Velocity];
        for ((name, shape), state) in sig.states.iter().zip(states) {
            let binding = match *shape {
                Shape::Scalar => Binding::Scalar(self.graph.var(state.component(0))),
                Shape::Array(len) => Binding::Array { state, len },
            };
            env.insert(name.to_string(), binding);
        }
        if let Some(t) = &sig.time {
            env.insert(t.to_string(), Binding::Scalar(self.graph.var(Var::T)));
        }
        for (k, c) in sig.consts.iter().enumerate() {
            env.insert(
                c.to_string(),
                Binding::Scalar(self.graph.var(Var::Const(k))),
            );
        }
        self.block(block, &mut env)
    }

    /// The graph built and the errors collected.
    pub fn finish(self) -> (Graph, Vec<syn::Error>) {
        (self.graph, self.errors)
    }

    fn error(&mut self, tokens: impl quote::ToTokens, msg: impl std::fmt::Display) -> Id {
        self.errors.push(syn::Error::new_spanned(tokens, msg));
        // A placeholder so that the walk goes on and reports the next error too.
        self.graph.num(0.0)
    }

    fn unsupported(&mut self, tokens: impl quote::ToTokens, what: &str) -> Id {
        self.error(tokens, format!("{what} not supported; {SUPPORTED}"))
    }

    fn block(&mut self, block: &syn::Block, env: &mut HashMap<String, Binding>) -> Id {
        let mut result = None;
        let n = block.stmts.len();
        for (k, stmt) in block.stmts.iter().enumerate() {
            let last = k + 1 == n;
            match stmt {
                Stmt::Local(local) => {
                    let Some(init) = &local.init else {
                        self.error(local, "a `let` needs a value: `let name = expression;`");
                        continue;
                    };
                    if let Some((_, diverge)) = &init.diverge {
                        self.unsupported(diverge, "`let ... else` is");
                    }
                    let value = self.expr(&init.expr, env);
                    if let Some(name) = self.let_pattern(&local.pat) {
                        env.insert(name, Binding::Scalar(value));
                    }
                }
                Stmt::Expr(e, None) if last => result = Some(self.expr(e, env)),
                Stmt::Expr(e, _) => {
                    self.unsupported(e, "a statement here is");
                }
                Stmt::Item(item) => {
                    self.unsupported(item, "an item inside the body is");
                }
                Stmt::Macro(m) => {
                    self.unsupported(&m.mac, "a macro is");
                }
            }
        }
        match result {
            Some(id) => id,
            None => {
                self.errors.push(syn::Error::new(
                    block.brace_token.span.close(),
                    "the body must end with the value of `L` (an expression without `;`)",
                ));
                self.graph.num(0.0)
            }
        }
    }

    fn let_pattern(&mut self, pat: &Pat) -> Option<String> {
        match pat {
            Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                if let Some(m) = &pi.mutability {
                    // Reported, and the name stays bound so that its uses are not errors too.
                    self.error(
                        m,
                        "`let mut` is not supported: bindings are immutable values",
                    );
                }
                Some(pi.ident.to_string())
            }
            Pat::Type(pt) => {
                if !is_f64(&pt.ty) {
                    self.error(&pt.ty, "a `let` binding must be an `f64`");
                    return None;
                }
                self.let_pattern(&pt.pat)
            }
            other => {
                self.error(
                    other,
                    "a `let` binding must be a plain name, e.g. `let r2 = x * x;`",
                );
                None
            }
        }
    }

    fn expr(&mut self, e: &Expr, env: &HashMap<String, Binding>) -> Id {
        match e {
            Expr::Paren(p) => self.expr(&p.expr, env),
            Expr::Group(g) => self.expr(&g.expr, env),
            Expr::Lit(l) => self.literal(&l.lit),
            Expr::Unary(u) => match u.op {
                UnOp::Neg(_) => {
                    // `x.powi(-2)`-style integer literals are handled in `powi`; here `-lit`
                    // and `-expr` are both ordinary negations.
                    let a = self.expr(&u.expr, env);
                    self.graph.neg(a)
                }
                _ => self.unsupported(u.op, "this unary operator is"),
            },
            Expr::Binary(b) => {
                let l = self.expr(&b.left, env);
                let r = self.expr(&b.right, env);
                match b.op {
                    BinOp::Add(_) => self.graph.add(l, r),
                    BinOp::Sub(_) => self.graph.sub(l, r),
                    BinOp::Mul(_) => self.graph.mul(l, r),
                    BinOp::Div(_) => self.graph.div(l, r),
                    op => self.unsupported(op, "this operator is"),
                }
            }
            Expr::Path(p) => self.path(p, env),
            Expr::Index(ix) => self.index(ix, env),
            Expr::MethodCall(mc) => {
                if let Some(tf) = &mc.turbofish {
                    return self.unsupported(tf, "a turbofish is");
                }
                let recv = self.expr(&mc.receiver, env);
                let args: Vec<&Expr> = mc.args.iter().collect();
                self.function(&mc.method, recv, &args, &mc.args, env)
            }
            Expr::Call(call) => {
                let Expr::Path(fp) = &*call.func else {
                    return self.unsupported(&call.func, "calling this is");
                };
                let segs: Vec<String> = fp
                    .path
                    .segments
                    .iter()
                    .map(|s| s.ident.to_string())
                    .collect();
                let generic = fp.path.segments.iter().any(|s| !s.arguments.is_none());
                if fp.qself.is_some()
                    || generic
                    || segs.len() != 2
                    || segs[0] != "f64"
                    || call.args.is_empty()
                {
                    return self.unsupported(
                        &call.func,
                        "calling a function other than the listed `f64::` functions is",
                    );
                }
                let method = &fp.path.segments[1].ident;
                if Func::from_name(&method.to_string()).is_none()
                    && !["powi", "powf", "hypot"].contains(&segs[1].as_str())
                {
                    return self.unsupported(method, &format!("`f64::{method}` is"));
                }
                let recv = self.expr(&call.args[0], env);
                let args: Vec<&Expr> = call.args.iter().skip(1).collect();
                self.function(method, recv, &args, &call.args, env)
            }
            Expr::If(x) => self.unsupported(
                x.if_token,
                "`if` is not supported: L must be one smooth formula, and branching is",
            ),
            Expr::Match(x) => self.unsupported(x.match_token, "`match` is"),
            Expr::ForLoop(x) => self.unsupported(x.for_token, "a loop is"),
            Expr::While(x) => self.unsupported(x.while_token, "a loop is"),
            Expr::Loop(x) => self.unsupported(x.loop_token, "a loop is"),
            Expr::Closure(x) => self.unsupported(x, "a closure is"),
            Expr::Macro(m) => self.unsupported(&m.mac, "a macro is"),
            Expr::Reference(r) => self.unsupported(r.and_token, "a reference is"),
            Expr::Cast(c) => self.unsupported(c, "a cast is"),
            Expr::Block(b) => self.unsupported(b, "a nested block is"),
            Expr::Return(r) => self.unsupported(r.return_token, "`return` is"),
            Expr::Assign(a) => self.unsupported(a, "an assignment is"),
            Expr::Field(f) => self.unsupported(f, "a field access is"),
            Expr::Tuple(t) => self.unsupported(t, "a tuple is"),
            Expr::Array(a) => self.unsupported(a, "an array is"),
            other => self.unsupported(other, "this expression is"),
        }
    }

    fn literal(&mut self, lit: &Lit) -> Id {
        let parsed = match lit {
            Lit::Float(f) if matches!(f.suffix(), "" | "f64") => f.base10_parse::<f64>(),
            Lit::Int(i) if matches!(i.suffix(), "" | "f64") => i.base10_parse::<f64>(),
            other => {
                return self.unsupported(other, "this literal is (only `f64` numbers are)");
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

    fn path(&mut self, p: &syn::ExprPath, env: &HashMap<String, Binding>) -> Id {
        if p.qself.is_some() || p.path.segments.iter().any(|s| !s.arguments.is_none()) {
            return self.unsupported(p, "this path is");
        }
        let segs: Vec<String> = p
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect();
        if segs.len() == 1 && p.path.leading_colon.is_none() {
            return match env.get(&segs[0]) {
                Some(Binding::Scalar(id)) => *id,
                Some(Binding::Array { .. }) => self.error(
                    p,
                    format!("`{}` is an array: use its components `{}[i]`", segs[0], segs[0]),
                ),
                None => self.error(
                    p,
                    format!(
                        "unknown name `{}`: the body may use the parameters, its own `let` bindings and `std::f64::consts::*`",
                        segs[0]
                    ),
                ),
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
        self.unsupported(p, "this path is")
    }

    fn index(&mut self, ix: &syn::ExprIndex, env: &HashMap<String, Binding>) -> Id {
        let name = match &*ix.expr {
            Expr::Path(p) if p.qself.is_none() => p.path.get_ident().map(Ident::to_string),
            _ => None,
        };
        let binding = name.as_ref().and_then(|n| env.get(n).copied());
        let (state, len) = match binding {
            Some(Binding::Array { state, len }) => (state, len),
            Some(Binding::Scalar(_)) => {
                let n = name.unwrap_or_default();
                return self.error(
                    &ix.expr,
                    format!(
                        "`{n}` is a scalar: only `x` and `v` declared as `[f64; D]` can be indexed"
                    ),
                );
            }
            None => {
                return self.unsupported(&ix.expr, "indexing anything but `x` and `v` is");
            }
        };
        let index = match &*ix.index {
            Expr::Lit(syn::ExprLit {
                lit: Lit::Int(i), ..
            }) => i.base10_parse::<usize>(),
            other => {
                return self.error(other, "the index must be an integer literal, e.g. `x[0]`");
            }
        };
        match (index, len) {
            (Ok(i), Length::Known(dim)) if i >= dim => self.error(
                &ix.index,
                format!("index {i} is out of bounds: the dimension is {dim}"),
            ),
            (Ok(i), _) => self.graph.var(state.component(i)),
            (Err(e), _) => {
                self.errors.push(e);
                self.graph.num(0.0)
            }
        }
    }

    /// A method `recv.name(args)` or the function `f64::name(recv, args)`.
    fn function(
        &mut self,
        name: &Ident,
        recv: Id,
        args: &[&Expr],
        all_args: &dyn quote::ToTokens,
        env: &HashMap<String, Binding>,
    ) -> Id {
        let s = name.to_string();
        let arity = match s.as_str() {
            "powi" | "powf" | "hypot" => 1,
            _ => 0,
        };
        if Func::from_name(&s).is_none() && arity == 0 {
            return self.unsupported(name, &format!("the method `{s}` is"));
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
                Some(Ok(n)) if n != i64::from(i32::MIN) && i32::try_from(n).is_ok() => {
                    self.graph.powi(recv, n as i32)
                }
                Some(Ok(_)) | Some(Err(_)) => {
                    self.error(args[0], "the `powi` exponent is out of range for `i32`")
                }
                None => self.error(
                    args[0],
                    "the `powi` exponent must be an integer literal (use `powf` for a general exponent)",
                ),
            },
            "powf" => {
                let b = self.expr(args[0], env);
                self.graph.powf(recv, b)
            }
            "hypot" => {
                let b = self.expr(args[0], env);
                self.graph.hypot(recv, b)
            }
            _ => match Func::from_name(&s) {
                Some(f) => self.graph.call(f, recv),
                None => self.unsupported(name, &format!("the method `{s}` is")),
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
