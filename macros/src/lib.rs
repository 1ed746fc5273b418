//! `#[lagrangian]`: compile-time symbolic differentiation of a Lagrangian; `#[force]` and
//! `#[constraint]`: the same for a vector-valued force or constraint.
//!
//! A pipeline, one module per stage, each a function from one typed value to the next
//! (strung together in `expand.rs`): `parse.rs` (syn → the IR, spanned errors, all collected) →
//! `diff.rs` (symbolic first and second derivatives) → `cse.rs` (which shared nodes each method
//! binds to temporaries) → `text.rs` (`DERIVATIVES`) → `emit.rs` (the struct and its
//! `Lagrangian<D>` impl, expressions written by `render.rs`). `ir.rs` is the hash-consed DAG they
//! share (its integer side, loop variables and index expressions, in `indices.rs`);
//! `simplify.rs` is the smart constructors every node is built through; `fallback.rs` is what
//! is emitted on error. A Lagrangian with loops takes `assemble.rs` (its terms and their
//! derivatives; `rewrite.rs` lifts the sums used as values and renames loop variables) and
//! `scatter.rs` (loop nests adding them into their entries) in place of `diff.rs`, `cse.rs`
//! and `emit.rs`'s methods (`names.rs` writes their indices, ranges and the `const` assertions
//! of the index checks left to the compiler); `loop_impl.rs` emits its `Lagrangian<N>` impl,
//! `lifted.rs` the values, adjoints and dense Hessian part of its lifted sums; `helpers.rs`
//! relays `#[lagrangian(helper)]` fns to the Lagrangians that call them. `dynamic.rs` emits
//! the `DynLagrangian` impl of a model with loops (the same loop nests on slices), `checks.rs`
//! the run-time index checks of a model whose dimension is a `usize` constant. `readable.rs`
//! is the normal form `DERIVATIVES` prints. A `#[force]` or `#[constraint]` fn is parsed the
//! same way (`parse/vector.rs`: its signature and the array its body ends with) and takes
//! `vector.rs` after the parse: `diff.rs`'s `jacobian`, `cse.rs`'s plans, `render.rs`.

mod assemble;
mod checks;
mod cse;
mod diff;
mod dynamic;
mod emit;
mod expand;
mod fallback;
mod helpers;
mod indices;
mod ir;
mod lifted;
mod loop_impl;
mod looped_force;
mod names;
mod parse;
mod readable;
mod render;
mod rewrite;
mod scatter;
mod simplify;
mod text;
mod vector;

#[cfg(test)]
mod tests;

use proc_macro::TokenStream;

