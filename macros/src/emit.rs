//! The emitting stage: the user's fn, the generated struct, `DERIVATIVES`, and the
//! `Lagrangian<D>` impl with `value`, `gradient`, `value_and_gradient`, `hessian`,
//! `gradient_and_hessian`, `hessian_dependence` and `hessian_bandwidth`.
//!
//! The step math of the schemes is not generated: core writes it once over these methods, so a
//! hand-written Lagrangian gets the same steps as a generated one. Every method is `#[inline]`:
//! inlined into a step that reads only some outputs of `gradient_and_hessian`, the optimiser
//! drops the work only the other outputs need.
//!
//! The generated code names core only through `::varembed::__private` ([`private`]), so core's
//! public API can change without breaking it.

use proc_macro2::{Ident, Literal, Span, TokenStream, TokenTree};
use quote::{format_ident, quote};

use crate::cse::Plans;
use crate::ir::{Attr, Dependence, Derivatives, Graph, HessianDependence, Id, Model, Var};
use crate::render::Render;
pub use crate::render::private;

/// The user's fn, the struct, its `DERIVATIVES` (the text `text`) and its `Lagrangian<D>` impl
/// evaluating `d` by `plans`.
pub fn emit(
    model: &Model,
    d: &Derivatives,
    plans: &Plans,
    text: &str,
    with_item: bool,
) -> TokenStream {
    let g = &model.graph;
    let leaf = leaf(&model.consts);
    let types = Types::new(model.dim);
    let (vector, hessian_ty) = (&types.vector, &types.hessian);

    // value
    let r = Render::new(g, &plans.value, &leaf);
    let (temps, out) = (r.temps(), r.root(model.root));
    let value = method(quote!(value), quote!(f64), quote!(#temps #out), &types);

    // gradient
    let r = Render::new(g, &plans.gradient, &leaf);
    let temps = r.temps();
    let (fx, fv) = gradient_vectors(&r, d, &types);
    let gradient = method(
        quote!(gradient),
        quote!((#vector, #vector)),
        quote!(#temps (#fx, #fv)),
        &types,
    );

    // value_and_gradient: one plan, so the gradient reuses what the value computed.
    let r = Render::new(g, &plans.value_and_gradient, &leaf);
    let (temps, out) = (r.temps(), r.root(model.root));
    let (fx, fv) = gradient_vectors(&r, d, &types);
    let value_and_gradient = method(
        quote!(value_and_gradient),
        quote!((f64, #vector, #vector)),
        quote!(#temps (#out, #fx, #fv)),
        &types,
    );

    // hessian
    let r = Render::new(g, &plans.hessian, &leaf);
    let temps = r.temps();
    let (blocks, hessian) = hessian_blocks(g, &r, d, &types);
    let hessian = method(
        quote!(hessian),
        quote!(#hessian_ty),
        quote!(#temps #blocks #hessian),
        &types,
    );

    // gradient_and_hessian: one plan, so the blocks reuse what the gradient computed.
    let r = Render::new(g, &plans.gradient_and_hessian, &leaf);
    let temps = r.temps();
    let (fx, fv) = gradient_vectors(&r, d, &types);
    let (blocks, both) = hessian_blocks(g, &r, d, &types);
    let gradient_and_hessian = method(
        quote!(gradient_and_hessian),
        quote!((#vector, #vector, #hessian_ty)),
        quote!(#temps #blocks (#fx, #fv, #both)),
        &types,
    );

    let methods = quote!(#value #gradient #value_and_gradient #hessian #gradient_and_hessian);
    let dim = &types.dim;
    let properties = properties(
        model,
        (
            &d.hessian_dependence,
            &d.dependence,
            Some(bandwidth(g, d, types.size)),
        ),
    );
    shell(model, text, quote!(#dim), methods, &properties, with_item)
}

/// The largest `|i − j|` over the nonzero entries of the three blocks of an unrolled model
/// (`dim × dim` entries each, row by row); `0` when every block is zero.
fn bandwidth(g: &Graph, d: &Derivatives, dim: usize) -> usize {
    [&d.xx, &d.xv, &d.vv]
        .into_iter()
        .flat_map(|entries| entries.iter().enumerate())
        .filter(|&(_, &id)| !g.is_num(id, 0.0))
        .map(|(k, _)| (k / dim).abs_diff(k % dim))
        .max()
        .unwrap_or(0)
}

/// The user's fn, the struct, `DERIVATIVES` and the `Lagrangian<dim>` impl holding `methods`
/// and the model's `properties`.
pub fn shell(
    model: &Model,
    text: &str,
    dim: TokenStream,
    methods: TokenStream,
    properties: &TokenStream,
    with_item: bool,
) -> TokenStream {
    let name = &model.struct_name;
    let head = head(model, text, with_item);
    let lagrangian = private("Lagrangian");
    quote! {
        #head

        impl #lagrangian<#dim> for #name {
            #methods
            #properties
        }
    }
}

/// The user's fn (when `with_item`), the struct and its `DERIVATIVES` (the text `text`).
pub fn head(model: &Model, text: &str, with_item: bool) -> TokenStream {
    let name = &model.struct_name;
    let item = &model.item;
    let item = if with_item {
        quote! {
            // The fn stays callable, but the generated struct is the usual entry point: a
            // program that only uses the struct has not made a mistake worth a `dead_code`
            // warning.
            #[allow(dead_code)]
            #item
        }
    } else {
        quote!()
    };
    let strukt = structure(model);
    // One `#[doc]` per line, as `///` lines would be.
    let derivatives_doc: &[&str] = match model.attr {
        Attr::Lagrangian => &[
            " The derivatives of `L` computed by `#[lagrangian]`, one per line (zero entries",
            " omitted; symmetric blocks listed once, `i ≤ j`).",
        ],
        Attr::Force => &[
            " The components of `f` and the entries of its Jacobian computed by `#[force]`, one",
            " per line (zero entries omitted).",
        ],
        Attr::Constraint => &[
            " The components of `g`, their gradients and second derivatives computed by",
            " `#[constraint]`, one per line (zero entries omitted; second derivatives listed",
            " once, `i ≤ j`).",
        ],
    };
    quote! {
        #item

        #strukt

        impl #name {
            #(#[doc = #derivatives_doc])*
            pub const DERIVATIVES: &str = #text;
        }
    }
}

/// The methods that state constants of the model, the same in `Lagrangian<D>` and
/// `DynLagrangian`: `hessian_dependence`, `hessian_bandwidth`, `dependence`, `constants`.
pub fn properties(
    model: &Model,
    (hessian_dep, dep, band): (&HessianDependence, &Dependence, Option<usize>),
) -> TokenStream {
    let hessian_dependence = hessian_dependence(hessian_dep);
    let bandwidth = hessian_bandwidth(band);
    let dependence = dependence(dep);
    let constants = constants(&model.consts);
    quote! {
        #hessian_dependence
        #bandwidth
        #dependence
        #constants
    }
}

/// The struct: the fn's docs and visibility, one `pub f64` field per model constant (a unit
/// struct without constants).
fn structure(model: &Model) -> TokenStream {
    let name = &model.struct_name;
    let vis = &model.vis;
    let docs = &model.docs;
    let fn_name = &model.item.sig.ident;
    let what = match model.attr {
        Attr::Lagrangian => "Lagrangian",
        Attr::Force => "Force",
        Attr::Constraint => "Constraint",
    };
    let generated_doc = format!(
        "{what} generated by `{}` from the fn [`{fn_name}`]; its derivatives are \
         listed in [`{name}::DERIVATIVES`].",
        model.attr.name()
    );
    let fields = model.consts.iter().map(|c| {
        let doc = format!("Model constant `{c}` of [`{fn_name}`].");
        quote!(#[doc = #doc] pub #c: f64)
    });
    let dimension = model.runtime_dim.iter().map(|n| {
        let doc = format!(
            "The dimension of [`{fn_name}`]: the length of `x` and `v` (a model constant \
             `{n}: usize`)."
        );
        quote!(#[doc = #doc] pub #n: usize)
    });
    let fields: Vec<TokenStream> = dimension.chain(fields).collect();
    let body = if fields.is_empty() {
        quote!(;)
    } else {
        quote!({ #(#fields),* })
    };
    quote! {
        #(#docs)*
        #[doc = ""]
        #[doc = #generated_doc]
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #vis struct #name #body
    }
}

/// The core types the methods name, at dimension `D`.
struct Types {
    /// `D`.
    size: usize,
    /// `D` as a literal.
    dim: Literal,
    /// `Vector<D>`.
    vector: TokenStream,
    /// `Vector::<D>`, in expression position.
    vector_expr: TokenStream,
    /// `Matrix::<D>`, in expression position.
    matrix_expr: TokenStream,
    /// `Hessian<D>`.
    hessian: TokenStream,
}

impl Types {
    fn new(dim: usize) -> Self {
        let (vector, matrix, hessian) = (private("Vector"), private("Matrix"), private("Hessian"));
        let d = index(dim);
        Self {
            vector: quote!(#vector<#d>),
            vector_expr: quote!(#vector::<#d>),
            matrix_expr: quote!(#matrix::<#d>),
            hessian: quote!(#hessian<#d>),
            size: dim,
            dim: d,
        }
    }
}

/// A method on a point `(x, v, t)`, with the parameters the body does not read named `_x` etc.
fn method(name: TokenStream, ret: TokenStream, body: TokenStream, types: &Types) -> TokenStream {
    method_on(name, ret, body, &types.vector)
}

/// A method on a point `(x, v, t)` of type `vector`, unused parameters named `_x` etc.
pub fn method_on(
    name: TokenStream,
    ret: TokenStream,
    body: TokenStream,
    vector: &TokenStream,
) -> TokenStream {
    let (x, v, t) = (param(&body, "x"), param(&body, "v"), param(&body, "t"));
    quote! {
        #[inline]
        fn #name(&self, #x: &#vector, #v: &#vector, #t: f64) -> #ret {
            #body
        }
    }
}

/// `(∂L/∂x, ∂L/∂v)` as two `Vector<D>` expressions.
fn gradient_vectors(r: &Render<'_>, d: &Derivatives, types: &Types) -> (TokenStream, TokenStream) {
    let vector = |ids: &[Id]| {
        let entries = ids.iter().map(|&i| r.root(i));
        let v = &types.vector_expr;
        quote!(#v::from([#(#entries),*]))
    };
    (vector(&d.fx), vector(&d.fv))
}

/// The statements `let xx = …; let xv = …; let vv = …;` that set the nonzero entries (the
/// mirrored entries of the symmetric blocks included), and the expression
/// `Hessian { xx, xv, vv }`.
fn hessian_blocks(
    g: &Graph,
    r: &Render<'_>,
    d: &Derivatives,
    types: &Types,
) -> (TokenStream, TokenStream) {
    let names = ["xx", "xv", "vv"].map(|n| Ident::new(n, Span::call_site()));
    let blocks = [&d.xx, &d.xv, &d.vv]
        .into_iter()
        .zip(&names)
        .map(|(entries, name)| {
            let zeros = &types.matrix_expr;
            matrix(
                r,
                g,
                (quote!(#name), quote!(#zeros::zeros())),
                entries,
                types.size,
            )
        });
    let hessian = private("Hessian");
    let [xx, xv, vv] = &names;
    (quote!(#(#blocks)*), quote!(#hessian { #xx, #xv, #vv }))
}

/// `let [mut] name = zeros; name[(i, j)] = …;` for the nonzero entries of the row-major
/// `entries` with `cols` columns (a Hessian block, a force's Jacobian block, a constraint's
/// `G`).
pub fn matrix(
    r: &Render<'_>,
    g: &Graph,
    (name, zeros): (TokenStream, TokenStream),
    entries: &[Id],
    cols: usize,
) -> TokenStream {
    let sets: Vec<TokenStream> = entries
        .iter()
        .enumerate()
        .filter(|&(_, &id)| !g.is_num(id, 0.0))
        .map(|(k, &id)| {
            let (i, j, e) = (index(k / cols), index(k % cols), r.root(id));
            quote!(#name[(#i, #j)] = #e;)
        })
        .collect();
    if sets.is_empty() {
        quote!(let #name = #zeros;)
    } else {
        quote!(let mut #name = #zeros; #(#sets)*)
    }
}

/// A [`Dependence`] as core's value.
pub fn dependence_value(d: &Dependence) -> TokenStream {
    let (x, v, t) = (d.x, d.v, d.t);
    let dependence = private("Dependence");
    quote!(#dependence { x: #x, v: #v, t: #t })
}

/// `dependence`: what `L` itself depends on, a constant of the model.
fn dependence(dep: &Dependence) -> TokenStream {
    let ty = private("Dependence");
    let value = dependence_value(dep);
    quote! {
        #[inline]
        fn dependence(&self) -> #ty {
            #value
        }
    }
}

/// `constants`: the model constants by field name.
pub fn constants(consts: &[Ident]) -> TokenStream {
    let names = consts.iter().map(|c| c.to_string());
    quote! {
        #[inline]
        fn constants(&self) -> ::std::vec::Vec<(&'static str, f64)> {
            ::std::vec![#((#names, self.#consts)),*]
        }
    }
}

/// `hessian_dependence`, a constant of the model.
fn hessian_dependence(dep: &HessianDependence) -> TokenStream {
    let ty = private("HessianDependence");
    let block = dependence_value;
    let (xx, xv, vv) = (block(&dep.xx), block(&dep.xv), block(&dep.vv));
    quote! {
        #[inline]
        fn hessian_dependence(&self) -> #ty {
            #ty { xx: #xx, xv: #xv, vv: #vv }
        }
    }
}

/// `hessian_bandwidth`, a constant of the model: the largest `|i − j|` of a structurally
/// nonzero Hessian entry, or `None` when the macro cannot bound it.
fn hessian_bandwidth(band: Option<usize>) -> TokenStream {
    let value = match band {
        Some(b) => {
            let b = index(b);
            quote!(::core::option::Option::Some(#b))
        }
        None => quote!(::core::option::Option::None),
    };
    quote! {
        #[inline]
        fn hessian_bandwidth(&self) -> ::core::option::Option<usize> {
            #value
        }
    }
}

pub fn index(i: usize) -> Literal {
    Literal::usize_unsuffixed(i)
}

/// Whether `ts` mentions the identifier `name` (to name unused parameters `_name`).
pub fn mentions(ts: &TokenStream, name: &str) -> bool {
    ts.clone().into_iter().any(|tt| match tt {
        TokenTree::Ident(i) => i == name,
        TokenTree::Group(g) => mentions(&g.stream(), name),
        _ => false,
    })
}

/// `name` if the body uses it, `_name` otherwise.
pub fn param(body: &TokenStream, name: &str) -> Ident {
    if mentions(body, name) {
        Ident::new(name, Span::call_site())
    } else {
        format_ident!("_{}", name)
    }
}

/// Leaves of the methods: their own arguments `x`, `v`, `t` and the struct's fields.
pub fn leaf(consts: &[Ident]) -> impl Fn(Var) -> TokenStream + '_ {
    move |v| match v {
        Var::X(i) => {
            let i = index(i);
            quote!(x[#i])
        }
        Var::V(i) => {
            let i = index(i);
            quote!(v[#i])
        }
        Var::T => quote!(t),
        Var::Const(k) => {
            let c = &consts[k];
            quote!(self.#c)
        }
        Var::F(_) | Var::FAt(_) => {
            unreachable!("the weights of a force's virtual work are differentiated away")
        }
        Var::XAt(_)
        | Var::VAt(_)
        | Var::Index(_)
        | Var::Dim
        | Var::Sym(_)
        | Var::Lifted(_)
        | Var::Adjoint(_) => {
            unreachable!("a model without loops reads literal components only")
        }
    }
}
