//! A differential fuzzer of `#[lagrangian]`: random Lagrangians, each differentiated by the
//! macro and by num-dual, must agree. A second test does the same for `#[force]` and
//! `#[constraint]` fns (one for every four Lagrangians, of dimension 1–4, each component a
//! loop-free body of the same language, written as an array, through `let`s, or set element
//! by element in an unrolled loop): the components, every Jacobian entry and a constraint's
//! `Σ_k λ_k ∂²g_k/∂x²` against hyper-dual numbers ([`check_vector`]). A third checks `#[force]`
//! fns with loops over a named dimension ([`check_looped_force`], below).
//!
//! `tests/build.rs` draws the programs from a fixed seed (100 by default, the 500 of the
//! figures below where the environment variable `CI` is set, as `.ci/run` sets it; e.g.
//! `CI=true cargo test -p varembed-tests --test macro_fuzz`) and writes them to
//! `OUT_DIR/macro_fuzz.rs`, included below. A program is one Lagrangian of dimension 1–8
//! written three times: a `#[lagrangian]` fn of arrays `[f64; N]` (the dimension a `const` or
//! a literal), a `#[lagrangian]` fn of slices whose dimension is the run-time constant
//! `n: usize`, and a generic fn over num-dual numbers that evaluates the same formula
//! straightforwardly (the oracle: its sums are loops adding to a local, its helpers are
//! rewritten by hand, nothing of the macro's transformation is in it). The bodies use the
//! language of core/docs/macro.md: `for` loops and iterator sums, nested and triangular loops,
//! accumulators declared outside and inside loops, sums bound to locals and used again
//! (squared, multiplied, divided, as a centre of mass read in a second loop), branches on
//! real and index conditions, helper fns, neighbour `x[i + 1]`, periodic `x[(i + 1) % N]`
//! and strided `x[2 * i + 1]` indices, time, model constants, and the `f64` functions on
//! arguments where they are defined (every one of the language: `exp_m1`, `ln_1p`, `atan2`,
//! `max`, `min`, `hypot`, and `powf` with a number or an expression as exponent among them).
//!
//! At random points (`x`, `v` uniform in `[−1, 1]`, `t` in `[0, 2]`; 3 per program, or
//! `VAREMBED_FUZZ_POINTS`) it checks:
//!
//! - `L` from both fns, from `Lagrangian::value` and from both `DynLagrangian::value`s, the
//!   gradient `(∂L/∂x, ∂L/∂v)` and the three Hessian blocks `xx`, `xv`, `vv` of the array
//!   model's `Lagrangian<N>` and of the slice model's `DynLagrangian`, against num-dual's
//!   hyper-dual numbers (every entry from its own evaluation, exact up to rounding);
//! - the array model's `DynLagrangian` against its `Lagrangian<N>` (bit for bit, as
//!   core/docs/macro.md states), and its fused methods (`gradient_and_hessian`,
//!   `value_and_gradient`) against the separate ones (bit for bit);
//! - the claimed sparsity: with `hessian_bandwidth() = Some(b)` every entry `|i − j| > b` of
//!   every block is exactly 0.0; a block that `hessian_dependence()` says does not depend on
//!   `x` (`v`, `t`) is unchanged, bit for bit, when `x` (`v`, `t`) is redrawn, and so is `L`
//!   where `dependence()` says so; `invalid_dimension()` finds nothing.
//!
//! **Looped forces.** One for every four Lagrangians (25 by default, 125 under `CI`), of
//! dimension `N = 1–8`, written three times: a `#[force]` fn over `[f64; N]` returning
//! `[f64; N]` (its `Force<N>` and `DynForce` impls), the same over slices with the run-time
//! `n: usize` returning `Vec<f64>` (a `DynForce`), and a generic fn over num-dual numbers that
//! pushes every contribution to `f[i]` onto the `i`th of an array of lists (the oracle: plain
//! loops, nothing of the macro's transformation). The body declares `f` once (first, or after
//! the sums that lead it), adds to it with `f[idx] += e` / `-= e` and ends with `f`, in one to
//! three parts: a scatter over links `(i, i + 1)` in `0..N - 1` or `(i - 1, i)` in `1..N` (each
//! link adding to both ends), a gather (`f[i]`, `f[N - 1 - i]`, `f[i + 1]`, `f[i - 1]` over
//! `0..N`, `1..N`, `0..N - 1`, `0..=N - 1`, with quadratic drag), a periodic ring
//! (`(i + 1) % N`, `(i + N - 1) % N`), neighbours guarded by `if i > 0`, `if i >= 1`,
//! `if i == 0` and `if i + 1 < N`, straight-line additions to `f[0]`, `f[1]`, `f[N / 2]`,
//! `f[N - 1]`, double loops (every pair, every pair once adding to both, an iterator sum times
//! an outer component), a sum bound to a local or accumulated in a loop and entering
//! polynomially (times a component, squared, a mean `s / N as f64`, a deviation from it
//! squared), and drives in `t` and the constants. The right-hand sides are the Lagrangians'
//! loop bodies (functions, branches on real and index conditions, helpers, `let`s, `t`,
//! constants). A force reads `x` and `v`, only one of them, or neither; at `N = 1` its links
//! `0..N - 1` and `1..N` are empty. At each point it checks the force and every entry of
//! `∂f/∂x`, `∂f/∂v` of `Force<N>` and of the slice model's `DynForce` against the oracle (one
//! dual evaluation per column, the scale of an entry the sum of its contributions' magnitudes
//! as for `L`, its floor at least `1e-3 · 10`: `ForceOracle::floor`), the array model's
//! `DynForce` against its `Force<N>` bit for bit, `add_force` adding to what its buffer holds,
//! with `bandwidth() = Some(b)` every entry `|i − j| > b` of both blocks exactly 0.0, the blocks
//! that `jacobian_dependence()` says do not depend on `x` (`v`, `t`) unchanged bit for bit when
//! that is redrawn (the impls claiming the same dependence and band), and
//! `invalid_dimension(N)` `None`, `invalid_dimension(N + 1)` `Some`.
//! **What it found.** A negated component in a branch or an argument of `max`
//! (`if x[0] > 0.0 { -x[0] } else { 0.0 }`, `(-x[i]).max(0.2)`) made `#[force]` over a named
//! dimension or slices panic at compile time: the derivative of the negation with respect to a
//! weight of the virtual work was `−0.0`, the branch between `−0.0` and `0.0` a node of its own,
//! and the weight survived into the generated code. The components are now the virtual work
//! with the weights substituted, and a zero derivative is `+0`.
//!
//! **Tolerance.** An oracle entry is a sum of the contributions of the terms that make `L`
//! (the oracle hands each one over: an iteration of a top-level loop, an additive term
//! outside loops), and a generated entry is the same quantity summed in another order and
//! arrangement. Its scale `S` is the sum of the absolute values of those contributions'
//! entries, so that an entry that cancels is not held to a relative error it could never
//! reach; and an entry is held to `1e-12 · max(S, 1e-3 · S_max)`, with `S_max` the largest
//! scale among the entries of the same quantity (`L`, the gradient, the Hessian), so that an
//! entry which is exactly zero in exact arithmetic but is computed from terms as large as the
//! others may come out a few rounding errors from zero (`1e-15 · S_max`), and no more. `S_max`
//! is at least 10, as for the looped forces: the parts the macro adds up are of the size of the
//! programs' coefficients even where `L` is small, which the scale does not see where they sit
//! inside a bound sum or where two index expressions name one component (`Oracle::floor`; seeds
//! 7 and 10 found one program each, off by 4e-17 and 2.2e-15).
//!
//! Every mismatch of every program is collected; the test fails with one message that lists
//! them (program id, forms, the quantity, the numbers, the program's text) after a table of
//! the forms the failing programs use. The generated programs, oracles included, are in the
//! file named in the message.
//!
//! `VAREMBED_FUZZ_COUNT=5000` runs a longer campaign, `VAREMBED_FUZZ_SEED=…` another. The
//! default level, `full`, includes nonlinear functions of sums (`s.sqrt()`,
//! `(1.0 + s * s).ln()`, `1.0 / (2.0 + s * s)`, `s.sin()`, …), a sum in an `if` condition, a
//! quotient of sums and a bound sum inside another loop's function; `VAREMBED_FUZZ_LEVEL=legacy`
//! keeps to sums that enter `L` polynomially (the language the macro accepted before sums were
//! values). At the default seed both levels find 0 mismatches in the 500 programs of `CI`'s count
//! (and in the 125 vector and 125 looped force programs drawn with them), and 0 in the quick
//! count's 100, 25 and 25.
//!
//! **What it finds.** Run at the legacy level against the macro as it was before sums became
//! values (the `macros/` of commit `b5fb080`, with this file and `tests/build.rs` unchanged),
//! it found 40 444 mismatches in 150 of the 500 programs: every program with an accumulator
//! declared inside a loop (63 of 63), 49 of the 56 that square a sum, 46 of the 52 with a
//! centre of mass, and a wrong value of `L` itself in 149 of the 150.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::panic::{self, AssertUnwindSafe};

