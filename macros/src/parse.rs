//! `syn::ItemFn` → [`Model`]: checks the signature, then walks the body into the expression
//! DAG. Every unsupported construct becomes a `syn::Error` on its own tokens; all of them are
//! collected and combined, so one mistake does not hide the next.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use syn::{
    Attribute, BinOp, Expr, FnArg, Ident, ItemFn, Lit, Pat, ReturnType, Stmt, Type, UnOp,
    Visibility,
};

use crate::expr::{Func, Graph, Id, Var};

/// What the body of a `#[lagrangian]` fn may contain (appended to every body error).
pub const SUPPORTED: &str = "supported in a #[lagrangian] body: `let` bindings, `+ - * /`, \
     unary `-`, float and integer literals, parentheses, `x[i]`/`v[i]` with a literal index, \
     the parameters, the f64 methods (or `f64::` functions) sin cos tan asin acos atan sinh \
     cosh tanh exp ln log10 sqrt cbrt recip abs powi powf hypot, and `std::f64::consts::*`";

const SIGNATURE: &str = "expected `fn name(x: T, v: T, [t: f64,] constants: f64...) -> f64` \
     with `T` either `f64` or `[f64; D]`";

/// A parsed Lagrangian: the user's fn, the facts the code generator needs, and `L` as a DAG.
pub struct Model {
    /// The user's fn, emitted unchanged.
    pub item: ItemFn,
    /// Name of the generated struct.
    pub struct_name: Ident,
    /// Visibility of the fn, given to the struct.
    pub vis: Visibility,
    /// Doc comments of the fn, given to the struct.
    pub docs: Vec<Attribute>,
    /// Dimension `D`.
    pub dim: usize,
    /// `x`, `v` declared as `f64` (printed as `x`, not `x[0]`).
    pub scalar: bool,
    /// The model constants, in order (`Var::Const(k)` is `consts[k]`).
    pub consts: Vec<Ident>,
    /// The expression graph.
    pub graph: Graph,
    /// `L` in `graph`.
    pub root: Id,
}

/// The usable names in the body.
#[derive(Clone, Copy)]
enum Binding {
    Scalar(Id),
    /// `x` or `v` declared as an array (`true` for `x`) of this length (`usize::MAX` when the
    /// length is not a literal, already reported).
    Array(bool, usize),
}

struct Parser {
    graph: Graph,
    errors: Vec<syn::Error>,
}

