//! Simplification, as the smart constructors every node is built through: the parser and the
//! differentiator call them, so the graph is simplified as it grows and an unsimplified node
//! never exists. A separate pass after differentiation would come too late: the product rule
//! applied to unsimplified nodes multiplies the `0·a` and `1·a` terms at every level, so the
//! second derivatives would be built from a graph many times the size of the simplified one.
//!
//! Rules (all exact in floating point for finite operands, except the structural-zero rules
//! `0 · a = 0`, `0 / a = 0`, `a − a = 0`, `a / a = 1`, which assume `a` finite and nonzero
//! where it matters — the usual convention of symbolic differentiation):
//! constant folding of every operation on constants; `a + 0 = a`, `a − 0 = a`, `0 − a = −a`,
//! `a · 1 = a`, `a · (−1) = −a`, `a / 1 = a`; `−(−a) = a`; `a + a = 2·a`, `a + (−b) = a − b`,
//! `a − (−b) = a + b`, `(−a)·b = −(a·b)`, `(−a)/b = −(a/b)`; `a^0 = 1`, `a^1 = a`.
//! `a + b` and `b + a` (likewise `·`) share one node (swapping them is exact), so
//! `a·b` and `b·a` are the same node. Nothing is reassociated, so no rounding changes.

use crate::ir::{Cmp, Func, Graph, Id, IndexVar, Node, Var};

impl Graph {
    /// The constant `c`.
    pub fn num(&mut self, c: f64) -> Id {
        self.intern(Node::Num(c.to_bits()))
    }

    /// The variable `var`.
    pub fn var(&mut self, var: Var) -> Id {
        self.intern(Node::Var(var))
    }

    fn neg_inner(&self, a: Id) -> Option<Id> {
        match self.node(a) {
            Node::Neg(b) => Some(b),
            _ => None,
        }
    }

    /// `a + b`.
    pub fn add(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.num_value(a), self.num_value(b)) {
            return self.num(x + y);
        }
        if self.is_num(a, 0.0) {
            return b;
        }
        if self.is_num(b, 0.0) {
            return a;
        }
        if let Some(nb) = self.neg_inner(b) {
            return self.sub(a, nb);
        }
        if let Some(na) = self.neg_inner(a) {
            return self.sub(b, na);
        }
        if a == b {
            // a + a = 2·a exactly.
            let two = self.num(2.0);
            return self.mul(two, a);
        }
        self.commutative(Node::Add(a, b), Node::Add(b, a))
    }

    /// `node`, or its mirror `swapped` if that exists already (`a·b` and `b·a` are the same
    /// value exactly, so they share one node; the first-built order is kept, so the emitted
    /// code reads like the user's).
    fn commutative(&mut self, node: Node, swapped: Node) -> Id {
        match self.lookup(swapped) {
            Some(id) => id,
            None => self.intern(node),
        }
    }

    /// `a − b`.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.num_value(a), self.num_value(b)) {
            return self.num(x - y);
        }
        if a == b {
            return self.num(0.0);
        }
        if self.is_num(b, 0.0) {
            return a;
        }
        if self.is_num(a, 0.0) {
            return self.neg(b);
        }
        if let Some(nb) = self.neg_inner(b) {
            return self.add(a, nb);
        }
        self.intern(Node::Sub(a, b))
    }

    /// `a · b`.
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.num_value(a), self.num_value(b)) {
            return self.num(x * y);
        }
        if self.is_num(a, 0.0) || self.is_num(b, 0.0) {
            return self.num(0.0);
        }
        if self.is_num(a, 1.0) {
            return b;
        }
        if self.is_num(b, 1.0) {
            return a;
        }
        if self.is_num(a, -1.0) {
            return self.neg(b);
        }
        if self.is_num(b, -1.0) {
            return self.neg(a);
        }
        match (self.neg_inner(a), self.neg_inner(b)) {
            (Some(na), Some(nb)) => return self.mul(na, nb),
            (Some(na), None) => {
                let m = self.mul(na, b);
                return self.neg(m);
            }
            (None, Some(nb)) => {
                let m = self.mul(a, nb);
                return self.neg(m);
            }
            (None, None) => {}
        }
        self.commutative(Node::Mul(a, b), Node::Mul(b, a))
    }

    /// `a / b`.
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.num_value(a), self.num_value(b)) {
            return self.num(x / y);
        }
        if self.is_num(a, 0.0) {
            return self.num(0.0);
        }
        if self.is_num(b, 1.0) {
            return a;
        }
        if self.is_num(b, -1.0) {
            return self.neg(a);
        }
        if a == b {
            return self.num(1.0);
        }
        if let Some(na) = self.neg_inner(a) {
            let d = self.div(na, b);
            return self.neg(d);
        }
        self.intern(Node::Div(a, b))
    }

    /// `−a`.
    pub fn neg(&mut self, a: Id) -> Id {
        if let Some(x) = self.num_value(a) {
            return self.num(-x);
        }
        if let Some(na) = self.neg_inner(a) {
            return na;
        }
        self.intern(Node::Neg(a))
    }

    /// `f(a)`.
    pub fn call(&mut self, f: Func, a: Id) -> Id {
        if let Some(x) = self.num_value(a) {
            return self.num(f.eval(x));
        }
        self.intern(Node::Call(f, a))
    }

    /// `a.powi(n)`.
    pub fn powi(&mut self, a: Id, n: i32) -> Id {
        if n == 0 {
            return self.num(1.0);
        }
        if n == 1 {
            return a;
        }
        if let Some(x) = self.num_value(a) {
            return self.num(x.powi(n));
        }
        self.intern(Node::Powi(a, n))
    }

    /// `a.powf(b)`.
    pub fn powf(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.num_value(a), self.num_value(b)) {
            return self.num(x.powf(y));
        }
        if self.is_num(b, 0.0) {
            return self.num(1.0);
        }
        if self.is_num(b, 1.0) {
            return a;
        }
        self.intern(Node::Powf(a, b))
    }

    /// `a.hypot(b)`.
    pub fn hypot(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.num_value(a), self.num_value(b)) {
            return self.num(x.hypot(y));
        }
        self.intern(Node::Hypot(a, b))
    }

    /// `y.atan2(x)`.
    pub fn atan2(&mut self, y: Id, x: Id) -> Id {
        if let (Some(a), Some(b)) = (self.num_value(y), self.num_value(x)) {
            return self.num(a.atan2(b));
        }
        self.intern(Node::Atan2(y, x))
    }

    /// `if l op r { a } else { b }`: one branch when both are the same node or the condition is
    /// a comparison of constants.
    pub fn select(&mut self, op: Cmp, l: Id, r: Id, a: Id, b: Id) -> Id {
        if a == b {
            return a;
        }
        if let (Some(x), Some(y)) = (self.num_value(l), self.num_value(r)) {
            return if op.eval(x, y) { a } else { b };
        }
        self.intern(Node::Select(op, l, r, a, b))
    }

    /// `Σ_i body` over the range of `i` (`0` when the body is `0`).
    pub fn sum(&mut self, i: IndexVar, body: Id) -> Id {
        if self.is_num(body, 0.0) {
            return body;
        }
        self.intern(Node::Sum(i, body))
    }
}
