//! Writes the programs of the differential fuzzer of `#[lagrangian]` (`tests/macro_fuzz.rs`)
//! into `OUT_DIR/macro_fuzz.rs`, from a fixed seed; and, from a generator of their own (so
//! that a seed's Lagrangians do not change), one `#[force]` or `#[constraint]` program for
//! every four ([`vector_program`]), and from a third one `#[force]` with loops over a named
//! dimension for every four ([`looped_force_program`]).
//!
//! Each program is one Lagrangian written three times: as a `#[lagrangian]` fn of arrays
//! `[f64; N]` (the dimension a `const` or a literal), as a `#[lagrangian]` fn of slices with a
//! run-time dimension `n: usize`, and as a plain generic fn over num-dual numbers, the oracle.
//! The oracle evaluates the same formula straightforwardly (every sum a loop adding to a
//! local, every accumulator a local, helpers rewritten by hand) and hands each term it adds
//! to `L` to its caller, so the test can weigh a derivative against the size of what was
//! added up to make it.
//!
//! The programs are drawn from the language of core/docs/macro.md, at one of two levels:
//!
//! - `legacy`: sums that enter `L` polynomially, products of sums and a bound sum times
//!   itself included (the language of the macro before sums were values);
//! - `full` (the default): also nonlinear functions of sums (`s.sqrt()`, `(1.0 + s * s).ln()`,
//!   `1.0 / (2.0 + s * s)`, `s.sin()`, …), a sum in an `if` condition, a quotient of sums, and a
//!   bound sum read inside another loop's nonlinear function.
//!
//! Environment: `VAREMBED_FUZZ_COUNT` (programs; by default 100, and 500 where `CI` is set,
//! as `.ci/run` sets it: the 500 cost about 4 CPU-minutes to compile, which the quick test
//! loop does not pay), `VAREMBED_FUZZ_SEED` (decimal
//! or `0x…` hex), `VAREMBED_FUZZ_LEVEL` (`legacy` or `full`). The generator has its own
//! SplitMix64, so that the build script needs no dependency.

use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::PathBuf;

/// The default seed: the programs a plain `cargo test` checks.
const DEFAULT_SEED: u64 = 0x5EED_F0A2_2024_0001;
/// Programs by default: a quick `cargo test` compiles these.
const QUICK_COUNT: usize = 100;
/// Programs by default where the environment variable `CI` is set (`.ci/run` sets it).
const CI_COUNT: usize = 500;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    for var in [
        "VAREMBED_FUZZ_COUNT",
        "VAREMBED_FUZZ_SEED",
        "VAREMBED_FUZZ_LEVEL",
        "CI",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    let count = env::var("VAREMBED_FUZZ_COUNT")
        .ok()
        .map(|s| {
            s.trim()
                .parse::<usize>()
                .expect("VAREMBED_FUZZ_COUNT: a number of programs")
        })
        .unwrap_or(match env::var("CI") {
            Ok(ci) if !ci.is_empty() && ci != "false" => CI_COUNT,
            _ => QUICK_COUNT,
        });
    let seed = env::var("VAREMBED_FUZZ_SEED")
        .ok()
        .map(|s| parse_seed(&s))
        .unwrap_or(DEFAULT_SEED);
    let level = match env::var("VAREMBED_FUZZ_LEVEL").as_deref() {
        Ok("legacy") => Level::Legacy,
        Err(_) | Ok("full") => Level::Full,
        Ok(other) => panic!("VAREMBED_FUZZ_LEVEL: `legacy` or `full`, not `{other}`"),
    };
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("macro_fuzz.rs"), generate(count, seed, level))
        .expect("OUT_DIR is writable");
}

fn parse_seed(s: &str) -> u64 {
    let s = s.trim().replace('_', "");
    let parsed = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => s.parse(),
    };
    parsed.expect("VAREMBED_FUZZ_SEED: a decimal or 0x-hex u64")
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Level {
    Legacy,
    Full,
}

/// SplitMix64, the file `varembed_tests::rng` includes (the build script cannot depend on the
/// crate it builds).
#[path = "src/rng/splitmix.rs"]
mod splitmix;

use splitmix::Rng;

impl Rng {
    fn chance(&mut self, p: f64) -> bool {
        self.next_f64() < p
    }
    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }
    /// A coefficient from a short list: readable, and none close to a named constant (which
    /// clippy would flag as an approximation of `PI` or `E`).
    fn coefficient(&mut self) -> f64 {
        self.pick(&[
            0.1, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.75, 0.8, 1.2, 1.25, 1.5, 2.0,
        ])
    }
}

// ---------------------------------------------------------------------------------------------
// The language: index expressions, real expressions, statements.

/// How the dimension is written in the `#[lagrangian]` fn being rendered.
#[derive(Clone, Copy)]
enum Dim {
    /// `N`, a `const` of the program's module.
    Named,
    /// An integer literal.
    Literal(usize),
    /// `n`, the run-time dimension (also how the oracle writes it).
    Runtime,
}

impl Dim {
    fn token(self) -> String {
        match self {
            Dim::Named => "N".into(),
            Dim::Literal(d) => d.to_string(),
            Dim::Runtime => "n".into(),
        }
    }
}

/// An index expression (a component, or the end of a range).
#[derive(Clone, PartialEq)]
enum Ix {
    Lit(usize),
    /// `D`.
    Dim,
    /// `D - 1`.
    Last,
    /// `D / 2`.
    Half,
    /// `i + c`.
    Var(String, usize),
    /// `D - 1 - i`.
    Mirror(String),
    /// `(i + 1) % D`.
    Next(String),
    /// `(i + D - 1) % D`.
    Prev(String),
    /// `2 * i + c`.
    Twice(String, usize),
    /// `i - c` (under a range or a guard that keeps it a component).
    Back(String, usize),
}

impl Ix {
    fn render(&self, dim: Dim) -> String {
        let d = dim.token();
        match self {
            Ix::Lit(k) => k.to_string(),
            Ix::Dim => d,
            Ix::Last => format!("{d} - 1"),
            // `5 / 2` would be clippy's `eq_op` at dimension 2 (`2 / 2`): a literal dimension
            // has its half written out.
            Ix::Half => match dim {
                Dim::Literal(n) => (n / 2).to_string(),
                Dim::Named | Dim::Runtime => format!("{d} / 2"),
            },
            Ix::Var(i, 0) => i.clone(),
            Ix::Var(i, c) => format!("{i} + {c}"),
            Ix::Mirror(i) => format!("{d} - 1 - {i}"),
            Ix::Next(i) => format!("({i} + 1) % {d}"),
            Ix::Prev(i) => format!("({i} + {d} - 1) % {d}"),
            Ix::Twice(i, 0) => format!("2 * {i}"),
            Ix::Twice(i, c) => format!("2 * {i} + {c}"),
            Ix::Back(i, c) => format!("{i} - {c}"),
        }
    }
    /// Whether it needs parentheses before `as f64`.
    fn is_compound(&self) -> bool {
        !matches!(self, Ix::Lit(_) | Ix::Dim | Ix::Var(_, 0))
    }
}

/// A loop range `lo..hi` (or `lo..=hi`).
#[derive(Clone)]
struct Range {
    lo: Ix,
    hi: Ix,
    inclusive: bool,
}

impl Range {
    fn render(&self, dim: Dim) -> String {
        let op = if self.inclusive { "..=" } else { ".." };
        format!("{}{op}{}", self.lo.render(dim), self.hi.render(dim))
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Fun {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    ExpM1,
    Ln,
    Ln1p,
    Log10,
    Sqrt,
    Cbrt,
    Recip,
    Abs,
}

impl Fun {
    fn name(self) -> &'static str {
        match self {
            Fun::Sin => "sin",
            Fun::Cos => "cos",
            Fun::Tan => "tan",
            Fun::Asin => "asin",
            Fun::Acos => "acos",
            Fun::Atan => "atan",
            Fun::Sinh => "sinh",
            Fun::Cosh => "cosh",
            Fun::Tanh => "tanh",
            Fun::Exp => "exp",
            Fun::ExpM1 => "exp_m1",
            Fun::Ln => "ln",
            Fun::Ln1p => "ln_1p",
            Fun::Log10 => "log10",
            Fun::Sqrt => "sqrt",
            Fun::Cbrt => "cbrt",
            Fun::Recip => "recip",
            Fun::Abs => "abs",
        }
    }
}

#[derive(Clone, Copy)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Clone, Copy)]
enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
}

impl Cmp {
    fn token(self) -> &'static str {
        match self {
            Cmp::Lt => "<",
            Cmp::Le => "<=",
            Cmp::Gt => ">",
            Cmp::Ge => ">=",
        }
    }
}

/// A condition of an `if`.
#[derive(Clone)]
enum Cond {
    Real(Cmp, E, E),
    /// Two indices compared (`i < j`, `i == 0`): `Some(cmp)` or `None` for `==`.
    Index(Option<Cmp>, Ix, Ix),
    And(Box<Cond>, Box<Cond>),
    Or(Box<Cond>, Box<Cond>),
}

/// A real expression.
#[derive(Clone)]
enum E {
    Num(f64),
    X(Ix),
    V(Ix),
    /// Model constant `k<j>`.
    K(usize),
    T,
    Local(String),
    /// An index as a number: `i as f64`, `(i + 1) as f64`, `D as f64`.
    IdxNum(Ix),
    /// `(D - i) as f64`.
    DimMinus(String),
    Neg(Box<E>),
    Bin(Op, Box<E>, Box<E>),
    F(Fun, Box<E>),
    Powi(Box<E>, i32),
    Powf(Box<E>, f64),
    Hypot(Box<E>, Box<E>),
    Max(Box<E>, Box<E>),
    /// `a.method(b)` for a method of two arguments other than `hypot` and `max`.
    Pair(PairFn, Box<E>, Box<E>),
    Signum(Box<E>),
    Helper(&'static str, Vec<E>),
    If(Box<Cond>, Box<E>, Box<E>),
    /// `(range).map(|i| body).sum::<f64>()`.
    Sum(String, Range, Box<E>),
    /// `{ let a = …; … e }`.
    Block(Vec<(String, E)>, Box<E>),
}

/// The methods of two arguments of [`E::Pair`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum PairFn {
    /// `y.atan2(x)`.
    Atan2,
    /// `a.powf(b)` with an exponent that is an expression (num-dual's `powd`).
    Powf,
    Min,
}

impl PairFn {
    fn name(self) -> &'static str {
        match self {
            PairFn::Atan2 => "atan2",
            PairFn::Powf => "powf",
            PairFn::Min => "min",
        }
    }
}

fn bin(op: Op, a: E, b: E) -> E {
    E::Bin(op, Box::new(a), Box::new(b))
}
fn add(a: E, b: E) -> E {
    bin(Op::Add, a, b)
}
fn sub(a: E, b: E) -> E {
    bin(Op::Sub, a, b)
}
fn mul(a: E, b: E) -> E {
    bin(Op::Mul, a, b)
}
fn div(a: E, b: E) -> E {
    bin(Op::Div, a, b)
}
fn num(a: f64) -> E {
    E::Num(a)
}
fn f(fun: Fun, a: E) -> E {
    E::F(fun, Box::new(a))
}
fn local(name: &str) -> E {
    E::Local(name.to_string())
}
/// `lo + y * y`.
fn positive(lo: f64, y: E) -> E {
    add(num(lo), mul(y.clone(), y))
}

/// Whether `text` has `word` as a whole word.
fn has_word(text: &str, word: &str) -> bool {
    text.match_indices(word).any(|(at, _)| {
        let part = |c: char| c.is_ascii_alphanumeric() || c == '_';
        let before = text[..at].chars().next_back().is_none_or(|c| !part(c));
        let after = text[at + word.len()..]
            .chars()
            .next()
            .is_none_or(|c| !part(c));
        before && after
    })
}

/// The text of `e` in the slice model (for the generator's own questions about it).
fn text(e: &E) -> String {
    render(e, Lang::Macro(Dim::Runtime)).0
}

/// Whether the text of `es` names the variable `var`.
fn mentions(es: &[&E], var: &str) -> bool {
    es.iter().any(|e| has_word(&text(e), var))
}

/// `e`, plus a small term in `x[i]` for each loop variable `i` of `vars` that neither `e` nor
/// `also` reads (an unused loop variable is a warning).
fn ensure_reads(e: E, also: &[&E], vars: &[&str]) -> E {
    let mut e = e;
    for var in vars {
        let mut all = also.to_vec();
        all.push(&e);
        if !mentions(&all, var) {
            e = add(e, mul(num(0.1), E::X(Ix::Var((*var).to_string(), 0))));
        }
    }
    e
}

/// A statement of a body.
#[derive(Clone)]
enum S {
    /// `let name = e;` (`let name: f64 = e;` when `typed`).
    Let(String, E, bool),
    /// `let mut name = e;`: an accumulator that is not `L`'s.
    LetMut(String, E),
    /// `name += e` (`-=` when `minus`) on an accumulator that is not `L`'s.
    Acc(String, E, bool),
    /// A contribution `±e` to `L`; where it goes is decided when the program is assembled.
    Term(E, bool),
    For(String, Range, Vec<S>),
}

// ---------------------------------------------------------------------------------------------
// Rendering: the `#[lagrangian]` fn's Rust and the oracle's.

#[derive(Clone, Copy, PartialEq)]
enum Lang {
    /// The `#[lagrangian]` fns: `f64` arithmetic as a user writes it.
    Macro(Dim),
    /// The oracle: generic `T` arithmetic, literals lifted by `c(…)`, run-time `n`.
    Oracle,
}

impl PartialEq for Dim {
    fn eq(&self, other: &Dim) -> bool {
        self.token() == other.token()
    }
}

impl Lang {
    fn dim(self) -> Dim {
        match self {
            Lang::Macro(d) => d,
            Lang::Oracle => Dim::Runtime,
        }
    }
}

/// Precedences: `if`/blocks 0, `+ -` 1, `* /` 2, unary and casts 3, atoms and calls 4.
fn paren(s: (String, u8), min: u8) -> String {
    if s.1 < min { format!("({})", s.0) } else { s.0 }
}

