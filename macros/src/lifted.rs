//! The code of a model's lifted sums (`assemble.rs`): their values, their adjoints, and the
//! dense part they add to the Hessian, around the loop nests of `scatter.rs`. A model without
//! lifted sums gets none of it.
//!
//! In a method, the values `lifted_k` come first (in order: a sum may read earlier ones),
//! then the adjoints `adjoint_k = ∂L/∂s_k` (in reverse order: the adjoint of a sum reads those
//! of the later sums that read it), then the loop nests, whose weighted terms read both. The
//! Hessian methods then add `Σ_k (U_k W_kᵀ + W_k U_kᵀ)` (see `assemble.rs`) over the blocks it
//! reaches, as a dense loop over every entry.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::assemble::{Block, Term};
use crate::ir::{Id, Var};
use crate::names::{adjoint, lifted};
use crate::scatter::{Loops, Style, Target, gradient_out, value_out};

/// The lifted sums of the model behind `loops`, emitted in `style`; `zeros` is an expression
/// of a zero vector of the dimension (`Vector::<N>::zeros()`, `vec![0.0; n]`).
pub struct Lifted<'a> {
    loops: &'a Loops<'a>,
    style: Style,
    zeros: TokenStream,
}

/// The two halves `(x, v)` of a vector over the state.
fn halves(name: &str, k: usize) -> (Ident, Ident) {
    (
        format_ident!("lifted_{}x_{}", name, k),
        format_ident!("lifted_{}v_{}", name, k),
    )
}

impl<'a> Lifted<'a> {
    pub fn new(loops: &'a Loops<'a>, style: Style, zeros: TokenStream) -> Self {
        Self {
            loops,
            style,
            zeros,
        }
    }

    fn count(&self) -> usize {
        self.loops.assembly().sums.len()
    }