use num_dual::{Dual64, DualNum, HyperDual64};
use varembed::{
    Constraint, Dependence, DynForce, DynLagrangian, Force, ForceDependence, Hessian,
    HessianDependence, Lagrangian, SparseForceJacobian, SparseHessian, Vector, constraint, force,
    lagrangian,
};
use varembed_tests::rng::Rng;

// The programs: `SEED`, `LEVEL`, `FORMS`, the helpers, one module per program and `PROGRAMS`.
include!(concat!(env!("OUT_DIR"), "/macro_fuzz.rs"));

/// The generated file, named in the failure message.
const GENERATED: &str = concat!(env!("OUT_DIR"), "/macro_fuzz.rs");

/// The relative tolerance against the scale of the contributions.
const TOLERANCE: f64 = 1e-12;
/// The floor of an entry's scale, relative to the largest of its quantity (see the docs).
const FLOOR: f64 = 1e-3;
/// The least scale of the largest entry of a quantity, for Lagrangians and looped forces (see
/// `Oracle::floor` and `ForceOracle::floor`).
const SUM_SCALE: f64 = 10.0;
/// Mismatch lines shown per program (all are counted).
const SHOWN: usize = 8;

/// `L` at `(x, v, t)`, of slices.
type ValueFn<'a> = dyn Fn(&[f64], &[f64], f64) -> f64 + 'a;
/// `∂L/∂x` or `∂L/∂v` at `(x, v, t)`, written into a buffer.
type GradientFn<'a> = dyn Fn(&[f64], &[f64], f64, &mut [f64]) + 'a;
/// The second derivatives at `(x, v, t)`, added to a `SparseHessian`.
type HessianFn<'a> = dyn Fn(&[f64], &[f64], f64, &mut SparseHessian) + 'a;
/// A method of `Lagrangian<D>` at `(x, v, t)`.
type ConstFn<'a, const D: usize, R> = dyn Fn(&Vector<D>, &Vector<D>, f64) -> R + 'a;
/// The oracle: the terms of `L` at `(x, v, t)`, pushed.
type OracleFn<'a> = dyn Fn(&[HyperDual64], &[HyperDual64], f64, &mut Vec<HyperDual64>) + 'a;
/// The blocks `xx`, `xv`, `vv`, dense, row by row.
type Blocks = [Vec<Vec<f64>>; 3];
/// `L` and the blocks at `(x, v, t)`.
type EvalFn<'a> = dyn Fn(&[f64], &[f64], f64) -> (f64, Blocks) + 'a;

/// One generated program, as `check` sees it.
pub struct Program<'a, const D: usize> {
    pub id: usize,
    pub forms: &'static [&'static str],
    /// The two `#[lagrangian]` fns, as written.
    pub text: &'static str,
    pub time: bool,
    /// The array model (`[f64; N]`) through its `Lagrangian<N>` impl.
    pub array: ConstModel<'a, D>,
    /// Its other derivative methods, for one program in four: the compile time of the test
    /// is mostly that of the generated methods.
    pub every_method: Option<OtherMethods<'a, D>>,
    /// The array model through its `DynLagrangian` impl, for every other program (for the
    /// same reason).
    pub array_dyn: Option<DynModel<'a>>,
    /// The slice model, of run-time dimension `n = N`.
    pub slice: DynModel<'a>,
    /// The array fn itself, called on slices.
    pub array_fn: &'a ValueFn<'a>,
    /// The slice fn itself.
    pub slice_fn: &'a ValueFn<'a>,
    /// The oracle: pushes the terms whose sum is `L`.
    pub oracle: &'a OracleFn<'a>,
}

/// The structural claims of a model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Claims {
    pub bandwidth: Option<usize>,
    pub hessian: HessianDependence,
    pub value: Dependence,
}

/// A `Lagrangian<D>` through `value`, the fused `gradient_and_hessian` (what the solvers
/// call) and its claims.
pub struct ConstModel<'a, const D: usize> {
    value: Box<ConstFn<'a, D, f64>>,
    fused: Box<ConstFn<'a, D, (Vector<D>, Vector<D>, Hessian<D>)>>,
    claims: Claims,
}

/// The methods of `lag` that every program checks.
pub fn const_model<const D: usize, L: Lagrangian<D>>(lag: &L) -> ConstModel<'_, D> {
    ConstModel {
        value: Box::new(|x, v, t| lag.value(x, v, t)),
        fused: Box::new(|x, v, t| lag.gradient_and_hessian(x, v, t)),
        claims: Claims {
            bandwidth: lag.hessian_bandwidth(),
            hessian: lag.hessian_dependence(),
            value: lag.dependence(),
        },
    }
}

