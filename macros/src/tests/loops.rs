//! Lagrangians with loops: the expansion does not grow with the dimension, and its snapshot.

use proc_macro2::{TokenStream, TokenTree};
use quote::quote;

use crate::expand::expand;

/// Number of tokens, groups counted with their contents.
fn count(ts: TokenStream) -> usize {
    ts.into_iter()
        .map(|tt| match tt {
            TokenTree::Group(g) => 1 + count(g.stream()),
            _ => 1,
        })
        .sum()
}

/// An FPUT chain with fixed ends, dimension `dim` (a literal or a `const` name).
pub(super) fn chain_item(dim: TokenStream) -> TokenStream {
    quote! {
        /// α-FPUT chain with fixed ends.
        fn chain(x: [f64; #dim], v: [f64; #dim], alpha: f64) -> f64 {
            let mut l = 0.0;
            for i in 0..#dim {
                l += 0.5 * v[i] * v[i];
            }
            for i in 0..#dim - 1 {
                let d = x[i + 1] - x[i];
                l -= 0.5 * d * d + alpha / 3.0 * d.powi(3);
            }
            l - 0.5 * x[0] * x[0] - 0.5 * x[#dim - 1] * x[#dim - 1]
        }
    }
}

/// The expansion of a chain of 4 and of 10⁴ particles has the same number of tokens: the
/// derivatives of the loops are loops, not unrolled entries.
#[test]
fn expansion_size_does_not_grow_with_the_dimension() {
    let size = |n: usize| {
        let lit = proc_macro2::Literal::usize_unsuffixed(n);
        let out = expand(quote!(), chain_item(quote!(#lit))).expect("the chain expands");
        count(out)
    };
    let (small, large) = (size(4), size(10_000));
    assert_eq!(small, large, "4 particles: {small} tokens, 10⁴: {large}");
    // A named dimension expands to the same code, but for the ranges and indices that a
    // literal dimension folds (`0..4 - 1` is `0..3`).
    let named = count(expand(quote!(), chain_item(quote!(N))).expect("the chain expands"));
    assert!(
        named.abs_diff(small) * 20 < small,
        "named: {named}, literal: {small}"
    );
    assert!(small < 3000, "{small} tokens");
}

/// The generated code of a chain: loops adding into the gradient and the three diagonals.
#[test]
fn chain_expansion_snapshot() {
    super::snapshots::check_snapshot("chain", chain_item(quote!(N)));
}

/// Nested loops (an n-link pendulum): the Hessian blocks are dense, filled by the double loop;
/// what depends on `i` only is computed once per `i`, outside the loop over `j`.
#[test]
fn n_link_expansion_snapshot() {
    super::snapshots::check_snapshot(
        "n_link",
        quote! {
            /// n-link pendulum, unit masses and lengths.
            fn n_link(x: [f64; N], v: [f64; N], g: f64) -> f64 {
                let mut kinetic = 0.0;
                for i in 0..N {
                    for j in 0..N {
                        let m = (N - i.max(j)) as f64;
                        kinetic += 0.5 * m * (x[i] - x[j]).cos() * v[i] * v[j];
                    }
                }
                let potential: f64 = (0..N).map(|i| -g * (N - i) as f64 * x[i].cos()).sum();
                kinetic - potential
            }
        },
    );
}

/// A chain of `M` dimers over `N / 2` pairs: a `usize` const other than the dimension and a
/// division of constants keep the loops loops (the expansion of 4 and 10⁴ particles has the
/// same size) and are named in the generated ranges, with their checks left to `const`
/// assertions.
#[test]
fn named_consts_and_divisions_stay_loops() {
    let item = |dim: TokenStream| {
        quote! {
            fn dimers(x: [f64; #dim], v: [f64; #dim], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..M {
                    l += 0.5 * v[2 * i] * v[2 * i] - k * (x[2 * i + 1] - x[2 * i]).powi(2);
                }
                for j in 0..#dim / 2 {
                    l -= (j as f64) * x[2 * j + 1].cos();
                }
                l - (M as f64) * x[#dim / 2]
            }
        }
    };
    let size = |n: usize| {
        let lit = proc_macro2::Literal::usize_unsuffixed(n);
        count(expand(quote!(), item(quote!(#lit))).expect("the dimers expand"))
    };
    assert_eq!(size(4), size(10_000));
    let out = expand(quote!(), item(quote!(N)))
        .expect("the dimers expand")
        .to_string();
    for loop_head in ["for i in 0 .. M", "for j in 0 .. (N / 2)"] {
        assert!(out.contains(loop_head), "{loop_head}: {out}");
    }
    assert!(out.contains("x [(N / 2)]"), "{out}");
    // `2 * i + 1 < N` at the last `i`, where the loop runs; `2 * i + 1 ≥ 0` is decided here.
    let checks: Vec<&str> = out
        .match_indices("const _ : () =")
        .collect::<Vec<_>>()
        .iter()
        .map(|&(k, _)| &out[k..])
        .collect();
    assert_eq!(checks.len(), 4, "{out}");
    assert!(
        out.contains("const _ : () = :: core :: assert ! (! (0 < M) || (2 * M < N + 1)"),
        "{out}"
    );
}

/// A chain of run-time length: slices `x: &[f64]`, the dimension the model constant
/// `n: usize`, used in ranges, indices and as a number. Only the `DynLagrangian` impl, with
/// `dimension() = self.n` and the index checks as `invalid_dimension()`.
#[test]
fn runtime_chain_expansion_snapshot() {
    super::snapshots::check_snapshot(
        "runtime_chain",
        quote! {
            /// α-FPUT chain with fixed ends, of `n` particles.
            pub fn runtime_chain(x: &[f64], v: &[f64], n: usize, alpha: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..n {
                    l += 0.5 * v[i] * v[i];
                }
                for i in 0..n - 1 {
                    let d = x[i + 1] - x[i];
                    l -= 0.5 * d * d + alpha / 3.0 * d.powi(3);
                }
                l - 0.5 * x[0] * x[0] - 0.5 * x[n - 1] * x[n - 1] / (n as f64)
            }
        },
    );
}

/// A chain with fixed ends whose neighbours are read in branches: the derivatives with
/// respect to `x[i - 1]` and `x[i + 1]` are added inside `if`s on `i` (the entries exist only
/// there), and a read of a guarded component is itself guarded, since a temporary holding it
/// is computed in every iteration. The expansion does not grow with the dimension.
#[test]
fn guarded_chain_expansion_snapshot() {
    let item = |dim: TokenStream| {
        quote! {
            /// A chain with fixed ends `x_{-1} = x_N = 0`.
            fn guarded_chain(x: [f64; #dim], v: [f64; #dim], k: f64) -> f64 {
                let mut l = 0.0;
                for i in 0..#dim {
                    let left = if i > 0 { x[i - 1] } else { 0.0 };
                    let right = if i + 1 < #dim { x[i + 1] } else { 0.0 };
                    l += 0.5 * v[i] * v[i] - 0.25 * k * ((x[i] - left).powi(2) + (right - x[i]).powi(2));
                }
                l
            }
        }
    };
    let size = |n: usize| {
        let lit = proc_macro2::Literal::usize_unsuffixed(n);
        count(expand(quote!(), item(quote!(#lit))).expect("the chain expands"))
    };
    assert_eq!(size(4), size(10_000));
    super::snapshots::check_snapshot("guarded_chain", item(quote!(N)));
}
