//! The parsing stage: `syn::ItemFn` → [`Model`] (the IR). Checks the signature
//! ([`signature`]), then walks the body into the expression DAG ([`body`]), simplifying as it
//! builds. Every unsupported construct becomes a `syn::Error` on its own tokens; all of them
//! are collected and combined, so one mistake does not hide the next.

mod body;
mod branch;
mod expr;
mod index;
mod looped_force;
mod scope;
pub mod signature;
mod values;
mod vector;

use proc_macro2::TokenStream;
use syn::ItemFn;

use crate::ir::{Attr, Model};

/// Parses the attribute arguments and the fn into a [`Model`] (no helper fns).
#[cfg(test)]
pub fn parse(args: TokenStream, item: TokenStream) -> syn::Result<Model> {
    parse_with_helpers(Attr::Lagrangian, args, item, Vec::new())
}

pub use scope::{Returns, returns};

/// The errors in the body of a helper fn with parameters `params`, returning what `returns`
/// says (`None`: a return type already reported, the value it ends with is not checked).
pub fn check_helper_body(
    f: &ItemFn,
    params: &[proc_macro2::Ident],
    returns: Option<Returns>,
) -> Vec<syn::Error> {
    let mut parser = body::Parser::new(Vec::new(), Vec::new());
    parser.helper_body(&f.sig.ident, &f.block, params, returns);
    parser.finish().1
}

/// Parses the fn, for `attr`, with the `#[lagrangian(helper)]` fns it may call.
pub fn parse_with_helpers(
    attr: Attr,
    args: TokenStream,
    item: TokenStream,
    helpers: Vec<ItemFn>,
) -> syn::Result<Model> {
    let item: ItemFn = syn::parse2(item).map_err(|e| {
        syn::Error::new(
            e.span(),
            format!(
                "{e}: {} applies to a `fn`; {}",
                attr.name(),
                signature::expected(attr)
            ),
        )
    })?;
    let mut errors = Vec::new();
    let mut sig = signature::check(&args, &item, attr, &mut errors);
    if attr != Attr::Lagrangian {
        let x_ty = item.sig.inputs.iter().find_map(|arg| match arg {
            syn::FnArg::Typed(pt) => Some(&*pt.ty),
            syn::FnArg::Receiver(_) => None,
        });
        let x_shape = sig.states.first().map_or(signature::Shape::Scalar, |s| s.1);
        let facts = (x_shape, sig.dim, sig.dim_name.as_ref());
        sig.outputs = vector::check_outputs(&item.sig, attr, x_ty, facts, &mut errors);
    }
    let mut parser = body::Parser::new(errors, helpers);
    parser.attr = attr;
    let (root, outputs) = match attr {
        Attr::Lagrangian => (parser.body(&item.block, &sig), Vec::new()),
        // A force with loops is its virtual work, a scalar like `L` (`looped_force.rs`).
        Attr::Force if sig.dim_name.is_some() || sig.runtime_dim.is_some() => {
            parser.looped_force = true;
            let mut env = parser.signature_env(&sig);
            let work = parser.looped_force_body(&item.block, &sig, &mut env);
            (work, Vec::new())
        }
        Attr::Force | Attr::Constraint => {
            let outputs = parser.vector_body(&item.block, &sig, &item.sig.ident);
            (parser.graph.num(0.0), outputs)
        }
    };
    let (graph, errors) = parser.finish();

    let mut errors = errors.into_iter();
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
        attr,
        vis: item.vis.clone(),
        struct_name: sig.struct_name,
        docs,
        dim: sig.dim,
        dim_name: sig.dim_name,
        runtime_dim: sig.runtime_dim,
        scalar: sig.scalar,
        consts: sig.consts,
        graph,
        root,
        outputs,
        item,
    })
}