/// The derivative methods of a `Lagrangian<D>` that the solvers call less, each of which the
/// macro writes out separately (its own evaluation plan).
pub struct OtherMethods<'a, const D: usize> {
    gradient: Box<ConstFn<'a, D, (Vector<D>, Vector<D>)>>,
    hessian: Box<ConstFn<'a, D, Hessian<D>>>,
    value_and_gradient: Box<ConstFn<'a, D, (f64, Vector<D>, Vector<D>)>>,
}

/// The methods of `lag` that one program in four checks.
pub fn other_methods<const D: usize, L: Lagrangian<D>>(lag: &L) -> OtherMethods<'_, D> {
    OtherMethods {
        gradient: Box::new(|x, v, t| lag.gradient(x, v, t)),
        hessian: Box::new(|x, v, t| lag.hessian(x, v, t)),
        value_and_gradient: Box::new(|x, v, t| lag.value_and_gradient(x, v, t)),
    }
}

/// A `DynLagrangian` through the methods the check calls. Not a trait object: that would
/// compile every provided method too (the default `energy`, which inlines `value` and
/// `momentum`, was a sixth of the test's code).
pub struct DynModel<'a> {
    value: Box<ValueFn<'a>>,
    force: Box<GradientFn<'a>>,
    momentum: Box<GradientFn<'a>>,
    hessian: Box<HessianFn<'a>>,
    claims: Claims,
    dimension: usize,
    invalid_dimension: Option<String>,
}

/// The methods of `lag` that every program checks.
pub fn dyn_model<L: DynLagrangian>(lag: &L) -> DynModel<'_> {
    DynModel {
        value: Box::new(|x, v, t| lag.value(x, v, t)),
        force: Box::new(|x, v, t, f| lag.force(x, v, t, f)),
        momentum: Box::new(|x, v, t, p| lag.momentum(x, v, t, p)),
        hessian: Box::new(|x, v, t, h| lag.hessian(x, v, t, h)),
        claims: Claims {
            bandwidth: lag.hessian_bandwidth(),
            hessian: lag.hessian_dependence(),
            value: lag.dependence(),
        },
        dimension: lag.dimension(),
        invalid_dimension: lag.invalid_dimension(),
    }
}

/// What one program's check found.
#[derive(Default)]
pub struct Report {
    id: usize,
    dimension: usize,
    forms: &'static [&'static str],
    text: &'static str,
    /// `(kind, line)` per mismatch.
    mismatches: Vec<(&'static str, String)>,
}

impl Report {
    fn mismatch(&mut self, kind: &'static str, line: String) {
        self.mismatches.push((kind, line));
    }
}

/// The oracle's value and derivatives at one point, each with its scale.
struct Oracle {
    value: (f64, f64),
    /// `∂L/∂z_a` for `z = (x, v)`, with scales.
    gradient: Vec<(f64, f64)>,
    /// `∂²L/∂z_a∂z_b`, with scales.
    hessian: Vec<Vec<(f64, f64)>>,
}

impl Oracle {
    fn at<const D: usize>(p: &Program<'_, D>, x: &[f64], v: &[f64], t: f64) -> Oracle {
        let m = 2 * D;
        let z: Vec<f64> = x.iter().chain(v).copied().collect();
        let mut terms = Vec::new();
        // One hyper-dual evaluation per pair `(a, b)`: `eps1` carries `∂/∂z_a`, `eps2`
        // `∂/∂z_b`, `eps1eps2` the mixed second derivative (`a = m`: no direction).
        let mut eval = |a: usize, b: usize| -> (f64, f64, f64, f64, f64, f64) {
            let w: Vec<HyperDual64> = (0..m)
                .map(|k| {
                    HyperDual64::new(
                        z[k],
                        f64::from(u8::from(k == a)),
                        f64::from(u8::from(k == b)),
                        0.0,
                    )
                })
                .collect();
            terms.clear();
            (p.oracle)(&w[..D], &w[D..], t, &mut terms);
            let sum = |part: &dyn Fn(&HyperDual64) -> f64| -> (f64, f64) {
                terms
                    .iter()
                    .fold((0.0, 0.0), |(s, a), e| (s + part(e), a + part(e).abs()))
            };
            let (re, re_scale) = sum(&|e| e.re);
            let (d1, d1_scale) = sum(&|e| e.eps1);
            let (d2, d2_scale) = sum(&|e| e.eps1eps2);
            (re, re_scale, d1, d1_scale, d2, d2_scale)
        };
        let (re, re_scale, ..) = eval(m, m);
        let mut gradient = vec![(0.0, 0.0); m];
        let mut hessian = vec![vec![(0.0, 0.0); m]; m];
        for a in 0..m {
            for b in a..m {
                let (_, _, d1, d1_scale, d2, d2_scale) = eval(a, b);
                if a == b {
                    gradient[a] = (d1, d1_scale);
                }
                hessian[a][b] = (d2, d2_scale);
                hessian[b][a] = (d2, d2_scale);
            }
        }
        Oracle {
            value: (re, re_scale),
            gradient,
            hessian,
        }
    }

    /// The floor of every entry's scale: `FLOOR` times the largest scale of `L`, its gradient
    /// and its Hessian, and at least `FLOOR · SUM_SCALE`, as for the looped forces: the parts
    /// the macro's code adds up are of the size of the programs' coefficients (order one) even
    /// where `L` and its derivatives are small, and the oracle's scale does not see them.
    /// - A sum bound to a local enters as one contribution: `−tanh(s)` at seed 10 has
    ///   `L_xx[0, 3] = −tanh''(s) ∂s/∂x₀ ∂s/∂x₃ ≈ 1.7e-4`, each factor a sum of terms of order
    ///   one that nearly cancel, off by 2.2e-15 (10 ε).
    /// - Two index expressions naming the same component at this dimension (`v[N − 1 − j]` and
    ///   `v[j]` at `j = (N − 1)/2`) are two partial derivatives in the macro's code, which cancel
    ///   only in their sum, whereas in the oracle the component is one number: `0.8 s²` with
    ///   `s = (v[N − 1 − j] − v[j]) x[j] + atan(v[j]) (v[j] x[j])² 0.6 x[j]³` at `N = 1` (seed
    ///   7) has `L_vv ≈ 2.6e-9`, made of parts `±0.8 x²` whose rounding (4e-17) is 1.7e-8 of it.
    fn floor(&self) -> f64 {
        let largest = self
            .gradient
            .iter()
            .chain(self.hessian.iter().flatten())
            .map(|e| e.1)
            .fold(self.value.1.max(SUM_SCALE), f64::max);
        FLOOR * largest
    }
}

