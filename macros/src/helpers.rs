//! Helper fns: `#[lagrangian(helper)] fn spring(d: f64, k: f64) -> f64 { … }`, callable from a
//! `#[lagrangian]` fn in the same module and differentiated through.
//!
//! A proc macro sees only the item it is applied to, so the helper's body reaches the
//! Lagrangian by a relay. `#[lagrangian(helper)]` keeps the fn and defines a hidden
//! `macro_rules!` named after it, which hands the fn's tokens on to whoever invokes it. A
//! `#[lagrangian]` fn that calls `spring(…)` keeps its own fn and expands to that macro, which
//! adds the helper and calls back `__private::lagrangian_helpers!`; once every helper called
//! (also from helpers) has been gathered, that expands the Lagrangian with their bodies. The
//! relay macro is made path-scoped by a `use`, so the helper may be written before or after
//! the Lagrangian.
//!
//! A fn that is not marked has no relay, and rustc's error names the macro it cannot find; so
//! the relay's name is the instruction, `mark_spring_with_lagrangian_helper`. A fallback relay
//! with a `compile_error!` cannot be given: the real relay reaches a Lagrangian in another
//! module through the user's glob import (`use super::*;`), and a second glob (or a glob in an
//! inner scope) that supplied a fallback would make the name ambiguous where the helper exists.

use std::collections::BTreeSet;

use proc_macro2::{Delimiter, Group, Ident, TokenStream, TokenTree};
use quote::{format_ident, quote, quote_spanned};
use syn::{FnArg, ItemFn, Pat, ReturnType};

use crate::parse::signature::is_f64;

/// The name of the relay macro of helper `name`: what a call of an unmarked fn reports as the
/// macro it cannot find, so it says what to do.
fn relay(name: &Ident) -> Ident {
    format_ident!("mark_{}_with_lagrangian_helper", name, span = name.span())
}

/// Whether the attribute arguments are `helper`.
pub fn is_helper(args: &TokenStream) -> bool {
    let mut it = args.clone().into_iter();
    matches!((it.next(), it.next()), (Some(TokenTree::Ident(i)), None) if i == "helper")
}

