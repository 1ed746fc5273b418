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
//! On error, [`fallback`] replaces the output.

use proc_macro2::TokenStream;

use crate::{cse, diff, emit, fallback, parse, text};

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
    let mut model = match parse::parse(args, item.clone()) {
        Ok(model) => model,
        Err(errors) => return Err(Rejected { item, errors }),
    };
    let derivatives = diff::differentiate(&mut model.graph, model.root, model.dim);
    let plans = cse::plan(&model.graph, model.root, &derivatives);
    let text = text::derivatives_text(&model, &derivatives);
    Ok(emit::emit(&model, &derivatives, &plans, &text))
}