/// Records a mismatch unless `got` is within the tolerance of `want = (value, scale)`.
fn compare(
    out: &mut Report,
    kind: &'static str,
    what: impl FnOnce() -> String,
    got: f64,
    want: (f64, f64),
    floor: f64,
) {
    let tol = TOLERANCE * want.1.max(floor);
    // Written so that a NaN on either side is a mismatch.
    let within = (got - want.0).abs() <= tol;
    if !within {
        out.mismatch(
            kind,
            format!(
                "{}: generated {got:e}, oracle {:e} (scale {:.1e}, difference {:.1e})",
                what(),
                want.0,
                want.1,
                (got - want.0).abs()
            ),
        );
    }
}

/// Records a mismatch unless `a == b` exactly (`-0.0 == 0.0`).
fn same(out: &mut Report, kind: &'static str, what: impl FnOnce() -> String, a: f64, b: f64) {
    if a != b && !(a.is_nan() && b.is_nan()) {
        out.mismatch(kind, format!("{}: {a:e} ≠ {b:e}", what()));
    }
}

/// The number of random points per program.
fn points() -> usize {
    std::env::var("VAREMBED_FUZZ_POINTS")
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(3)
}

/// The three blocks of a `DynLagrangian` at a point, as dense row-major `D × D` arrays.
fn dyn_blocks(lag: &DynModel<'_>, x: &[f64], v: &[f64], t: f64) -> Blocks {
    let d = x.len();
    let mut h = SparseHessian::new(d);
    (lag.hessian)(x, v, t, &mut h);
    let dense = |b: &varembed::SparseBlock| -> Vec<Vec<f64>> {
        (0..d)
            .map(|i| (0..d).map(|j| b.get(i, j)).collect())
            .collect()
    };
    [dense(&h.xx), dense(&h.xv), dense(&h.vv)]
}

fn const_blocks<const D: usize>(h: &Hessian<D>) -> Blocks {
    let dense = |b: &varembed::Matrix<D>| -> Vec<Vec<f64>> {
        (0..D)
            .map(|i| (0..D).map(|j| b[(i, j)]).collect())
            .collect()
    };
    [dense(&h.xx), dense(&h.xv), dense(&h.vv)]
}

const BLOCKS: [&str; 3] = ["xx", "xv", "vv"];

/// The generated derivatives of one model against the oracle.
fn against_oracle(
    out: &mut Report,
    model: &str,
    o: &Oracle,
    force: &[f64],
    momentum: &[f64],
    blocks: &Blocks,
) {
    let d = force.len();
    let floor = o.floor();
    for i in 0..d {
        compare(
            out,
            "gradient",
            || format!("{model} ∂L/∂x[{i}]"),
            force[i],
            o.gradient[i],
            floor,
        );
        compare(
            out,
            "gradient",
            || format!("{model} ∂L/∂v[{i}]"),
            momentum[i],
            o.gradient[d + i],
            floor,
        );
    }
    for (k, block) in blocks.iter().enumerate() {
        let (ro, co) = match k {
            0 => (0, 0),
            1 => (0, d),
            _ => (d, d),
        };
        for i in 0..d {
            for j in 0..d {
                compare(
                    out,
                    "hessian",
                    || format!("{model} {}[({i}, {j})]", BLOCKS[k]),
                    block[i][j],
                    o.hessian[ro + i][co + j],
                    floor,
                );
            }
        }
    }
}

/// `Some(b)` ⇒ every entry beyond the band is exactly zero.
fn band(out: &mut Report, model: &str, claim: Option<usize>, blocks: &Blocks) {
    let Some(b) = claim else { return };
    for (k, block) in blocks.iter().enumerate() {
        for (i, row) in block.iter().enumerate() {
            for (j, &e) in row.iter().enumerate() {
                if i.abs_diff(j) > b && e != 0.0 {
                    out.mismatch(
                        "bandwidth",
                        format!(
                            "{model}: hessian_bandwidth() = Some({b}) but {}[({i}, {j})] = {e:e}",
                            BLOCKS[k]
                        ),
                    );
                }
            }
        }
    }
}

/// The claims of `hessian_dependence()` and `dependence()`: redrawing what a block (or `L`)
/// does not depend on leaves it unchanged, bit for bit.
#[allow(
    clippy::too_many_arguments,
    reason = "a model, its claims and the point"
)]
fn dependence_claims(
    out: &mut Report,
    model: &str,
    eval: &EvalFn<'_>,
    claims: Claims,
    rng: &mut Rng,
    x: &[f64],
    v: &[f64],
    t: f64,
) {
    let value_claim = claims.value;
    let claims = [claims.hessian.xx, claims.hessian.xv, claims.hessian.vv];
    let (l0, b0) = eval(x, v, t);
    let redraw = |rng: &mut Rng, w: &[f64]| -> Vec<f64> {
        w.iter().map(|_| rng.uniform(-1.0, 1.0)).collect()
    };
    for (name, which) in [("x", 0), ("v", 1), ("t", 2)] {
        let independent = |d: &Dependence| match which {
            0 => !d.x,
            1 => !d.v,
            _ => !d.t,
        };
        if !claims.iter().any(independent) && !independent(&value_claim) {
            continue;
        }
        let (x1, v1, t1) = match which {
            0 => (redraw(rng, x), v.to_vec(), t),
            1 => (x.to_vec(), redraw(rng, v), t),
            _ => (x.to_vec(), v.to_vec(), t + 0.75),
        };
        let (l1, b1) = eval(&x1, &v1, t1);
        if independent(&value_claim) && l0 != l1 {
            out.mismatch(
                "dependence",
                format!("{model}: dependence() says L does not depend on {name}, but L went from {l0:e} to {l1:e}"),
            );
        }
        for k in 0..3 {
            if !independent(&claims[k]) {
                continue;
            }
            let changed = (0..x.len())
                .flat_map(|i| (0..x.len()).map(move |j| (i, j)))
                .find(|&(i, j)| b0[k][i][j] != b1[k][i][j]);
            if let Some((i, j)) = changed {
                out.mismatch(
                    "dependence",
                    format!(
                        "{model}: hessian_dependence() says {} does not depend on {name}, but {}[({i}, {j})] went from {:e} to {:e}",
                        BLOCKS[k], BLOCKS[k], b0[k][i][j], b1[k][i][j]
                    ),
                );
            }
        }
    }
}