/// `#[lagrangian(helper)] fn …`: the fn, checked, and its relay macro.
pub fn define(item: TokenStream) -> TokenStream {
    let f: ItemFn = match syn::parse2(item.clone()) {
        Ok(f) => f,
        Err(e) => {
            let e = e.to_compile_error();
            return quote!(#e #item);
        }
    };
    let errors = check(&f).map(|e| e.to_compile_error());
    let name = &f.sig.ident;
    let relay = relay(name);
    let mut plain = f.clone();
    plain.attrs.retain(|a| !a.path().is_ident("doc"));
    quote! {
        #errors
        #item
        #[doc(hidden)]
        #[allow(unused_macros)]
        macro_rules! #relay {
            ([$($done:tt)*] $($rest:tt)*) => {
                ::varembed::__private::lagrangian_helpers! { [$($done)* #plain] $($rest)* }
            };
        }
        #[doc(hidden)]
        #[allow(unused_imports)]
        pub(crate) use #relay;
    }
}

/// The errors of a helper: its signature must be `fn name(a: f64, …) -> R` with `R` one of
/// `f64`, `(f64, …)`, `[f64; K]`, and its body what a Lagrangian's body may be, ending with
/// what `R` says.
fn check(f: &ItemFn) -> Option<syn::Error> {
    let mut errors = Vec::new();
    let sig = &f.sig;
    if !sig.generics.params.is_empty() {
        errors.push(syn::Error::new_spanned(
            &sig.generics,
            "a helper cannot be generic",
        ));
    }
    let mut params = Vec::new();
    for arg in &sig.inputs {
        match arg {
            FnArg::Typed(pt) if is_f64(&pt.ty) => match &*pt.pat {
                Pat::Ident(pi) => params.push(pi.ident.clone()),
                other => errors.push(syn::Error::new_spanned(
                    other,
                    "a helper's parameters are plain names",
                )),
            },
            FnArg::Typed(pt) => errors.push(syn::Error::new_spanned(
                &pt.ty,
                "a helper's parameters are `f64`",
            )),
            FnArg::Receiver(r) => {
                errors.push(syn::Error::new_spanned(r, "a helper cannot take `self`"))
            }
        }
    }
    let returns = crate::parse::returns(&sig.output);
    if returns.is_none() {
        let msg = "a helper returns `f64`, a tuple `(f64, f64, …)` or an array `[f64; K]` (`K` an integer literal)";
        errors.push(match &sig.output {
            ReturnType::Type(_, ty) => syn::Error::new_spanned(ty, msg),
            ReturnType::Default => syn::Error::new_spanned(&sig.ident, msg),
        });
    }
    errors.extend(crate::parse::check_helper_body(f, &params, returns));
    let mut it = errors.into_iter();
    let mut first = it.next()?;
    for e in it {
        first.combine(e);
    }
    Some(first)
}

/// The plain fns `item` calls (`name(…)`, not methods, paths or macros), in order of name.
fn calls(tokens: TokenStream, out: &mut BTreeSet<Ident>) {
    const KEYWORDS: [&str; 10] = [
        "if", "while", "match", "in", "return", "for", "let", "as", "else", "mut",
    ];
    let tokens: Vec<TokenTree> = tokens.into_iter().collect();
    for (k, tt) in tokens.iter().enumerate() {
        if let TokenTree::Group(g) = tt {
            if let (Some(TokenTree::Ident(name)), Delimiter::Parenthesis) =
                (k.checked_sub(1).map(|j| &tokens[j]), g.delimiter())
            {
                let before = k.checked_sub(2).map(|j| &tokens[j]);
                let qualified = matches!(before, Some(TokenTree::Punct(p)) if p.as_char() == '.' || p.as_char() == ':');
                let s = name.to_string();
                if !qualified && !KEYWORDS.contains(&s.as_str()) && s != "f64" {
                    out.insert(name.clone());
                }
            }
            calls(g.stream(), out);
        }
    }
}

/// The helper fns called by `item` and by `helpers`, that `helpers` does not define.
fn missing(item: &ItemFn, helpers: &[ItemFn]) -> Vec<Ident> {
    let mut called = BTreeSet::new();
    calls(quote::ToTokens::to_token_stream(&item.block), &mut called);
    for h in helpers {
        calls(quote::ToTokens::to_token_stream(&h.block), &mut called);
    }
    called
        .into_iter()
        .filter(|c| !helpers.iter().any(|h| h.sig.ident == *c))
        .collect()
}

/// If `item` calls helpers, the relay that gathers them (the fn is kept, so that a helper
/// that is not marked is one error, not one more for every use of the fn).
pub fn start(args: &TokenStream, item: &TokenStream) -> Option<TokenStream> {
    let f: ItemFn = syn::parse2(item.clone()).ok()?;
    let first = missing(&f, &[]).into_iter().next()?;
    let relay = relay(&first);
    Some(quote_spanned! {first.span()=>
        #[allow(dead_code)]
        #item
        #relay! { [] (#args) #item }
    })
}

/// `lagrangian_helpers! { [helpers…] (args) item }`: the next relay, or the expansion once
/// every helper is there. The fn itself was kept by [`start`].
pub fn gather(input: TokenStream) -> Result<(TokenStream, TokenStream, Vec<ItemFn>), TokenStream> {
    let mut it = input.into_iter();
    let (Some(TokenTree::Group(done)), Some(TokenTree::Group(args))) = (it.next(), it.next())
    else {
        return Err(quote!(::core::compile_error!("malformed helper relay");));
    };
    let item: TokenStream = it.collect();
    let helpers: Vec<ItemFn> = syn::parse2::<syn::File>(done.stream())
        .map(|f| {
            f.items
                .into_iter()
                .filter_map(|i| match i {
                    syn::Item::Fn(f) => Some(f),
                    _ => None,
                })
                .collect()
        })
        .unwrap_or_default();
    let f: ItemFn = syn::parse2(item.clone()).map_err(|e| e.to_compile_error())?;
    if let Some(next) = missing(&f, &helpers).into_iter().next() {
        let relay = relay(&next);
        let done = Group::new(Delimiter::Bracket, done.stream());
        return Err(quote_spanned! {next.span()=> #relay! { #done #args #item }});
    }
    Ok((args.stream(), item, helpers))
}