/// Parses the attribute arguments and the fn into a [`Model`].
pub fn parse(args: TokenStream, item: TokenStream) -> syn::Result<Model> {
    let item: ItemFn = syn::parse2(item).map_err(|e| {
        syn::Error::new(
            e.span(),
            format!("{e}: #[lagrangian] applies to a `fn`; {SIGNATURE}"),
        )
    })?;
    let mut errors = Vec::new();
    if !args.is_empty() {
        errors.push(syn::Error::new_spanned(
            &args,
            "#[lagrangian] takes no arguments: model constants are the fn's parameters after `x`, `v` (and `t`)",
        ));
    }
    let sig = &item.sig;
    if let Some(c) = &sig.constness {
        errors.push(syn::Error::new_spanned(
            c,
            "a #[lagrangian] fn cannot be `const`",
        ));
    }
    if let Some(a) = &sig.asyncness {
        errors.push(syn::Error::new_spanned(
            a,
            "a #[lagrangian] fn cannot be `async`",
        ));
    }
    if let Some(u) = &sig.unsafety {
        errors.push(syn::Error::new_spanned(
            u,
            "a #[lagrangian] fn cannot be `unsafe`",
        ));
    }
    if let Some(abi) = &sig.abi {
        errors.push(syn::Error::new_spanned(
            abi,
            "a #[lagrangian] fn cannot have an ABI",
        ));
    }
    if !sig.generics.params.is_empty() || sig.generics.where_clause.is_some() {
        errors.push(syn::Error::new_spanned(
            &sig.generics,
            "a #[lagrangian] fn cannot be generic: its variables are `f64` or `[f64; D]` with a literal `D`",
        ));
    }
    if let Some(var) = &sig.variadic {
        errors.push(syn::Error::new_spanned(
            var,
            "a #[lagrangian] fn cannot be variadic",
        ));
    }
    match &sig.output {
        ReturnType::Default => errors.push(syn::Error::new_spanned(
            &sig.ident,
            "a #[lagrangian] fn must return `f64`: add `-> f64`",
        )),
        ReturnType::Type(_, ty) => {
            if !is_f64(ty) {
                errors.push(syn::Error::new_spanned(
                    ty,
                    "a #[lagrangian] fn must return `f64`",
                ));
            }
        }
    }

    // Parameters: x, v, optional t, constants.
    let mut names: Vec<(Ident, Type)> = Vec::new();
    for arg in &sig.inputs {
        match arg {
            FnArg::Receiver(r) => errors.push(syn::Error::new_spanned(
                r,
                format!("`self` is not allowed; {SIGNATURE}"),
            )),
            FnArg::Typed(pt) => match &*pt.pat {
                Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                    names.push((pi.ident.clone(), (*pt.ty).clone()));
                }
                other => errors.push(syn::Error::new_spanned(
                    other,
                    "parameters of a #[lagrangian] fn must be plain names",
                )),
            },
        }
    }
    let mut dim = 1;
    let mut scalar = true;
    let mut shapes: [Option<usize>; 2] = [None, None];
    let mut has_t = false;
    let mut consts = Vec::new();
    if names.len() < 2 {
        errors.push(syn::Error::new_spanned(
            &sig.inputs,
            format!("missing parameters: {SIGNATURE}"),
        ));
        if sig.inputs.is_empty() {
            // An empty list has no tokens of its own: point at the fn name instead.
            errors.pop();
            errors.push(syn::Error::new_spanned(
                &sig.ident,
                format!("missing parameters: {SIGNATURE}"),
            ));
        }
    } else {
        for (k, expected) in ["x", "v"].iter().enumerate() {
            if bare(&names[k].0) != *expected {
                errors.push(syn::Error::new_spanned(
                    &names[k].0,
                    format!(
                        "parameter {} must be named `{expected}` (or `_{expected}`); {SIGNATURE}",
                        k + 1
                    ),
                ));
            }
        }
        // Each of `x`, `v` is bound with its own declared shape even when the two differ, so
        // that the body is still checked without a cascade of follow-up errors.
        let (x_shape, x_err) = state_type(&names[0].1);
        let (v_shape, v_err) = state_type(&names[1].1);
        errors.extend(x_err);
        errors.extend(v_err);
        if v_shape != x_shape {
            errors.push(syn::Error::new_spanned(
                &names[1].1,
                "`v` must have the same type as `x`",
            ));
        }
        shapes = [x_shape, v_shape];
        if let Some(d) = x_shape {
            dim = d;
            scalar = false;
        }
        for (k, (name, ty)) in names.iter().enumerate().skip(2) {
            if !is_f64(ty) {
                errors.push(syn::Error::new_spanned(
                    ty,
                    format!(
                        "`{name}` must be `f64`: after `x` and `v` come an optional time `t: f64` and the model constants, all `f64`"
                    ),
                ));
            }
            let plain = bare(name);
            if plain == "t" {
                if k == 2 {
                    has_t = true;
                } else {
                    errors.push(syn::Error::new_spanned(
                        name,
                        "the time `t` must be the third parameter, right after `v`",
                    ));
                    // Still usable in the body (as a constant), so no "unknown name" follows.
                    consts.push(name.clone());
                }
            } else if plain == "x" || plain == "v" {
                errors.push(syn::Error::new_spanned(
                    name,
                    format!(
                        "`{name}` must be parameter {}",
                        if plain == "x" { 1 } else { 2 }
                    ),
                ));
            } else {
                consts.push(name.clone());
            }
        }
    }

    let struct_name = Ident::new(&camel_case(&sig.ident.to_string()), sig.ident.span());
    if struct_name == sig.ident {
        errors.push(syn::Error::new_spanned(
            &sig.ident,
            format!(
                "the generated struct is named after the fn in CamelCase; name the fn in snake_case so that `{struct_name}` does not clash with it"
            ),
        ));
    }

    let mut parser = Parser {
        graph: Graph::new(),
        errors,
    };
    let mut env: HashMap<String, Binding> = HashMap::new();
    for (k, is_x) in [(0, true), (1, false)] {
        if let Some((name, _)) = names.get(k) {
            let binding = match shapes[k] {
                None => Binding::Scalar(parser.graph.var(if is_x { Var::X(0) } else { Var::V(0) })),
                Some(d) => Binding::Array(is_x, d),
            };
            env.insert(name.to_string(), binding);
        }
    }
    if has_t {
        env.insert(
            names[2].0.to_string(),
            Binding::Scalar(parser.graph.var(Var::T)),
        );
    }
    for (k, c) in consts.iter().enumerate() {
        env.insert(
            c.to_string(),
            Binding::Scalar(parser.graph.var(Var::Const(k))),
        );
    }
    let root = parser.block(&item.block, &mut env);

    let mut errors = parser.errors.into_iter();
    if let Some(mut first) = errors.next() {
        for e in errors {
            first.combine(e);
        }
        return Err(first);
    }
    let docs = item
        .attrs
        .iter()
        .filter(|a| a.path().is_ident("doc"))
        .cloned()
        .collect();
    Ok(Model {
        vis: item.vis.clone(),
        item,
        struct_name,
        docs,
        dim,
        scalar,
        consts,
        graph: parser.graph,
        root,
    })
}

