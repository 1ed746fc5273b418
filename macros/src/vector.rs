//! The vector-valued path: a `#[force]` fn's components `f(x, v, t)` or a `#[constraint]` fn's
//! `g(x)`, differentiated by [`diff::jacobian`] (the Lagrangian's first derivatives are the same
//! call on one root), planned by [`Plan`] and rendered by [`Render`] like a Lagrangian's
//! methods, into the struct's `Force<D>` or `Constraint<D, M>` impl.
//!
//! A force's Jacobian blocks `∂f/∂x`, `∂f/∂v` are in general not symmetric: every entry is its
//! own derivative. A constraint's second derivatives are symmetric: `Σ_k λ_k ∂²g_k/∂x_i∂x_j` is
//! written once for `i ≤ j` and mirrored.

use proc_macro2::TokenStream;
use quote::quote;

use crate::cse::Plan;
use crate::diff::{self, Differentiator};
use crate::emit::{
    constants, dependence_value, head, index, leaf, matrix, mentions, param, private,
};
use crate::ir::{Attr, Graph, Id, Model, Prec, Var};
use crate::render::Render;
use crate::text;

/// The struct, its `DERIVATIVES` and its `Force<D>` or `Constraint<D, M>` impl.
pub fn emit(model: &mut Model, with_item: bool) -> TokenStream {
    let mut d = Differentiator::new();
    let outputs = model.outputs.clone();
    let g = &mut model.graph;
    let xs = diff::positions(model.dim);
    let dx = diff::jacobian(&mut d, g, &outputs, &xs);
    match model.attr {
        Attr::Force => {
            let dv = diff::jacobian(&mut d, g, &outputs, &diff::velocities(model.dim));
            force(model, &dx, &dv, with_item)
        }
        Attr::Constraint => {
            // `∂²g_k/∂x_i∂x_j` for `i ≤ j`: entry `(k, i, j)` of the list.
            let dim = model.dim;
            let mut second = Vec::new();
            for k in 0..outputs.len() {
                for i in 0..dim {
                    for j in i..dim {
                        second.push(d.diff(g, dx[k * dim + i], Var::X(j)));
                    }
                }
            }
            constraint(model, &dx, &second, with_item)
        }
        Attr::Lagrangian => unreachable!("a Lagrangian takes the scalar path"),
    }
}

/// The nonzero entries of `ids`.
fn nonzero(g: &Graph, ids: &[Id]) -> Vec<Id> {
    ids.iter()
        .copied()
        .filter(|&id| !g.is_num(id, 0.0))
        .collect()
}

