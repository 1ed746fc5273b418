//! The pipeline, on `proc_macro2` tokens so that it can be unit-tested. Each stage is one
//! function from one typed value to the next:
//!
//! | stage | function | input → output |
//! | --- | --- | --- |
//! | parse (simplifying as it builds) | [`parse::parse_with_helpers`] | tokens → [`Model`] |
//! | differentiate | [`diff::differentiate`] | graph, `L` → [`Derivatives`](crate::ir::Derivatives) |
//! | CSE | [`cse::plan`] | graph, `L`, derivatives → [`Plans`](crate::cse::Plans) |
//! | text | [`text::derivatives_text`] | model, derivatives → `String` |
//! | emit | [`emit::emit`] | model, derivatives, plans, text → tokens |
//!
//! A Lagrangian with loops (or a named dimension) takes the loop path instead: [`assemble`]
//! (its terms and their derivatives), [`text::loops_text`], [`loop_impl::emit`] (loops that add
//! each term's derivatives into their entries, with scoped temporaries: the `Lagrangian<N>`
//! impl) and [`dynamic::emit`] (the same loops on slices: the `DynLagrangian` impl, alone for a
//! run-time dimension `x: &[f64]`, `n: usize`). A `#[force]` or `#[constraint]` fn takes
//! [`vector::emit`] after the parse (its components differentiated by the same
//! [`diff::jacobian`]). Helper fns are gathered first ([`helpers`]). On error, [`fallback`]
//! replaces the output.

use proc_macro2::TokenStream;

use crate::ir::{Attr, Model, Node, Var};
use crate::{
    assemble, cse, diff, dynamic, emit, fallback, helpers, loop_impl, looped_force, parse, scatter,
    text, vector,
};

/// The errors of a rejected fn, with the fn's tokens, which the fallback output keeps.
#[derive(Debug)]
pub struct Rejected {
    item: TokenStream,
    errors: syn::Error,
}

impl Rejected {
    /// What the macro emits instead of the expansion: the errors, then the fn untouched.
    pub fn into_tokens(self) -> TokenStream {
        fallback::emit(self.item, &self.errors)
    }
}

/// Expands `#[lagrangian(args)] item`. Errors are spanned on the offending tokens.
pub fn expand(args: TokenStream, item: TokenStream) -> Result<TokenStream, Rejected> {
    expand_as(Attr::Lagrangian, args, item)
}

/// Expands `item` under the attribute `attr` with the arguments `args`.
pub fn expand_as(
    attr: Attr,
    args: TokenStream,
    item: TokenStream,
) -> Result<TokenStream, Rejected> {
    if attr == Attr::Lagrangian && helpers::is_helper(&args) {
        return Ok(helpers::define(item));
    }
    // The relay hands the arguments back: a force's or constraint's carry its attribute.
    if let Some(relay) = helpers::start(&marked(attr, args.clone()), &item) {
        return Ok(relay);
    }
    expand_with(attr, args, item, Vec::new(), true)
}

/// The marker a vector-valued fn's arguments carry through the helper relay.
fn marker(attr: Attr) -> Option<&'static str> {
    match attr {
        Attr::Lagrangian => None,
        Attr::Force => Some("__varembed_force"),
        Attr::Constraint => Some("__varembed_constraint"),
    }
}

