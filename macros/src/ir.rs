//! The intermediate representation every stage shares: a hash-consed DAG of scalar operations
//! ([`Graph`]), the parsed Lagrangian ([`Model`]) and its derivatives ([`Derivatives`]).
//!
//! Every node lives once in a [`Graph`]; building a node that already exists returns the
//! existing [`Id`], so identical subexpressions are shared by construction. Children are always
//! created before their parents, hence `Id` order is a topological order: analyses walk the
//! nodes in increasing id without recursion, and the emitted temporaries follow that order.
//!
//! # Loops
//!
//! A Lagrangian written with `for` loops or `(0..N).map(|i| …).sum()` keeps its index structure
//! in this same graph, with three kinds of leaves and one node more:
//!
//! - an *index variable* ([`IndexVar`]), bound by the loop or closure that introduces it, with
//!   its range in [`Graph::ranges`]; an *index expression* ([`Affine`]: `a·i + b·N + k·s + c`,
//!   `s` a constant the macro does not know, [`Sym`]: a `usize` const, `N / 2`) and a
//!   component ([`Component`]: an affine index, optionally taken modulo `N` for periodic
//!   chains), so that `x[i + 1]` is the leaf `Var::XAt(…)`. Literal components stay
//!   `Var::X(k)`;
//! - `Var::Index(i)`, `Var::Dim` and `Var::Sym(s)`: the value of a loop variable, of the
//!   dimension and of a [`Sym`] as numbers (`(N - i) as f64`);
//! - the node `Sum(i, body)`: `Σ_i body` over the range of `i`. Its body is built before it, so
//!   ids stay topological.
//!
//! Derivatives of a sum are not unrolled: `assemble.rs` writes `L` as a sum of *terms*, each a
//! body under a nest of loops, and differentiates each body with respect to the components it
//! reads. The generated code then keeps the loops and *scatters* each body's derivatives into
//! the entries its components name (`f[i] += …; f[i + 1] += …`), as a finite-element code
//! assembles its matrices. The dependence analysis treats every `XAt` like an `X`.

use std::collections::HashMap;

pub use crate::indices::{Affine, Bound, Cmp, Component, Guard, IndexVar, Range, Sym, SymId};

use proc_macro2::Ident;
use syn::{Attribute, ItemFn, Visibility};

/// Index of a node in its [`Graph`].
pub type Id = usize;

/// A leaf variable of the Lagrangian.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    /// Position component `x_i`, `i` a literal.
    X(usize),
    /// Velocity component `v_i`, `i` a literal.
    V(usize),
    /// Position component at an index that names a loop variable or the dimension.
    XAt(Component),
    /// Velocity component at an index that names a loop variable or the dimension.
    VAt(Component),
    /// The weight of component `k` of a `#[force]` with loops, `k` a literal: the force is
    /// parsed as its virtual work `Σ_k w_k f_k`, linear in these leaves, so that `f_k` is the
    /// derivative with respect to `w_k` (`assemble::assemble_force`). Never emitted.
    F(usize),
    /// The weight of a force component at an index that names a loop variable or the
    /// dimension.
    FAt(Component),
    /// The value of a loop variable, as a number.
    Index(IndexVar),
    /// The dimension `N` as a number, when it is a named constant.
    Dim,
    /// A constant the macro does not know (a `usize` const, `N / 2`) as a number.
    Sym(SymId),
    /// Time `t`.
    T,
    /// Model constant number `k` (a field of the generated struct): fixed for a whole run, so
    /// it counts for no [`Dependence`].
    Const(usize),
    /// The value of the `k`-th sum that the Lagrangian uses as a value (inside a function, a
    /// divisor or a condition): `assemble.rs` replaces such a sum by this leaf and
    /// differentiates through it by the chain rule.
    Lifted(usize),
    /// The adjoint `∂L/∂s_k` of the `k`-th lifted sum at the point: a number the generated code
    /// computes before it adds the sum's derivatives, weighted by it. Not differentiated.
    Adjoint(usize),
}