/// Turns `fn name(x, v, [t: f64,] constants: f64...) -> f64 { body }` into a struct that
/// implements `varembed::Lagrangian<D>` with derivatives computed at compile time.
///
/// `x` and `v` are both `f64` (`D = 1`), both `[f64; D]` (`D` a literal or a `const` item) or
/// both `&[f64]` (below);
/// an optional `t: f64` follows, then
/// any number of `f64` model constants. The macro keeps the fn as written and adds
/// `struct CamelCaseName { pub constant: f64, … }` (a unit struct without constants, with the
/// fn's visibility and docs) implementing `Lagrangian<D>`:
///
/// - `value`, `gradient` (`∂L/∂x`, `∂L/∂v`), `hessian` (the blocks `xx`, `xv`, `vv`) and
///   `gradient_and_hessian` (both, sharing their common subexpressions; `value_and_gradient`
///   likewise), from symbolic
///   derivatives simplified at compile time (constants folded, `0`/`1` identities, zero
///   entries dropped, symmetric blocks computed once) with every common subexpression computed
///   once per method; all `#[inline]`;
/// - `hessian_dependence`: on which of `x`, `v`, `t` each block depends, read off the
///   symbolic derivatives (e.g. `L = ½ vᵀMv − U(x)` has constant `vv` and zero `xv`). Core
///   decides from it which steps of the classical schemes have a closed-form update;
/// - `NAME::DERIVATIVES`, the derivatives as text.
///
/// A model with loops also implements `varembed::DynLagrangian` (slices, sparse second
/// derivatives). With `x: &[f64]`, `v: &[f64]` and one `usize` model constant, the dimension is
/// that run-time value and only `DynLagrangian` is implemented, its index checks made by
/// `invalid_dimension()` (`core/docs/macro.md`, "Run-time dimension and sparse second derivatives"):
///
/// ```ignore
/// #[lagrangian]
/// fn toda(x: &[f64], v: &[f64], n: usize, a: f64) -> f64 {
///     (0..n).map(|i| 0.5 * v[i] * v[i] - (-(x[(i + 1) % n] - x[i])).exp() * a).sum()
/// }
/// let lattice = Toda { n: 10_000, a: 1.0 }; // `lattice.dimension() == 10_000`
/// ```
///
/// The generated code reaches `varembed` only through its hidden `__private` module.
///
/// The body may use `let` bindings (also of tuples), local arrays `let a = [e0, e1, e2];` read
/// at constant indices (a loop over a literal range that reads one at its variable is
/// unrolled), `let mut` accumulators with `for i in
/// a..b { acc += … }`, iterator sums `(a..b).map(|i| …).sum::<f64>()`, `x[i]`/`v[i]` at a
/// literal or an index expression (`x[i + 1]`, `x[(i + 1) % N]`, `x[2 * i + 1]`), other `usize`
/// consts where `N` may stand (`for i in 0..M`), division of constants by a literal (`0..N / 2`,
/// `x[N / 2]`), indices as numbers (`(N - i) as f64`), `+ - * /`, unary `-`, literals, the
/// parameters, the `f64` methods (or `f64::` functions) `sin cos tan asin acos atan atan2 sinh
/// cosh tanh exp exp_m1 ln ln_1p log10 sqrt cbrt recip abs signum powi powf hypot max min`,
/// `if c { a } else { b }`, `std::f64::consts::*`, and helper fns marked
/// `#[lagrangian(helper)]` (returning `f64`, `(f64, …)` or `[f64; K]`). The derivatives of loops are loops (the expansion does not grow
/// with the dimension). A sum is a value: bound to a local or accumulated (also in an
/// accumulator declared inside a loop), it may be squared, divided by, passed to a function,
/// compared or read in another loop, and is differentiated exactly through the chain rule (a
/// sum inside a function is computed first and differentiated through in reverse mode; its
/// Hessian part is dense, and such a model claims no band). Anything else is a compile error on the
/// offending tokens; all of them are reported at once. `core/docs/macro.md` has the details.
///
/// Derivative conventions: `if` is differentiated branch by branch (the condition is not),
/// and a branch whose condition keeps an index in range (`if i > 0 { x[i - 1] } else { 0.0 }`)
/// adds the derivatives with respect to that component only where it holds;
/// `abs` is differentiated as `sign(a)·a'` with `sign(0) = 0`;
/// `a.powf(b)` contributes `a^b·ln a·b'` when the exponent is not constant, which needs
/// `a > 0` (it is NaN otherwise, as is `powf` itself for a negative base).
///
/// # Example
///
/// This example is compiled and run as `tests/tests/macros/doc_example.rs`.
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
    expand::expand(args.into(), item.into())
        .unwrap_or_else(expand::Rejected::into_tokens)
        .into()
}

/// Turns `fn name(x, v, [t: f64,] constants: f64...) -> [f64; D] { body }` into a struct that
/// implements `varembed::Force<D>`, its Jacobian computed at compile time.
///
/// The fn is a generalised force `f(x, v, t)`, one component per degree of freedom; the
/// signature is a `#[lagrangian]` fn's with `x`, `v` either `f64` (the force then returns
/// `f64`) or `[f64; D]` with `D` an integer literal (the derivatives are written out entry by
/// entry). The macro keeps the fn and adds `struct CamelCaseName { pub constant: f64, … }`
/// implementing `Force<D>`:
///
/// - `force`, and `jacobian` (`∂f/∂x`, `∂f/∂v`, every entry differentiated on its own: the
///   blocks of a force are in general not symmetric), each with its common subexpressions
///   computed once;
/// - `jacobian_dependence`: which of `x`, `v`, `t` each block reads, from the symbolic
///   derivatives (a linear damping has constant blocks, which keeps the model's closed-form
///   steps);
/// - `constants`, and `NAME::DERIVATIVES`, the components and Jacobian entries as text.
///
/// A force that shares constants with the model is constructed with the same values: its
/// struct and the model's are separate values, and nothing ties their fields.
///
/// The body is what a `#[lagrangian]` body may be, ending with an array `[f0, f1, …]` (after
/// any `let`s), a helper's array, or a local array set element by element:
/// `let mut f = [0.0; 2]; for i in 0..2 { f[i] = …; } f` (also `f[i] += …`). Every loop runs
/// over a literal range and is unrolled, so that `x` and `v` are read at constant indices
/// (`x[(i + 1) % D]` included); a loop over a `const` range is a compile error, as is anything
/// else a `#[lagrangian]` body may not hold, each on its tokens.
///
/// **With loops.** Over a named dimension (`x: [f64; N]`, returning `[f64; N]`) or slices
/// (`x: &[f64]` with a `usize` constant `n`, returning `Vec<f64>`), the body starts from a zero
/// force, `let mut f = [0.0; N];` (`vec![0.0; n]`), adds to its components, `f[i] += …;` or
/// `f[i + 1] -= …;` in straight-line code or in loops, and ends with `f`. The force is
/// differentiated as its virtual work `Σ_k w_k f_k`, term by term like a Lagrangian with loops
/// (the generated code keeps the loops), and the macro implements `Force<N>` and
/// `varembed::DynForce` (over slices, `DynForce` alone), with `bandwidth` read off the index
/// expressions and `invalid_dimension` checking the indices at a run-time `n`
/// (`core/docs/forces.md`, "A force with loops"):
///
/// ```ignore
/// #[force]
/// fn dashpots(_x: &[f64], v: &[f64], n: usize, c: f64) -> Vec<f64> {
///     let mut f = vec![0.0; n];
///     for i in 0..n - 1 {
///         let pull = c * (v[i + 1] - v[i]);
///         f[i] += pull;
///         f[i + 1] -= pull;
///     }
///     f
/// }
/// ```
///
/// # Example
///
/// This example is compiled and run in `tests/tests/macros/doc_example.rs`.
///
/// ```ignore
/// use varembed::{Force, Vector, force};
///
/// /// A drag `f = −c |v| v` and a spring toward the origin that turns (not a gradient).
/// #[force]
/// fn drag(x: [f64; 2], v: [f64; 2], c: f64, w: f64) -> [f64; 2] {
///     let speed = v[0].hypot(v[1]);
///     [-c * speed * v[0] - w * x[1], -c * speed * v[1] + w * x[0]]
/// }
/// let f = Drag { c: 0.5, w: 2.0 };
/// let (x, v) = (Vector::<2>::new(1.0, 0.0), Vector::<2>::new(0.0, 2.0));
/// assert_eq!(f.force(&x, &v, 0.0)[1], -0.5 * 2.0 * 2.0 + 2.0);
/// let j = f.jacobian(&x, &v, 0.0);
/// assert_eq!((j.x[(0, 1)], j.x[(1, 0)]), (-2.0, 2.0));
/// ```
#[proc_macro_attribute]
pub fn force(args: TokenStream, item: TokenStream) -> TokenStream {
    expand::expand_as(ir::Attr::Force, args.into(), item.into())
        .unwrap_or_else(expand::Rejected::into_tokens)
        .into()
}

