//! The impls of a `#[force]` with loops (a named dimension `[f64; N]`, or slices with a
//! `usize` constant `n`): the loop nests of [`scatter`](crate::scatter) over the terms of its
//! virtual work ([`assemble_force`](crate::assemble::assemble_force)), adding each term's
//! force components into `f` and its Jacobian entries into `jx`, `jv` (dense, `Force<N>`) or
//! into core's `SparseForceJacobian` (`DynForce`). A named dimension gets both impls, slices
//! `DynForce` alone, with the index checks of a run-time dimension made by its
//! `invalid_dimension` ([`checks`](crate::checks)).

use proc_macro2::{Literal, TokenStream};
use quote::quote;

use crate::assemble::{ForceAssembly, Term};
use crate::emit::{constants, dependence_value, head, method_on, private};
use crate::ir::{Model, Node, Var};
use crate::scatter::{Loops, Style, Target, force_bandwidth};

/// The force's components a term adds.
fn force_out(t: &Term) -> Vec<(Target, crate::ir::Id)> {
    t.gradient
        .iter()
        .map(|&(u, id)| (Target::Gradient(u), id))
        .collect()
}

/// The Jacobian entries a term adds.
fn jacobian_out(t: &Term) -> Vec<(Target, crate::ir::Id)> {
    t.hessian
        .iter()
        .map(|e| (Target::Hessian(e.block, e.row, e.col), e.id))
        .collect()
}

/// The user's fn, the struct with its `DERIVATIVES`, and the force's impls.
pub fn emit(
    model: &Model,
    force: &ForceAssembly,
    loops: &Loops<'_>,
    text: &str,
    with_item: bool,
) -> TokenStream {
    let strukt = &model.struct_name;
    let names = &loops.names;
    let dim = &names.dim;
    let dependence = {
        let ty = private("ForceDependence");
        let (x, v) = (
            dependence_value(&force.dependence[0]),
            dependence_value(&force.dependence[1]),
        );
        quote! {
            #[inline]
            fn jacobian_dependence(&self) -> #ty {
                #ty { x: #x, v: #v }
            }
        }
    };
    let constants = constants(&model.consts);
    let (force_code, force_used) = loops.body(&force_out, Style::Dense);
    let f_mut = if force_used[1] { quote!(mut) } else { quote!() };
    let (dense_jacobian, used) = loops.body(&jacobian_out, Style::Dense);
    let (jx_mut, jv_mut) = (
        if used[3] { quote!(mut) } else { quote!() },
        if used[4] { quote!(mut) } else { quote!() },
    );

    let const_impl = if model.runtime_dim.is_none() {
        let (vector, matrix) = (private("Vector"), private("Matrix"));
        let vector_ty = quote!(#vector<#dim>);
        let force_m = method_on(
            quote!(force),
            vector_ty.clone(),
            quote!(let #f_mut f = #vector::<#dim>::zeros(); #force_code f),
            &vector_ty,
        );
        let jac_ty = private("ForceJacobian");
        let jacobian = method_on(
            quote!(jacobian),
            quote!(#jac_ty<#dim>),
            quote! {
                let #jx_mut jx = #matrix::<#dim>::zeros();
                let #jv_mut jv = #matrix::<#dim>::zeros();
                #dense_jacobian
                #jac_ty { x: jx, v: jv }
            },
            &vector_ty,
        );
        let trait_ = private("Force");
        // A literal component `f[k]` of a named dimension `N` is checked when `N` is known.
        let largest = (0..model.graph.len())
            .filter_map(|id| match model.graph.node(id) {
                Node::Var(Var::X(k) | Var::V(k) | Var::F(k)) => Some(k),
                _ => None,
            })
            .max();
        let bounds = match largest {
            Some(k) => {
                let msg = format!(
                    "#[force] fn `{}` reads or adds to component {k}: its dimension must be at least {}",
                    model.item.sig.ident,
                    k + 1
                );
                let k = Literal::usize_unsuffixed(k);
                quote!(
                    const _: () = ::core::assert!(#k < #dim, #msg);
                )
            }
            None => quote!(),
        };
        let checks = names.bounds(model);
        quote! {
            impl #trait_<#dim> for #strukt {
                #force_m
                #jacobian
                #dependence
                #constants
            }
            #bounds
            #checks
        }
    } else {
        quote!()
    };

    let dyn_impl = {
        let (code, _) = loops.body(&force_out, Style::Dense);
        let (sparse, used) = loops.body(&jacobian_out, Style::Sparse);
        // The blocks held open for the loop's entries, as the Hessian's (`dynamic`).
        let (out, writer) = if used[3] || used[4] {
            (quote!(out), quote!(let mut out = out.writer();))
        } else {
            (quote!(_out), quote!())
        };
        let on_slices = |name: TokenStream, body: TokenStream, output: TokenStream| {
            let t = crate::emit::param(&body, "t");
            let (x, v) = (
                crate::emit::param(&body, "x"),
                crate::emit::param(&body, "v"),
            );
            quote! {
                #[inline]
                fn #name(&self, #x: &[f64], #v: &[f64], #t: f64, #output) {
                    #body
                }
            }
        };
        let check = quote! {
            ::core::debug_assert_eq!(x.len(), #dim);
            ::core::debug_assert_eq!(v.len(), #dim);
        };
        let add_force = on_slices(
            quote!(add_force),
            quote!(#check ::core::debug_assert_eq!(f.len(), #dim); #code),
            quote!(f: &mut [f64]),
        );
        let sparse_ty = private("SparseForceJacobian");
        let jacobian = on_slices(
            quote!(jacobian),
            quote!(#check #writer #sparse),
            quote!(#out: &mut #sparse_ty),
        );
        let band = match force_bandwidth(&loops.assembly().terms) {
            Some(b) => {
                let b = Literal::usize_unsuffixed(b);
                quote!(::core::option::Option::Some(#b))
            }
            None => quote!(::core::option::Option::None),
        };
        let index_checks = if model.runtime_dim.is_some() {
            crate::checks::index_checks(model, names)
        } else {
            quote!(::core::option::Option::None)
        };
        let trait_ = private("DynForce");
        quote! {
            impl #trait_ for #strukt {
                #add_force
                #jacobian
                #dependence
                #constants
                fn invalid_dimension(&self, d: usize) -> ::core::option::Option<::std::string::String> {
                    if d != #dim {
                        return ::core::option::Option::Some(::std::format!(
                            "the force has dimension {}, the model it acts on {}", #dim, d
                        ));
                    }
                    #index_checks
                }
                #[inline]
                fn bandwidth(&self) -> ::core::option::Option<usize> {
                    #band
                }
            }
        }
    };
    let head = head(model, text, with_item);
    quote!(#head #const_impl #dyn_impl)
}