/// Elementary functions of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
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
    /// `exp(a) − 1`, accurate near `a = 0`.
    ExpM1,
    Ln,
    /// `ln(1 + a)`, accurate near `a = 0`.
    Ln1p,
    Log10,
    Sqrt,
    Cbrt,
    Recip,
    Abs,
    /// `f64::signum` (`±1`, NaN for NaN); its derivative is zero.
    Signum,
    /// `sign(a)` with `sign(0) = 0` (and `sign(NaN) = 0`): the derivative of `abs`. Not
    /// available to the user; emitted as an `if`.
    Sign,
    /// `sech² a = 1 − tanh² a`, the derivative of `tanh`, computed without that cancellation
    /// ([`sech2`]). Not available to the user; emitted as a call of core's `sech2`.
    Sech2,
    /// `1 − a²` as `(1 − a)(1 + a)`, under the root of `asin`'s and `acos`'s derivatives: no
    /// cancellation where `|a|` nears 1, where `1 − a·a` loses the low bits of `a·a` (a
    /// relative error up to 1.9e-9 in the derivative, at `1 − a ≈ 7e-9`). Its derivative is
    /// `−2a`. Not available to the user; emitted as that product.
    OneMinusSquare,
}

impl Func {
    /// Whether the emitted code reads the argument twice (an `if` on it, a product of two
    /// factors with it): the argument must then be a value, a temporary or a leaf.
    pub fn reads_argument_twice(self) -> bool {
        matches!(self, Func::Sign | Func::OneMinusSquare)
    }

    /// The functions a body may call, by their `f64` method name.
    const USER: [Func; 19] = [
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Asin,
        Func::Acos,
        Func::Atan,
        Func::Sinh,
        Func::Cosh,
        Func::Tanh,
        Func::Exp,
        Func::ExpM1,
        Func::Ln,
        Func::Ln1p,
        Func::Log10,
        Func::Sqrt,
        Func::Cbrt,
        Func::Recip,
        Func::Abs,
        Func::Signum,
    ];

    /// The Rust method name (`Sign` has no method; it is emitted as an `if`).
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Sinh => "sinh",
            Func::Cosh => "cosh",
            Func::Tanh => "tanh",
            Func::Exp => "exp",
            Func::ExpM1 => "exp_m1",
            Func::Ln => "ln",
            Func::Ln1p => "ln_1p",
            Func::Log10 => "log10",
            Func::Sqrt => "sqrt",
            Func::Cbrt => "cbrt",
            Func::Recip => "recip",
            Func::Abs => "abs",
            Func::Signum => "signum",
            Func::Sign => "sign",
            Func::Sech2 => "sech2",
            Func::OneMinusSquare => "one_minus_square",
        }
    }

    /// The function behind an `f64` method name a body may call (`sign` is internal).
    pub fn from_name(s: &str) -> Option<Func> {
        Func::USER.into_iter().find(|f| f.name() == s)
    }

    /// Evaluates the function (also used for constant folding).
    pub fn eval(self, a: f64) -> f64 {
        match self {
            Func::Sin => a.sin(),
            Func::Cos => a.cos(),
            Func::Tan => a.tan(),
            Func::Asin => a.asin(),
            Func::Acos => a.acos(),
            Func::Atan => a.atan(),
            Func::Sinh => a.sinh(),
            Func::Cosh => a.cosh(),
            Func::Tanh => a.tanh(),
            Func::Exp => a.exp(),
            Func::ExpM1 => a.exp_m1(),
            Func::Ln => a.ln(),
            Func::Ln1p => a.ln_1p(),
            Func::Log10 => a.log10(),
            Func::Sqrt => a.sqrt(),
            Func::Cbrt => a.cbrt(),
            Func::Recip => a.recip(),
            Func::Abs => a.abs(),
            Func::Signum => a.signum(),
            Func::Sign => sign(a),
            Func::Sech2 => sech2(a),
            Func::OneMinusSquare => (1.0 - a) * (1.0 + a),
        }
    }
}

/// `sech² a` as `4u/(1 + u)²`, `u = e^{−2|a|}`: relative error a few ulps at every `a`, where
/// `1 − tanh² a` loses `ε cosh² a` relative to cancellation (all of it from `|a| ≈ 19` on, where
/// `tanh a` rounds to ±1), and no overflow (`u` underflows to 0, and so does the result). The
/// same formula as core's `__private::sech2`, which the generated code calls.
pub fn sech2(a: f64) -> f64 {
    let u = (-2.0 * a.abs()).exp();
    4.0 * u / ((1.0 + u) * (1.0 + u))
}

