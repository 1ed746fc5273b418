//! The `DynLagrangian` impl of a model with loops: the same loop nests as its
//! `Lagrangian<N>` impl ([`scatter`](crate::scatter)), on slices, writing the gradient into the
//! caller's buffers and the second derivatives as the entries of core's `SparseHessian`
//! (`out.xx.add(i, j, e)`, the mirrored entries of the symmetric blocks included). A model
//! with a named dimension `[f64; N]` gets it next to its `Lagrangian<N>` impl; a model of
//! slices `x: &[f64]` whose length is a `usize` model constant gets it alone, with the index
//! checks that a named dimension leaves to the compiler made at run time
//! ([`checks`](crate::checks)).

use proc_macro2::TokenStream;
use quote::quote;

use crate::emit::{param, private};
use crate::ir::{Id, Model, Var};
use crate::lifted::Lifted;
use crate::scatter::{Loops, Style, Target, gradient_out, hessian_out, value_out};

/// `impl DynLagrangian for Name { … }`, its model constants (`properties`) as in the
/// `Lagrangian<N>` impl.
pub fn emit(model: &Model, loops: &Loops<'_>, properties: &TokenStream) -> TokenStream {
    let name = &model.struct_name;
    let dim = &loops.names.dim;
    let dyn_lagrangian = private("DynLagrangian");
    let sparse = private("SparseHessian");
    let check = quote! {
        ::core::debug_assert_eq!(x.len(), #dim);
        ::core::debug_assert_eq!(v.len(), #dim);
    };

    let lifted = Lifted::new(loops, Style::Sparse, quote!(::std::vec![0.0; #dim]));
    let (values, adjoints) = (lifted.values(), lifted.adjoints());
    let (dense, dense_used) = lifted.dense_part();

    let (code, _) = loops.body(&value_out, Style::Dense);
    let value = method(
        quote!(value),
        quote!(-> f64),
        quote!(#check #values let mut value = 0.0; #code value),
        None,
    );

    let state = |x: bool| {
        move |t: &crate::assemble::Term| -> Vec<(Target, Id)> {
            gradient_out(t)
                .into_iter()
                .filter(|(target, _)| match target {
                    Target::Gradient(Var::X(_) | Var::XAt(_)) => x,
                    _ => !x,
                })
                .collect()
        }
    };
    let (code, _) = loops.body(&state(true), Style::Dense);
    let force = method(
        quote!(force),
        quote!(),
        quote!(#check ::core::debug_assert_eq!(fx.len(), #dim); fx.fill(0.0); #values #adjoints #code),
        Some(quote!(fx: &mut [f64])),
    );
    let (code, _) = loops.body(&state(false), Style::Dense);
    let momentum = method(
        quote!(momentum),
        quote!(),
        quote!(#check ::core::debug_assert_eq!(fv.len(), #dim); fv.fill(0.0); #values #adjoints #code),
        Some(quote!(fv: &mut [f64])),
    );

    let (code, used) = loops.body(&hessian_out, Style::Sparse);
    // The blocks held open for the loop's entries (`SparseHessian::writer`): the same
    // `out.xx.add(i, j, e)`, without reloading each block's fields after every write.
    let (out, writer) = if used[3..].iter().chain(&dense_used).any(|&u| u) {
        (quote!(out), quote!(let mut out = out.writer();))
    } else {
        (quote!(_out), quote!())
    };
    let hessian = method(
        quote!(hessian),
        quote!(),
        quote!(#check #writer #values #adjoints #code #dense),
        Some(quote!(#out: &mut #sparse)),
    );

    let invalid = if model.runtime_dim.is_some() {
        crate::checks::invalid_dimension(model, &loops.names)
    } else {
        quote!()
    };
    quote! {
        impl #dyn_lagrangian for #name {
            #[inline]
            fn dimension(&self) -> usize {
                #dim
            }
            #value
            #force
            #momentum
            #hessian
            #properties
            #invalid
        }
    }
}

/// A method on a point `(x, v, t)` of slices, with an optional output parameter; `t` is
/// named `_t` when the body does not read it.
fn method(
    name: TokenStream,
    ret: TokenStream,
    body: TokenStream,
    output: Option<TokenStream>,
) -> TokenStream {
    let t = param(&body, "t");
    let output = output.map(|o| quote!(, #o));
    quote! {
        #[inline]
        fn #name(&self, x: &[f64], v: &[f64], #t: f64 #output) #ret {
            #body
        }
    }
}