/// `e` in `lang`, with its precedence. In the oracle the value is a `T` (a lifted number
/// if the expression is a plain number).
fn render(e: &E, lang: Lang) -> (String, u8) {
    let Lang::Macro(dim) = lang else {
        let (s, p, scalar) = oracle(e);
        return if scalar {
            (format!("c({s})"), 4)
        } else {
            (s, p)
        };
    };
    let r = |e: &E| render(e, lang);
    match e {
        E::Num(a) => (format!("{a:?}"), if *a < 0.0 { 3 } else { 4 }),
        E::X(ix) => (format!("x[{}]", ix.render(dim)), 4),
        E::V(ix) => (format!("v[{}]", ix.render(dim)), 4),
        E::K(j) => (format!("k{j}"), 4),
        E::T => ("t".into(), 4),
        E::Local(name) => (name.clone(), 4),
        E::IdxNum(ix) => index_number(ix, dim),
        E::DimMinus(i) => (format!("({} - {i}) as f64", dim.token()), 3),
        E::Neg(a) => (format!("-{}", paren(r(a), 3)), 3),
        E::Bin(op, a, b) => {
            let (tok, p) = op.token();
            (
                format!("{} {tok} {}", paren(r(a), p), paren(r(b), p + 1)),
                p,
            )
        }
        E::F(fun, a) => (format!("{}.{}()", paren(r(a), 4), fun.name()), 4),
        E::Powi(a, k) => (format!("{}.powi({k})", paren(r(a), 4)), 4),
        E::Powf(a, p) => (format!("{}.powf({p:?})", paren(r(a), 4)), 4),
        E::Hypot(a, b) => (format!("{}.hypot({})", paren(r(a), 4), r(b).0), 4),
        E::Max(a, b) => (format!("{}.max({})", paren(r(a), 4), r(b).0), 4),
        E::Pair(g, a, b) => (format!("{}.{}({})", paren(r(a), 4), g.name(), r(b).0), 4),
        E::Signum(a) => (format!("{}.signum()", paren(r(a), 4)), 4),
        E::Helper(name, args) => {
            let args: Vec<String> = args.iter().map(|a| r(a).0).collect();
            (format!("{name}({})", args.join(", ")), 4)
        }
        E::If(c, a, b) => (
            format!(
                "if {} {{ {} }} else {{ {} }}",
                render_cond(c, lang),
                r(a).0,
                r(b).0
            ),
            0,
        ),
        E::Sum(i, range, body) => (
            format!(
                "({}).map(|{i}| {}).sum::<f64>()",
                range.render(dim),
                r(body).0
            ),
            4,
        ),
        E::Block(lets, value) => {
            let mut s = String::from("{ ");
            for (name, e) in lets {
                let _ = write!(s, "let {name} = {}; ", r(e).0);
            }
            let _ = write!(s, "{} }}", r(value).0);
            (s, 0)
        }
    }
}

/// An index as a number: `i as f64`, `(i + 1) as f64`, `N as f64`.
fn index_number(ix: &Ix, dim: Dim) -> (String, u8) {
    match (ix, dim) {
        // `5 as f64` is clippy's `unnecessary_cast`: a literal dimension is `5.0`.
        (Ix::Dim, Dim::Literal(d)) => (format!("{:?}", d as f64), 4),
        (ix, _) if ix.is_compound() => (format!("({}) as f64", ix.render(dim)), 3),
        (ix, _) => (format!("{} as f64", ix.render(dim)), 3),
    }
}

impl Op {
    fn token(self) -> (&'static str, u8) {
        match self {
            Op::Add => ("+", 1),
            Op::Sub => ("-", 1),
            Op::Mul => ("*", 2),
            Op::Div => ("/", 2),
        }
    }
}

/// `e` in the oracle: its text, its precedence and whether it is a plain `f64` (made of
/// numbers, model constants, `t` and indices only). A plain number stays an `f64` and
/// multiplies or adds to a `T` from the right (`y * 0.5`, not `c(0.5) * y`): the oracle is
/// instantiated with hyper-dual numbers, and a product with an `f64` is a quarter of the code
/// of a product of two of them.
fn oracle(e: &E) -> (String, u8, bool) {
    let dim = Dim::Runtime;
    // A `T` operand: a plain number lifted.
    let t_of = |e: &E| -> (String, u8) {
        let (s, p, scalar) = oracle(e);
        if scalar {
            (format!("c({s})"), 4)
        } else {
            (s, p)
        }
    };
    match e {
        E::Num(a) => {
            // A negative literal is a unary minus: precedence 3.
            let p = if *a < 0.0 { 3 } else { 4 };
            (format!("{a:?}"), p, true)
        }
        E::X(ix) => (format!("x[{}]", ix.render(dim)), 4, false),
        E::V(ix) => (format!("v[{}]", ix.render(dim)), 4, false),
        E::K(j) => (format!("k[{j}]"), 4, true),
        E::T => ("t".into(), 4, true),
        E::Local(name) => (name.clone(), 4, false),
        E::IdxNum(ix) => {
            let (s, p) = index_number(ix, dim);
            (s, p, true)
        }
        E::DimMinus(i) => (format!("(n - {i}) as f64"), 3, true),
        E::Neg(a) => {
            let (s, p, scalar) = oracle(a);
            (format!("-{}", paren((s, p), 3)), 3, scalar)
        }
        E::Bin(op, a, b) => {
            let (sa, pa, ca) = oracle(a);
            let (sb, pb, cb) = oracle(b);
            let (tok, p) = op.token();
            let plain = |sa: String, pa: u8, sb: String, pb: u8| {
                format!("{} {tok} {}", paren((sa, pa), p), paren((sb, pb), p + 1))
            };
            match (ca, cb, op) {
                // `f64 op f64`, `T op f64`, `T op T`: as written.
                (true, true, _) => (plain(sa, pa, sb, pb), p, true),
                (_, true, _) | (false, false, _) => (plain(sa, pa, sb, pb), p, false),
                // `f64 op T`: turned round.
                (true, false, Op::Add) => (plain(sb, pb, sa, pa), 1, false),
                (true, false, Op::Mul) => (plain(sb, pb, sa, pa), 2, false),
                (true, false, Op::Sub) => (
                    format!("-{} + {}", paren((sb, pb), 3), paren((sa, pa), 2)),
                    1,
                    false,
                ),
                (true, false, Op::Div) => (
                    format!("{}.recip() * {}", paren((sb, pb), 4), paren((sa, pa), 3)),
                    2,
                    false,
                ),
            }
        }
        // num-dual's `tanh` is `sinh/cosh`, whose derivatives cancel where `|a|` is large: the
        // oracle's own, `dual_tanh`, does not.
        E::F(Fun::Tanh, a) if !oracle(a).2 => {
            let (s, _, _) = oracle(a);
            (format!("dual_tanh({s})"), 4, false)
        }
        E::F(fun, a) => {
            let (s, p, scalar) = oracle(a);
            (format!("{}.{}()", paren((s, p), 4), fun.name()), 4, scalar)
        }
        E::Powi(a, k) => {
            let (s, p, scalar) = oracle(a);
            (format!("{}.powi({k})", paren((s, p), 4)), 4, scalar)
        }
        E::Powf(a, q) => {
            let (s, p, scalar) = oracle(a);
            (format!("{}.powf({q:?})", paren((s, p), 4)), 4, scalar)
        }
        E::Hypot(a, b) => {
            let (a, b) = (paren(t_of(a), 2), paren(t_of(b), 2));
            (format!("({a} * {a} + {b} * {b}).sqrt()"), 4, false)
        }
        E::Max(a, b) => (format!("dual_max({}, {})", t_of(a).0, t_of(b).0), 4, false),
        E::Pair(g, a, b) => {
            let (a, b) = (t_of(a).0, t_of(b).0);
            match g {
                PairFn::Atan2 => (format!("({a}).atan2({b})"), 4, false),
                PairFn::Powf => (format!("({a}).powd({b})"), 4, false),
                PairFn::Min => (format!("dual_min({a}, {b})"), 4, false),
            }
        }
        E::Signum(a) => {
            let (s, p, scalar) = oracle(a);
            let re = if scalar {
                paren((s, p), 4)
            } else {
                format!("{}.re()", paren((s, p), 4))
            };
            (format!("{re}.signum()"), 4, true)
        }
        E::Helper(name, args) => {
            let args: Vec<String> = args.iter().map(|a| t_of(a).0).collect();
            (
                format!("{}({})", name.replacen("fz_", "dual_", 1), args.join(", ")),
                4,
                false,
            )
        }
        E::If(c, a, b) => (
            format!(
                "if {} {{ {} }} else {{ {} }}",
                render_cond(c, Lang::Oracle),
                t_of(a).0,
                t_of(b).0
            ),
            0,
            false,
        ),
        E::Sum(i, range, body) => (
            format!(
                "{{ let mut sum_{i} = c(0.0); for {i} in {} {{ sum_{i} += {}; }} sum_{i} }}",
                range.render(dim),
                oracle(body).0
            ),
            0,
            false,
        ),
        E::Block(lets, value) => {
            let mut s = String::from("{ ");
            for (name, e) in lets {
                let _ = write!(s, "let {name} = {}; ", t_of(e).0);
            }
            let _ = write!(s, "{} }}", t_of(value).0);
            (s, 0, false)
        }
    }
}

fn render_cond(c: &Cond, lang: Lang) -> String {
    match c {
        Cond::Real(cmp, a, b) => {
            if lang == Lang::Oracle {
                let value = |e: &E| {
                    let (s, p, scalar) = oracle(e);
                    if scalar {
                        paren((s, p), 1)
                    } else {
                        format!("{}.re()", paren((s, p), 4))
                    }
                };
                format!("{} {} {}", value(a), cmp.token(), value(b))
            } else {
                format!(
                    "{} {} {}",
                    paren(render(a, lang), 1),
                    cmp.token(),
                    paren(render(b, lang), 1)
                )
            }
        }
        Cond::Index(cmp, a, b) => {
            let tok = cmp.map_or("==", Cmp::token);
            format!("{} {tok} {}", a.render(lang.dim()), b.render(lang.dim()))
        }
        Cond::And(a, b) => format!("{} && {}", render_cond(a, lang), render_cond(b, lang)),
        Cond::Or(a, b) => format!("{} || {}", render_cond(a, lang), render_cond(b, lang)),
    }
}

/// Where the `Term`s of a part go in the `#[lagrangian]` fn.
#[derive(Clone, Copy)]
enum Target<'a> {
    /// `name += e` (`-=`); in the oracle, negated when `flip`.
    Acc(&'a str, bool),
}

fn render_stmts(out: &mut String, stmts: &[S], lang: Lang, target: Target<'_>, indent: usize) {
    let pad = "    ".repeat(indent);
    let dim = lang.dim();
    for s in stmts {
        match s {
            S::Let(name, e, typed) => {
                let ty = if *typed && lang != Lang::Oracle {
                    ": f64"
                } else {
                    ""
                };
                let _ = writeln!(out, "{pad}let {name}{ty} = {};", render(e, lang).0);
            }
            S::LetMut(name, e) => {
                let _ = writeln!(out, "{pad}let mut {name} = {};", render(e, lang).0);
            }
            S::Acc(name, e, minus) => {
                let op = if *minus { "-=" } else { "+=" };
                let _ = writeln!(out, "{pad}{name} {op} {};", render(e, lang).0);
            }
            S::Term(e, minus) => match (lang, target) {
                (Lang::Macro(_), Target::Acc(name, _)) => {
                    let op = if *minus { "-=" } else { "+=" };
                    let _ = writeln!(out, "{pad}{name} {op} {};", render(e, lang).0);
                }
                (Lang::Oracle, Target::Acc(_, flip)) => {
                    push_terms(out, e, *minus != flip, &pad);
                }
            },
            S::For(i, range, body) => {
                let _ = writeln!(out, "{pad}for {i} in {} {{", range.render(dim));
                render_stmts(out, body, lang, target, indent + 1);
                let _ = writeln!(out, "{pad}}}");
            }
        }
    }
}

