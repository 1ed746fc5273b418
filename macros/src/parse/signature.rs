//! The signature of a `#[lagrangian]` fn: `x`, `v`, an optional `t`, the model constants.

use proc_macro2::TokenStream;
use quote::ToTokens;
use syn::{Expr, FnArg, Ident, ItemFn, Lit, Pat, ReturnType, Type};

use crate::ir::Attr;

/// The accepted signature, quoted in the signature errors.
pub const SIGNATURE: &str = "expected `fn name(x: T, v: T, [t: f64,] constants: f64...) -> f64` \
     with `T` either `f64` or `[f64; D]` (or `&[f64]`, its length one constant `n: usize`)";

/// The signature of a `#[force]` fn, quoted in its signature errors.
const FORCE_SIGNATURE: &str = "expected `fn name(x: T, v: T, [t: f64,] constants: f64...) -> T` \
     with `T` either `f64` or `[f64; D]` (`D` an integer literal)";

/// The signature of a `#[constraint]` fn, quoted in its signature errors.
const CONSTRAINT_SIGNATURE: &str = "expected `fn name(x: T, constants: f64...) -> [f64; M]` with `T` either `f64` or \
     `[f64; D]` (`D` and `M` integer literals)";

/// The accepted signature of a fn for `attr`.
pub fn expected(attr: Attr) -> &'static str {
    match attr {
        Attr::Lagrangian => SIGNATURE,
        Attr::Force => FORCE_SIGNATURE,
        Attr::Constraint => CONSTRAINT_SIGNATURE,
    }
}

/// The declared type of `x` or `v`.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// `f64`.
    Scalar,
    /// `[f64; len]`.
    Array(Length),
    /// `&[f64]`: the dimension is the model's `usize` constant, a run-time value.
    Slice,
}

/// The length of a state array.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Length {
    /// A valid literal length.
    Known(usize),
    /// A named constant (`[f64; N]` with `const N: usize = …;` in scope).
    Named,
    /// The length was rejected (and reported): any index is accepted, so that only the
    /// declaration is an error.
    Rejected,
}

/// What the signature declares.
pub struct Signature {
    /// The names of `x` and `v` as written (`_x` is allowed) with their shapes; fewer than two
    /// when parameters are missing.
    pub states: Vec<(Ident, Shape)>,
    /// The name of the time parameter, when there is one.
    pub time: Option<Ident>,
    /// The model constants, in order.
    pub consts: Vec<Ident>,
    /// Dimension `D` (1 when it could not be read or is named).
    pub dim: usize,
    /// The named constant that is the dimension, if it is one.
    pub dim_name: Option<syn::Path>,
    /// The `usize` model constant that is the dimension of slices `x: &[f64]`, `v: &[f64]`.
    pub runtime_dim: Option<Ident>,
    /// `x`, `v` declared as `f64`.
    pub scalar: bool,
    /// Name of the generated struct.
    pub struct_name: Ident,
    /// The number of components a vector-valued fn returns (`#[force]`: `D`, `#[constraint]`:
    /// `M`); `None` when its return type is in error; `Some(1)` for a Lagrangian.
    pub outputs: Option<usize>,
}

