//! `#[lagrangian]`: compile-time symbolic differentiation of a Lagrangian (see issue 3).

use proc_macro::TokenStream;

/// Placeholder entry point until the macro pipeline lands: returns the item unchanged.
#[proc_macro_attribute]
pub fn lagrangian(_args: TokenStream, item: TokenStream) -> TokenStream {
    item
}