/// The oracle's `terms.push(±e)`, one push per additive term of `e` and per iteration of a
/// sum that `e` adds: the contributions whose magnitudes make the scale of the comparison.
fn push_terms(out: &mut String, e: &E, minus: bool, pad: &str) {
    match e {
        E::Bin(Op::Add, a, b) => {
            push_terms(out, a, minus, pad);
            push_terms(out, b, minus, pad);
        }
        E::Bin(Op::Sub, a, b) => {
            push_terms(out, a, minus, pad);
            push_terms(out, b, !minus, pad);
        }
        E::Neg(a) => push_terms(out, a, !minus, pad),
        E::Sum(i, range, body) => {
            let _ = writeln!(out, "{pad}for {i} in {} {{", range.render(Dim::Runtime));
            push_terms(out, body, minus, &format!("{pad}    "));
            let _ = writeln!(out, "{pad}}}");
        }
        _ => {
            let s = render(e, Lang::Oracle);
            if minus {
                let _ = writeln!(out, "{pad}terms.push(-{});", paren(s, 3));
            } else {
                let _ = writeln!(out, "{pad}terms.push({});", s.0);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Generation.

/// The constructs a program uses, for the report's table.
const FORMS: &[&str] = &[
    "loop",
    "iter_sum",
    "nested",
    "neighbour",
    "periodic",
    "strided",
    "inner_acc",
    "sum_square",
    "centre",
    "sum_product",
    "sum_quotient",
    "sum_in_loop",
    "branch",
    "sum_branch",
    "helper",
    "time",
    "unrolled",
    "index_number",
    // `full` only:
    "sum_sqrt",
    "sum_ln",
    "sum_recip",
    "sum_fn",
    "sum_condition",
    "sum_in_loop_fn",
    "sum_over_sum",
    // Looped forces:
    "force_scatter",
    "force_gather",
    "force_periodic",
    "force_guarded",
    "force_literal",
    "force_double",
    "force_sum",
    "force_drive",
    "force_no_x",
    "force_no_v",
];

/// A loop variable in scope: its name and its largest value (`None`: the loop never runs at
/// this dimension).
#[derive(Clone)]
struct LoopVar {
    name: String,
    max: Option<usize>,
    /// Runs over `0..D / 2`: `2 * i + 1` is a component at every dimension. (The macro
    /// checks an index for every `N` where it can: `x[2 * i + 1]` in `0..N - 1` is valid at
    /// `N = 2` only, and an error.)
    half: bool,
}

struct Gen<'a> {
    rng: &'a mut Rng,
    level: Level,
    d: usize,
    /// Model constants available (0–2).
    consts: usize,
    /// Whether `t` may be used.
    time: bool,
    forms: Vec<&'static str>,
    fresh: usize,
    /// Components of `x` only (a constraint's body).
    positions_only: bool,
    /// Components of `v` only (a looped force that reads no position).
    velocities_only: bool,
}

impl<'a> Gen<'a> {
    /// A generator at dimension `d` with `consts` model constants, `t` if `time`.
    fn new(
        rng: &'a mut Rng,
        level: Level,
        (d, consts, time): (usize, usize, bool),
        positions_only: bool,
    ) -> Self {
        Gen {
            rng,
            level,
            d,
            consts,
            time,
            forms: Vec::new(),
            fresh: 0,
            positions_only,
            velocities_only: false,
        }
    }

    fn form(&mut self, name: &'static str) {
        debug_assert!(FORMS.contains(&name));
        if !self.forms.contains(&name) {
            self.forms.push(name);
        }
    }
    fn name(&mut self, stem: &str) -> String {
        self.fresh += 1;
        format!("{stem}{}", self.fresh)
    }
    fn k(&mut self) -> Option<E> {
        if self.consts == 0 {
            return None;
        }
        Some(E::K(self.rng.below(self.consts)))
    }
    fn t(&mut self) -> E {
        E::T
    }

    /// The component indices valid for every value of the variables in scope.
    fn indices(&mut self, vars: &[LoopVar]) -> Vec<Ix> {
        let d = self.d;
        let mut out = vec![Ix::Lit(0), Ix::Last, Ix::Half];
        if d >= 2 {
            out.push(Ix::Lit(1));
        }
        for var in vars {
            let name = var.name.clone();
            // A loop that does not run reads nothing: every index of it is valid, but keep to
            // the ones that are valid when it does run at a larger dimension too.
            let max = var.max.unwrap_or(0);
            // Weighted by repetition: mostly `i` itself.
            for _ in 0..8 {
                out.push(Ix::Var(name.clone(), 0));
            }
            if max + 1 < d {
                out.push(Ix::Var(name.clone(), 1));
            }
            out.push(Ix::Mirror(name.clone()));
            if d >= 2 && self.rng.chance(0.5) {
                out.push(Ix::Next(name.clone()));
                out.push(Ix::Prev(name.clone()));
            }
            if var.half {
                for _ in 0..4 {
                    out.push(Ix::Twice(name.clone(), 0));
                    out.push(Ix::Twice(name.clone(), 1));
                }
            }
        }
        out
    }

    fn index(&mut self, vars: &[LoopVar]) -> Ix {
        let all = self.indices(vars);
        // Prefer the loop variables: a body that reads only literals is a constant's worth
        // of loop.
        let own: Vec<Ix> = all
            .iter()
            .filter(|ix| !matches!(ix, Ix::Lit(_) | Ix::Last | Ix::Half))
            .cloned()
            .collect();
        if !own.is_empty() && self.rng.chance(0.85) {
            own[self.rng.below(own.len())].clone()
        } else {
            all[self.rng.below(all.len())].clone()
        }
    }

    fn component(&mut self, vars: &[LoopVar]) -> E {
        let ix = self.index(vars);
        if self.velocities_only {
            E::V(ix)
        } else if self.positions_only || self.rng.chance(0.5) {
            E::X(ix)
        } else {
            E::V(ix)
        }
    }

    /// A bounded combination of components (|y| ≲ 2).
    fn combo(&mut self, vars: &[LoopVar]) -> E {
        let a = self.component(vars);
        match self.rng.below(11) {
            0 | 8 | 9 => a,
            1 | 10 => E::Neg(Box::new(a)),
            2 => {
                let b = self.distinct(vars, &a);
                sub(a, b)
            }
            3 => {
                let b = self.distinct(vars, &a);
                add(a, mul(num(self.rng.coefficient()), b))
            }
            4 => {
                let b = self.component(vars);
                mul(a, b)
            }
            5 => match self.k() {
                Some(k) => mul(k, a),
                None => a,
            },
            6 if self.time => {
                let t = self.t();
                add(a, mul(num(self.rng.coefficient()), t))
            }
            _ => {
                let b = self.distinct(vars, &a);
                mul(num(self.rng.coefficient()), sub(a, b))
            }
        }
    }

    /// A component whose text differs from `a`'s (so that `a - b` is no `eq_op`).
    fn distinct(&mut self, vars: &[LoopVar], a: &E) -> E {
        let ra = text(a);
        for _ in 0..8 {
            let b = self.component(vars);
            if text(&b) != ra {
                return b;
            }
        }
        // Always distinct from a component.
        num(0.5)
    }

    /// A function of `y`, applied where it is defined.
    fn smooth(&mut self, y: E) -> E {
        let half = |y: E| mul(num(0.5), y);
        let pair = |g, a, b| E::Pair(g, Box::new(a), Box::new(b));
        match self.rng.below(27) {
            0 => y,
            1 => mul(y.clone(), y),
            2 => f(Fun::Sin, y),
            3 => f(Fun::Cos, y),
            4 => f(Fun::Atan, y),
            5 => f(Fun::Tanh, y),
            6 => f(Fun::Exp, half(y)),
            7 => f(Fun::Ln, positive(1.5, y)),
            8 => f(Fun::Sqrt, positive(1.5, y)),
            9 => div(num(1.0), positive(2.0, y)),
            10 => f(Fun::Recip, positive(2.0, y)),
            11 => E::Powi(Box::new(y), self.rng.pick(&[2, 3, 4])),
            12 => E::Powf(Box::new(positive(1.0, y)), 0.75),
            13 => f(Fun::Abs, sub(y, num(0.37))),
            14 => f(Fun::Asin, half(f(Fun::Tanh, y))),
            15 => f(Fun::Acos, half(f(Fun::Tanh, y))),
            16 => f(Fun::Tan, half(f(Fun::Tanh, y))),
            17 => f(Fun::Sinh, half(y)),
            18 => f(Fun::Cosh, half(y)),
            19 => f(Fun::Cbrt, positive(2.0, y)),
            20 => f(Fun::Log10, positive(1.5, y)),
            21 => f(Fun::ExpM1, half(y)),
            22 => f(Fun::Ln1p, half(f(Fun::Tanh, y))),
            // The second argument at least 1.2 (the constants are positive, `t ≥ 0`), so that
            // `(0, 0)`, where `atan2` is not differentiable, is never near.
            23 => {
                let x = match self.k() {
                    Some(k) => add(num(1.5), k),
                    None if self.time => add(num(1.2), E::T),
                    None => num(1.2),
                };
                pair(PairFn::Atan2, y, x)
            }
            // An exponent that is an expression: of `t`, or of a component.
            24 => {
                let z = if self.time { E::T } else { y.clone() };
                let e = add(num(0.75), mul(num(0.25), f(Fun::Sin, z)));
                pair(PairFn::Powf, positive(1.0, y), e)
            }
            25 => pair(PairFn::Min, y, num(-0.1)),
            _ => {
                let h = match self.k() {
                    Some(k) => k,
                    None => num(0.5),
                };
                E::Hypot(Box::new(y), Box::new(h))
            }
        }
    }

    fn condition(&mut self, vars: &[LoopVar]) -> Cond {
        let cmp = self.rng.pick(&[Cmp::Lt, Cmp::Le, Cmp::Gt, Cmp::Ge]);
        let real = match self.rng.below(5) {
            0 | 1 => {
                let a = self.component(vars);
                let b = self.distinct(vars, &a);
                Cond::Real(cmp, a, b)
            }
            2 if self.time => {
                let t = self.t();
                Cond::Real(cmp, t, num(1.0))
            }
            3 if self.consts > 0 => {
                let a = self.component(vars);
                let k = self.k().expect("consts > 0");
                Cond::Real(cmp, a, mul(num(0.5), k))
            }
            _ => {
                let a = self.combo(vars);
                Cond::Real(cmp, a, num(self.rng.pick(&[0.0, 0.1, -0.2, 0.3])))
            }
        };
        if vars.is_empty() || self.rng.chance(0.6) {
            return real;
        }
        let i = vars[self.rng.below(vars.len())].name.clone();
        let index = match self.rng.below(3) {
            0 => Cond::Index(None, Ix::Var(i, 0), Ix::Lit(0)),
            1 if vars.len() >= 2 => {
                let j = vars[0].name.clone();
                let k = vars[1].name.clone();
                Cond::Index(Some(Cmp::Lt), Ix::Var(j, 0), Ix::Var(k, 0))
            }
            // (`i + 1 < N - 1` would be clippy's `absurd_extreme_comparisons` at `N = 1`.)
            _ => Cond::Index(Some(Cmp::Lt), Ix::Var(i, 1), Ix::Dim),
        };
        if self.rng.chance(0.5) {
            Cond::And(Box::new(index), Box::new(real))
        } else {
            Cond::Or(Box::new(real), Box::new(index))
        }
    }

    /// One factor of a loop body.
    fn factor(&mut self, vars: &[LoopVar], depth: usize) -> E {
        match self.rng.below(12) {
            0..=2 => {
                let y = self.combo(vars);
                self.smooth(y)
            }
            3 | 4 => {
                let y = self.combo(vars);
                let s = self.smooth(y);
                mul(num(self.rng.coefficient()), s)
            }
            5 => {
                let y = self.combo(vars);
                let s = self.smooth(y);
                match self.k() {
                    Some(k) => mul(k, s),
                    None => s,
                }
            }
            6 => self.helper(vars),
            7 if !vars.is_empty() => {
                self.form("index_number");
                let i = vars[self.rng.below(vars.len())].name.clone();
                let w = match self.rng.below(3) {
                    0 => E::IdxNum(Ix::Var(i, 1)),
                    1 => E::DimMinus(i),
                    _ => add(E::IdxNum(Ix::Var(i, 0)), num(0.5)),
                };
                let y = self.combo(vars);
                let s = self.smooth(y);
                mul(mul(num(0.1), w), s)
            }
            8 if depth > 0 => {
                self.form("branch");
                let c = self.condition(vars);
                let a = self.factor(vars, depth - 1);
                let b = self.factor(vars, depth - 1);
                E::If(Box::new(c), Box::new(a), Box::new(b))
            }
            9 if self.time => {
                let t = self.t();
                let y = self.combo(vars);
                let s = self.smooth(y);
                mul(f(Fun::Cos, mul(num(self.rng.coefficient()), t)), s)
            }
            10 => {
                let y = self.combo(vars);
                let z = self.combo(vars);
                match self.rng.below(3) {
                    0 => mul(E::Max(Box::new(y), Box::new(num(0.2))), z),
                    1 => mul(E::Signum(Box::new(sub(y, num(0.37)))), z),
                    _ => {
                        let s = self.smooth(y);
                        let r = self.smooth(z);
                        mul(s, r)
                    }
                }
            }
            _ => {
                let y = self.combo(vars);
                let s = self.smooth(y);
                let a = self.component(vars);
                mul(s, a)
            }
        }
    }

    fn helper(&mut self, vars: &[LoopVar]) -> E {
        match self.rng.below(3) {
            0 => {
                let y = self.combo(vars);
                let k = self.k().unwrap_or(num(0.8));
                E::Helper("fz_spring", vec![y, k])
            }
            1 => {
                let y = self.combo(vars);
                E::Helper("fz_well", vec![y])
            }
            _ => {
                let a = self.component(vars);
                let b = self.component(vars);
                E::Helper("fz_bond", vec![a, b])
            }
        }
    }

    /// A loop body: one to three factors or products of two, with signs. Mostly one: the
    /// compile time of a program grows with the components its bodies read (the Hessian of
    /// a body has an entry per pair of them), and one form per program is what the test is
    /// after.
    fn body(&mut self, vars: &[LoopVar]) -> E {
        let n = self.rng.pick(&[1, 1, 1, 1, 1, 1, 2, 2, 2, 3]);
        let mut acc: Option<E> = None;
        for _ in 0..n {
            let mut term = self.factor(vars, 1);
            if self.rng.chance(0.15) {
                let g = self.factor(vars, 0);
                term = mul(term, g);
            }
            acc = Some(match acc {
                None => term,
                Some(a) if self.rng.chance(0.5) => add(a, term),
                Some(a) => sub(a, term),
            });
        }
        acc.expect("n ≥ 1")
    }

    /// `0.5 * v[i] * v[i]`-like: the kinetic term most Lagrangians have.
    fn kinetic(&mut self, i: &str) -> E {
        let vi = E::V(Ix::Var(i.to_string(), 0));
        let m = match self.k() {
            Some(k) if self.rng.chance(0.3) => mul(num(0.5), k),
            _ => num(0.5),
        };
        mul(mul(m, vi.clone()), vi)
    }

    fn var(&self, name: &str, max: Option<usize>) -> LoopVar {
        LoopVar {
            name: name.to_string(),
            max,
            half: false,
        }
    }

    /// `0..D`.
    fn full_range(&self) -> Range {
        Range {
            lo: Ix::Lit(0),
            hi: Ix::Dim,
            inclusive: false,
        }
    }

    /// A sum over one loop variable of a body, as an iterator sum or an accumulator loop;
    /// `positive` makes every term positive (for `sqrt`).
    fn sum_expr(&mut self, outer: &[LoopVar], positive_terms: bool) -> E {
        let j = self.name("j");
        let mut vars = outer.to_vec();
        vars.push(self.var(&j, Some(self.d - 1)));
        let body = if positive_terms {
            let y = self.combo(&vars);
            positive(self.rng.pick(&[0.5, 1.0, 1.5]), y)
        } else {
            self.body(&vars)
        };
        let body = ensure_reads(body, &[], &[&j]);
        E::Sum(j, self.full_range(), Box::new(body))
    }

    // --- the parts: each adds `Term`s to `L` and records its forms ---

    /// Adds one part to `out`; returns its kind.
    fn part(&mut self, out: &mut Vec<S>) -> &'static str {
        let legacy: &[(&'static str, usize)] = &[
            ("loop", 6),
            ("iter_sum", 4),
            ("nested", 5),
            ("neighbour", 4),
            ("periodic", 3),
            ("strided", 1),
            ("inner_acc", 4),
            ("sum_square", 4),
            ("centre", 4),
            ("sum_product", 3),
            ("sum_quotient", 2),
            ("sum_in_loop", 3),
            ("sum_branch", 2),
            ("unrolled", 2),
        ];
        let full: &[(&'static str, usize)] = &[
            ("sum_sqrt", 3),
            ("sum_ln", 3),
            ("sum_recip", 3),
            ("sum_fn", 3),
            ("sum_condition", 3),
            ("sum_in_loop_fn", 4),
            ("sum_over_sum", 2),
        ];
        let mut table = legacy.to_vec();
        if self.level == Level::Full {
            table.extend_from_slice(full);
        }
        let total: usize = table.iter().map(|e| e.1).sum();
        let mut r = self.rng.below(total);
        let mut kind: &'static str = table[0].0;
        for &(name, w) in &table {
            if r < w {
                kind = name;
                break;
            }
            r -= w;
        }
        let minus = self.rng.chance(0.3);
        let d = self.d;
        match kind {
            "loop" => {
                self.form("loop");
                let i = self.name("i");
                let (range, max) = match self.rng.below(4) {
                    0 if d >= 2 => (
                        Range {
                            lo: Ix::Lit(1),
                            hi: Ix::Dim,
                            inclusive: false,
                        },
                        d - 1,
                    ),
                    1 => (
                        Range {
                            lo: Ix::Lit(0),
                            hi: Ix::Last,
                            inclusive: true,
                        },
                        d - 1,
                    ),
                    _ => (self.full_range(), d - 1),
                };
                let vars = vec![self.var(&i, Some(max))];
                let mut stmts = Vec::new();
                let mut body = self.body(&vars);
                if self.rng.chance(0.3) {
                    // A `let` in the loop, read by the body.
                    let y = self.name("y");
                    let e = self.combo(&vars);
                    let s = self.smooth(local(&y));
                    stmts.push(S::Let(y, e, false));
                    body = add(body, s);
                }
                if self.rng.chance(0.4) {
                    body = add(self.kinetic(&i), body);
                }
                let lets: Vec<&E> = stmts
                    .iter()
                    .filter_map(|s| match s {
                        S::Let(_, e, _) => Some(e),
                        _ => None,
                    })
                    .collect();
                let body = ensure_reads(body, &lets, &[&i]);
                stmts.push(S::Term(body, minus));
                out.push(S::For(i, range, stmts));
            }
            "iter_sum" => {
                self.form("iter_sum");
                let i = self.name("i");
                let vars = vec![self.var(&i, Some(d - 1))];
                let body = if self.rng.chance(0.4) {
                    let y = self.name("y");
                    let e = self.combo(&vars);
                    let s = self.smooth(local(&y));
                    let rest = self.factor(&vars, 1);
                    E::Block(vec![(y, e)], Box::new(add(s, rest)))
                } else {
                    self.body(&vars)
                };
                let body = ensure_reads(body, &[], &[&i]);
                let sum = E::Sum(i, self.full_range(), Box::new(body));
                let p = self.name("p");
                out.push(S::Let(p.clone(), sum, self.rng.chance(0.5)));
                let scaled = match self.k() {
                    Some(k) if self.rng.chance(0.4) => mul(k, local(&p)),
                    _ => local(&p),
                };
                out.push(S::Term(scaled, minus));
            }
            "nested" => {
                self.form("nested");
                let i = self.name("i");
                let j = self.name("j");
                let (inner, jmax) = match self.rng.below(4) {
                    0 => (
                        Range {
                            lo: Ix::Var(i.clone(), 1),
                            hi: Ix::Dim,
                            inclusive: false,
                        },
                        if d >= 2 { Some(d - 1) } else { None },
                    ),
                    1 => (self.full_range(), Some(d - 1)),
                    2 => (
                        Range {
                            lo: Ix::Lit(0),
                            hi: Ix::Var(i.clone(), 0),
                            inclusive: false,
                        },
                        if d >= 2 { Some(d - 2) } else { None },
                    ),
                    _ => (
                        Range {
                            lo: Ix::Var(i.clone(), 0),
                            hi: Ix::Dim,
                            inclusive: false,
                        },
                        Some(d - 1),
                    ),
                };
                let vars = vec![self.var(&i, Some(d - 1)), self.var(&j, jmax)];
                if self.rng.chance(0.3) {
                    // The inner loop as an iterator sum, times a factor of the outer index.
                    let body = ensure_reads(self.body(&vars), &[], &[&j]);
                    let outer = ensure_reads(self.component(&vars[..1]), &[], &[&i]);
                    let term = mul(outer, E::Sum(j, inner, Box::new(body)));
                    out.push(S::For(i, self.full_range(), vec![S::Term(term, minus)]));
                } else {
                    let body = ensure_reads(self.body(&vars), &[], &[&i, &j]);
                    out.push(S::For(
                        i,
                        self.full_range(),
                        vec![S::For(j, inner, vec![S::Term(body, minus)])],
                    ));
                }
            }
            // `0..N - 1` at `N = 1` is clippy's `reversed_empty_ranges`.
            "neighbour" if d >= 2 => {
                self.form("neighbour");
                let i = self.name("i");
                let dn = self.name("d");
                let vars = vec![self.var(&i, d.checked_sub(2))];
                let diff = sub(E::X(Ix::Var(i.clone(), 1)), E::X(Ix::Var(i.clone(), 0)));
                let mut term = if self.rng.chance(0.5) {
                    let k = self.k().unwrap_or(num(1.0));
                    E::Helper("fz_spring", vec![local(&dn), k])
                } else {
                    self.smooth(local(&dn))
                };
                if self.rng.chance(0.4) {
                    let c = self.rng.coefficient();
                    term = add(
                        term,
                        mul(
                            mul(num(c), E::V(Ix::Var(i.clone(), 0))),
                            E::V(Ix::Var(i.clone(), 1)),
                        ),
                    );
                }
                if self.rng.chance(0.3) {
                    let extra = self.factor(&vars, 0);
                    term = sub(term, extra);
                }
                out.push(S::For(
                    i,
                    Range {
                        lo: Ix::Lit(0),
                        hi: Ix::Last,
                        inclusive: false,
                    },
                    vec![S::Let(dn, diff, false), S::Term(term, !minus)],
                ));
            }
            "periodic" if d >= 2 => {
                self.form("periodic");
                let i = self.name("i");
                let dn = self.name("d");
                let vars = vec![self.var(&i, Some(d - 1))];
                let next = if self.rng.chance(0.7) {
                    Ix::Next(i.clone())
                } else {
                    Ix::Prev(i.clone())
                };
                let diff = sub(E::X(next), E::X(Ix::Var(i.clone(), 0)));
                let mut term = self.smooth(local(&dn));
                if self.rng.chance(0.5) {
                    term = add(self.kinetic(&i), term);
                }
                if self.rng.chance(0.3) {
                    let extra = self.factor(&vars, 0);
                    term = add(term, extra);
                }
                out.push(S::For(
                    i,
                    self.full_range(),
                    vec![S::Let(dn, diff, false), S::Term(term, minus)],
                ));
            }
            "strided" if d >= 2 => {
                self.form("strided");
                let i = self.name("i");
                let vars = vec![LoopVar {
                    half: true,
                    ..self.var(&i, Some(d / 2 - 1))
                }];
                let a = E::X(Ix::Twice(i.clone(), 0));
                let b = E::X(Ix::Twice(i.clone(), 1));
                let y = self.smooth(sub(b, a));
                let va = E::V(Ix::Twice(i.clone(), 0));
                let vb = E::V(Ix::Twice(i.clone(), 1));
                let extra = self.factor(&vars, 0);
                let term = add(add(mul(mul(num(0.5), va), vb), y), extra);
                out.push(S::For(
                    i,
                    Range {
                        lo: Ix::Lit(0),
                        hi: Ix::Half,
                        inclusive: false,
                    },
                    vec![S::Term(term, minus)],
                ));
            }
            "inner_acc" => {
                self.form("inner_acc");
                let k = self.name("m");
                let i = self.name("i");
                let a = self.name("a");
                let kv = self.var(&k, Some(d - 1));
                let vars = vec![kv.clone(), self.var(&i, Some(d - 1))];
                let (range, vars) = if self.rng.chance(0.6) {
                    (
                        Range {
                            lo: Ix::Lit(0),
                            hi: Ix::Var(k.clone(), 0),
                            inclusive: true,
                        },
                        vars,
                    )
                } else {
                    (
                        Range {
                            lo: Ix::Var(k.clone(), 0),
                            hi: Ix::Dim,
                            inclusive: false,
                        },
                        vars,
                    )
                };
                let g = if self.rng.chance(0.5) {
                    let ix = self.index(&vars[1..]);
                    if self.rng.chance(0.5) {
                        E::X(ix)
                    } else {
                        E::V(ix)
                    }
                } else {
                    self.factor(&vars, 0)
                };
                let g = ensure_reads(g, &[], &[&i]);
                let al = local(&a);
                let use_a = match self.rng.below(4) {
                    0 | 1 => mul(mul(num(0.5), al.clone()), al),
                    2 => {
                        let w = self.component(&[kv]);
                        mul(al, w)
                    }
                    _ => {
                        let kk = self.k().unwrap_or(num(0.25));
                        mul(mul(kk, al.clone()), al)
                    }
                };
                out.push(S::For(
                    k,
                    self.full_range(),
                    vec![
                        S::LetMut(a.clone(), num(0.0)),
                        S::For(i, range, vec![S::Acc(a, g, false)]),
                        S::Term(use_a, minus),
                    ],
                ));
            }
            "sum_square" => {
                self.form("sum_square");
                let s = self.name("s");
                if self.rng.chance(0.5) {
                    let sum = self.sum_expr(&[], false);
                    out.push(S::Let(s.clone(), sum, self.rng.chance(0.3)));
                } else {
                    // An accumulator, read after its loop.
                    let j = self.name("j");
                    let vars = vec![self.var(&j, Some(d - 1))];
                    let body = ensure_reads(self.body(&vars), &[], &[&j]);
                    out.push(S::LetMut(s.clone(), num(0.0)));
                    out.push(S::For(
                        j,
                        self.full_range(),
                        vec![S::Acc(s.clone(), body, false)],
                    ));
                }
                let c = self.rng.coefficient();
                let sq = match self.rng.below(3) {
                    0 => mul(mul(num(c), local(&s)), local(&s)),
                    1 => mul(local(&s), local(&s)),
                    _ => {
                        let k = self.k().unwrap_or(num(c));
                        mul(mul(local(&s), local(&s)), k)
                    }
                };
                out.push(S::Term(sq, minus));
            }
            "centre" => {
                self.form("centre");
                let cx = self.name("cx");
                let j = self.name("j");
                let i = self.name("i");
                let vel = self.rng.chance(0.3);
                let comp = |ix: Ix| if vel { E::V(ix) } else { E::X(ix) };
                let mean = div(
                    E::Sum(j.clone(), self.full_range(), Box::new(comp(Ix::Var(j, 0)))),
                    E::IdxNum(Ix::Dim),
                );
                out.push(S::Let(cx.clone(), mean, false));
                let dev = sub(comp(Ix::Var(i.clone(), 0)), local(&cx));
                let c = self.rng.coefficient();
                let mut stmts = Vec::new();
                let term = if self.rng.chance(0.5) {
                    mul(mul(num(c), dev.clone()), dev)
                } else {
                    let dn = self.name("dev");
                    stmts.push(S::Let(dn.clone(), dev, false));
                    mul(mul(num(c), local(&dn)), local(&dn))
                };
                stmts.push(S::Term(term, !minus));
                out.push(S::For(i, self.full_range(), stmts));
            }
            "sum_product" => {
                self.form("sum_product");
                let (s1, s2) = (self.name("s"), self.name("s"));
                let a = self.sum_expr(&[], false);
                let b = self.sum_expr(&[], false);
                out.push(S::Let(s1.clone(), a, false));
                out.push(S::Let(s2.clone(), b, false));
                let c = self.rng.coefficient();
                out.push(S::Term(mul(mul(num(c), local(&s1)), local(&s2)), minus));
            }
            "sum_quotient" => {
                self.form("sum_quotient");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                let divisor = match self.k() {
                    Some(k) if self.rng.chance(0.5) => positive(2.0, k),
                    _ => E::IdxNum(Ix::Dim),
                };
                out.push(S::Term(div(local(&s), divisor), minus));
            }
            "sum_in_loop" => {
                self.form("sum_in_loop");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                let i = self.name("i");
                let vars = vec![self.var(&i, Some(d - 1))];
                let g = ensure_reads(self.factor(&vars, 0), &[], &[&i]);
                out.push(S::For(
                    i,
                    self.full_range(),
                    vec![S::Term(mul(mul(num(0.1), g), local(&s)), minus)],
                ));
            }
            "sum_branch" => {
                self.form("sum_branch");
                self.form("branch");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                let c = self.condition(&[]);
                let other = self.factor(&[], 0);
                let b = E::If(
                    Box::new(c),
                    Box::new(mul(num(self.rng.coefficient()), local(&s))),
                    Box::new(other),
                );
                out.push(S::Term(b, minus));
            }
            "sum_sqrt" => {
                self.form("sum_sqrt");
                let s = self.name("s");
                let a = self.sum_expr(&[], true);
                out.push(S::Let(s.clone(), a, false));
                out.push(S::Term(f(Fun::Sqrt, local(&s)), minus));
            }
            "sum_ln" => {
                self.form("sum_ln");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                out.push(S::Term(f(Fun::Ln, positive(1.0, local(&s))), minus));
            }
            "sum_recip" => {
                self.form("sum_recip");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                out.push(S::Term(div(num(1.0), positive(2.0, local(&s))), minus));
            }
            "sum_fn" => {
                self.form("sum_fn");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                let scaled = mul(num(self.rng.pick(&[0.1, 0.2, 0.5])), local(&s));
                let g = match self.rng.below(5) {
                    0 => f(Fun::Sin, local(&s)),
                    1 => f(Fun::Cos, scaled),
                    2 => f(Fun::Tanh, local(&s)),
                    3 => f(Fun::Exp, scaled),
                    _ => E::Powi(Box::new(local(&s)), 3),
                };
                out.push(S::Term(g, minus));
            }
            "sum_condition" => {
                self.form("sum_condition");
                self.form("branch");
                let s = self.name("s");
                let a = self.sum_expr(&[], false);
                out.push(S::Let(s.clone(), a, false));
                let cmp = self.rng.pick(&[Cmp::Lt, Cmp::Gt]);
                let yes = self.factor(&[], 0);
                let no = mul(num(0.5), local(&s));
                let b = E::If(
                    Box::new(Cond::Real(cmp, local(&s), num(0.0))),
                    Box::new(yes),
                    Box::new(no),
                );
                out.push(S::Term(b, minus));
            }
            "sum_in_loop_fn" => {
                self.form("sum_in_loop_fn");
                let i = self.name("i");
                let s = self.name("s");
                let vars = vec![self.var(&i, Some(d - 1))];
                let (value, arg) = if self.rng.chance(0.5) {
                    // A centre of mass under a function.
                    self.form("centre");
                    let j = self.name("j");
                    let mean = div(
                        E::Sum(j.clone(), self.full_range(), Box::new(E::X(Ix::Var(j, 0)))),
                        E::IdxNum(Ix::Dim),
                    );
                    (mean, sub(E::X(Ix::Var(i.clone(), 0)), local(&s)))
                } else {
                    let a = self.sum_expr(&[], false);
                    let c = ensure_reads(self.component(&vars), &[], &[&i]);
                    (a, mul(mul(num(0.2), c), local(&s)))
                };
                out.push(S::Let(s, value, false));
                let g = self.smooth(arg);
                out.push(S::For(i, self.full_range(), vec![S::Term(g, minus)]));
            }
            "sum_over_sum" => {
                self.form("sum_over_sum");
                let (s1, s2) = (self.name("s"), self.name("s"));
                let a = self.sum_expr(&[], false);
                let b = self.sum_expr(&[], false);
                out.push(S::Let(s1.clone(), a, false));
                out.push(S::Let(s2.clone(), b, false));
                out.push(S::Term(div(local(&s1), positive(2.0, local(&s2))), minus));
            }
            _ => {
                // "unrolled", and the forms that need two components at dimension 1.
                self.form("unrolled");
                let mut term = self.factor(&[], 1);
                if self.rng.chance(0.5) {
                    let g = self.factor(&[], 0);
                    term = add(term, g);
                }
                out.push(S::Term(term, minus));
            }
        }
        kind
    }
}

/// Whether `stmts` hold a loop (a sum): then the array model gets `DynLagrangian` too.
fn has_loop(stmts: &[S]) -> bool {
    fn in_expr(e: &E) -> bool {
        match e {
            E::Sum(..) => true,
            E::Neg(a) | E::F(_, a) | E::Powi(a, _) | E::Powf(a, _) | E::Signum(a) => in_expr(a),
            E::Bin(_, a, b) | E::Hypot(a, b) | E::Max(a, b) | E::Pair(_, a, b) => {
                in_expr(a) || in_expr(b)
            }
            E::Helper(_, args) => args.iter().any(in_expr),
            E::If(_, a, b) => in_expr(a) || in_expr(b),
            E::Block(lets, v) => lets.iter().any(|l| in_expr(&l.1)) || in_expr(v),
            _ => false,
        }
    }
    stmts.iter().any(|s| match s {
        S::For(..) => true,
        S::Let(_, e, _) | S::LetMut(_, e) | S::Acc(_, e, _) | S::Term(e, _) => in_expr(e),
    })
}

struct Program {
    id: usize,
    d: usize,
    literal: bool,
    time: bool,
    consts: Vec<f64>,
    /// The parts, each with the sign it enters `L` with (locals mode) and its statements.
    parts: Vec<(bool, Vec<S>)>,
    /// One accumulator `l` for every part, or one local per part.
    single: bool,
    forms: Vec<&'static str>,
}

fn draw(rng: &mut Rng, id: usize, level: Level) -> Program {
    let d = 1 + rng.below(8);
    let literal = d >= 2 && rng.chance(0.35);
    let consts = rng.below(3);
    let time = rng.chance(0.35);
    let mut g = Gen::new(rng, level, (d, consts, time), false);
    let nparts = g.rng.pick(&[1, 1, 1, 1, 1, 1, 1, 2, 2, 2]);
    let mut parts = Vec::new();
    let mut looped = false;
    for _ in 0..nparts {
        let mut stmts = Vec::new();
        let kind = g.part(&mut stmts);
        // An accumulator declared inside a loop does not count: the macro may drop such a
        // loop, and a literal-dimension model with no loop left has no `DynLagrangian`.
        looped |= kind != "inner_acc" && has_loop(&stmts);
        parts.push((g.rng.chance(0.25), stmts));
    }
    // Every program has a loop (so that the array model implements `DynLagrangian` too), and
    // reads `x` and `v` (an unused parameter would be a warning).
    if !looped {
        let i = g.name("i");
        let kin = g.kinetic(&i);
        let stmts = vec![S::For(i, g.full_range(), vec![S::Term(kin, false)])];
        g.form("loop");
        parts.push((false, stmts));
    }
    let slice_text = |parts: &[(bool, Vec<S>)]| {
        let all: Vec<S> = parts.iter().flat_map(|p| p.1.clone()).collect();
        let mut s = String::new();
        render_stmts(
            &mut s,
            &all,
            Lang::Macro(Dim::Runtime),
            Target::Acc("l", false),
            0,
        );
        s
    };
    let text = slice_text(&parts);
    let mut extra = Vec::new();
    if !text.contains("x[") {
        extra.push(mul(num(-0.5), mul(E::X(Ix::Lit(0)), E::X(Ix::Lit(0)))));
    }
    if !text.contains("v[") {
        extra.push(mul(num(0.5), mul(E::V(Ix::Last), E::V(Ix::Last))));
    }
    for j in 0..consts {
        if !has_word(&text, &format!("k{j}")) {
            extra.push(mul(E::K(j), f(Fun::Cos, E::X(Ix::Half))));
        }
    }
    if !extra.is_empty() {
        let mut e = extra.remove(0);
        for x in extra {
            e = add(e, x);
        }
        parts.push((false, vec![S::Term(e, false)]));
    }
    let text = slice_text(&parts);
    // The forms read off the text are those the program really uses (a component drawn and
    // then discarded left no trace there).
    let time = has_word(&text, "t");
    if time {
        g.form("time");
    }
    for (needle, form) in [
        (") % n", "periodic"),
        ("[2 * ", "strided"),
        ("fz_spring(", "helper"),
        ("fz_well(", "helper"),
        ("fz_bond(", "helper"),
    ] {
        if text.contains(needle) {
            g.form(form);
        }
    }
    let single = parts.len() == 1 || g.rng.chance(0.5);
    let mut forms = g.forms.clone();
    forms.sort_by_key(|f| FORMS.iter().position(|g| g == f));
    let consts = (0..consts).map(|_| rng_const(g.rng)).collect();
    Program {
        id,
        d,
        literal,
        time,
        consts,
        parts,
        single,
        forms,
    }
}

fn rng_const(rng: &mut Rng) -> f64 {
    rng.pick(&[0.6, 0.75, 0.9, 1.1, 1.25, 1.4])
}

/// The body of the `#[lagrangian]` fn in `dim`, or of the oracle.
fn body(p: &Program, lang: Lang) -> String {
    let mut out = String::new();
    if lang == Lang::Oracle {
        for (k, (flip, stmts)) in p.parts.iter().enumerate() {
            let flip = !p.single && *flip;
            let _ = writeln!(out, "// part {k}");
            render_stmts(&mut out, stmts, lang, Target::Acc("l", flip), 0);
        }
        return out;
    }
    if p.single {
        out.push_str("let mut l = 0.0;\n");
        for (_, stmts) in &p.parts {
            render_stmts(&mut out, stmts, lang, Target::Acc("l", false), 0);
        }
        out.push_str("l\n");
        return out;
    }
    let mut fin = String::new();
    for (k, (flip, stmts)) in p.parts.iter().enumerate() {
        let name = format!("p{k}_");
        let _ = writeln!(out, "let mut {name} = 0.0;");
        render_stmts(&mut out, stmts, lang, Target::Acc(&name, false), 0);
        let sign = match (k, flip) {
            (0, false) => "",
            (0, true) => "-",
            (_, false) => " + ",
            (_, true) => " - ",
        };
        let _ = write!(fin, "{sign}{name}");
    }
    out.push_str(&fin);
    out.push('\n');
    out
}

fn indent(text: &str, pad: &str) -> String {
    text.lines()
        .map(|l| {
            if l.is_empty() {
                String::new()
            } else {
                format!("{pad}{l}\n")
            }
        })
        .collect()
}

fn signature(p: &Program, dim: Dim) -> String {
    let ty = match dim {
        Dim::Named => "[f64; N]".to_string(),
        Dim::Literal(d) => format!("[f64; {d}]"),
        Dim::Runtime => "&[f64]".to_string(),
    };
    let mut params = vec![format!("x: {ty}"), format!("v: {ty}")];
    if p.time {
        params.push("t: f64".into());
    }
    let mut consts: Vec<String> = (0..p.consts.len()).map(|j| format!("k{j}: f64")).collect();
    if let Dim::Runtime = dim {
        // The run-time dimension among the constants, where the program's id puts it.
        let at = p.id % (consts.len() + 1);
        consts.insert(at, "n: usize".into());
    }
    params.extend(consts);
    params.join(", ")
}

fn program(p: &Program) -> String {
    let array_dim = if p.literal {
        Dim::Literal(p.d)
    } else {
        Dim::Named
    };
    let array_fn = format!(
        "#[lagrangian]\npub fn array_model({}) -> f64 {{\n{}}}\n",
        signature(p, array_dim),
        indent(&body(p, Lang::Macro(array_dim)), "    ")
    );
    let slice_fn = format!(
        "#[lagrangian]\npub fn slice_model({}) -> f64 {{\n{}}}\n",
        signature(p, Dim::Runtime),
        indent(&body(p, Lang::Macro(Dim::Runtime)), "    ")
    );
    let oracle = format!(
        "#[allow(unused_variables, reason = \"a program need not read `t`, `k` or `n`\")]\n\
         pub fn oracle<T: DualNum<Primitive = f64> + Copy>(x: &[T], v: &[T], t: f64, k: &[f64], terms: &mut Vec<T>) {{\n\
         \x20   let n = x.len();\n\
         \x20   let c = |a: f64| T::from(a);\n\
         {}}}\n",
        indent(&body(p, Lang::Oracle), "    ")
    );
    let consts: Vec<String> = p.consts.iter().map(|c| format!("{c:?}")).collect();
    let fields: Vec<String> = (0..p.consts.len())
        .map(|j| format!("k{j}: K[{j}]"))
        .collect();
    let mut args_array = vec!["x.try_into().expect(\"dimension\")".to_string(); 2];
    args_array[1] = "v.try_into().expect(\"dimension\")".into();
    let mut args_slice = vec!["x".to_string(), "v".to_string()];
    if p.time {
        args_array.push("t".into());
        args_slice.push("t".into());
    }
    let mut kargs: Vec<String> = (0..p.consts.len()).map(|j| format!("K[{j}]")).collect();
    args_array.extend(kargs.clone());
    kargs.insert(p.id % (p.consts.len() + 1), "N".into());
    args_slice.extend(kargs);
    let forms: Vec<String> = p.forms.iter().map(|f| format!("{f:?}")).collect();
    let mut text = String::new();
    text.push_str(&array_fn);
    text.push_str(&slice_fn);
    let mut m = String::new();
    let _ = writeln!(
        m,
        "#[allow(clippy::impossible_comparisons, clippy::eq_op, clippy::if_same_then_else, \
         reason = \"the run-time index checks that `#[lagrangian]` writes for a slice model \
         compare constants clippy folds; components drawn apart may name one entry at a literal \
         dimension (`x[2 - 1] - x[1]`), and then a branch may read the same on both sides\")]"
    );
    let _ = writeln!(m, "pub mod p{:04} {{", p.id);
    let _ = writeln!(m, "    use super::*;");
    let _ = writeln!(m, "    pub const N: usize = {};", p.d);
    let _ = writeln!(
        m,
        "    const K: [f64; {}] = [{}];",
        p.consts.len(),
        consts.join(", ")
    );
    m.push_str(&indent(&array_fn, "    "));
    m.push_str(&indent(&slice_fn, "    "));
    m.push_str(&indent(&oracle, "    "));
    let _ = writeln!(m, "    pub fn run(report: &mut Report) {{");
    let _ = writeln!(
        m,
        "        let array = ArrayModel {{ {} }};",
        fields.join(", ")
    );
    let mut slice_fields = fields.clone();
    slice_fields.push("n: N".into());
    let _ = writeln!(
        m,
        "        let slice = SliceModel {{ {} }};",
        slice_fields.join(", ")
    );
    let t_unused = if p.time { "" } else { "_" };
    // What a program compiles is most of the test's compile time: every program checks the
    // array model's `value` and fused `gradient_and_hessian` and every method of the slice
    // model; every other program also its `DynLagrangian` impl, and one in four every other
    // method of its `Lagrangian<N>` impl.
    let every = if p.id % 4 == 1 {
        "Some(other_methods(&array))"
    } else {
        "None"
    };
    let array_dyn = if p.id.is_multiple_of(2) {
        "Some(dyn_model(&array))"
    } else {
        "None"
    };
    let _ = writeln!(
        m,
        "        check::<N>(report, &Program {{\n\
         \x20           id: {},\n\
         \x20           forms: &[{}],\n\
         \x20           text: {:?},\n\
         \x20           time: {},\n\
         \x20           array: const_model(&array),\n\
         \x20           every_method: {every},\n\
         \x20           array_dyn: {array_dyn},\n\
         \x20           slice: dyn_model(&slice),\n\
         \x20           array_fn: &|x, v, {t_unused}t| array_model({}),\n\
         \x20           slice_fn: &|x, v, {t_unused}t| slice_model({}),\n\
         \x20           oracle: &|x, v, t, terms| oracle(x, v, t, &K, terms),\n\
         \x20       }});",
        p.id,
        forms.join(", "),
        text,
        p.time,
        args_array.join(", "),
        args_slice.join(", "),
    );
    let _ = writeln!(m, "    }}");
    let _ = writeln!(m, "}}");
    m
}

/// The helpers every program may call, for the macro and (rewritten by hand) for the oracle.
const PRELUDE: &str = r#"
/// A quartic spring.
#[lagrangian(helper)]
fn fz_spring(d: f64, k: f64) -> f64 {
    0.5 * k * d * d + 0.1 * d.powi(4)
}

/// A soft well.
#[lagrangian(helper)]
fn fz_well(y: f64) -> f64 {
    -1.0 / (1.0 + y * y)
}

/// A bond that calls another helper, through a local.
#[lagrangian(helper)]
fn fz_bond(a: f64, b: f64) -> f64 {
    let d = a - b;
    fz_well(d) + 0.25 * a.sin() * b
}

fn dual_spring<T: DualNum<Primitive = f64> + Copy>(d: T, k: T) -> T {
    d * d * k * 0.5 + d.powi(4) * 0.1
}

fn dual_well<T: DualNum<Primitive = f64> + Copy>(y: T) -> T {
    -(y * y + 1.0).recip()
}

fn dual_bond<T: DualNum<Primitive = f64> + Copy>(a: T, b: T) -> T {
    dual_well(a - b) + a.sin() * b * 0.25
}

/// `tanh a` as `σ (1 − e)/(1 + e)`, `e = exp(−2σa)`, `σ` the sign of `a`'s value: every
/// derivative a sum of terms of one sign, where num-dual's `sinh/cosh` leaves `ε cosh² a`
/// relative in them.
fn dual_tanh<T: DualNum<Primitive = f64> + Copy>(a: T) -> T {
    let sigma = if a.re() < 0.0 { -1.0 } else { 1.0 };
    let e = (a * (-2.0 * sigma)).exp();
    (-e + 1.0) / (e + 1.0) * sigma
}

/// `a.max(b)`, where `f64::max` has no num-dual counterpart: the larger by value.
fn dual_max<T: DualNum<Primitive = f64> + Copy>(a: T, b: T) -> T {
    if a.re() >= b.re() { a } else { b }
}

/// `a.min(b)`: the smaller by value.
fn dual_min<T: DualNum<Primitive = f64> + Copy>(a: T, b: T) -> T {
    if a.re() <= b.re() { a } else { b }
}
"#;

fn generate(count: usize, seed: u64, level: Level) -> String {
    let mut rng = Rng(seed);
    let mut out = String::new();
    let level_name = match level {
        Level::Legacy => "legacy",
        Level::Full => "full",
    };
    let _ = writeln!(
        out,
        "// Generated by tests/build.rs: {count} programs, seed {seed:#x}, level `{level_name}`.\n"
    );
    let _ = writeln!(out, "/// The seed the programs were drawn from.");
    let _ = writeln!(out, "pub const SEED: u64 = {seed:#x};");
    let _ = writeln!(out, "/// The grammar level of the programs.");
    let _ = writeln!(out, "pub const LEVEL: &str = {level_name:?};");
    let forms: Vec<String> = FORMS.iter().map(|f| format!("{f:?}")).collect();
    let _ = writeln!(
        out,
        "/// Every form the generator knows, in the report's order."
    );
    let _ = writeln!(out, "pub const FORMS: &[&str] = &[{}];", forms.join(", "));
    out.push_str(PRELUDE);
    let mut runs = Vec::new();
    for id in 0..count {
        let p = draw(&mut rng, id, level);
        out.push('\n');
        out.push_str(&program(&p));
        runs.push(format!("p{id:04}::run"));
    }
    // The vector-valued programs draw from a generator of their own, so that the Lagrangians
    // of a seed stay what they were.
    let mut vector_rng = Rng(seed ^ 0x5EC7_0A00_F0AC_E000);
    let mut vector_runs = Vec::new();
    for id in 0..count.div_ceil(4) {
        out.push('\n');
        out.push_str(&vector_program(&mut vector_rng, id, level));
        vector_runs.push(format!("vf{id:04}::run"));
    }
    // The looped forces, likewise from a generator of their own.
    let mut force_rng = Rng(seed ^ 0x100F_ED0F_0ACE_0000);
    let mut force_runs = Vec::new();
    for id in 0..count.div_ceil(4) {
        out.push('\n');
        out.push_str(&looped_force_program(&mut force_rng, id, level));
        force_runs.push(format!("lf{id:04}::run"));
    }
    let _ = writeln!(
        out,
        "\n/// Every looped `#[force]` program's check, in order."
    );
    let _ = writeln!(
        out,
        "pub const LOOPED_FORCE_PROGRAMS: &[fn(&mut Report)] = &[{}];",
        force_runs.join(", ")
    );
    let _ = writeln!(
        out,
        "\n/// Every `#[force]` and `#[constraint]` program's check, in order."
    );
    let _ = writeln!(
        out,
        "pub const VECTOR_PROGRAMS: &[fn(&mut Report)] = &[{}];",
        vector_runs.join(", ")
    );
    let _ = writeln!(out, "\n/// Every program's check, in order.");
    let _ = writeln!(
        out,
        "pub const PROGRAMS: &[fn(&mut Report)] = &[{}];",
        runs.join(", ")
    );
    out
}

/// A `#[force]` (even `id`) or `#[constraint]` (odd `id`) program of literal dimension
/// `D = 1..=4`: each component one loop-free body of the Lagrangians' language (components
/// at literal indices, the functions where they are defined, branches, helpers, constants,
/// `t`; a constraint reads `x` only), bound to `let`s or written in the array, or set element
/// by element in a loop over `0..M`; and the oracle, the same components on dual numbers.
fn vector_program(rng: &mut Rng, id: usize, level: Level) -> String {
    let force = id.is_multiple_of(2);
    let d = 1 + rng.below(4);
    let m = if force { d } else { 1 + rng.below(3) };
    let consts = rng.below(3);
    let time = force && rng.chance(0.5);
    let mut g = Gen::new(rng, level, (d, consts, time), !force);
    let components: Vec<E> = (0..m).map(|_| g.body(&[])).collect();
    let form = g.rng.below(3);
    let consts: Vec<f64> = (0..consts).map(|_| rng_const(g.rng)).collect();
    let dim = Lang::Macro(Dim::Literal(d));
    let rendered: Vec<String> = components.iter().map(|e| render(e, dim).0).collect();
    // Three ways to write the value: the array itself, `let`s then the array, or a local
    // array set in a loop over `0..M` (unrolled by the macro) from the `let`s.
    let mut text = String::new();
    match form {
        0 => {
            let _ = writeln!(text, "[{}]", rendered.join(", "));
        }
        1 => {
            for (k, r) in rendered.iter().enumerate() {
                let _ = writeln!(text, "let c{k} = {r};");
            }
            let names: Vec<String> = (0..m).map(|k| format!("c{k}")).collect();
            let _ = writeln!(text, "[{}]", names.join(", "));
        }
        _ => {
            let names: Vec<String> = (0..m).map(|k| format!("c{k}")).collect();
            for (k, r) in rendered.iter().enumerate() {
                let _ = writeln!(text, "let c{k} = {r};");
            }
            let _ = writeln!(text, "let c = [{}];", names.join(", "));
            let _ = writeln!(text, "let mut out = [0.0; {m}];");
            let _ = writeln!(
                text,
                "for k in 0..{m} {{\n    out[k] = 2.0 * c[k];\n    out[k] -= c[k];\n}}"
            );
            let _ = writeln!(text, "out");
        }
    }
    let (attr, name) = if force {
        ("force", "force_model")
    } else {
        ("constraint", "constraint_model")
    };
    let mut params = vec![format!("x: [f64; {d}]")];
    if force {
        params.push(format!("v: [f64; {d}]"));
        if time {
            params.push("t: f64".into());
        }
    }
    params.extend((0..consts.len()).map(|j| format!("k{j}: f64")));
    let struct_name = if force {
        "ForceModel"
    } else {
        "ConstraintModel"
    };
    let macro_fn = format!(
        "#[{attr}]\n#[allow(unused_variables, clippy::needless_range_loop, clippy::eq_op, reason = \"a program need not read every parameter; the loop is a form the macro takes; components drawn apart may name one entry at a literal dimension (`x[1 - 1] - x[0]`)\")]\npub fn {name}({}) -> [f64; {m}] {{\n{}}}\n",
        params.join(", "),
        indent(&text, "    ")
    );
    let oracle_components: Vec<String> = components
        .iter()
        .map(|e| render(e, Lang::Oracle).0)
        .collect();
    let oracle = format!(
        "#[allow(unused_variables, reason = \"a program need not read `v`, `t`, `k` or `n`\")]\n\
         pub fn oracle<T: DualNum<Primitive = f64> + Copy>(x: &[T], v: &[T], t: f64, k: &[f64]) -> Vec<T> {{\n\
         \x20   let n = x.len();\n\
         \x20   let c = |a: f64| T::from(a);\n\
         \x20   vec![{}]\n}}\n",
        oracle_components.join(", ")
    );
    let fields: Vec<String> = (0..consts.len()).map(|j| format!("k{j}: K[{j}]")).collect();
    let k_list: Vec<String> = consts.iter().map(|c| format!("{c:?}")).collect();
    let t_arg = "t";
    let (value, jacobian, weighted) = if force {
        (
            format!(
                "&|x, v, {t_arg}| model.force(&Vector::<{d}>::from_column_slice(x), &Vector::<{d}>::from_column_slice(v), {t_arg}).iter().copied().collect()"
            ),
            format!(
                "&|x, v, {t_arg}| {{ let j = model.jacobian(&Vector::<{d}>::from_column_slice(x), &Vector::<{d}>::from_column_slice(v), {t_arg}); (0..{m}).map(|i| (0..{d}).map(|c| j.x[(i, c)]).chain((0..{d}).map(|c| j.v[(i, c)])).collect()).collect() }}"
            ),
            "None".to_string(),
        )
    } else {
        (
            format!(
                "&|x, _v, _t| model.value(&Vector::<{d}>::from_column_slice(x)).iter().copied().collect()"
            ),
            format!(
                "&|x, _v, _t| {{ let g = model.jacobian(&Vector::<{d}>::from_column_slice(x)); (0..{m}).map(|i| (0..{d}).map(|c| g[(i, c)]).chain((0..{d}).map(|_| 0.0)).collect()).collect() }}"
            ),
            format!(
                "Some(&|x, lambda| {{ let h = model.weighted_hessian(&Vector::<{d}>::from_column_slice(x), &nalgebra::SVector::<f64, {m}>::from_column_slice(lambda)); (0..{d}).map(|a| (0..{d}).map(|b| h[(a, b)]).collect()).collect() }})"
            ),
        )
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "#[allow(clippy::eq_op, clippy::if_same_then_else, reason = \"components drawn apart may \
         name one entry at a literal dimension (`x[2 - 1] - x[1]`), and then a branch may read the \
         same on both sides\")]"
    );
    let _ = writeln!(out, "pub mod vf{id:04} {{");
    let _ = writeln!(out, "    use super::*;");
    let _ = writeln!(
        out,
        "    const K: [f64; {}] = [{}];",
        consts.len(),
        k_list.join(", ")
    );
    out.push_str(&indent(&macro_fn, "    "));
    out.push_str(&indent(&oracle, "    "));
    let _ = writeln!(out, "    pub fn run(report: &mut Report) {{");
    let _ = writeln!(
        out,
        "        let model = {struct_name} {{ {} }};",
        fields.join(", ")
    );
    let _ = writeln!(
        out,
        "        check_vector(report, &VectorProgram {{ id: {id}, force: {force}, d: {d}, m: {m}, text: {macro_fn:?}, value: {value}, jacobian: {jacobian}, weighted: {weighted}, oracle: &|x, v, t| oracle(x, v, t, &K) }});"
    );
    let _ = writeln!(out, "    }}");
    let _ = writeln!(out, "}}");
    out
}

// ---------------------------------------------------------------------------------------------
// Forces with loops over a named dimension.

/// What a looped force reads of the state.
#[derive(Clone, Copy, PartialEq)]
enum Reads {
    Both,
    Positions,
    Velocities,
    /// Neither: drives in `t` and the constants only.
    Nothing,
}

/// A statement of the body of a `#[force]` with loops.
#[derive(Clone)]
enum FS {
    /// `let name = e;`
    Let(String, E),
    /// `let mut name = 0.0;`: an accumulator, read after its loop.
    LetMut(String),
    /// `name += e;`
    Acc(String, E),
    /// `f[ix] += e;` (`-=` when `minus`).
    Add(Ix, E, bool),
    For(String, Range, Vec<FS>),
}

/// Whether `stmts` add to the force.
fn adds_to_force(stmts: &[FS]) -> bool {
    stmts.iter().any(|s| match s {
        FS::Add(..) => true,
        FS::For(_, _, body) => adds_to_force(body),
        _ => false,
    })
}

/// The statements of a looped force in `lang`: the `#[force]` fns add to `f[ix]`, the oracle
/// pushes each additive term of a contribution to `f[ix]`'s list.
fn render_force(out: &mut String, stmts: &[FS], lang: Lang, indent: usize) {
    let pad = "    ".repeat(indent);
    let dim = lang.dim();
    for s in stmts {
        match s {
            FS::Let(name, e) => {
                let _ = writeln!(out, "{pad}let {name} = {};", render(e, lang).0);
            }
            FS::LetMut(name) => {
                let _ = writeln!(out, "{pad}let mut {name} = {};", render(&num(0.0), lang).0);
            }
            FS::Acc(name, e) => {
                let _ = writeln!(out, "{pad}{name} += {};", render(e, lang).0);
            }
            FS::Add(ix, e, minus) => match lang {
                Lang::Macro(_) => {
                    let op = if *minus { "-=" } else { "+=" };
                    let _ = writeln!(
                        out,
                        "{pad}f[{}] {op} {};",
                        ix.render(dim),
                        render(e, lang).0
                    );
                }
                Lang::Oracle => push_force_terms(out, &ix.render(dim), e, *minus, &pad),
            },
            FS::For(i, range, body) => {
                let _ = writeln!(out, "{pad}for {i} in {} {{", range.render(dim));
                render_force(out, body, lang, indent + 1);
                let _ = writeln!(out, "{pad}}}");
            }
        }
    }
}

/// The oracle's `f[ix].push(±e)`, one push per additive term of `e` and per iteration of a sum
/// that `e` adds (as [`push_terms`] for `L`).
fn push_force_terms(out: &mut String, ix: &str, e: &E, minus: bool, pad: &str) {
    match e {
        E::Bin(Op::Add, a, b) => {
            push_force_terms(out, ix, a, minus, pad);
            push_force_terms(out, ix, b, minus, pad);
        }
        E::Bin(Op::Sub, a, b) => {
            push_force_terms(out, ix, a, minus, pad);
            push_force_terms(out, ix, b, !minus, pad);
        }
        E::Neg(a) => push_force_terms(out, ix, a, !minus, pad),
        E::Sum(i, range, body) => {
            let _ = writeln!(out, "{pad}for {i} in {} {{", range.render(Dim::Runtime));
            push_force_terms(out, ix, body, minus, &format!("{pad}    "));
            let _ = writeln!(out, "{pad}}}");
        }
        _ => {
            let s = render(e, Lang::Oracle);
            if minus {
                let _ = writeln!(out, "{pad}f[{ix}].push(-{});", paren(s, 3));
            } else {
                let _ = writeln!(out, "{pad}f[{ix}].push({});", s.0);
            }
        }
    }
}

/// `lo..hi` (`lo..=hi`) from a literal.
fn span(lo: usize, hi: Ix, inclusive: bool) -> Range {
    Range {
        lo: Ix::Lit(lo),
        hi,
        inclusive,
    }
}

impl Gen<'_> {
    /// A component at `ix`, of what the force reads.
    fn state(&mut self, reads: Reads, ix: Ix) -> E {
        match reads {
            Reads::Positions => E::X(ix),
            Reads::Velocities => E::V(ix),
            _ if self.rng.chance(0.5) => E::X(ix),
            _ => E::V(ix),
        }
    }

    /// `e`, plus a small term in a component at each loop variable of `vars` that neither `e`
    /// nor `also` names (an index number when the force reads no state).
    fn force_reads(&mut self, reads: Reads, e: E, also: &[&E], vars: &[&str]) -> E {
        let mut e = e;
        for var in vars {
            let mut all = also.to_vec();
            all.push(&e);
            if !mentions(&all, var) {
                let ix = Ix::Var((*var).to_string(), 0);
                let term = match reads {
                    Reads::Nothing => E::IdxNum(Ix::Var((*var).to_string(), 1)),
                    _ => self.state(reads, ix),
                };
                e = add(e, mul(num(0.1), term));
            }
        }
        e
    }

    /// A function of a difference `d` between two components: a bond's tension.
    fn link(&mut self, d: &str, vars: &[LoopVar]) -> E {
        match self.rng.below(4) {
            0 => self.smooth(local(d)),
            1 => {
                let c = match self.k() {
                    Some(k) => k,
                    None => num(self.rng.coefficient()),
                };
                add(
                    mul(c, local(d)),
                    mul(num(0.1), E::Powi(Box::new(local(d)), 3)),
                )
            }
            2 => {
                let s = self.smooth(local(d));
                let a = self.component(vars);
                mul(s, a)
            }
            _ => mul(num(self.rng.coefficient()), local(d)),
        }
    }

    /// `e` modulated in time: `e * (c * t).cos()`, or `(1.0 + c * t) * e`.
    fn in_time(&mut self, e: E) -> E {
        let c = self.rng.coefficient();
        if self.rng.chance(0.5) {
            mul(e, f(Fun::Cos, mul(num(c), E::T)))
        } else {
            mul(add(num(1.0), mul(num(c), E::T)), e)
        }
    }

    /// A drive: `t` and the constants only.
    fn drive(&mut self, out: &mut Vec<FS>, minus: bool) {
        self.form("force_drive");
        let amplitude = |g: &mut Gen<'_>| match g.k() {
            Some(k) if g.rng.chance(0.6) => k,
            _ => num(g.rng.coefficient()),
        };
        let target = self.rng.pick(&[0, 1, 2]);
        let target = match target {
            0 => Ix::Lit(0),
            1 => Ix::Last,
            _ => Ix::Half,
        };
        match self.rng.below(3) {
            0 if self.time => {
                let a = amplitude(self);
                let w = self.rng.coefficient();
                let e = mul(a, f(Fun::Sin, mul(num(w), E::T)));
                out.push(FS::Add(target, e, minus));
            }
            1 => {
                let i = self.name("i");
                let w = E::IdxNum(Ix::Var(i.clone(), 1));
                let e = if self.time {
                    let c = self.rng.coefficient();
                    mul(num(0.1), f(Fun::Cos, mul(mul(num(c), w), E::T)))
                } else {
                    let a = amplitude(self);
                    mul(mul(num(0.1), w), a)
                };
                out.push(FS::For(
                    i.clone(),
                    self.full_range(),
                    vec![FS::Add(Ix::Var(i, 0), e, minus)],
                ));
            }
            _ => {
                let a = amplitude(self);
                out.push(FS::Add(target, a, minus));
            }
        }
    }

    /// Adds one part of a looped force to `out`.
    fn force_part(&mut self, reads: Reads, out: &mut Vec<FS>) {
        let table: &[(&'static str, usize)] = &[
            ("force_scatter", 4),
            ("force_gather", 5),
            ("force_periodic", 3),
            ("force_guarded", 3),
            ("force_literal", 2),
            ("force_double", 3),
            ("force_sum", 4),
            ("force_drive", 1),
        ];
        let total: usize = table.iter().map(|e| e.1).sum();
        let mut r = self.rng.below(total);
        let mut kind = table[0].0;
        for &(name, w) in table {
            if r < w {
                kind = name;
                break;
            }
            r -= w;
        }
        let minus = self.rng.chance(0.3);
        let d = self.d;
        if reads == Reads::Nothing {
            self.drive(out, minus);
            return;
        }
        match kind {
            "force_scatter" => {
                self.form("force_scatter");
                let i = self.name("i");
                let dn = self.name("d");
                // Links `(i, i + 1)` over `0..N - 1`, or `(i - 1, i)` over `1..N`: empty at
                // `N = 1`.
                let back = self.rng.chance(0.4);
                let (range, lo, hi, max) = if back {
                    (
                        span(1, Ix::Dim, false),
                        Ix::Back(i.clone(), 1),
                        Ix::Var(i.clone(), 0),
                        (d >= 2).then_some(d - 1),
                    )
                } else {
                    (
                        span(0, Ix::Last, false),
                        Ix::Var(i.clone(), 0),
                        Ix::Var(i.clone(), 1),
                        d.checked_sub(2),
                    )
                };
                let vars = vec![self.var(&i, max)];
                let on_x =
                    reads == Reads::Positions || (reads == Reads::Both && self.rng.chance(0.6));
                let comp = |ix: Ix| if on_x { E::X(ix) } else { E::V(ix) };
                let diff = sub(comp(hi.clone()), comp(lo.clone()));
                let mut link = self.link(&dn, &vars);
                if reads == Reads::Both && on_x && self.rng.chance(0.4) {
                    let c = self.rng.coefficient();
                    let dv = sub(E::V(hi.clone()), E::V(lo.clone()));
                    link = add(link, mul(num(c), dv));
                }
                if self.time && self.rng.chance(0.3) {
                    link = self.in_time(link);
                }
                let mut stmts = vec![FS::Let(dn, diff)];
                if self.rng.chance(0.6) {
                    let e = self.name("e");
                    stmts.push(FS::Let(e.clone(), link));
                    link = local(&e);
                }
                stmts.push(FS::Add(lo, link.clone(), minus));
                stmts.push(FS::Add(hi, link, !minus));
                out.push(FS::For(i, range, stmts));
            }
            "force_gather" => {
                self.form("force_gather");
                let i = self.name("i");
                let own = Ix::Var(i.clone(), 0);
                let (range, max, target) = match self.rng.below(5) {
                    0 => {
                        let target = if self.rng.chance(0.5) {
                            Ix::Back(i.clone(), 1)
                        } else {
                            own
                        };
                        (span(1, Ix::Dim, false), (d >= 2).then_some(d - 1), target)
                    }
                    1 => {
                        let target = if self.rng.chance(0.5) {
                            Ix::Var(i.clone(), 1)
                        } else {
                            own
                        };
                        (span(0, Ix::Last, false), d.checked_sub(2), target)
                    }
                    2 => (span(0, Ix::Last, true), Some(d - 1), own),
                    3 => (self.full_range(), Some(d - 1), Ix::Mirror(i.clone())),
                    _ => (self.full_range(), Some(d - 1), own),
                };
                let vars = vec![self.var(&i, max)];
                let mut stmts = Vec::new();
                let mut body = self.body(&vars);
                if self.rng.chance(0.3) {
                    let y = self.name("y");
                    let e = self.combo(&vars);
                    let s = self.smooth(local(&y));
                    stmts.push(FS::Let(y, e));
                    body = add(body, s);
                }
                let lets: Vec<&E> = stmts
                    .iter()
                    .filter_map(|s| match s {
                        FS::Let(_, e) => Some(e),
                        _ => None,
                    })
                    .collect();
                let mut body = self.force_reads(reads, body, &lets, &[&i]);
                if self.time && self.rng.chance(0.35) {
                    body = self.in_time(body);
                }
                stmts.push(FS::Add(target.clone(), body, minus));
                if reads != Reads::Positions && self.rng.chance(0.3) {
                    // Quadratic drag on the same component.
                    let vi = E::V(target.clone());
                    let c = self.rng.coefficient();
                    let drag = mul(mul(num(c), vi.clone()), f(Fun::Abs, vi));
                    stmts.push(FS::Add(target, drag, true));
                }
                out.push(FS::For(i, range, stmts));
            }
            "force_periodic" if d >= 2 => {
                self.form("force_periodic");
                let i = self.name("i");
                let dn = self.name("d");
                let vars = vec![self.var(&i, Some(d - 1))];
                let next = if self.rng.chance(0.7) {
                    Ix::Next(i.clone())
                } else {
                    Ix::Prev(i.clone())
                };
                let own = Ix::Var(i.clone(), 0);
                let on_x =
                    reads == Reads::Positions || (reads == Reads::Both && self.rng.chance(0.6));
                let comp = |ix: Ix| if on_x { E::X(ix) } else { E::V(ix) };
                let diff = sub(comp(next.clone()), comp(own.clone()));
                let link = self.link(&dn, &vars);
                let mut stmts = vec![FS::Let(dn, diff)];
                if self.rng.chance(0.5) {
                    // Each bond adds to both of its ends.
                    let e = self.name("e");
                    stmts.push(FS::Let(e.clone(), link));
                    stmts.push(FS::Add(own, local(&e), minus));
                    stmts.push(FS::Add(next, local(&e), !minus));
                } else {
                    stmts.push(FS::Add(own, link, minus));
                }
                out.push(FS::For(i, self.full_range(), stmts));
            }
            "force_guarded" => {
                self.form("force_guarded");
                self.form("branch");
                let i = self.name("i");
                let vars = vec![self.var(&i, Some(d - 1))];
                let own = Ix::Var(i.clone(), 0);
                let on_x =
                    reads == Reads::Positions || (reads == Reads::Both && self.rng.chance(0.6));
                let comp = |ix: Ix| if on_x { E::X(ix) } else { E::V(ix) };
                let var = |c: usize| Ix::Var(i.clone(), c);
                let guard_left = |g: &mut Gen<'_>, yes: E, no: E| match g.rng.below(3) {
                    0 => E::If(
                        Box::new(Cond::Index(Some(Cmp::Gt), var(0), Ix::Lit(0))),
                        Box::new(yes),
                        Box::new(no),
                    ),
                    1 => E::If(
                        Box::new(Cond::Index(Some(Cmp::Ge), var(0), Ix::Lit(1))),
                        Box::new(yes),
                        Box::new(no),
                    ),
                    _ => E::If(
                        Box::new(Cond::Index(None, var(0), Ix::Lit(0))),
                        Box::new(no),
                        Box::new(yes),
                    ),
                };
                let guard_right = |yes: E, no: E| {
                    E::If(
                        Box::new(Cond::Index(Some(Cmp::Lt), var(1), Ix::Dim)),
                        Box::new(yes),
                        Box::new(no),
                    )
                };
                let left = comp(Ix::Back(i.clone(), 1));
                let right = comp(var(1));
                let mut stmts = Vec::new();
                if self.rng.chance(0.5) {
                    // Neighbours read into locals (a chain with fixed ends).
                    let (l, r) = (self.name("left"), self.name("right"));
                    stmts.push(FS::Let(l.clone(), guard_left(self, left, num(0.0))));
                    let lap = if self.rng.chance(0.6) {
                        stmts.push(FS::Let(r.clone(), guard_right(right, num(0.0))));
                        add(sub(local(&l), mul(num(2.0), comp(own.clone()))), local(&r))
                    } else {
                        sub(local(&l), comp(own.clone()))
                    };
                    let c = match self.k() {
                        Some(k) => k,
                        None => num(self.rng.coefficient()),
                    };
                    let e = match self.rng.below(3) {
                        0 => mul(c, lap),
                        1 => {
                            let g = self.component(&vars);
                            mul(mul(c, lap), g)
                        }
                        _ => {
                            let dn = self.name("lap");
                            stmts.push(FS::Let(dn.clone(), lap));
                            let s = self.smooth(local(&dn));
                            add(mul(c, local(&dn)), s)
                        }
                    };
                    stmts.push(FS::Add(own, e, minus));
                } else {
                    // A branch as the contribution itself.
                    let c = self.rng.coefficient();
                    let g = self.component(&vars);
                    let yes = mul(mul(num(c), left), g);
                    let no = if self.rng.chance(0.5) {
                        num(0.0)
                    } else {
                        self.factor(&vars, 0)
                    };
                    let e = guard_left(self, yes, no);
                    stmts.push(FS::Add(own.clone(), e, minus));
                    if self.rng.chance(0.5) {
                        let s = self.smooth(sub(right, comp(own.clone())));
                        let e = guard_right(s, num(0.0));
                        stmts.push(FS::Add(own, e, !minus));
                    }
                }
                out.push(FS::For(i, self.full_range(), stmts));
            }
            "force_literal" => {
                self.form("force_literal");
                for _ in 0..1 + self.rng.below(2) {
                    let mut targets = vec![Ix::Lit(0), Ix::Last, Ix::Half];
                    if d >= 2 {
                        targets.push(Ix::Lit(1));
                    }
                    let target = targets[self.rng.below(targets.len())].clone();
                    let e = self.body(&[]);
                    let minus = self.rng.chance(0.4);
                    out.push(FS::Add(target, e, minus));
                }
            }
            "force_double" => {
                self.form("force_double");
                self.form("nested");
                let i = self.name("i");
                let j = self.name("j");
                let dn = self.name("d");
                let on_x =
                    reads == Reads::Positions || (reads == Reads::Both && self.rng.chance(0.6));
                let comp = |ix: Ix| if on_x { E::X(ix) } else { E::V(ix) };
                let (xi, xj) = (comp(Ix::Var(i.clone(), 0)), comp(Ix::Var(j.clone(), 0)));
                match self.rng.below(3) {
                    0 => {
                        // Every pair, both ways: a gather over `j`.
                        let vars = vec![self.var(&i, Some(d - 1)), self.var(&j, Some(d - 1))];
                        let e = mul(num(0.1), self.link(&dn, &vars));
                        out.push(FS::For(
                            i.clone(),
                            self.full_range(),
                            vec![FS::For(
                                j,
                                self.full_range(),
                                vec![FS::Let(dn, sub(xj, xi)), FS::Add(Ix::Var(i, 0), e, minus)],
                            )],
                        ));
                    }
                    1 => {
                        // Every pair once, `i < j`, adding to both.
                        let jmax = (d >= 2).then_some(d - 1);
                        let vars = vec![self.var(&i, Some(d - 1)), self.var(&j, jmax)];
                        let link = self.link(&dn, &vars);
                        let e = self.name("e");
                        out.push(FS::For(
                            i.clone(),
                            self.full_range(),
                            vec![FS::For(
                                j.clone(),
                                Range {
                                    lo: Ix::Var(i.clone(), 1),
                                    hi: Ix::Dim,
                                    inclusive: false,
                                },
                                vec![
                                    FS::Let(dn, sub(xj, xi)),
                                    FS::Let(e.clone(), mul(num(0.1), link)),
                                    FS::Add(Ix::Var(i, 0), local(&e), minus),
                                    FS::Add(Ix::Var(j, 0), local(&e), !minus),
                                ],
                            )],
                        ));
                    }
                    _ => {
                        // An iterator sum times a component of the outer index.
                        self.form("iter_sum");
                        let outer = [self.var(&i, Some(d - 1))];
                        let s = self.smooth(sub(xj, xi));
                        let body = self.force_reads(reads, s, &[], &[&j]);
                        let g = self.component(&outer);
                        let outer = self.force_reads(reads, g, &[], &[&i]);
                        let e = mul(
                            mul(num(0.1), outer),
                            E::Sum(j, self.full_range(), Box::new(body)),
                        );
                        out.push(FS::For(
                            i.clone(),
                            self.full_range(),
                            vec![FS::Add(Ix::Var(i, 0), e, minus)],
                        ));
                    }
                }
            }
            "force_sum" => {
                self.form("force_sum");
                let s = self.name("s");
                let j = self.name("j");
                let i = self.name("i");
                let ivars = vec![self.var(&i, Some(d - 1))];
                let centre = self.rng.chance(0.35);
                let on_x =
                    reads == Reads::Positions || (reads == Reads::Both && self.rng.chance(0.6));
                let comp = |ix: Ix| if on_x { E::X(ix) } else { E::V(ix) };
                let body = if centre {
                    self.form("centre");
                    comp(Ix::Var(j.clone(), 0))
                } else {
                    let jvars = vec![self.var(&j, Some(d - 1))];
                    let b = self.body(&jvars);
                    self.force_reads(reads, b, &[], &[&j])
                };
                if self.rng.chance(0.65) {
                    self.form("iter_sum");
                    out.push(FS::Let(
                        s.clone(),
                        E::Sum(j, self.full_range(), Box::new(body)),
                    ));
                } else {
                    out.push(FS::LetMut(s.clone()));
                    out.push(FS::For(
                        j,
                        self.full_range(),
                        vec![FS::Acc(s.clone(), body)],
                    ));
                }
                let mean = div(local(&s), E::IdxNum(Ix::Dim));
                let c = self.rng.coefficient();
                let e = match self.rng.below(5) {
                    0 => {
                        let a = self.state(reads, Ix::Var(i.clone(), 0));
                        mul(mul(num(c), local(&s)), a)
                    }
                    1 if centre => {
                        self.form("sum_square");
                        let dev = sub(comp(Ix::Var(i.clone(), 0)), mean);
                        let a = self.component(&ivars);
                        mul(mul(mul(num(c), dev.clone()), dev), a)
                    }
                    1 => {
                        self.form("sum_square");
                        mul(mul(num(0.1), local(&s)), local(&s))
                    }
                    2 => mul(num(c), mean),
                    3 => {
                        let g = self.factor(&ivars, 0);
                        mul(local(&s), g)
                    }
                    _ => {
                        let k = match self.k() {
                            Some(k) => k,
                            None => num(c),
                        };
                        mul(k, sub(comp(Ix::Var(i.clone(), 0)), mean))
                    }
                };
                let e = self.force_reads(reads, e, &[], &[&i]);
                out.push(FS::For(
                    i.clone(),
                    self.full_range(),
                    vec![FS::Add(Ix::Var(i, 0), e, minus)],
                ));
                if self.rng.chance(0.3) {
                    let c = self.rng.coefficient();
                    out.push(FS::Add(Ix::Lit(0), mul(num(c), local(&s)), !minus));
                }
            }
            _ => self.drive(out, minus),
        }
    }
}

/// A `#[force]` with loops over a named dimension `N = 1..=8`, written three times: over
/// `[f64; N]` (a `Force<N>` and a `DynForce`), over slices with a run-time `n: usize` (a
/// `DynForce`), and as the oracle, a generic fn that pushes each contribution to a component
/// onto that component's list (a plain loop filling an array of lists: no macro
/// transformation). The body: one to three parts (a scatter over links `(i, i + 1)`, a
/// gather, a periodic ring, guarded neighbours, literal components, a double loop, a sum
/// entering polynomially, a drive in `t`), reading `x` and `v`, one of them, or neither.
fn looped_force_program(rng: &mut Rng, id: usize, level: Level) -> String {
    let d = 1 + rng.below(8);
    let consts = rng.below(3);
    let time = rng.chance(0.4);
    let reads = match rng.below(10) {
        0..=4 => Reads::Both,
        5 | 6 => Reads::Positions,
        7 | 8 => Reads::Velocities,
        _ => Reads::Nothing,
    };
    let mut g = Gen::new(rng, level, (d, consts, time), reads == Reads::Positions);
    g.velocities_only = reads == Reads::Velocities;
    let nparts = g.rng.pick(&[1, 1, 2, 2, 3]);
    let mut stmts = Vec::new();
    for _ in 0..nparts {
        g.force_part(reads, &mut stmts);
    }
    // The force is declared first, or after the sums that lead the body.
    let declare_at = if g.rng.chance(0.5) {
        0
    } else {
        stmts
            .iter()
            .position(|s| adds_to_force(std::slice::from_ref(s)))
            .unwrap_or(stmts.len())
    };
    let consts: Vec<f64> = (0..consts).map(|_| rng_const(g.rng)).collect();
    let body = |dim: Dim| -> String {
        let lang = Lang::Macro(dim);
        let mut s = String::new();
        render_force(&mut s, &stmts[..declare_at], lang, 0);
        match dim {
            Dim::Runtime => s.push_str("let mut f = vec![0.0; n];\n"),
            _ => s.push_str("let mut f = [0.0; N];\n"),
        }
        render_force(&mut s, &stmts[declare_at..], lang, 0);
        s.push_str("f\n");
        s
    };
    let slice_body = body(Dim::Runtime);
    let time = has_word(&slice_body, "t");
    if time {
        g.form("time");
    }
    for (needle, form) in [
        (") % n", "periodic"),
        ("fz_spring(", "helper"),
        ("fz_well(", "helper"),
        ("fz_bond(", "helper"),
    ] {
        if slice_body.contains(needle) {
            g.form(form);
        }
    }
    if !slice_body.contains("x[") {
        g.form("force_no_x");
    }
    if !slice_body.contains("v[") {
        g.form("force_no_v");
    }
    let mut forms = g.forms.clone();
    forms.sort_by_key(|f| FORMS.iter().position(|g| g == f));

    let params = |ty: &str, n: bool| -> String {
        let mut p = vec![format!("x: {ty}"), format!("v: {ty}")];
        if time {
            p.push("t: f64".into());
        }
        let mut ks: Vec<String> = (0..consts.len()).map(|j| format!("k{j}: f64")).collect();
        if n {
            ks.insert(id % (consts.len() + 1), "n: usize".into());
        }
        p.extend(ks);
        p.join(", ")
    };
    let allow =
        "#[allow(unused_variables, reason = \"a force need not read `x`, `v` or every constant\")]";
    let array_fn = format!(
        "#[force]\n{allow}\npub fn array_force({}) -> [f64; N] {{\n{}}}\n",
        params("[f64; N]", false),
        indent(&body(Dim::Named), "    ")
    );
    let slice_fn = format!(
        "#[force]\n{allow}\npub fn slice_force({}) -> Vec<f64> {{\n{}}}\n",
        params("&[f64]", true),
        indent(&slice_body, "    ")
    );
    let mut oracle_body = String::new();
    render_force(&mut oracle_body, &stmts, Lang::Oracle, 0);
    let oracle = format!(
        "#[allow(unused_variables, reason = \"a force need not read `x`, `v`, `t`, `k` or `n`\")]\n\
         pub fn oracle<T: DualNum<Primitive = f64> + Copy>(x: &[T], v: &[T], t: f64, k: &[f64], f: &mut [Vec<T>]) {{\n\
         \x20   let n = x.len();\n\
         \x20   let c = |a: f64| T::from(a);\n\
         {}}}\n",
        indent(&oracle_body, "    ")
    );
    let k_list: Vec<String> = consts.iter().map(|c| format!("{c:?}")).collect();
    let fields: Vec<String> = (0..consts.len()).map(|j| format!("k{j}: K[{j}]")).collect();
    let mut slice_fields = fields.clone();
    slice_fields.push("n: N".into());
    let forms: Vec<String> = forms.iter().map(|f| format!("{f:?}")).collect();
    let text = format!("{array_fn}{slice_fn}");
    let mut m = String::new();
    let _ = writeln!(
        m,
        "#[allow(clippy::needless_range_loop, clippy::reversed_empty_ranges, \
         clippy::impossible_comparisons, reason = \"a loop over components is the form \
         `#[force]` takes; at `N = 1` the links `0..N - 1` and `1..N` are none; the run-time \
         index checks of a slice force compare constants clippy folds\")]"
    );
    let _ = writeln!(
        m,
        "#[allow(clippy::eq_op, clippy::if_same_then_else, reason = \"components drawn apart may \
         name one entry at a literal dimension (`x[2 - 1] - x[1]`), and then a branch may read the \
         same on both sides\")]"
    );
    let _ = writeln!(m, "pub mod lf{id:04} {{");
    let _ = writeln!(m, "    use super::*;");
    let _ = writeln!(m, "    pub const N: usize = {d};");
    let _ = writeln!(
        m,
        "    const K: [f64; {}] = [{}];",
        consts.len(),
        k_list.join(", ")
    );
    m.push_str(&indent(&array_fn, "    "));
    m.push_str(&indent(&slice_fn, "    "));
    m.push_str(&indent(&oracle, "    "));
    let _ = writeln!(m, "    pub fn run(report: &mut Report) {{");
    let _ = writeln!(
        m,
        "        let array = ArrayForce {{ {} }};",
        fields.join(", ")
    );
    let _ = writeln!(
        m,
        "        let slice = SliceForce {{ {} }};",
        slice_fields.join(", ")
    );
    let _ = writeln!(
        m,
        "        check_looped_force::<N>(report, &LoopedForce {{\n\
         \x20           id: {id},\n\
         \x20           forms: &[{}],\n\
         \x20           text: {text:?},\n\
         \x20           time: {time},\n\
         \x20           array: &array,\n\
         \x20           array_dyn: &array,\n\
         \x20           slice: &slice,\n\
         \x20           oracle: &|x, v, t, f| oracle(x, v, t, &K, f),\n\
         \x20       }});",
        forms.join(", "),
    );
    let _ = writeln!(m, "    }}");
    let _ = writeln!(m, "}}");
    m
}