/// `args` with the marker of `attr` in front.
fn marked(attr: Attr, args: TokenStream) -> TokenStream {
    match marker(attr) {
        Some(m) => {
            let m = proc_macro2::Ident::new(m, proc_macro2::Span::call_site());
            quote::quote!(#m #args)
        }
        None => args,
    }
}

/// The attribute of relayed arguments, and the arguments without its marker.
fn unmarked(args: TokenStream) -> (Attr, TokenStream) {
    let mut it = args.clone().into_iter();
    if let Some(proc_macro2::TokenTree::Ident(first)) = it.next() {
        for attr in [Attr::Force, Attr::Constraint] {
            if marker(attr).is_some_and(|m| first == m) {
                return (attr, it.collect());
            }
        }
    }
    (Attr::Lagrangian, args)
}

/// `lagrangian_helpers! { … }`: the next helper relay, or the expansion with the helpers.
pub fn expand_gathered(input: TokenStream) -> TokenStream {
    match helpers::gather(input) {
        Ok((args, item, helpers)) => {
            let (attr, args) = unmarked(args);
            expand_with(attr, args, item, helpers, false)
                .unwrap_or_else(|r| r.errors.to_compile_error())
        }
        Err(next) => next,
    }
}

/// Expands `item` with the helper fns `helpers`; `with_item`: emit the fn itself too.
fn expand_with(
    attr: Attr,
    args: TokenStream,
    item: TokenStream,
    helpers: Vec<syn::ItemFn>,
    with_item: bool,
) -> Result<TokenStream, Rejected> {
    let mut model = match parse::parse_with_helpers(attr, args, item.clone(), helpers) {
        Ok(model) => model,
        Err(errors) => return Err(Rejected { item, errors }),
    };
    let looped = model.dim_name.is_some() || model.runtime_dim.is_some();
    let out = if attr == Attr::Force && looped {
        let force = match assemble::assemble_force(&mut model.graph, model.root) {
            Ok(f) => f,
            Err(msg) => {
                let errors = syn::Error::new_spanned(&model.item.sig.ident, msg);
                return Err(Rejected { item, errors });
            }
        };
        let text = text::loops_text(&model, &force.assembly);
        let loops = scatter::Loops::new(&model, &force.assembly);
        looped_force::emit(&model, &force, &loops, &text, with_item)
    } else if attr != Attr::Lagrangian {
        vector::emit(&mut model, with_item)
    } else if has_loops(&model) {
        let assembly = match assemble::assemble(&mut model.graph, model.root) {
            Ok(a) => a,
            Err(msg) => {
                let errors = syn::Error::new_spanned(&model.item.sig.ident, msg);
                return Err(Rejected { item, errors });
            }
        };
        let text = text::loops_text(&model, &assembly);
        let loops = scatter::Loops::new(&model, &assembly);
        let properties = emit::properties(
            &model,
            (
                &assembly.hessian_dependence,
                &assembly.dependence,
                scatter::bandwidth(&assembly),
            ),
        );
        let dynamic = dynamic::emit(&model, &loops, &properties);
        let lagrangian = if model.runtime_dim.is_some() {
            // A run-time dimension: `DynLagrangian` only.
            emit::head(&model, &text, with_item)
        } else {
            loop_impl::emit(&model, &loops, &properties, &text, with_item)
        };
        quote::quote!(#lagrangian #dynamic)
    } else {
        let derivatives = diff::differentiate(&mut model.graph, model.root, model.dim);
        let plans = cse::plan(&model.graph, model.root, &derivatives);
        let text = text::derivatives_text(&model, &derivatives);
        emit::emit(&model, &derivatives, &plans, &text, with_item)
    };
    Ok(out)
}

/// Whether the model takes the loop path: a named dimension, a sum, or an index or number
/// that names a const the macro does not know (`x[M]`, `M as f64`). A sum counts even when a
/// constant condition folded it out of `L` (`if v[1] - v[1] > 0.1 { s } else { … }`), so that
/// such a model implements `DynLagrangian` as the others with loops do. (A sum whose body
/// folds to zero, or that the parser unrolls, leaves no `Sum` node: such a model takes the
/// loop-free path.)
fn has_loops(model: &Model) -> bool {
    model.dim_name.is_some()
        || model.runtime_dim.is_some()
        || model.graph.has_sum()
        || model.graph.reachable(&[model.root]).into_iter().any(|id| {
            matches!(
                model.graph.node(id),
                Node::Sum(..) | Node::Var(Var::XAt(_) | Var::VAt(_) | Var::Sym(_))
            )
        })
}
