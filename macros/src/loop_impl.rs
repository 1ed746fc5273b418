//! The `Lagrangian<N>` impl of a model with loops: each method the loop nests of
//! [`scatter`](crate::scatter) in the dense style, around the values, adjoints and dense part
//! of the model's lifted sums ([`lifted`](crate::lifted)).

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

use crate::assemble::Term;
use crate::emit::{method_on, private, shell};
use crate::ir::{Id, Model, Node, Var};
use crate::lifted::Lifted;
use crate::scatter::{Loops, Style, Target, gradient_out, hessian_out, value_out};

/// The user's fn, the struct and the `Lagrangian<N>` impl of a model with loops of a named
/// (or literal) dimension, with the model's `properties`.
pub fn emit(
    model: &Model,
    loops: &Loops<'_>,
    properties: &TokenStream,
    text: &str,
    with_item: bool,
) -> TokenStream {
    let g = &model.graph;
    let names = &loops.names;
    let dim = names.dim.clone();
    let vector = {
        let v = private("Vector");
        quote!(#v<#dim>)
    };
    let hessian_ty = {
        let h = private("Hessian");
        quote!(#h<#dim>)
    };
    let both_out = |t: &Term| {
        let mut out = gradient_out(t);
        out.extend(hessian_out(t));
        out
    };
    let value_gradient_out = |t: &Term| {
        let mut out = value_out(t);
        out.extend(gradient_out(t));
        out
    };
    let body = |pick: &dyn Fn(&Term) -> Vec<(Target, Id)>| loops.body(pick, Style::Dense);
    let [fx, fv, xx, xv, vv] =
        ["fx", "fv", "xx", "xv", "vv"].map(|n| Ident::new(n, Span::call_site()));
    let (vec_expr, mat_expr) = {
        let (v, m) = (private("Vector"), private("Matrix"));
        (quote!(#v::<#dim>), quote!(#m::<#dim>))
    };
    let decl = |name: &Ident, used: bool, zeros: &TokenStream| {
        if used {
            quote!(let mut #name = #zeros::zeros();)
        } else {
            quote!(let #name = #zeros::zeros();)
        }
    };
    let gradient_decls = |used: &[bool; 6]| {
        let (a, b) = (decl(&fx, used[1], &vec_expr), decl(&fv, used[2], &vec_expr));
        quote!(#a #b)
    };
    let hessian_decls = |used: &[bool; 6]| {
        let (a, b, c) = (
            decl(&xx, used[3], &mat_expr),
            decl(&xv, used[4], &mat_expr),
            decl(&vv, used[5], &mat_expr),
        );
        quote!(#a #b #c)
    };
    let hessian = private("Hessian");
    let lifted = Lifted::new(loops, Style::Dense, quote!(#vec_expr::zeros()));
    let (values, adjoints) = (lifted.values(), lifted.adjoints());
    let (dense, dense_used) = lifted.dense_part();
    let with_dense = |mut used: [bool; 6]| {
        for (u, d) in used[3..].iter_mut().zip(dense_used) {
            *u |= d;
        }
        used
    };

    let (code, _) = body(&value_out);
    let value = method_on(
        quote!(value),
        quote!(f64),
        quote!(#values let mut value = 0.0; #code value),
        &vector,
    );
    let (code, used) = body(&gradient_out);
    let decls = gradient_decls(&used);
    let gradient = method_on(
        quote!(gradient),
        quote!((#vector, #vector)),
        quote!(#values #adjoints #decls #code (#fx, #fv)),
        &vector,
    );
    let (code, used) = body(&value_gradient_out);
    let decls = gradient_decls(&used);
    let value_and_gradient = method_on(
        quote!(value_and_gradient),
        quote!((f64, #vector, #vector)),
        quote!(#values #adjoints let mut value = 0.0; #decls #code (value, #fx, #fv)),
        &vector,
    );
    let (code, used) = body(&hessian_out);
    let decls = hessian_decls(&with_dense(used));
    let hessian_m = method_on(
        quote!(hessian),
        quote!(#hessian_ty),
        quote!(#values #adjoints #decls #code #dense #hessian { #xx, #xv, #vv }),
        &vector,
    );
    let (code, used) = body(&both_out);
    let used = with_dense(used);
    let decls = (gradient_decls(&used), hessian_decls(&used));
    let (gd, hd) = decls;
    let both = method_on(
        quote!(gradient_and_hessian),
        quote!((#vector, #vector, #hessian_ty)),
        quote!(#values #adjoints #gd #hd #code #dense (#fx, #fv, #hessian { #xx, #xv, #vv })),
        &vector,
    );
    // A literal component `x[k]` of a named dimension `N` is checked when `N` is known.
    let largest = (0..g.len())
        .filter_map(|id| match g.node(id) {
            Node::Var(Var::X(k) | Var::V(k)) => Some(k),
            _ => None,
        })
        .max();
    let bounds = match (&model.dim_name, largest) {
        (Some(n), Some(k)) => {
            let msg = format!(
                "#[lagrangian] fn `{}` reads component {k}: its dimension must be at least {}",
                model.item.sig.ident,
                k + 1
            );
            let k = Literal::usize_unsuffixed(k);
            quote!(
                const _: () = ::core::assert!(#k < #n, #msg);
            )
        }
        _ => quote!(),
    };
    // The model implements `DynLagrangian` too (`dynamic::emit`): large runs of `Problem` go
    // to the run-time engine through it.
    let dyn_lagrangian = private("DynLagrangian");
    let run_time = quote! {
        fn run_time(&self) -> ::core::option::Option<&dyn #dyn_lagrangian> {
            ::core::option::Option::Some(self)
        }
    };
    let methods = quote! {
        #value
        #gradient
        #value_and_gradient
        #hessian_m
        #both
        #run_time
    };
    let shell = shell(model, text, dim, methods, properties, with_item);
    let checks = names.bounds(model);
    quote!(#shell #bounds #checks)
}
