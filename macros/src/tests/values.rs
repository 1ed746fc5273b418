//! Local arrays, tuples and helpers returning them: what the parser makes of them.

use quote::quote;

use super::model;
use crate::ir::Var;

/// `L` of a model without loops at `x = (1, 2, 3)`, `v = 0`.
fn value_at_123(item: proc_macro2::TokenStream) -> f64 {
    let (model, _) = model(item);
    model.graph.eval(model.root, &|u| match u {
        Var::X(i) => (i + 1) as f64,
        _ => 0.0,
    })
}

/// An unrolled loop is straight-line code: a product, and an accumulator that a `let` of the
/// body shadows keeps what it had received.
#[test]
fn unrolled_loops_read_as_straight_line_code() {
    let product = value_at_123(quote! {
        fn f(x: [f64; 3], v: [f64; 3]) -> f64 {
            let a = [x[0], x[1], x[2]];
            let mut p = 1.0;
            for k in 0..3 {
                p *= a[k] + 1.0;
            }
            p
        }
    });
    assert_eq!(product, 2.0 * 3.0 * 4.0);
    let shadowed = value_at_123(quote! {
        fn f(x: [f64; 3], v: [f64; 3]) -> f64 {
            let a = [x[0], x[1], x[2]];
            let mut s = 0.0;
            for k in 0..3 {
                s += a[k];
                let s = 100.0 * a[k];
                let _ = s;
            }
            s
        }
    });
    assert_eq!(shadowed, 6.0);
    // A loop nested in an unrolled one, and an index `let` of its variable.
    let nested = value_at_123(quote! {
        fn f(x: [f64; 3], v: [f64; 3]) -> f64 {
            let a = [x[0], x[1], x[2]];
            let mut s = 0.0;
            for j in 0..3 {
                for k in 0..=j {
                    let m = j - k;
                    s += a[k] * a[m];
                }
            }
            s
        }
    });
    // Σ_{j} Σ_{k ≤ j} a_k a_{j−k} = a0² + 2 a0 a1 + (2 a0 a2 + a1²) = 1 + 4 + 6 + 4.
    assert_eq!(nested, 15.0);
}

/// A helper that calls another helper returning values is checked on its own without knowing
/// that helper's shape: no error.
#[test]
fn a_helper_calling_a_helper_returning_values_checks_on_its_own() {
    let f: syn::ItemFn = syn::parse2(quote! {
        fn radius(r: f64, t: f64) -> [f64; 2] {
            let mut s = spring(r);
            s += spring(t) * 2.0;
            let p = polar(r, t);
            let (a, b) = polar(r, t);
            let [c, d] = cross(r, t);
            [p.0 * p.1 + a * b + s, c * d + cross(t, r)[1]]
        }
    })
    .expect("a fn");
    let params: Vec<proc_macro2::Ident> =
        vec![quote::format_ident!("r"), quote::format_ident!("t")];
    let returns = crate::parse::returns(&f.sig.output);
    assert!(returns.is_some(), "an array of two");
    let errors = crate::parse::check_helper_body(&f, &params, returns);
    assert!(
        errors.is_empty(),
        "{:?}",
        errors.iter().map(ToString::to_string).collect::<Vec<_>>()
    );
}

/// What a helper's body ends with must be what its signature says.
#[test]
fn a_helper_ends_with_what_it_returns() {
    let f: syn::ItemFn = syn::parse2(quote! {
        fn pair(r: f64) -> (f64, f64) {
            [r, r]
        }
    })
    .expect("a fn");
    let returns = crate::parse::returns(&f.sig.output);
    assert!(returns.is_some(), "a tuple of two");
    let errors = crate::parse::check_helper_body(&f, &[quote::format_ident!("r")], returns);
    let text: Vec<String> = errors.iter().map(ToString::to_string).collect();
    assert_eq!(
        text,
        ["`pair` returns `(f64, f64)`: its body ends with an array of 2 values"]
    );
}