/// Checks one program at random points (the generated modules call it).
pub fn check<const D: usize>(out: &mut Report, p: &Program<'_, D>) {
    out.id = p.id;
    out.dimension = D;
    out.forms = p.forms;
    out.text = p.text;
    let mut rng = Rng(SEED ^ (p.id as u64 + 1).wrapping_mul(0xD1B5_4A32_D192_ED03));
    if let Some(why) = &p.slice.invalid_dimension {
        out.mismatch("invalid_dimension", format!("slice model: {why}"));
    }
    if p.slice.dimension != D {
        out.mismatch(
            "dimension",
            format!(
                "the slice model's dimension() is {}, not {D}",
                p.slice.dimension
            ),
        );
    }
    if let Some(array_dyn) = &p.array_dyn {
        if let Some(why) = &array_dyn.invalid_dimension {
            out.mismatch("invalid_dimension", format!("array model: {why}"));
        }
        if array_dyn.dimension != D {
            out.mismatch(
                "dimension",
                format!(
                    "the array model's dimension() is {}, not {D}",
                    array_dyn.dimension
                ),
            );
        }
        if array_dyn.claims != p.array.claims {
            out.mismatch(
                "array≠dyn",
                format!(
                    "the array model claims {:?} as a DynLagrangian, {:?} as a Lagrangian<N>",
                    array_dyn.claims, p.array.claims
                ),
            );
        }
    }
    for point in 0..points() {
        let x: Vec<f64> = (0..D).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let v: Vec<f64> = (0..D).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let t = if p.time { rng.uniform(0.0, 2.0) } else { 0.0 };
        let at = |s: &str| format!("point {point}: {s}");
        let o = Oracle::at(p, &x, &v, t);
        let vf = o.floor();
        let xs = Vector::<D>::from_column_slice(&x);
        let vs = Vector::<D>::from_column_slice(&v);

        // L, five ways.
        let l = (p.array.value)(&xs, &vs, t);
        compare(
            out,
            "value",
            || at("array fn L"),
            (p.array_fn)(&x, &v, t),
            o.value,
            vf,
        );
        compare(
            out,
            "value",
            || at("slice fn L"),
            (p.slice_fn)(&x, &v, t),
            o.value,
            vf,
        );
        compare(out, "value", || at("array Lagrangian<N> L"), l, o.value, vf);
        compare(
            out,
            "value",
            || at("slice DynLagrangian L"),
            (p.slice.value)(&x, &v, t),
            o.value,
            vf,
        );

        // The array model's `Lagrangian<N>`: the fused method, and for some programs every
        // method, the separate ones bit for bit the fused ones.
        let (f, q, h) = (p.array.fused)(&xs, &vs, t);
        let blocks = const_blocks(&h);
        against_oracle(
            out,
            &at("array Lagrangian<N>"),
            &o,
            f.as_slice(),
            q.as_slice(),
            &blocks,
        );
        if let Some(all) = &p.every_method {
            let (gf, gq) = (all.gradient)(&xs, &vs, t);
            let gh = const_blocks(&(all.hessian)(&xs, &vs, t));
            let (vl, vf, vq) = (all.value_and_gradient)(&xs, &vs, t);
            same(out, "fused", || at("value_and_gradient L vs value"), vl, l);
            for i in 0..D {
                let pairs = [
                    ("gradient ∂L/∂x", gf[i], f[i]),
                    ("gradient ∂L/∂v", gq[i], q[i]),
                    ("value_and_gradient ∂L/∂x", vf[i], f[i]),
                    ("value_and_gradient ∂L/∂v", vq[i], q[i]),
                ];
                for (what, a, b) in pairs {
                    same(
                        out,
                        "fused",
                        || at(&format!("{what}[{i}] vs gradient_and_hessian")),
                        a,
                        b,
                    );
                }
            }
            for (k, (a, b)) in gh.iter().zip(&blocks).enumerate() {
                for i in 0..D {
                    for j in 0..D {
                        same(
                            out,
                            "fused",
                            || {
                                at(&format!(
                                    "hessian {}[({i}, {j})] vs gradient_and_hessian",
                                    BLOCKS[k]
                                ))
                            },
                            a[i][j],
                            b[i][j],
                        );
                    }
                }
            }
        }
        band(
            out,
            &at("array Lagrangian<N>"),
            p.array.claims.bandwidth,
            &blocks,
        );

        // The array model's `DynLagrangian`, bit for bit its `Lagrangian<N>`.
        if let Some(array_dyn) = &p.array_dyn {
            let mut df = vec![0.0; D];
            let mut dq = vec![0.0; D];
            (array_dyn.force)(&x, &v, t, &mut df);
            (array_dyn.momentum)(&x, &v, t, &mut dq);
            let dblocks = dyn_blocks(array_dyn, &x, &v, t);
            let dl = (array_dyn.value)(&x, &v, t);
            same(out, "array≠dyn", || at("array DynLagrangian L"), dl, l);
            for i in 0..D {
                let what = |s: &str| at(&format!("array DynLagrangian ∂L/∂{s}[{i}]"));
                same(out, "array≠dyn", || what("x"), df[i], f[i]);
                same(out, "array≠dyn", || what("v"), dq[i], q[i]);
            }
            for k in 0..3 {
                for i in 0..D {
                    for j in 0..D {
                        same(
                            out,
                            "array≠dyn",
                            || at(&format!("array DynLagrangian {}[({i}, {j})]", BLOCKS[k])),
                            dblocks[k][i][j],
                            blocks[k][i][j],
                        );
                    }
                }
            }
        }

        // The slice model.
        let mut sf = vec![0.0; D];
        let mut sq = vec![0.0; D];
        (p.slice.force)(&x, &v, t, &mut sf);
        (p.slice.momentum)(&x, &v, t, &mut sq);
        let sblocks = dyn_blocks(&p.slice, &x, &v, t);
        against_oracle(out, &at("slice DynLagrangian"), &o, &sf, &sq, &sblocks);
        band(
            out,
            &at("slice DynLagrangian"),
            p.slice.claims.bandwidth,
            &sblocks,
        );

        // The dependence claims.
        let array_eval = |x: &[f64], v: &[f64], t: f64| {
            let (xs, vs) = (
                Vector::<D>::from_column_slice(x),
                Vector::<D>::from_column_slice(v),
            );
            (
                (p.array.value)(&xs, &vs, t),
                const_blocks(&(p.array.fused)(&xs, &vs, t).2),
            )
        };
        let slice_eval = |x: &[f64], v: &[f64], t: f64| {
            ((p.slice.value)(x, v, t), dyn_blocks(&p.slice, x, v, t))
        };
        dependence_claims(
            out,
            &at("array Lagrangian<N>"),
            &array_eval,
            p.array.claims,
            &mut rng,
            &x,
            &v,
            t,
        );
        dependence_claims(
            out,
            &at("slice DynLagrangian"),
            &slice_eval,
            p.slice.claims,
            &mut rng,
            &x,
            &v,
            t,
        );
    }
}

/// The message of a panic.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

/// A vector program's components, or rows of derivatives, at `(x, v, t)`.
type VectorFn<'a, R> = dyn Fn(&[f64], &[f64], f64) -> R + 'a;
/// A constraint's weighted Hessian at `(x, λ)`, row by row.
type WeightedFn<'a> = dyn Fn(&[f64], &[f64]) -> Vec<Vec<f64>> + 'a;
/// A vector program's oracle: its components on hyper-dual numbers.
type VectorOracleFn<'a> = dyn Fn(&[HyperDual64], &[HyperDual64], f64) -> Vec<HyperDual64> + 'a;

