//! What names mean in a body ([`Binding`]), shared by the statement, expression and index
//! walkers.

use std::collections::HashMap;

use syn::{Expr, Lit, ReturnType, Type};

use super::signature::{Length, is_f64};
use crate::ir::{Affine, Id, IndexVar, Var};

/// The usable names in the body.
#[derive(Clone)]
pub enum Binding {
    /// A value: a scalar parameter or a `let`.
    Scalar(Id),
    /// `x` or `v` declared as an array: only its components can be used.
    Array { state: State, len: Length },
    /// A loop variable.
    Index(IndexVar),
    /// The named dimension `N`.
    Dim,
    /// An integer `let` (an index expression).
    Int(Int),
    /// A `let mut` accumulator, declared at loop depth `depth`.
    Mut { id: Id, depth: usize },
    /// A local tuple or array of values: `let a = [b * x[1], -b * x[0], 0.0];`, or what a
    /// helper returning `(f64, f64)` or `[f64; K]` returned.
    Values(Values),
    /// The value of a call of another helper, while a helper is checked on its own (its shape
    /// is not known there): every use of it is accepted.
    Unknown,
    /// The force a `#[force]` with loops declares and adds to (`looped_force.rs`): only its
    /// components are updated, and it is never read.
    Output,
}

/// Values bound together: a tuple `(a, b)` (read as `r.0`) or an array `[a, b]` (read as
/// `r[0]`, also in an unrolled loop over a literal range).
#[derive(Clone)]
pub struct Values {
    pub ids: Vec<Id>,
    pub kind: Kind,
}

/// Whether [`Values`] are a tuple or an array: what they are read with.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Kind {
    Tuple,
    Array,
}

impl Kind {
    /// `a tuple`, `an array`.
    pub fn noun(self) -> &'static str {
        match self {
            Kind::Tuple => "a tuple",
            Kind::Array => "an array",
        }
    }
}

/// Which of the two state parameters an array is.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum State {
    Position,
    Velocity,
}

impl State {
    /// The variable of component `i`.
    pub fn component(self, i: usize) -> Var {
        match self {
            State::Position => Var::X(i),
            State::Velocity => Var::V(i),
        }
    }
}

pub type Env = HashMap<String, Binding>;

/// An integer expression: its affine form when it has one, whether it is taken modulo `N`,
/// and its value as a number when it can be one.
#[derive(Clone, Copy)]
pub struct Int {
    pub affine: Option<Affine>,
    pub wrap: bool,
    pub value: Option<Id>,
}

/// `e` without parentheses and invisible groups.
pub fn strip(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip(&p.expr),
        Expr::Group(g) => strip(&g.expr),
        other => other,
    }
}

/// What a helper returns, read off its signature.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Returns {
    Scalar,
    Values(Kind, usize),
}

/// What a helper's signature says it returns: `f64`, `(f64, …)` or `[f64; K]` with `K` a
/// literal; `None` for anything else.
pub fn returns(output: &ReturnType) -> Option<Returns> {
    let ReturnType::Type(_, ty) = output else {
        return None;
    };
    match strip_type(ty) {
        ty if is_f64(ty) => Some(Returns::Scalar),
        Type::Tuple(t) if !t.elems.is_empty() && t.elems.iter().all(is_f64) => {
            Some(Returns::Values(Kind::Tuple, t.elems.len()))
        }
        Type::Array(a) if is_f64(&a.elem) => match strip(&a.len) {
            Expr::Lit(syn::ExprLit {
                lit: Lit::Int(k), ..
            }) => k
                .base10_parse::<usize>()
                .ok()
                .filter(|&k| k > 0)
                .map(|k| Returns::Values(Kind::Array, k)),
            _ => None,
        },
        _ => None,
    }
}

fn strip_type(ty: &Type) -> &Type {
    match ty {
        Type::Paren(p) => strip_type(&p.elem),
        Type::Group(g) => strip_type(&g.elem),
        other => other,
    }
}

/// What the conditions of the branches being read say of a loop variable: `low ≤ var`,
/// `var < high` (each side free of loop variables; `branch.rs`).
#[derive(Clone, Copy, Debug)]
pub struct Fact {
    pub var: IndexVar,
    pub low: Option<Affine>,
    pub high: Option<Affine>,
}