/// Checks the attribute arguments and the signature of `item`, a fn for `attr`; the errors go
/// to `errors`, in source order, and the declared facts are returned as far as they could be
/// read.
pub fn check(
    args: &TokenStream,
    item: &ItemFn,
    attr: Attr,
    errors: &mut Vec<syn::Error>,
) -> Signature {
    let sig = &item.sig;
    let name = attr.name();
    if !args.is_empty() {
        let msg = match attr {
            Attr::Lagrangian => {
                "#[lagrangian] takes no arguments (or `helper`, on a helper fn): model constants are the fn's parameters after `x`, `v` (and `t`)"
            }
            Attr::Force | Attr::Constraint => {
                "this attribute takes no arguments: the constants are the fn's parameters after the state"
            }
        };
        errors.push(syn::Error::new_spanned(args, msg));
    }
    let qualifiers: [(Option<&dyn ToTokens>, &str); 4] = [
        (sig.constness.as_ref().map(|c| c as _), "be `const`"),
        (sig.asyncness.as_ref().map(|a| a as _), "be `async`"),
        (sig.unsafety.as_ref().map(|u| u as _), "be `unsafe`"),
        (sig.abi.as_ref().map(|a| a as _), "have an ABI"),
    ];
    for (tokens, what) in qualifiers {
        if let Some(tokens) = tokens {
            errors.push(syn::Error::new_spanned(
                tokens,
                format!("a {name} fn cannot {what}"),
            ));
        }
    }
    if !sig.generics.params.is_empty() || sig.generics.where_clause.is_some() {
        errors.push(syn::Error::new_spanned(
            &sig.generics,
            format!("a {name} fn cannot be generic: its variables are `f64` or `[f64; N]` with `N` a literal or a `const` item"),
        ));
    }
    if let Some(var) = &sig.variadic {
        errors.push(syn::Error::new_spanned(
            var,
            format!("a {name} fn cannot be variadic"),
        ));
    }
    if attr == Attr::Lagrangian {
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
    }

    // Parameters: x, v, optional t, constants.
    let signature = expected(attr);
    let mut names: Vec<(Ident, Type)> = Vec::new();
    for arg in &sig.inputs {
        match arg {
            FnArg::Receiver(r) => errors.push(syn::Error::new_spanned(
                r,
                format!("`self` is not allowed; {signature}"),
            )),
            FnArg::Typed(pt) => match &*pt.pat {
                Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                    names.push((pi.ident.clone(), (*pt.ty).clone()));
                }
                other => errors.push(syn::Error::new_spanned(
                    other,
                    format!("parameters of a {name} fn must be plain names"),
                )),
            },
        }
    }
    if attr == Attr::Constraint {
        states_only(&mut names, errors);
    }
    let mut dim = 1;
    let mut dim_name = None;
    let mut scalar = true;
    let mut shapes = [Shape::Scalar; 2];
    let mut has_t = false;
    let mut consts = Vec::new();
    let mut usizes: Vec<(&Ident, &Type)> = Vec::new();
    if names.len() < 2 {
        errors.push(syn::Error::new_spanned(
            &sig.inputs,
            format!("missing parameters: {signature}"),
        ));
        if sig.inputs.is_empty() {
            // An empty list has no tokens of its own: point at the fn name instead.
            errors.pop();
            errors.push(syn::Error::new_spanned(
                &sig.ident,
                format!("missing parameters: {signature}"),
            ));
        }
    } else {
        for (k, expected) in ["x", "v"].iter().enumerate() {
            if bare(&names[k].0) != *expected {
                errors.push(syn::Error::new_spanned(
                    &names[k].0,
                    format!(
                        "parameter {} must be named `{expected}` (or `_{expected}`); {signature}",
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
            let msg = if x_shape == Shape::Slice || v_shape == Shape::Slice {
                "`v` must have the same type as `x`: both slices `&[f64]` (a run-time dimension, \
                 the `usize` constant) or both arrays `[f64; N]`"
            } else {
                "`v` must have the same type as `x`"
            };
            errors.push(syn::Error::new_spanned(&names[1].1, msg));
        }
        shapes = [x_shape, v_shape];
        if x_shape == Shape::Slice {
            scalar = false;
        }
        if let Shape::Array(len) = x_shape {
            scalar = false;
            if let Length::Known(d) = len {
                dim = d;
            }
            if let (Length::Named, Type::Array(arr)) = (len, &names[0].1)
                && let Expr::Path(p) = &arr.len
            {
                dim_name = Some(p.path.clone());
            }
        }
        for (k, (name, ty)) in names.iter().enumerate().skip(2) {
            if is_usize(ty) && bare(name) != "t" {
                usizes.push((name, ty));
                continue;
            }
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

    let runtime_dim = runtime_dimension(sig, &names, shapes[0], &usizes, errors);

    let struct_name = Ident::new(&camel_case(&sig.ident.to_string()), sig.ident.span());
    if struct_name == sig.ident {
        errors.push(syn::Error::new_spanned(
            &sig.ident,
            format!(
                "the generated struct is named after the fn in CamelCase; name the fn in snake_case so that `{struct_name}` does not clash with it"
            ),
        ));
    }

    // A constraint's `v` is the copy of `x` that [`states_only`] made: not bound in the body.
    let states = names
        .iter()
        .take(if attr == Attr::Constraint { 1 } else { 2 })
        .zip(shapes)
        .map(|((name, _), shape)| (name.clone(), shape))
        .collect();
    Signature {
        states,
        time: has_t.then(|| names[2].0.clone()),
        consts,
        dim,
        dim_name,
        runtime_dim,
        scalar,
        struct_name,
        // A force's or constraint's, from its return type: `vector::check_outputs`.
        outputs: Some(1),
    }
}

/// A constraint's parameters: `v` and `t` are errors (removed), and a copy of `x` stands
/// where `v` is in a Lagrangian's, so that the checks of `x` and the constants are the same.
fn states_only(names: &mut Vec<(Ident, Type)>, errors: &mut Vec<syn::Error>) {
    names.retain(|(n, _)| {
        let what = match bare(n).as_str() {
            "v" => "the velocity",
            "t" => "the time",
            _ => return true,
        };
        errors.push(syn::Error::new_spanned(
            n,
            format!("a #[constraint] depends on `x` alone: `{n}` ({what}) cannot be a parameter"),
        ));
        false
    });
    if let Some((x, ty)) = names.first().cloned() {
        names.insert(1, (Ident::new("v", x.span()), ty));
    }
}

/// The run-time dimension: with slices `x: &[f64]`, `v: &[f64]`, the one `usize` model
/// constant. The errors: slices without one, two of them, one without slices.
fn runtime_dimension(
    sig: &syn::Signature,
    names: &[(Ident, Type)],
    x_shape: Shape,
    usizes: &[(&Ident, &Type)],
    errors: &mut Vec<syn::Error>,
) -> Option<Ident> {
    if x_shape != Shape::Slice {
        for (name, ty) in usizes {
            errors.push(syn::Error::new_spanned(
                ty,
                format!(
                    "`{name}: usize` is the run-time dimension of slices `x: &[f64]`, `v: &[f64]`; with `x` an array or `f64` the constants are `f64` (a dimension `N` is a `const N: usize` in `[f64; N]`)"
                ),
            ));
        }
        return None;
    }
    match usizes {
        [] => {
            let at: &dyn quote::ToTokens = match names.first() {
                Some((_, ty)) => ty,
                None => &sig.ident,
            };
            errors.push(syn::Error::new_spanned(
                at,
                "with slices `x: &[f64]`, `v: &[f64]` the dimension is a model constant of type `usize`: add one, e.g. `fn name(x: &[f64], v: &[f64], n: usize, …)`",
            ));
            None
        }
        [(name, _)] => Some((*name).clone()),
        [(first, _), rest @ ..] => {
            for (_, ty) in rest {
                errors.push(syn::Error::new_spanned(
                    ty,
                    format!(
                        "only one model constant may be `usize`: it is the dimension (here `{first}`); the other constants are `f64`"
                    ),
                ));
            }
            Some((*first).clone())
        }
    }
}

/// Whether `ty` is `usize`.
fn is_usize(ty: &Type) -> bool {
    matches!(ty, Type::Path(tp) if tp.qself.is_none() && tp.path.is_ident("usize"))
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

/// Whether `ty` is `f64`, possibly parenthesised.
pub fn is_f64(ty: &Type) -> bool {
    match ty {
        Type::Path(tp) => tp.qself.is_none() && tp.path.is_ident("f64"),
        Type::Paren(p) => is_f64(&p.elem),
        Type::Group(g) => is_f64(&g.elem),
        _ => false,
    }
}

/// The shape of `x` or `v`, with the error if the type is not `f64` or `[f64; D]` (the shape
/// is then the closest guess, so that the body can still be checked).
fn state_type(ty: &Type) -> (Shape, Option<syn::Error>) {
    if is_f64(ty) {
        return (Shape::Scalar, None);
    }
    if let Type::Reference(r) = ty
        && let Type::Slice(slice) = &*r.elem
    {
        let err = if r.mutability.is_some() {
            Some(syn::Error::new_spanned(
                r.mutability,
                "`x` and `v` are read only: `&[f64]`",
            ))
        } else if !is_f64(&slice.elem) {
            Some(syn::Error::new_spanned(
                &slice.elem,
                "the state slices must hold `f64`: `&[f64]`",
            ))
        } else {
            None
        };
        return (Shape::Slice, err);
    }
    if let Type::Array(arr) = ty {
        let elem = (!is_f64(&arr.elem))
            .then(|| syn::Error::new_spanned(&arr.elem, "the state arrays must hold `f64`"));
        let rejected = |e| (Shape::Array(Length::Rejected), Some(e));
        // A length passed through a `macro_rules!` fragment (`[f64; $n]`) arrives grouped.
        let len = match &arr.len {
            Expr::Group(g) => &*g.expr,
            other => other,
        };
        if let Expr::Lit(syn::ExprLit {
            lit: Lit::Int(n), ..
        }) = len
        {
            return match n.base10_parse::<usize>() {
                Ok(0) => rejected(syn::Error::new_spanned(
                    n,
                    "the dimension must be at least 1",
                )),
                Ok(d) => (Shape::Array(Length::Known(d)), elem),
                Err(e) => rejected(e),
            };
        }
        if let Expr::Path(p) = len
            && p.qself.is_none()
            && p.path.get_ident().is_some()
        {
            return (Shape::Array(Length::Named), elem);
        }
        return rejected(syn::Error::new_spanned(
            &arr.len,
            "the dimension must be an integer literal or the name of a `const`, e.g. `[f64; 2]` or `[f64; N]`",
        ));
    }
    (
        Shape::Scalar,
        Some(syn::Error::new_spanned(
            ty,
            format!("`x` and `v` must be `f64`, `[f64; D]` or `&[f64]`; {SIGNATURE}"),
        )),
    )
}
