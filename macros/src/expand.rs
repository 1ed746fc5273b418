//! The pipeline on `proc_macro2` tokens (so that it can be unit-tested): parse → differentiate →
//! simplify (during construction) → CSE → code.

use proc_macro2::TokenStream;

use crate::{codegen, parse};

/// Expands `#[lagrangian(args)] item`. Errors are spanned on the offending tokens.
pub fn expand(args: TokenStream, item: TokenStream) -> syn::Result<TokenStream> {
    let mut model = parse::parse(args, item)?;
    Ok(codegen::emit(&mut model))
}
