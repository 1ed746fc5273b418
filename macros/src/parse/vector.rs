//! What a vector-valued fn (`#[force]`, `#[constraint]`) adds to the parsing of a Lagrangian:
//! its return type, the parameters a constraint may not have, and a body that ends with its
//! components (an array `[e0, e1]`, or a local array set element by element,
//! `let mut f = [0.0; 2]; for i in 0..2 { f[i] = …; } f`). The components are differentiated
//! entry by entry, so every loop runs over a literal range and is unrolled (`unrolls` in
//! `values.rs`): the dimension must be a literal.

use syn::{BinOp, Expr, Ident, ReturnType, Type};

use super::body::{Parser, is_compound};
use super::scope::{Binding, Env, Kind, Returns, State, returns, strip};
use super::signature::{Length, Shape, Signature, is_f64};
use crate::ir::{Attr, Id, Node, Var};

impl Parser {
    /// The names of the signature bound: `x`, `v` (a constraint: `x` only), `t`, the
    /// dimension and the constants.
    pub(super) fn signature_env(&mut self, sig: &Signature) -> Env {
        let mut env = Env::new();
        let states = [State::Position, State::Velocity];
        for ((name, shape), state) in sig.states.iter().zip(states) {
            let binding = match *shape {
                Shape::Scalar => Binding::Scalar(self.graph.var(state.component(0))),
                Shape::Array(len) => Binding::Array { state, len },
                Shape::Slice => Binding::Array {
                    state,
                    len: Length::Named,
                },
            };
            env.insert(name.to_string(), binding);
        }
        if let Some(Length::Known(d)) = sig.states.first().and_then(|s| match s.1 {
            Shape::Array(len) => Some(len),
            Shape::Scalar | Shape::Slice => None,
        }) {
            self.dim = Some(d);
        }
        if let Some(name) = sig.dim_name.as_ref().and_then(|p| p.get_ident()) {
            env.insert(name.to_string(), Binding::Dim);
        }
        if let Some(n) = &sig.runtime_dim {
            env.insert(n.to_string(), Binding::Dim);
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
        env
    }

    /// The components of a vector-valued fn `name`: the values its body ends with (a force on
    /// `x: f64`: the one value).
    pub fn vector_body(&mut self, block: &syn::Block, sig: &Signature, name: &Ident) -> Vec<Id> {
        let mut env = self.signature_env(sig);
        let outputs = match sig.outputs {
            Some(_) if self.attr == Attr::Force && sig.scalar => vec![self.block(block, &mut env)],
            Some(n) => {
                let name = name.to_string();
                let values = self.values_block(block, &mut env, Some((&name, Kind::Array, n)));
                values.ids
            }
            None => {
                // The return type was reported: the body's statements are still checked, and
                // not its value against a type that is not there.
                let n = block.stmts.len();
                for stmt in block.stmts.iter().take(n.saturating_sub(1)) {
                    self.statement(stmt, &mut env);
                }
                return Vec::new();
            }
        };
        // A loop over a range that is not a literal (a `const`) stays a sum, which the entry by
        // entry derivatives do not take.
        let looped = self.graph.reachable(&outputs).into_iter().any(|id| {
            matches!(
                self.graph.node(id),
                Node::Sum(..)
                    | Node::Var(Var::XAt(_) | Var::VAt(_) | Var::Index(_) | Var::Dim | Var::Sym(_))
            )
        });
        if looped {
            self.error(
                name,
                format!(
                    "a {} fn is differentiated entry by entry: its loops run over literal ranges (`for i in 0..3`, unrolled) and read `x`, `v` at constant indices",
                    self.attr.name()
                ),
            );
        }
        outputs
    }

    /// `a[k] = e;`, `a[k] += e;` (`-=`, `*=`, `/=`) on a local array `a`, at a constant index
    /// (a literal, or the variable of an unrolled loop): the new value replaces the element.
    /// `false` when `e` is not such a statement (it is then read as any other).
    pub(super) fn sets_element(&mut self, e: &Expr, env: &mut Env) -> bool {
        let (left, op, right) = match e {
            Expr::Assign(a) => (&*a.left, None, &*a.right),
            Expr::Binary(b) if is_compound(b.op) => (&*b.left, Some(b.op), &*b.right),
            _ => return false,
        };
        let Expr::Index(ix) = strip(left) else {
            return false;
        };
        let name = match strip(&ix.expr) {
            Expr::Path(p) => p.path.get_ident().map(Ident::to_string),
            _ => None,
        };
        let Some(Binding::Values(mut values)) = name.as_ref().and_then(|n| env.get(n)).cloned()
        else {
            return false;
        };
        if values.kind != Kind::Array || self.attr == Attr::Lagrangian {
            return false;
        }
        if !self.frames_open() {
            let Some(k) = self.constant_index(&ix.index, env) else {
                return true;
            };
            let Some(k) = usize::try_from(k).ok().filter(|&k| k < values.ids.len()) else {
                self.error(
                    &ix.index,
                    format!(
                        "index {k} is out of bounds: the array has {} values",
                        values.ids.len()
                    ),
                );
                return true;
            };
            let value = self.expr(right, env);
            let old = values.ids[k];
            values.ids[k] = match op {
                None => value,
                Some(BinOp::AddAssign(_)) => self.graph.add(old, value),
                Some(BinOp::SubAssign(_)) => self.graph.sub(old, value),
                Some(BinOp::MulAssign(_)) => self.graph.mul(old, value),
                Some(_) => self.graph.div(old, value),
            };
            env.insert(name.unwrap_or_default(), Binding::Values(values));
        } else {
            self.error(
                left,
                "an element of an array is set in straight-line code or in a loop over a literal range (unrolled), not in a sum",
            );
        }
        true
    }

    /// Why `name` cannot be read here, when it is a state a constraint does not take.
    pub(super) fn not_a_state(&self, name: &str) -> Option<String> {
        let what = match (self.attr, name) {
            (Attr::Constraint, "v") => "the velocity `v`",
            (Attr::Constraint, "t") => "the time `t`",
            _ => return None,
        };
        Some(format!(
            "a #[constraint] depends on `x` alone and cannot read {what}"
        ))
    }
}

/// The number of components of a force or constraint, from its return type, and the errors of
/// its signature that a Lagrangian's does not have: a dimension that is not a literal, a
/// return type that is not `[f64; D]` (a force on `x: f64`: `f64`) or `[f64; M]`. `None` when
/// the return type is not one of them (reported) or a dimension in error leaves `D` unknown.
pub fn check_outputs(
    sig: &syn::Signature,
    attr: Attr,
    x_ty: Option<&Type>,
    (shape, dim, dim_name): (Shape, usize, Option<&syn::Path>),
    errors: &mut Vec<syn::Error>,
) -> Option<usize> {
    let name = attr.name();
    if attr == Attr::Force && matches!(shape, Shape::Slice | Shape::Array(Length::Named)) {
        return looped_force_output(sig, shape, dim_name, errors);
    }
    if let (Some(ty), Shape::Slice | Shape::Array(Length::Named)) = (x_ty, shape) {
        errors.push(syn::Error::new_spanned(
            ty,
            format!("a {name} fn takes `x: [f64; D]` with `D` an integer literal, or `x: f64`: its derivatives are written out entry by entry"),
        ));
    }
    let known = matches!(shape, Shape::Scalar | Shape::Array(Length::Known(_)));
    if attr == Attr::Force && !known {
        return None;
    }
    let want = match (attr, shape) {
        (Attr::Force, Shape::Scalar) => "`f64`, like `x`".to_string(),
        (Attr::Force, _) => format!("`[f64; {dim}]`, one component per degree of freedom"),
        _ => "`[f64; M]`, one value per constraint (`M` an integer literal)".to_string(),
    };
    let ty = match &sig.output {
        ReturnType::Type(_, ty) => ty,
        ReturnType::Default => {
            errors.push(syn::Error::new_spanned(
                &sig.ident,
                format!("a {name} fn must return {want}"),
            ));
            return None;
        }
    };
    let outputs = match (attr, returns(&sig.output)) {
        (Attr::Force, Some(Returns::Scalar)) if shape == Shape::Scalar => Some(1),
        (Attr::Force, Some(Returns::Values(Kind::Array, n))) if shape != Shape::Scalar => {
            (n == dim).then_some(dim)
        }
        (Attr::Constraint, Some(Returns::Values(Kind::Array, m))) => Some(m),
        _ => None,
    };
    if outputs.is_none() {
        errors.push(syn::Error::new_spanned(
            ty,
            format!("a {name} fn must return {want}"),
        ));
    }
    outputs
}

/// The return type of a force over a named dimension, `[f64; N]` (`N` the dimension), or over
/// slices, `Vec<f64>`; `Some(1)` when it is that (the force is then one value, its virtual
/// work), `None` when it is not (reported).
fn looped_force_output(
    sig: &syn::Signature,
    shape: Shape,
    dim_name: Option<&syn::Path>,
    errors: &mut Vec<syn::Error>,
) -> Option<usize> {
    let same_path = |e: &Expr| match (strip(e), dim_name) {
        (Expr::Path(p), Some(n)) => p.path == *n,
        _ => false,
    };
    let (ok, want) = match (&sig.output, shape) {
        (ReturnType::Type(_, ty), Shape::Slice) => (
            matches!(&**ty, Type::Path(p) if p.qself.is_none() && p.path.segments.last().is_some_and(|s| {
                s.ident == "Vec" && matches!(&s.arguments, syn::PathArguments::AngleBracketed(a)
                    if a.args.len() == 1 && matches!(a.args.first(), Some(syn::GenericArgument::Type(t)) if is_f64(t)))
            })),
            "`Vec<f64>`, one component per degree of freedom (slices `x: &[f64]`)".to_string(),
        ),
        (ReturnType::Type(_, ty), _) => (
            matches!(&**ty, Type::Array(a) if is_f64(&a.elem) && same_path(&a.len)),
            format!(
                "`[f64; {}]`, one component per degree of freedom",
                dim_name.map_or("N".into(), |n| quote::ToTokens::to_token_stream(n)
                    .to_string())
            ),
        ),
        (ReturnType::Default, Shape::Slice) => (false, "`Vec<f64>`".to_string()),
        (ReturnType::Default, _) => (false, "`[f64; N]`".to_string()),
    };
    if !ok {
        let msg = format!("a #[force] fn must return {want}");
        match &sig.output {
            ReturnType::Type(_, ty) => errors.push(syn::Error::new_spanned(ty, msg)),
            ReturnType::Default => errors.push(syn::Error::new_spanned(&sig.ident, msg)),
        }
        return None;
    }
    Some(1)
}