/// `Force<D>`: `force`, `jacobian`, `jacobian_dependence`, `constants`.
fn force(model: &Model, dx: &[Id], dv: &[Id], with_item: bool) -> TokenStream {
    let g = &model.graph;
    let dim = model.dim;
    let leaf = leaf(&model.consts);
    let (vector, matrix_ty) = (private("Vector"), private("Matrix"));
    let d = index(dim);

    let plan = Plan::new(g, &model.outputs);
    let r = Render::new(g, &plan, &leaf);
    let (temps, entries) = (r.temps(), model.outputs.iter().map(|&id| r.root(id)));
    let body = quote!(#temps #vector::<#d>::from([#(#entries),*]));
    let force = on_state(quote!(force), quote!(#vector<#d>), body, &vector, &d);

    let roots: Vec<Id> = nonzero(g, dx).into_iter().chain(nonzero(g, dv)).collect();
    let plan = Plan::new(g, &roots);
    let r = Render::new(g, &plan, &leaf);
    let temps = r.temps();
    let zeros = quote!(#matrix_ty::<#d>::zeros());
    let jx = matrix(&r, g, (quote!(jx), zeros.clone()), dx, dim);
    let jv = matrix(&r, g, (quote!(jv), zeros), dv, dim);
    let ty = private("ForceJacobian");
    let body = quote!(#temps #jx #jv #ty { x: jx, v: jv });
    let jacobian = on_state(quote!(jacobian), quote!(#ty<#d>), body, &vector, &d);

    let (on_x, on_v) = (
        dependence_value(&g.dependence(dx)),
        dependence_value(&g.dependence(dv)),
    );
    let dependence = private("ForceDependence");
    let constants = constants(&model.consts);

    let xs = diff::positions(dim);
    let name = |k: usize| text::state_name(model, xs[k]).replacen('x', "f", 1);
    let mut lines: Vec<(String, Id)> = (0..dim).map(|k| (name(k), model.outputs[k])).collect();
    for (block, state) in [(dx, Var::X as fn(usize) -> Var), (dv, Var::V)] {
        for (e, &id) in block.iter().enumerate() {
            if !g.is_num(id, 0.0) {
                let by = text::state_name(model, state(e % dim));
                lines.push((format!("∂{}/∂{by}", name(e / dim)), id));
            }
        }
    }
    let head = head(model, &text::lines_text(model, &lines), with_item);
    let strukt = &model.struct_name;
    let trait_ = private("Force");
    quote! {
        #head

        impl #trait_<#d> for #strukt {
            #force
            #jacobian
            #[inline]
            fn jacobian_dependence(&self) -> #dependence {
                #dependence { x: #on_x, v: #on_v }
            }
            #constants
        }
    }
}

/// `Constraint<D, M>`: `value`, `jacobian`, `weighted_hessian`. `second` lists
/// `∂²g_k/∂x_i∂x_j` for each `k`, then `i ≤ j`.
fn constraint(model: &Model, dx: &[Id], second: &[Id], with_item: bool) -> TokenStream {
    let g = &model.graph;
    let (dim, m) = (model.dim, model.outputs.len());
    let leaf = leaf(&model.consts);
    let matrix_ty = private("Matrix");
    let (svector, smatrix) = (private("SVector"), private("SMatrix"));
    let (d, mm) = (index(dim), index(m));

    let plan = Plan::new(g, &model.outputs);
    let r = Render::new(g, &plan, &leaf);
    let (temps, entries) = (r.temps(), model.outputs.iter().map(|&id| r.root(id)));
    let body = quote!(#temps #svector::<f64, #mm>::from([#(#entries),*]));
    let value = on_x(
        (quote!(value), quote!(#svector<f64, #mm>)),
        body,
        quote!(),
        &d,
    );

    let plan = Plan::new(g, &nonzero(g, dx));
    let r = Render::new(g, &plan, &leaf);
    let temps = r.temps();
    let zeros = quote!(#smatrix::<f64, #mm, #d>::zeros());
    let body = if nonzero(g, dx).is_empty() {
        zeros
    } else {
        let jac = matrix(&r, g, (quote!(jac), zeros), dx, dim);
        quote!(#temps #jac jac)
    };
    let ret = quote!(#smatrix<f64, #mm, #d>);
    let jacobian = on_x((quote!(jacobian), ret), body, quote!(), &d);

    // Entry `(i, j)`, `i ≤ j`: `Σ_k λ_k ∂²g_k/∂x_i∂x_j` over the nonzero second derivatives.
    let pairs: Vec<(usize, usize)> = (0..dim)
        .flat_map(|i| (i..dim).map(move |j| (i, j)))
        .collect();
    let plan = Plan::new(g, &nonzero(g, second));
    let r = Render::new(g, &plan, &leaf);
    let temps = r.temps();
    let sets: Vec<TokenStream> = pairs
        .iter()
        .enumerate()
        .filter_map(|(p, &(i, j))| {
            // `λ_k · e`, with a second derivative of ±1 written as `±λ_k` (what clippy asks
            // of generated code too): each term with the sign it enters the sum with.
            let terms: Vec<(bool, TokenStream)> = (0..m)
                .map(|k| (k, second[k * pairs.len() + p]))
                .filter(|&(_, id)| !g.is_num(id, 0.0))
                .map(|(k, id)| {
                    let k = index(k);
                    match (g.is_num(id, 1.0), g.is_num(id, -1.0)) {
                        (true, _) => (false, quote!(lambda[#k])),
                        (_, true) => (true, quote!(lambda[#k])),
                        _ => {
                            let e = r.wrapped(id, Prec::Neg);
                            (false, quote!(lambda[#k] * #e))
                        }
                    }
                })
                .collect();
            let (first, rest) = terms.split_first()?;
            let first = match first {
                (true, t) => quote!(-#t),
                (false, t) => quote!(#t),
            };
            let rest = rest.iter().map(|(negative, t)| match negative {
                true => quote!(- #t),
                false => quote!(+ #t),
            });
            let (ii, jj) = (index(i), index(j));
            let mirror = (i != j).then(|| quote!(h[(#jj, #ii)] = h[(#ii, #jj)];));
            Some(quote!(h[(#ii, #jj)] = #first #(#rest)*; #mirror))
        })
        .collect();
    let zeros = quote!(#matrix_ty::<#d>::zeros());
    let body = if sets.is_empty() {
        quote!(#zeros)
    } else {
        quote!(#temps let mut h = #zeros; #(#sets)* h)
    };
    let lambda_ty = quote!(#svector<f64, #mm>);
    let lambda = if mentions(&body, "lambda") {
        quote!(lambda)
    } else {
        quote!(_lambda)
    };
    let weighted = on_x(
        (quote!(weighted_hessian), quote!(#matrix_ty<#d>)),
        body,
        quote!(, #lambda: &#lambda_ty),
        &d,
    );

    let xs = diff::positions(dim);
    let x_name = |i: usize| text::state_name(model, xs[i]);
    let name = |k: usize| format!("g[{k}]");
    let mut lines: Vec<(String, Id)> = (0..m).map(|k| (name(k), model.outputs[k])).collect();
    for (e, &id) in dx.iter().enumerate() {
        if !g.is_num(id, 0.0) {
            lines.push((format!("∂{}/∂{}", name(e / dim), x_name(e % dim)), id));
        }
    }
    for k in 0..m {
        for (p, &(i, j)) in pairs.iter().enumerate() {
            let id = second[k * pairs.len() + p];
            if !g.is_num(id, 0.0) {
                let label = format!("∂²{}/∂{}∂{}", name(k), x_name(i), x_name(j));
                lines.push((label, id));
            }
        }
    }
    let head = head(model, &text::lines_text(model, &lines), with_item);
    let strukt = &model.struct_name;
    let trait_ = private("Constraint");
    quote! {
        #head

        impl #trait_<#d, #mm> for #strukt {
            #value
            #jacobian
            #weighted
        }
    }
}

/// A method on `(x, v, t)` of `Vector<D>`, with the parameters the body does not read named
/// `_x` etc.
fn on_state(
    name: TokenStream,
    ret: TokenStream,
    body: TokenStream,
    vector: &TokenStream,
    d: &proc_macro2::Literal,
) -> TokenStream {
    crate::emit::method_on(name, ret, body, &quote!(#vector<#d>))
}

/// A method of a constraint on `x: &Vector<D>` (and the parameters `more`), `_x` if the body
/// does not read it.
fn on_x(
    (name, ret): (TokenStream, TokenStream),
    body: TokenStream,
    more: TokenStream,
    d: &proc_macro2::Literal,
) -> TokenStream {
    let x = param(&body, "x");
    let vector = private("Vector");
    quote! {
        #[inline]
        fn #name(&self, #x: &#vector<#d> #more) -> #ret {
            #body
        }
    }
}