/// A generated `#[force]` or `#[constraint]` fn, as [`check_vector`] sees it.
pub struct VectorProgram<'a> {
    pub id: usize,
    pub force: bool,
    /// The dimension `D` and the number of components `M` (a force: `D`).
    pub d: usize,
    pub m: usize,
    /// The fn, as written.
    pub text: &'static str,
    /// `f` or `g` at `(x, v, t)`.
    pub value: &'a VectorFn<'a, Vec<f64>>,
    /// Row `i`: `[∂f_i/∂x | ∂f_i/∂v]` (a constraint: `[G_i | 0]`).
    pub jacobian: &'a VectorFn<'a, Vec<Vec<f64>>>,
    /// A constraint's `Σ_k λ_k ∂²g_k/∂x²` at `(x, λ)`.
    pub weighted: Option<&'a WeightedFn<'a>>,
    /// The components on hyper-dual numbers.
    pub oracle: &'a VectorOracleFn<'a>,
}

/// Checks a vector program at random points against its oracle: the components, every
/// Jacobian entry (one dual direction per column) and, for a constraint, every entry of
/// `Σ_k λ_k ∂²g_k/∂x²` at random `λ` (one hyper-dual evaluation per pair), each within
/// `TOLERANCE · max(|oracle|, 1)` (a component is a single expression of bounded terms); and
/// the weighted Hessian symmetric, bit for bit.
pub fn check_vector(out: &mut Report, p: &VectorProgram<'_>) {
    out.dimension = p.d;
    out.text = p.text;
    out.forms = if p.force { &["force"] } else { &["constraint"] };
    let (d, m) = (p.d, p.m);
    let mut rng = Rng(0xF0AC_E000 ^ p.id as u64);
    for _ in 0..points() {
        let x: Vec<f64> = (0..d).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let v: Vec<f64> = (0..d).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let t = rng.uniform(0.0, 2.0);
        let lambda: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let z: Vec<f64> = x.iter().chain(&v).copied().collect();
        let eval = |a: usize, b: usize| -> Vec<HyperDual64> {
            let w: Vec<HyperDual64> = (0..2 * d)
                .map(|k| {
                    let (e1, e2) = (u8::from(k == a), u8::from(k == b));
                    HyperDual64::new(z[k], f64::from(e1), f64::from(e2), 0.0)
                })
                .collect();
            (p.oracle)(&w[..d], &w[d..], t)
        };
        let near = |out: &mut Report, kind, what: String, got: f64, want: f64| {
            compare(out, kind, || what, got, (want, want.abs()), 1.0);
        };
        let value = (p.value)(&x, &v, t);
        let base = eval(2 * d, 2 * d);
        for i in 0..m {
            near(out, "value", format!("component {i}"), value[i], base[i].re);
        }
        let jacobian = (p.jacobian)(&x, &v, t);
        for c in 0..2 * d {
            let column = eval(c, 2 * d);
            for i in 0..m {
                let what = format!("∂[{i}]/∂z[{c}] at x = {x:?}, v = {v:?}, t = {t}");
                near(out, "jacobian", what, jacobian[i][c], column[i].eps1);
            }
        }
        if let Some(weighted) = p.weighted {
            let h = weighted(&x, &lambda);
            for a in 0..d {
                for b in a..d {
                    let e = eval(a, b);
                    let want: f64 = (0..m).map(|k| lambda[k] * e[k].eps1eps2).sum();
                    let what = format!("Σλ∇²g[({a}, {b})] at x = {x:?}, λ = {lambda:?}");
                    near(out, "weighted hessian", what, h[a][b], want);
                    same(out, "symmetry", || format!("({a}, {b})"), h[a][b], h[b][a]);
                }
            }
        }
    }
}

/// A looped force's oracle: each contribution to component `i` pushed onto `f[i]`.
type ForceOracleFn<'a> = dyn Fn(&[Dual64], &[Dual64], f64, &mut [Vec<Dual64>]) + 'a;
/// A force and its Jacobian blocks `∂f/∂x`, `∂f/∂v` at a point, dense, row by row.
type ForceAt = (Vec<f64>, [Vec<Vec<f64>>; 2]);
/// A force model evaluated at `(x, v, t)`.
type ForceEvalFn<'a> = dyn Fn(&[f64], &[f64], f64) -> ForceAt + 'a;

const FORCE_BLOCKS: [&str; 2] = ["∂f/∂x", "∂f/∂v"];

/// A generated `#[force]` with loops over `N`, as [`check_looped_force`] sees it.
pub struct LoopedForce<'a, const D: usize> {
    pub id: usize,
    pub forms: &'static [&'static str],
    /// The two `#[force]` fns, as written.
    pub text: &'static str,
    pub time: bool,
    /// The force over `[f64; N]` through its `Force<N>` impl…
    pub array: &'a dyn Force<D>,
    /// … and through its `DynForce` impl.
    pub array_dyn: &'a dyn DynForce,
    /// The force over slices, of run-time dimension `n = N`.
    pub slice: &'a dyn DynForce,
    pub oracle: &'a ForceOracleFn<'a>,
}

fn const_force<const D: usize>(force: &dyn Force<D>, x: &[f64], v: &[f64], t: f64) -> ForceAt {
    let (xs, vs) = (
        Vector::<D>::from_column_slice(x),
        Vector::<D>::from_column_slice(v),
    );
    let f = force.force(&xs, &vs, t);
    let j = force.jacobian(&xs, &vs, t);
    let dense = |b: &varembed::Matrix<D>| -> Vec<Vec<f64>> {
        (0..D)
            .map(|i| (0..D).map(|k| b[(i, k)]).collect())
            .collect()
    };
    (f.iter().copied().collect(), [dense(&j.x), dense(&j.v)])
}

/// `add_force` from zero and `jacobian` into fresh blocks.
fn dyn_force(force: &dyn DynForce, x: &[f64], v: &[f64], t: f64) -> ForceAt {
    let d = x.len();
    let mut f = vec![0.0; d];
    force.add_force(x, v, t, &mut f);
    let mut j = SparseForceJacobian::new(d);
    force.jacobian(x, v, t, &mut j);
    let dense = |b: &varembed::SparseBlock| -> Vec<Vec<f64>> {
        (0..d)
            .map(|i| (0..d).map(|k| b.get(i, k)).collect())
            .collect()
    };
    (f, [dense(&j.x), dense(&j.v)])
}

/// The oracle's force and Jacobian at a point, each entry with its scale (the sum of the
/// absolute values of the contributions it adds up, as for `L`).
struct ForceOracle {
    value: Vec<(f64, f64)>,
    /// `[block][i][j]`.
    jacobian: [Vec<Vec<(f64, f64)>>; 2],
}