    /// `{ let mut value = 0.0; <nest>; value }` over `terms` with the outputs `pick` gives.
    fn scalar(&self, terms: &[Term], pick: &dyn Fn(&Term) -> Vec<(Target, Id)>) -> TokenStream {
        let (code, used) = self.loops.body_of(terms, pick, self.style);
        if used[0] {
            quote!({ let mut value = 0.0; #code value })
        } else {
            quote!(0.0)
        }
    }

    /// `let lifted_k = s_k;` for every lifted sum, in order.
    pub fn values(&self) -> TokenStream {
        let a = self.loops.assembly();
        let lets = a.sums.iter().enumerate().map(|(k, terms)| {
            let name = lifted(k);
            let e = self.scalar(terms, &value_out);
            quote!(#[allow(unused_variables)] let #name: f64 = #e;)
        });
        quote!(#(#lets)*)
    }

    /// `let adjoint_k = ∂L/∂s_k;` for every lifted sum, last first.
    pub fn adjoints(&self) -> TokenStream {
        let a = self.loops.assembly();
        let lets = (0..self.count()).rev().map(|k| {
            let name = adjoint(k);
            let e = self.scalar(&a.terms, &partial(Var::Lifted(k)));
            quote!(#[allow(unused_variables)] let #name: f64 = #e;)
        });
        quote!(#(#lets)*)
    }

    /// A vector over the state: `fx`, `fv` from the nest of `terms` with the outputs `pick`
    /// gives, plus `c_j·(the vectors of extra[j])`.
    fn vector(
        &self,
        terms: &[Term],
        pick: &dyn Fn(&Term) -> Vec<(Target, Id)>,
        extra: &[(TokenStream, (Ident, Ident))],
    ) -> TokenStream {
        let (code, used) = self.loops.body_of(terms, pick, self.style);
        let zeros = &self.zeros;
        let dim = &self.loops.names.dim;
        let (mx, mv) = (
            (used[1] || !extra.is_empty()).then(|| quote!(mut)),
            (used[2] || !extra.is_empty()).then(|| quote!(mut)),
        );
        let adds = extra.iter().map(|(c, (wx, wv))| {
            quote! {
                let c: f64 = #c;
                for row in 0..#dim {
                    fx[row] += c * #wx[row];
                    fv[row] += c * #wv[row];
                }
            }
        });
        quote!({
            let #mx fx = #zeros;
            let #mv fv = #zeros;
            #code
            #(#adds)*
            (fx, fv)
        })
    }

    /// What the Hessian methods add: `W_k`, `U_k`, then `Σ_k (U_k W_kᵀ + W_k U_kᵀ)` over the
    /// blocks it reaches, and which of `xx`, `xv`, `vv` that writes.
    pub fn dense_part(&self) -> (TokenStream, [bool; 3]) {
        let a = self.loops.assembly();
        if !a.dense_blocks.iter().any(|&d| d) {
            return (quote!(), [false; 3]);
        }
        let mut code = Vec::new();
        for (k, terms) in a.sums.iter().enumerate() {
            // `W_k = ∂s_k/∂z + Σ_j (∂s_k/∂s_j) W_j`.
            let extra: Vec<_> = (0..k)
                .filter(|&j| reads(terms, Var::Lifted(j)))
                .map(|j| (self.scalar(terms, &partial(Var::Lifted(j))), halves("w", j)))
                .collect();
            let e = self.vector(terms, &gradient_out, &extra);
            let (wx, wv) = halves("w", k);
            code.push(quote!(#[allow(unused_variables)] let (#wx, #wv) = #e;));
        }
        for k in 0..a.sums.len() {
            // `U_k = Φ_{z s_k} + ½ Σ_l Φ_{s_k s_l} W_l`.
            let extra: Vec<_> = (0..a.sums.len())
                .filter(|&l| second(&a.terms, k, l))
                .map(|l| {
                    let c = self.scalar(&a.terms, &sums_entry(k, l));
                    (quote!(0.5 * #c), halves("w", l))
                })
                .collect();
            let e = self.vector(&a.terms, &state_sum_entry(k), &extra);
            let (ux, uv) = halves("u", k);
            code.push(quote!(#[allow(unused_variables)] let (#ux, #uv) = #e;));
        }
        let dim = &self.loops.names.dim;
        let blocks = [("xx", 'x', 'x'), ("xv", 'x', 'v'), ("vv", 'v', 'v')];
        for (b, &(name, r, c)) in blocks.iter().enumerate() {
            if !a.dense_blocks[b] {
                continue;
            }
            let products = (0..a.sums.len()).map(|k| {
                let pick = |side: char, which: &str| {
                    let (x, v) = halves(which, k);
                    if side == 'x' { x } else { v }
                };
                let (ur, wc, wr, uc) = (pick(r, "u"), pick(c, "w"), pick(r, "w"), pick(c, "u"));
                quote!(#ur[row] * #wc[col] + #wr[row] * #uc[col])
            });
            let block = Ident::new(name, proc_macro2::Span::call_site());
            let add = match self.style {
                Style::Dense => quote!(#block[(row, col)] += e;),
                Style::Sparse => quote!(out.#block.add(row, col, e);),
            };
            code.push(quote! {
                for row in 0..#dim {
                    for col in 0..#dim {
                        let e = #(#products)+*;
                        #add
                    }
                }
            });
        }
        (quote!(#(#code)*), a.dense_blocks)
    }
}

/// Whether some term of `terms` has a nonzero derivative with respect to `u`.
fn reads(terms: &[Term], u: Var) -> bool {
    terms.iter().flat_map(|t| &t.gradient).any(|e| e.0 == u)
}

/// Whether `Φ_{s_k s_l}` has a nonzero entry.
fn second(terms: &[Term], k: usize, l: usize) -> bool {
    terms.iter().any(|t| !sums_entry(k, l)(t).is_empty())
}

/// The derivative with respect to `u`, as a value.
fn partial(u: Var) -> impl Fn(&Term) -> Vec<(Target, Id)> {
    move |t: &Term| {
        t.gradient
            .iter()
            .filter(|e| e.0 == u)
            .map(|e| (Target::Value, e.1))
            .collect()
    }
}

/// `∂²/∂z∂s_k`, as a vector over the state.
fn state_sum_entry(k: usize) -> impl Fn(&Term) -> Vec<(Target, Id)> {
    move |t: &Term| {
        t.hessian
            .iter()
            .filter(|e| e.block == Block::Zs && e.col == Var::Lifted(k))
            .map(|e| (Target::Gradient(e.row), e.id))
            .collect()
    }
}

/// `∂²/∂s_k∂s_l`, as a value.
fn sums_entry(k: usize, l: usize) -> impl Fn(&Term) -> Vec<(Target, Id)> {
    let (sk, sl) = (Var::Lifted(k), Var::Lifted(l));
    move |t: &Term| {
        t.hessian
            .iter()
            .filter(|e| {
                e.block == Block::Ss
                    && ((e.row == sk && e.col == sl) || (e.mirror && e.row == sl && e.col == sk))
            })
            .map(|e| (Target::Value, e.id))
            .collect()
    }
}