/// A parameter name without the leading `_` that silences "unused" warnings.
fn bare(name: &Ident) -> String {
    let s = name.to_string();
    s.strip_prefix('_').map(str::to_string).unwrap_or(s)
}

/// `snake_case` → `CamelCase`.
fn camel_case(s: &str) -> String {
    let s = s.strip_prefix("r#").unwrap_or(s);
    let mut out = String::new();
    for part in s.split('_').filter(|p| !p.is_empty()) {
        let mut chars = part.chars();
        if let Some(c) = chars.next() {
            out.extend(c.to_uppercase());
            out.push_str(chars.as_str());
        }
    }
    if out.is_empty() {
        "Lagrangian".into()
    } else {
        out
    }
}

fn is_f64(ty: &Type) -> bool {
    match ty {
        Type::Path(tp) => tp.qself.is_none() && tp.path.is_ident("f64"),
        Type::Paren(p) => is_f64(&p.elem),
        Type::Group(g) => is_f64(&g.elem),
        _ => false,
    }
}

/// `f64` → `None`, `[f64; D]` → `Some(D)`, with the error if the type is not one of these (the
/// shape is then the closest guess, so that the body can still be checked).
fn state_type(ty: &Type) -> (Option<usize>, Option<syn::Error>) {
    if is_f64(ty) {
        return (None, None);
    }
    if let Type::Array(arr) = ty {
        let elem = (!is_f64(&arr.elem))
            .then(|| syn::Error::new_spanned(&arr.elem, "the state arrays must hold `f64`"));
        if let Expr::Lit(syn::ExprLit {
            lit: Lit::Int(n), ..
        }) = &arr.len
        {
            return match n.base10_parse::<usize>() {
                Ok(0) => (
                    Some(usize::MAX),
                    Some(syn::Error::new_spanned(
                        n,
                        "the dimension must be at least 1",
                    )),
                ),
                Ok(d) => (Some(d), elem),
                Err(e) => (Some(usize::MAX), Some(e)),
            };
        }
        return (
            Some(usize::MAX),
            Some(syn::Error::new_spanned(
                &arr.len,
                "the dimension must be an integer literal, e.g. `[f64; 2]`",
            )),
        );
    }
    (
        None,
        Some(syn::Error::new_spanned(
            ty,
            format!("`x` and `v` must be `f64` or `[f64; D]`; {SIGNATURE}"),
        )),
    )
}

impl Parser {
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
                Some(Binding::Array(..)) => self.error(
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
        if consts_path && let Some(c) = float_const(&segs[n - 1]) {
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
        let (is_x, dim) = match binding {
            Some(Binding::Array(is_x, dim)) => (is_x, dim),
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
        match index {
            Ok(i) if i < dim => {
                let var = if is_x { Var::X(i) } else { Var::V(i) };
                self.graph.var(var)
            }
            Ok(i) => self.error(
                &ix.index,
                format!("index {i} is out of bounds: the dimension is {dim}"),
            ),
            Err(e) => {
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

/// `std::f64::consts::NAME`.
fn float_const(name: &str) -> Option<f64> {
    use std::f64::consts::*;
    Some(match name {
        "PI" => PI,
        "TAU" => TAU,
        "E" => E,
        "SQRT_2" => SQRT_2,
        "FRAC_1_SQRT_2" => FRAC_1_SQRT_2,
        "LN_2" => LN_2,
        "LN_10" => LN_10,
        "LOG2_E" => LOG2_E,
        "LOG10_E" => LOG10_E,
        "LOG2_10" => LOG2_10,
        "LOG10_2" => LOG10_2,
        "FRAC_PI_2" => FRAC_PI_2,
        "FRAC_PI_3" => FRAC_PI_3,
        "FRAC_PI_4" => FRAC_PI_4,
        "FRAC_PI_6" => FRAC_PI_6,
        "FRAC_PI_8" => FRAC_PI_8,
        "FRAC_1_PI" => FRAC_1_PI,
        "FRAC_2_PI" => FRAC_2_PI,
        "FRAC_2_SQRT_PI" => FRAC_2_SQRT_PI,
        _ => return None,
    })
}

impl Func {
    /// The function behind an `f64` method name (`sign` is internal, not user-facing).
    pub fn from_name(s: &str) -> Option<Func> {
        Some(match s {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "asin" => Func::Asin,
            "acos" => Func::Acos,
            "atan" => Func::Atan,
            "sinh" => Func::Sinh,
            "cosh" => Func::Cosh,
            "tanh" => Func::Tanh,
            "exp" => Func::Exp,
            "ln" => Func::Ln,
            "log10" => Func::Log10,
            "sqrt" => Func::Sqrt,
            "cbrt" => Func::Cbrt,
            "recip" => Func::Recip,
            "abs" => Func::Abs,
            _ => return None,
        })
    }
}
