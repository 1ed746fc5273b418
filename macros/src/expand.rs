//! The pipeline, on `proc_macro2` tokens so that it can be unit-tested. Each stage is one
//! function from one typed value to the next:
//!
//! | stage | function | input → output |
//! | --- | --- | --- |
//! | parse (simplifying as it builds) | [`parse::parse`] | tokens → [`Model`](crate::ir::Model) |
//! | differentiate | [`diff::differentiate`] | graph, `L` → [`Derivatives`](crate::ir::Derivatives) |
//! | CSE | [`cse::plan`] | graph, `L`, derivatives → [`Plans`](crate::cse::Plans) |
//! | text | [`text::derivatives_text`] | model, derivatives → `String` |
//! | emit | [`emit::emit`] | model, derivatives, plans, text → tokens |
//!
//! A Lagrangian with loops (or a named dimension) takes the loop path instead: [`assemble`]
//! (its terms and their derivatives), [`text::loops_text`], [`scatter::emit`] (loops that add
//! each term's derivatives into their entries, with scoped temporaries: the `Lagrangian<N>`
//! impl) and [`dynamic::emit`] (the same loops on slices: the `DynLagrangian` impl, alone for a
//! run-time dimension `x: &[f64]`, `n: usize`). Helper fns are
//! gathered first ([`helpers`]). On error, [`fallback`] replaces the output.

use proc_macro2::TokenStream;

use crate::ir::{Model, Node, Var};
use crate::{
    assemble, cse, diff, dynamic, emit, fallback, helpers, loop_impl, parse, scatter, text,
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
    if helpers::is_helper(&args) {
        return Ok(helpers::define(item));
    }
    if let Some(relay) = helpers::start(&args, &item) {
        return Ok(relay);
    }
    expand_with(args, item, Vec::new(), true)
}

/// `lagrangian_helpers! { … }`: the next helper relay, or the expansion with the helpers.
pub fn expand_gathered(input: TokenStream) -> TokenStream {
    match helpers::gather(input) {
        Ok((args, item, helpers)) => {
            expand_with(args, item, helpers, false).unwrap_or_else(|r| r.errors.to_compile_error())
        }
        Err(next) => next,
    }
}

/// Expands `item` with the helper fns `helpers`; `with_item`: emit the fn itself too.
fn expand_with(
    args: TokenStream,
    item: TokenStream,
    helpers: Vec<syn::ItemFn>,
    with_item: bool,
) -> Result<TokenStream, Rejected> {
    let mut model = match parse::parse_with_helpers(args, item.clone(), helpers) {
        Ok(model) => model,
        Err(errors) => return Err(Rejected { item, errors }),
    };
    let out = if has_loops(&model) {
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
/// that names a const the macro does not know (`x[M]`, `M as f64`).
fn has_loops(model: &Model) -> bool {
    model.dim_name.is_some()
        || model.runtime_dim.is_some()
        || model.graph.reachable(&[model.root]).into_iter().any(|id| {
            matches!(
                model.graph.node(id),
                Node::Sum(..) | Node::Var(Var::XAt(_) | Var::VAt(_) | Var::Sym(_))
            )
        })
}
