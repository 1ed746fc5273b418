//! Unit tests of the pipeline on `proc_macro2` tokens.

use quote::quote;

use crate::expand::expand;

fn pretty(ts: proc_macro2::TokenStream) -> String {
    let file: syn::File = syn::parse2(ts).expect("the expansion is a valid file");
    prettyplease::unparse(&file)
}

#[test]
fn print_pendulum() {
    let out = expand(
        quote!(),
        quote! {
            /// Planar pendulum.
            pub fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
                0.5 * l * l * v * v + g * l * x.cos()
            }
        },
    )
    .unwrap();
    println!("{}", pretty(out));
}