/// `sign` with `sign(±0) = 0`: the derivative used for `abs` (a subgradient at 0).
pub fn sign(a: f64) -> f64 {
    if a > 0.0 {
        1.0
    } else if a < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The `std::f64::consts` a body may name, with their values. The renderers write a number
/// that is one of them exactly by name: it reads better than 17 digits, and it is what clippy's
/// `approx_constant` asks of the user's crate, where the generated code lands.
const NAMED_CONSTANTS: [(&str, f64); 19] = {
    use std::f64::consts::*;
    [
        ("PI", PI),
        ("TAU", TAU),
        ("E", E),
        ("SQRT_2", SQRT_2),
        ("FRAC_1_SQRT_2", FRAC_1_SQRT_2),
        ("LN_2", LN_2),
        ("LN_10", LN_10),
        ("LOG2_E", LOG2_E),
        ("LOG10_E", LOG10_E),
        ("LOG2_10", LOG2_10),
        ("LOG10_2", LOG10_2),
        ("FRAC_PI_2", FRAC_PI_2),
        ("FRAC_PI_3", FRAC_PI_3),
        ("FRAC_PI_4", FRAC_PI_4),
        ("FRAC_PI_6", FRAC_PI_6),
        ("FRAC_PI_8", FRAC_PI_8),
        ("FRAC_1_PI", FRAC_1_PI),
        ("FRAC_2_PI", FRAC_2_PI),
        ("FRAC_2_SQRT_PI", FRAC_2_SQRT_PI),
    ]
};

/// The value of `std::f64::consts::<name>`.
pub fn constant_value(name: &str) -> Option<f64> {
    NAMED_CONSTANTS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, c)| c)
}

/// The `std::f64::consts` name of `c`, if `c` is one of them bit for bit.
pub fn constant_name(c: f64) -> Option<&'static str> {
    NAMED_CONSTANTS
        .iter()
        .find(|(_, v)| v.to_bits() == c.to_bits())
        .map(|&(name, _)| name)
}

/// Binding strength of the Rust syntax a node is written in, weakest first; both renderers
/// (tokens and the text of `DERIVATIVES`) parenthesise an operand weaker than its position
/// needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Prec {
    /// An `if` expression.
    If,
    /// `a + b`, `a - b`.
    Add,
    /// `a * b`, `a / b`.
    Mul,
    /// Unary `-a`.
    Neg,
    /// A name, a literal, a call or a parenthesised expression.
    Atom,
}

impl Prec {
    /// What the right operand of a left-associative binary operator of this strength needs:
    /// one level more (`a - (b - c)`).
    pub fn right_operand(self) -> Prec {
        match self {
            Prec::If => Prec::Add,
            Prec::Add => Prec::Mul,
            Prec::Mul => Prec::Neg,
            Prec::Neg | Prec::Atom => Prec::Atom,
        }
    }
}

/// One node. Floating constants are stored by their bits so that nodes can be hashed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    Num(u64),
    Var(Var),
    Add(Id, Id),
    Sub(Id, Id),
    Mul(Id, Id),
    Div(Id, Id),
    Neg(Id),
    Call(Func, Id),
    Powi(Id, i32),
    Powf(Id, Id),
    Hypot(Id, Id),
    /// `y.atan2(x)`, the angle of the point `(x, y)`.
    Atan2(Id, Id),
    /// `if l op r { a } else { b }`.
    Select(Cmp, Id, Id, Id, Id),
    /// `Σ_i body` over the range of `i`.
    Sum(IndexVar, Id),
}

impl Node {
    /// The children of the node, in order.
    pub fn children(&self) -> Vec<Id> {
        match *self {
            Node::Num(_) | Node::Var(_) => vec![],
            Node::Neg(a) | Node::Call(_, a) | Node::Powi(a, _) | Node::Sum(_, a) => vec![a],
            Node::Select(_, l, r, a, b) => vec![l, r, a, b],
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Powf(a, b)
            | Node::Hypot(a, b)
            | Node::Atan2(a, b) => vec![a, b],
        }
    }

    /// A leaf (a number or a variable) is never bound to a temporary.
    pub fn is_leaf(&self) -> bool {
        matches!(self, Node::Num(_) | Node::Var(_))
    }
}