/// Turns `fn name(x, constants: f64...) -> [f64; M] { body }` into a struct that implements
/// `varembed::Constraint<D, M>`: `M` holonomic constraints `g(x) = 0`.
///
/// `x` is `f64` or `[f64; D]` (`D` an integer literal), then any number of `f64` constants.
/// A constraint depends on `x` alone: a parameter `v` or `t`, or a body that reads them, is a
/// compile error naming it. The macro keeps the fn and adds a struct (named and built like a
/// `#[lagrangian]` fn's) implementing `Constraint<D, M>`: `value` (`g`), `jacobian` (`G`, row
/// `k` the gradient of `g_k`) and `weighted_hessian` (`Σ_k λ_k ∂²g_k/∂x²`, symmetric, each
/// entry written once), from symbolic derivatives; and `NAME::DERIVATIVES`. The body is what a
/// `#[force]` body may be.
///
/// # Example
///
/// This example is compiled and run in `tests/tests/macros/doc_example.rs`.
///
/// ```ignore
/// use varembed::{Constraint, Vector, constraint};
/// use nalgebra::SVector;
///
/// /// Two rods: the first point at distance `a` from the origin, the second at `b` from it.
/// #[constraint]
/// fn rods(x: [f64; 4], a: f64, b: f64) -> [f64; 2] {
///     let d = [x[2] - x[0], x[3] - x[1]];
///     [x[0] * x[0] + x[1] * x[1] - a * a, d[0] * d[0] + d[1] * d[1] - b * b]
/// }
/// let g = Rods { a: 1.0, b: 2.0 };
/// let x = Vector::<4>::new(1.0, 0.0, 1.0, 2.0);
/// assert_eq!(g.value(&x), SVector::<f64, 2>::zeros());
/// assert_eq!(g.jacobian(&x)[(1, 3)], 4.0);
/// let h = g.weighted_hessian(&x, &SVector::<f64, 2>::new(1.0, 0.5));
/// assert_eq!((h[(0, 0)], h[(0, 2)], h[(2, 2)]), (3.0, -1.0, 1.0));
/// ```
#[proc_macro_attribute]
pub fn constraint(args: TokenStream, item: TokenStream) -> TokenStream {
    expand::expand_as(ir::Attr::Constraint, args.into(), item.into())
        .unwrap_or_else(expand::Rejected::into_tokens)
        .into()
}

/// The relay of `#[lagrangian(helper)]` fns (see `helpers.rs`): not to be called by hand.
#[doc(hidden)]
#[proc_macro]
pub fn __lagrangian_helpers(input: TokenStream) -> TokenStream {
    expand::expand_gathered(input.into()).into()
}