impl ForceOracle {
    fn at(oracle: &ForceOracleFn<'_>, x: &[f64], v: &[f64], t: f64) -> ForceOracle {
        let d = x.len();
        let z: Vec<f64> = x.iter().chain(v).copied().collect();
        let mut parts: Vec<Vec<Dual64>> = vec![Vec::new(); d];
        // One dual evaluation per column `c` of `[∂f/∂x | ∂f/∂v]` (`c = 2d`: no direction).
        let mut eval = |c: usize| -> Vec<((f64, f64), (f64, f64))> {
            let w: Vec<Dual64> = (0..2 * d)
                .map(|k| Dual64::new(z[k], f64::from(u8::from(k == c))))
                .collect();
            for p in &mut parts {
                p.clear();
            }
            oracle(&w[..d], &w[d..], t, &mut parts);
            parts
                .iter()
                .map(|p| {
                    p.iter().fold(((0.0, 0.0), (0.0, 0.0)), |(re, eps), e| {
                        (
                            (re.0 + e.re, re.1 + e.re.abs()),
                            (eps.0 + e.eps, eps.1 + e.eps.abs()),
                        )
                    })
                })
                .collect()
        };
        let value = eval(2 * d).iter().map(|e| e.0).collect();
        let mut jacobian = [vec![vec![(0.0, 0.0); d]; d], vec![vec![(0.0, 0.0); d]; d]];
        for c in 0..2 * d {
            for (i, e) in eval(c).into_iter().enumerate() {
                jacobian[c / d][i][c % d] = e.1;
            }
        }
        ForceOracle { value, jacobian }
    }

    /// `FLOOR` times the largest scale of the force and its Jacobian, and at least
    /// `FLOOR · SUM_SCALE`: a sum bound to a local is added up before the oracle pushes a
    /// contribution that reads it, so the scale of an entry does not count its terms (up to
    /// eight, each of order one), and an entry that cancels exactly in the oracle's order
    /// (`Σ_j g(x_j, x_{N−1−j}) (x_{N−1−j} − x_j)`, antisymmetric) may come out a few rounding
    /// errors of them from zero in the macro's.
    fn floor(&self) -> f64 {
        let largest = self
            .value
            .iter()
            .chain(self.jacobian.iter().flatten().flatten())
            .map(|e| e.1)
            .fold(SUM_SCALE, f64::max);
        FLOOR * largest
    }
}

/// A force and its Jacobian against the oracle.
fn against_force_oracle(out: &mut Report, model: &str, o: &ForceOracle, got: &ForceAt) {
    let floor = o.floor();
    for (i, &want) in o.value.iter().enumerate() {
        compare(
            out,
            "force",
            || format!("{model} f[{i}]"),
            got.0[i],
            want,
            floor,
        );
    }
    for (b, block) in o.jacobian.iter().enumerate() {
        for (i, row) in block.iter().enumerate() {
            for (j, &want) in row.iter().enumerate() {
                compare(
                    out,
                    "jacobian",
                    || format!("{model} {}[({i}, {j})]", FORCE_BLOCKS[b]),
                    got.1[b][i][j],
                    want,
                    floor,
                );
            }
        }
    }
}

/// `bandwidth() = Some(b)` ⇒ every entry of both blocks beyond the band is exactly zero.
fn force_band(out: &mut Report, model: &str, claim: Option<usize>, got: &ForceAt) {
    let Some(b) = claim else { return };
    for (k, block) in got.1.iter().enumerate() {
        for (i, row) in block.iter().enumerate() {
            for (j, &e) in row.iter().enumerate() {
                if i.abs_diff(j) > b && e != 0.0 {
                    out.mismatch(
                        "bandwidth",
                        format!(
                            "{model}: bandwidth() = Some({b}) but {}[({i}, {j})] = {e:e}",
                            FORCE_BLOCKS[k]
                        ),
                    );
                }
            }
        }
    }
}

/// The claims of `jacobian_dependence()`: redrawing what a block does not depend on leaves
/// it unchanged, bit for bit.
#[allow(
    clippy::too_many_arguments,
    reason = "a model, its claims and the point"
)]
fn force_dependence_claims(
    out: &mut Report,
    model: &str,
    eval: &ForceEvalFn<'_>,
    claims: ForceDependence,
    rng: &mut Rng,
    x: &[f64],
    v: &[f64],
    t: f64,
) {
    let claims = [claims.x, claims.v];
    let (_, b0) = eval(x, v, t);
    let redraw = |rng: &mut Rng, w: &[f64]| -> Vec<f64> {
        w.iter().map(|_| rng.uniform(-1.0, 1.0)).collect()
    };
    for (name, which) in [("x", 0), ("v", 1), ("t", 2)] {
        let independent = |d: &Dependence| match which {
            0 => !d.x,
            1 => !d.v,
            _ => !d.t,
        };
        if !claims.iter().any(independent) {
            continue;
        }
        let (x1, v1, t1) = match which {
            0 => (redraw(rng, x), v.to_vec(), t),
            1 => (x.to_vec(), redraw(rng, v), t),
            _ => (x.to_vec(), v.to_vec(), t + 0.75),
        };
        let (_, b1) = eval(&x1, &v1, t1);
        for k in 0..2 {
            if !independent(&claims[k]) {
                continue;
            }
            let changed = (0..x.len())
                .flat_map(|i| (0..x.len()).map(move |j| (i, j)))
                .find(|&(i, j)| b0[k][i][j] != b1[k][i][j]);
            if let Some((i, j)) = changed {
                out.mismatch(
                    "dependence",
                    format!(
                        "{model}: jacobian_dependence() says {} does not depend on {name}, but its ({i}, {j}) went from {:e} to {:e}",
                        FORCE_BLOCKS[k], b0[k][i][j], b1[k][i][j]
                    ),
                );
            }
        }
    }
}