/// The hash-consed node store. Nodes are built through the smart constructors of
/// `simplify.rs`, so the graph only ever holds simplified expressions.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
    /// The range of each loop variable, by number.
    pub ranges: Vec<Range>,
    /// The constants the macro does not know, by number.
    pub syms: Vec<Sym>,
    /// The index checks left to the compiler.
    pub bounds: Vec<Bound>,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Returns the id of `node`, creating it if it is new. No simplification happens here.
    pub fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = self.nodes.len();
        self.nodes.push(node);
        self.index.insert(node, id);
        id
    }

    /// The number of `sym`, added if it is new.
    pub fn sym(&mut self, sym: Sym) -> SymId {
        let k = match self.syms.iter().position(|s| *s == sym) {
            Some(k) => k,
            None => {
                self.syms.push(sym);
                self.syms.len() - 1
            }
        };
        SymId(k as u32)
    }

    /// The id of `node` if it exists.
    pub fn lookup(&self, node: Node) -> Option<Id> {
        self.index.get(&node).copied()
    }

    /// The node behind `id`.
    pub fn node(&self, id: Id) -> Node {
        self.nodes[id]
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The value of a numeric constant node.
    pub fn num_value(&self, id: Id) -> Option<f64> {
        match self.nodes[id] {
            Node::Num(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    /// Whether `id` is the constant `c` (bitwise, so `-0.0` is not `0.0`, except that both
    /// zeros count as zero).
    pub fn is_num(&self, id: Id, c: f64) -> bool {
        self.num_value(id) == Some(c) || (c == 0.0 && self.num_value(id) == Some(-0.0))
    }

    /// On which of `x`, `v`, `t` the nodes `ids` depend, together (structurally: a variable
    /// that reaches a node counts, even if it would cancel mathematically).
    pub fn dependence(&self, ids: &[Id]) -> Dependence {
        let mut dep = Dependence::NONE;
        for id in self.reachable(ids) {
            match self.nodes[id] {
                Node::Var(Var::X(_) | Var::XAt(_)) => dep.x = true,
                Node::Var(Var::V(_) | Var::VAt(_)) => dep.v = true,
                Node::Var(Var::T) => dep.t = true,
                _ => {}
            }
        }
        dep
    }

    /// Whether a sum was written: some node, reachable or not, is a [`Node::Sum`] (a constant
    /// condition may fold the branch that held it away).
    pub fn has_sum(&self) -> bool {
        self.nodes.iter().any(|node| matches!(node, Node::Sum(..)))
    }

    /// All nodes reachable from `roots`, in increasing (topological) id order.
    pub fn reachable(&self, roots: &[Id]) -> Vec<Id> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if !seen[id] {
                seen[id] = true;
                stack.extend(self.nodes[id].children());
            }
        }
        (0..self.nodes.len()).filter(|&i| seen[i]).collect()
    }

    /// Evaluates `roots` with variable values from `env`, sharing the work over the DAG.
    #[cfg(test)]
    pub fn eval_many(&self, roots: &[Id], env: &dyn Fn(Var) -> f64) -> Vec<f64> {
        // Children have smaller ids, so evaluating the reachable nodes in increasing id order
        // needs no recursion (and cannot overflow the stack on deep expressions).
        let mut value: HashMap<Id, f64> = HashMap::new();
        for id in self.reachable(roots) {
            let val = |i: Id| value[&i];
            let x = match self.nodes[id] {
                Node::Num(bits) => f64::from_bits(bits),
                Node::Var(var) => env(var),
                Node::Add(a, b) => val(a) + val(b),
                Node::Sub(a, b) => val(a) - val(b),
                Node::Mul(a, b) => val(a) * val(b),
                Node::Div(a, b) => val(a) / val(b),
                Node::Neg(a) => -val(a),
                Node::Call(f, a) => f.eval(val(a)),
                Node::Powi(a, n) => val(a).powi(n),
                Node::Powf(a, b) => val(a).powf(val(b)),
                Node::Hypot(a, b) => val(a).hypot(val(b)),
                Node::Atan2(a, b) => val(a).atan2(val(b)),
                Node::Select(op, l, r, a, b) => {
                    if op.eval(val(l), val(r)) {
                        val(a)
                    } else {
                        val(b)
                    }
                }
                Node::Sum(..) => panic!("the test evaluator does not run loops"),
            };
            value.insert(id, x);
        }
        roots.iter().map(|r| value[r]).collect()
    }

    /// Evaluates one node.
    #[cfg(test)]
    pub fn eval(&self, root: Id, env: &dyn Fn(Var) -> f64) -> f64 {
        self.eval_many(&[root], env)[0]
    }
}

/// On which of `x`, `v`, `t` a function of `(x, v, t)` depends (model constants do not
/// count: they are fixed for a run). Emitted as core's `Dependence`, field for field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dependence {
    pub x: bool,
    pub v: bool,
    pub t: bool,
}

