//! `#[lagrangian]`: compile-time symbolic differentiation of a Lagrangian.
//!
//! The pipeline, one module per stage: [`parse`] (syn → expression DAG, spanned errors),
//! [`expr`] (the hash-consed DAG), [`simplify`] (smart constructors: folding, identities),
//! [`diff`] (symbolic derivatives), [`cse`] (which shared nodes become temporaries),
//! [`codegen`] (the struct and the `Lagrangian<D>` impl), [`fallback`] (what is emitted on
//! error). [`expand`] strings them together on `proc_macro2` tokens.

mod codegen;
mod cse;
mod diff;
mod expand;
mod expr;
mod fallback;
mod parse;
mod simplify;

#[cfg(test)]
mod tests;

use proc_macro::TokenStream;

/// Turns `fn name(x, v, [t: f64,] constants: f64...) -> f64 { body }` into a struct that
/// implements `varembed::Lagrangian<D>` with derivatives computed at compile time.
///
/// `x` and `v` are both `f64` (`D = 1`) or both `[f64; D]`; an optional `t: f64` follows, then
/// any number of `f64` model constants. The macro keeps the fn as written and adds
/// `struct CamelCaseName { pub constant: f64, … }` (a unit struct without constants, with the
/// fn's visibility and docs) implementing `Lagrangian<D>`:
///
/// - `value`, `gradient` (`∂L/∂x`, `∂L/∂v`) and `hessian` (the blocks `xx`, `xv`, `vv`), from
///   symbolic derivatives simplified at compile time (constants folded, `0`/`1` identities,
///   zero entries dropped, symmetric blocks computed once) with every common subexpression
///   computed once per method;
/// - fused step kernels `step_momentum` and `step_residual` for the four classical schemes,
///   and, when the step equation is affine in the newest node with a constant matrix (e.g.
///   `L = ½ vᵀMv − U(x)`), `step_is_affine` and the closed-form `step_explicit`;
/// - `NAME::DERIVATIVES`, the derivatives as text.
///
/// The body may use `let` bindings, `+ - * /`, unary `-`, float and integer literals,
/// parentheses, `x[i]`/`v[i]` with a literal index, the parameters, the `f64` methods (or
/// `f64::` functions) `sin cos tan asin acos atan sinh cosh tanh exp ln log10 sqrt cbrt recip
/// abs powi powf hypot` (`powi` with an integer-literal exponent), and `std::f64::consts::*`.
/// Anything else is a compile error on the offending tokens; all of them are reported at once.
///
/// Derivative conventions: `abs` is differentiated as `sign(a)·a'` with `sign(0) = 0`;
/// `a.powf(b)` contributes `a^b·ln a·b'` when the exponent is not constant, which needs
/// `a > 0` (it is NaN otherwise, as is `powf` itself for a negative base).
///
/// # Example
///
/// This example is compiled and run as `tests/tests/macro_doc_example.rs`.
///
/// ```ignore
/// use varembed::{lagrangian, Lagrangian, Vector};
///
/// /// Planar pendulum of length `l` under gravity `g`.
/// #[lagrangian]
/// fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
///     0.5 * l * l * v * v + g * l * x.cos()
/// }
///
/// let lag = Pendulum { g: 9.81, l: 2.0 };
/// let (x, v) = (Vector::<1>::new(0.3), Vector::<1>::new(-1.0));
/// let (f, p) = lag.gradient(&x, &v, 0.0);
/// assert_eq!(f[0], -9.81 * 2.0 * 0.3f64.sin());
/// assert_eq!(p[0], -4.0);
/// assert_eq!(pendulum(0.3, -1.0, 9.81, 2.0), lag.value(&x, &v, 0.0));
/// println!("{}", Pendulum::DERIVATIVES);
/// ```
#[proc_macro_attribute]
pub fn lagrangian(args: TokenStream, item: TokenStream) -> TokenStream {
    let original: proc_macro2::TokenStream = item.clone().into();
    expand::expand(args.into(), item.into())
        .unwrap_or_else(|err| fallback::emit(original, &err))
        .into()
}