/// Checks a looped force at random points: `Force<N>` (force and every Jacobian entry) and the
/// slice model's `DynForce` against the oracle's duals; the array model's `DynForce` against its
/// `Force<N>`, bit for bit; `add_force` adding to what the buffer holds; the declared band, the
/// claimed dependences (the three impls claiming the same) and `invalid_dimension`.
pub fn check_looped_force<const D: usize>(out: &mut Report, p: &LoopedForce<'_, D>) {
    out.id = p.id;
    out.dimension = D;
    out.forms = p.forms;
    out.text = p.text;
    let mut rng =
        Rng(SEED ^ 0x100F_ED0F_0ACE ^ (p.id as u64 + 1).wrapping_mul(0xD1B5_4A32_D192_ED03));
    let claims = p.array.jacobian_dependence();
    for (model, other) in [
        (
            "the array model's DynForce",
            p.array_dyn.jacobian_dependence(),
        ),
        ("the slice model", p.slice.jacobian_dependence()),
    ] {
        if other != claims {
            out.mismatch(
                "claims",
                format!("{model} claims {other:?}, the array model's Force<N> {claims:?}"),
            );
        }
    }
    if p.array_dyn.bandwidth() != p.slice.bandwidth() {
        out.mismatch(
            "claims",
            format!(
                "bandwidth() is {:?} over arrays, {:?} over slices",
                p.array_dyn.bandwidth(),
                p.slice.bandwidth()
            ),
        );
    }
    for (model, force) in [("array DynForce", p.array_dyn), ("slice DynForce", p.slice)] {
        if let Some(why) = force.invalid_dimension(D) {
            out.mismatch("invalid_dimension", format!("{model}, at N: {why}"));
        }
        if force.invalid_dimension(D + 1).is_none() {
            out.mismatch(
                "invalid_dimension",
                format!("{model}: invalid_dimension(N + 1) finds nothing"),
            );
        }
    }
    for point in 0..points() {
        let x: Vec<f64> = (0..D).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let v: Vec<f64> = (0..D).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let t = if p.time { rng.uniform(0.0, 2.0) } else { 0.0 };
        let at = |s: &str| format!("point {point}: {s}");
        let o = ForceOracle::at(p.oracle, &x, &v, t);

        let array = const_force::<D>(p.array, &x, &v, t);
        against_force_oracle(out, &at("array Force<N>"), &o, &array);
        force_band(out, &at("array Force<N>"), p.array_dyn.bandwidth(), &array);

        // The array model's `DynForce`, bit for bit its `Force<N>`.
        let array_dyn = dyn_force(p.array_dyn, &x, &v, t);
        for i in 0..D {
            same(
                out,
                "array≠dyn",
                || at(&format!("array DynForce f[{i}]")),
                array_dyn.0[i],
                array.0[i],
            );
            for b in 0..2 {
                for j in 0..D {
                    same(
                        out,
                        "array≠dyn",
                        || at(&format!("array DynForce {}[({i}, {j})]", FORCE_BLOCKS[b])),
                        array_dyn.1[b][i][j],
                        array.1[b][i][j],
                    );
                }
            }
        }
        force_band(
            out,
            &at("array DynForce"),
            p.array_dyn.bandwidth(),
            &array_dyn,
        );

        // The slice model; `add_force` adds to the buffer.
        let slice = dyn_force(p.slice, &x, &v, t);
        against_force_oracle(out, &at("slice DynForce"), &o, &slice);
        force_band(out, &at("slice DynForce"), p.slice.bandwidth(), &slice);
        let mut held: Vec<f64> = (0..D).map(|i| 1.0 + i as f64).collect();
        p.slice.add_force(&x, &v, t, &mut held);
        for (i, &h) in held.iter().enumerate() {
            let base = 1.0 + i as f64;
            compare(
                out,
                "add_force",
                || at(&format!("slice DynForce f[{i}] added to {base}")),
                h,
                (base + slice.0[i], base + slice.0[i].abs()),
                0.0,
            );
        }

        // The dependence claims.
        let array_eval = |x: &[f64], v: &[f64], t: f64| const_force::<D>(p.array, x, v, t);
        let slice_eval = |x: &[f64], v: &[f64], t: f64| dyn_force(p.slice, x, v, t);
        force_dependence_claims(
            out,
            &at("array Force<N>"),
            &array_eval,
            claims,
            &mut rng,
            &x,
            &v,
            t,
        );
        force_dependence_claims(
            out,
            &at("slice DynForce"),
            &slice_eval,
            p.slice.jacobian_dependence(),
            &mut rng,
            &x,
            &v,
            t,
        );
    }
}

/// Every generated Lagrangian against num-dual; one message lists every mismatch.
#[test]
fn generated_lagrangians_match_num_dual() {
    run_all(PROGRAMS, "programs");
}

/// Every generated `#[force]` and `#[constraint]` fn against num-dual, the same way.
#[test]
fn generated_forces_and_constraints_match_num_dual() {
    run_all(VECTOR_PROGRAMS, "force and constraint programs");
}

/// Every generated `#[force]` with loops over a named dimension against num-dual, the same way.
#[test]
fn generated_looped_forces_match_num_dual() {
    run_all(LOOPED_FORCE_PROGRAMS, "looped force programs");
}

/// Runs `programs` and fails with one message that lists every mismatch.
fn run_all(programs: &[fn(&mut Report)], noun: &str) {
    let mut reports = Vec::new();
    // A panicking model (an entry outside its dimension, an index out of bounds) is a
    // mismatch like the others: keep the default hook from printing each one.
    let hook = panic::take_hook();
    panic::set_hook(Box::new(|_| {}));
    for (k, run) in programs.iter().enumerate() {
        let mut report = Report {
            id: k,
            ..Report::default()
        };
        if let Err(payload) = panic::catch_unwind(AssertUnwindSafe(|| run(&mut report))) {
            report.mismatch("panic", format!("panicked: {}", panic_message(&*payload)));
        }
        reports.push(report);
    }
    panic::set_hook(hook);

    let failing: Vec<&Report> = reports
        .iter()
        .filter(|r| !r.mismatches.is_empty())
        .collect();
    let total: usize = failing.iter().map(|r| r.mismatches.len()).sum();
    let mut msg = String::new();
    let _ = writeln!(
        msg,
        "{} {noun} (seed {SEED:#x}, level `{LEVEL}`, {} points each): {total} mismatches in {} programs",
        reports.len(),
        points(),
        failing.len()
    );
    if !failing.is_empty() {
        let _ = writeln!(msg, "\nform: programs using it, of which failing");
        for form in FORMS {
            let using = reports.iter().filter(|r| r.forms.contains(form)).count();
            let bad = failing.iter().filter(|r| r.forms.contains(form)).count();
            if using > 0 {
                let _ = writeln!(msg, "  {form:<16} {using:>5} {bad:>5}");
            }
        }
        let mut kinds: BTreeMap<&str, (usize, usize)> = BTreeMap::new();
        for r in &failing {
            let mut seen = Vec::new();
            for (kind, _) in &r.mismatches {
                let e = kinds.entry(kind).or_default();
                e.1 += 1;
                if !seen.contains(kind) {
                    seen.push(kind);
                    e.0 += 1;
                }
            }
        }
        let _ = writeln!(msg, "\nquantity: programs, mismatches");
        for (kind, (programs, count)) in &kinds {
            let _ = writeln!(msg, "  {kind:<18} {programs:>5} {count:>7}");
        }
        let _ = writeln!(msg, "\nthe programs (and their oracles) are in {GENERATED}");
        for r in &failing {
            let _ = writeln!(
                msg,
                "\n=== program {} (N = {}) [{}]: {} mismatches",
                r.id,
                r.dimension,
                r.forms.join(", "),
                r.mismatches.len()
            );
            for (_, line) in r.mismatches.iter().take(SHOWN) {
                let _ = writeln!(msg, "  {line}");
            }
            if r.mismatches.len() > SHOWN {
                let _ = writeln!(msg, "  … and {} more", r.mismatches.len() - SHOWN);
            }
            msg.push_str(r.text);
        }
    }
    println!("{msg}");
    assert!(failing.is_empty(), "{msg}");
}