impl Dependence {
    /// Depends on none of `x`, `v`, `t`.
    pub const NONE: Dependence = Dependence {
        x: false,
        v: false,
        t: false,
    };
}

/// Which attribute a fn is expanded by: what its body's value is and which trait the struct
/// implements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Attr {
    /// `#[lagrangian]`: a scalar `L(x, v, t)`, `Lagrangian<D>`.
    Lagrangian,
    /// `#[force]`: a vector `f(x, v, t)` of `D` components, `Force<D>`.
    Force,
    /// `#[constraint]`: a vector `g(x)` of `M` components, `Constraint<D, M>`.
    Constraint,
}

impl Attr {
    /// The attribute as written, for the errors.
    pub fn name(self) -> &'static str {
        match self {
            Attr::Lagrangian => "#[lagrangian]",
            Attr::Force => "#[force]",
            Attr::Constraint => "#[constraint]",
        }
    }
}

/// A parsed fn: the facts of its signature and its value (`L`, or the components of a force
/// or constraint) as nodes of its graph.
pub struct Model {
    /// The attribute the fn is expanded by.
    pub attr: Attr,
    /// The user's fn, emitted unchanged.
    pub item: ItemFn,
    /// Name of the generated struct.
    pub struct_name: Ident,
    /// Visibility of the fn, given to the struct.
    pub vis: Visibility,
    /// Doc comments of the fn, given to the struct.
    pub docs: Vec<Attribute>,
    /// Dimension `D` (when it is a named constant: 1, and `dim_name` is set).
    pub dim: usize,
    /// The named constant that is the dimension (`[f64; N]`), if it is one.
    pub dim_name: Option<syn::Path>,
    /// The `usize` model constant that is the run-time dimension of slices `x: &[f64]` (a
    /// field of the struct, not in `consts`).
    pub runtime_dim: Option<Ident>,
    /// `x`, `v` declared as `f64` (printed as `x`, not `x[0]`).
    pub scalar: bool,
    /// The model constants, in order (`Var::Const(k)` is `consts[k]`).
    pub consts: Vec<Ident>,
    /// The expression graph.
    pub graph: Graph,
    /// `L` in `graph` (a vector-valued fn: the number 0, unused).
    pub root: Id,
    /// The components of a vector-valued fn (`#[force]`, `#[constraint]`) in `graph`; empty
    /// for a Lagrangian.
    pub outputs: Vec<Id>,
}

/// The first and second derivatives of `L`, as nodes of the model's graph, with what each
/// second-derivative block depends on.
#[derive(Clone, Debug)]
pub struct Derivatives {
    /// `∂L/∂x_i`.
    pub fx: Vec<Id>,
    /// `∂L/∂v_i`.
    pub fv: Vec<Id>,
    /// `∂²L/∂x_i∂x_j`, row-major; symmetric by construction (the lower triangle is the same
    /// nodes as the upper one).
    pub xx: Vec<Id>,
    /// `∂²L/∂x_i∂v_j`, row-major.
    pub xv: Vec<Id>,
    /// `∂²L/∂v_i∂v_j`, row-major, symmetric like `xx`.
    pub vv: Vec<Id>,
    /// On what the entries of each block depend (an all-zero block: on nothing).
    pub hessian_dependence: HessianDependence,
    /// What `L` itself depends on.
    pub dependence: Dependence,
}

/// What each second-derivative block depends on. Emitted as core's `HessianDependence`, which
/// decides from it which step equations are affine in the newest node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HessianDependence {
    pub xx: Dependence,
    pub xv: Dependence,
    pub vv: Dependence,
}
