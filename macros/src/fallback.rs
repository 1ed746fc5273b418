//! What is emitted when the fn cannot be turned into a Lagrangian: the errors as
//! `compile_error!`s, and the user's item untouched, so that the only errors the user sees are
//! ours (no cascade of "cannot find type `Pendulum`"-style secondary errors about the fn).

use proc_macro2::TokenStream;
use quote::quote;

/// `compile_error!`s for `err`, followed by `item` unchanged.
pub fn emit(item: TokenStream, err: &syn::Error) -> TokenStream {
    let errors = err.to_compile_error();
    quote!(#errors #item)
}
