//! The differentiation stage: `L` → its first and second derivatives ([`Derivatives`]), by
//! symbolic differentiation on the DAG, memoised per `(node, variable)` so that shared
//! subexpressions are differentiated once and their derivatives are shared too.
//!
//! Derivative rules (`n` is the node itself, reused where the derivative contains it):
//!
//! | node | derivative |
//! | --- | --- |
//! | `a / b` | `(a' − n·b') / b`; `−n·(1/b)·b'` when `a' = 0` (one division fewer in series) |
//! | `sin a`, `cos a`, `tan a` | `cos a·a'`, `−sin a·a'`, `(1 + n²)·a'` |
//! | `asin a`, `acos a`, `atan a` | `a'/√(1 − a²)`, `−a'/√(1 − a²)`, `a'/(1 + a²)` |
//! | `sinh a`, `cosh a`, `tanh a` | `cosh a·a'`, `sinh a·a'`, `sech² a·a'` |
//! | `sech² a` (internal: `tanh`'s derivative) | `−2 tanh a·n·a'` |
//! | `exp a`, `ln a`, `log10 a` | `n·a'`, `a'/a`, `a'/(a·ln 10)` |
//! | `exp_m1 a`, `ln_1p a` | `exp a·a'`, `a'/(1 + a)` |
//! | `sqrt a`, `cbrt a`, `recip a` | `a'/(2n)`, `a'/(3n²)`, `−n²·a'` |
//! | `abs a` | `sign(a)·a'`, with `sign(0) = 0` (a subgradient; `abs` is not differentiable at 0) |
//! | `a.powi(k)` | `k·a^(k−1)·a'` |
//! | `a.powf(b)` | `b·a^(b−1)·a' + n·ln a·b'` (the second term, present only when the exponent is not constant, needs `a > 0`) |
//! | `a.hypot(b)` | `(a·a' + b·b')/n` |
//! | `y.atan2(x)` | `((x/r)·y' − (y/r)·x')/r`, `r = hypot(x, y)` (the squares of `(x·y' − y·x')/(x² + y²)` overflow past about 1e154) |
//! | `if c { a } else { b }` | `if c { a' } else { b' }` (the condition is not differentiated) |
//! | `a.signum()` | `0` |

use std::collections::HashMap;

use crate::ir::{Derivatives, Func, Graph, HessianDependence, Id, Node, Var};

/// Differentiates nodes of one graph; keeps the memo between calls so that second
/// derivatives reuse first ones.
#[derive(Default)]
pub struct Differentiator {
    memo: HashMap<(Id, Var), Id>,
}

impl Differentiator {
    /// A differentiator with an empty memo.
    pub fn new() -> Self {
        Self::default()
    }

    /// `∂root/∂var`.
    pub fn diff(&mut self, g: &mut Graph, root: Id, var: Var) -> Id {
        // Reachable nodes in topological order: every child's derivative exists before its
        // parent's, and no recursion is needed.
        for id in g.reachable(&[root]) {
            if self.memo.contains_key(&(id, var)) {
                continue;
            }
            let d = self.rule(g, id, var);
            self.memo.insert((id, var), d);
        }
        self.memo[&(root, var)]
    }

    fn rule(&self, g: &mut Graph, id: Id, var: Var) -> Id {
        let d = |i: Id| self.memo[&(i, var)];
        match g.node(id) {
            Node::Num(_) => g.num(0.0),
            Node::Var(w) => g.num(if w == var { 1.0 } else { 0.0 }),
            Node::Add(a, b) => g.add(d(a), d(b)),
            Node::Sub(a, b) => g.sub(d(a), d(b)),
            Node::Mul(a, b) => {
                let l = g.mul(d(a), b);
                let r = g.mul(a, d(b));
                g.add(l, r)
            }
            Node::Div(a, b) => {
                let (da, db) = (d(a), d(b));
                if g.is_num(da, 0.0) && !g.is_num(db, 0.0) {
                    // `(c/b)' = −n·(1/b)·b'`: the general rule would divide `n·b'` by `b`, a
                    // second division in series after the one inside `b'` (e.g. `√u`'s), where
                    // this form computes `1/b` alongside (it is `n` itself when `c = 1`).
                    let one = g.num(1.0);
                    let inv = g.div(one, b);
                    let scale = g.mul(id, inv);
                    let t = g.mul(scale, db);
                    return g.neg(t);
                }
                let nb = g.mul(id, db);
                let num = g.sub(da, nb);
                g.div(num, b)
            }
            // A derivative that is zero is `+0`: `−0.0` is a number of its own in the graph, and
            // a branch between `−0.0` and `0.0` would be a nonzero node (a derivative that
            // claims to depend on what its condition reads, or a weight of a force's virtual
            // work left behind).
            Node::Neg(a) => {
                let da = d(a);
                if g.is_num(da, 0.0) {
                    return g.num(0.0);
                }
                g.neg(da)
            }
            Node::Call(f, a) => {
                let da = d(a);
                if g.is_num(da, 0.0) {
                    return g.num(0.0);
                }
                let outer = match f {
                    Func::Sin => g.call(Func::Cos, a),
                    Func::Cos => {
                        let s = g.call(Func::Sin, a);
                        g.neg(s)
                    }
                    Func::Tan => {
                        let sq = g.mul(id, id);
                        let one = g.num(1.0);
                        g.add(one, sq)
                    }
                    // Not `1 − a·a`, which cancels where `|a|` nears 1 (see
                    // `Func::OneMinusSquare`).
                    Func::Asin | Func::Acos => {
                        let one = g.num(1.0);
                        let diff = g.call(Func::OneMinusSquare, a);
                        let root = g.call(Func::Sqrt, diff);
                        let inv = g.div(one, root);
                        if f == Func::Acos { g.neg(inv) } else { inv }
                    }
                    Func::Atan => {
                        let sq = g.mul(a, a);
                        let one = g.num(1.0);
                        let den = g.add(one, sq);
                        return g.div(da, den);
                    }
                    Func::Sinh => g.call(Func::Cosh, a),
                    Func::Cosh => g.call(Func::Sinh, a),
                    // Not `1 − n²`, which cancels where `|a|` is large (see `ir::sech2`).
                    Func::Tanh => g.call(Func::Sech2, a),
                    Func::Sech2 => {
                        let t = g.call(Func::Tanh, a);
                        let minus_two = g.num(-2.0);
                        let m = g.mul(minus_two, t);
                        g.mul(m, id)
                    }
                    Func::OneMinusSquare => {
                        let minus_two = g.num(-2.0);
                        g.mul(minus_two, a)
                    }
                    Func::Exp => id,
                    // `exp a`, not `n + 1`: exact where `n` is, and shared with an `exp a` of
                    // the body.
                    Func::ExpM1 => g.call(Func::Exp, a),
                    Func::Ln => return g.div(da, a),
                    Func::Ln1p => {
                        let one = g.num(1.0);
                        let den = g.add(one, a);
                        return g.div(da, den);
                    }
                    Func::Log10 => {
                        let ln10 = g.num(std::f64::consts::LN_10);
                        let den = g.mul(a, ln10);
                        return g.div(da, den);
                    }
                    Func::Sqrt => {
                        let two = g.num(2.0);
                        let den = g.mul(two, id);
                        return g.div(da, den);
                    }
                    Func::Cbrt => {
                        let three = g.num(3.0);
                        let sq = g.mul(id, id);
                        let den = g.mul(three, sq);
                        return g.div(da, den);
                    }
                    Func::Recip => {
                        let sq = g.mul(id, id);
                        g.neg(sq)
                    }
                    Func::Abs => g.call(Func::Sign, a),
                    Func::Sign | Func::Signum => return g.num(0.0),
                };
                g.mul(outer, da)
            }
            Node::Powi(a, n) => {
                let da = d(a);
                if g.is_num(da, 0.0) {
                    return g.num(0.0);
                }
                let k = g.num(f64::from(n));
                // n − 1 cannot overflow: n = i32::MIN is rejected by the parser.
                let p = g.powi(a, n.saturating_sub(1));
                let kp = g.mul(k, p);
                g.mul(kp, da)
            }
            Node::Powf(a, b) => {
                let (da, db) = (d(a), d(b));
                let one = g.num(1.0);
                let bm1 = g.sub(b, one);
                let p = g.powf(a, bm1);
                let bp = g.mul(b, p);
                let base = g.mul(bp, da);
                let ln = g.call(Func::Ln, a);
                let nl = g.mul(id, ln);
                let expo = g.mul(nl, db);
                g.add(base, expo)
            }
            Node::Hypot(a, b) => {
                let l = g.mul(a, d(a));
                let r = g.mul(b, d(b));
                let num = g.add(l, r);
                g.div(num, id)
            }
            // `(x y' − y x')/(x² + y²)` as `((x/r) y' − (y/r) x')/r`, `r = hypot(x, y)`: the
            // squares overflow once `|x|` or `|y|` passes about 1e154 (the derivative, about
            // `1/r`, is then a normal number read as 0) and underflow below about 1e-154 (to
            // subnormals that lose digits, then to 0 and a quotient of ±∞), where `x/r` and
            // `y/r` are at most 1 and `r` is what `hypot` returns.
            Node::Atan2(y, x) => {
                let (dy, dx) = (d(y), d(x));
                if g.is_num(dy, 0.0) && g.is_num(dx, 0.0) {
                    return g.num(0.0);
                }
                let r = g.hypot(x, y);
                let (cos, sin) = (g.div(x, r), g.div(y, r));
                let l = g.mul(cos, dy);
                let rr = g.mul(sin, dx);
                let num = g.sub(l, rr);
                g.div(num, r)
            }
            // The branch rule: each branch is differentiated, the condition is kept (its
            // derivative is zero wherever it is defined).
            Node::Select(op, l, r, a, b) => {
                let (da, db) = (d(a), d(b));
                if g.is_num(da, 0.0) && g.is_num(db, 0.0) {
                    return g.num(0.0);
                }
                g.select(op, l, r, da, db)
            }
            // A sum's derivative is assembled term by term (`assemble.rs`): a body differentiated
            // here never contains one.
            Node::Sum(..) => unreachable!("sums are differentiated by assemble.rs"),
        }
    }
}

/// `∂roots[i]/∂vars[j]`, row-major (one row per root): the derivative of a vector-valued
/// function (a force's `∂f/∂x`, a constraint's `G`), and of a Lagrangian's gradient.
pub fn jacobian(d: &mut Differentiator, g: &mut Graph, roots: &[Id], vars: &[Var]) -> Vec<Id> {
    roots
        .iter()
        .flat_map(|&r| vars.iter().map(move |&var| (r, var)))
        .map(|(r, var)| d.diff(g, r, var))
        .collect()
}

/// The position variables `x_0 … x_{dim−1}`.
pub fn positions(dim: usize) -> Vec<Var> {
    (0..dim).map(Var::X).collect()
}

/// The velocity variables `v_0 … v_{dim−1}`.
pub fn velocities(dim: usize) -> Vec<Var> {
    (0..dim).map(Var::V).collect()
}

/// Differentiates `root`, a Lagrangian of dimension `dim` in `graph`, twice, and finds what
/// each second-derivative block depends on.
pub fn differentiate(graph: &mut Graph, root: Id, dim: usize) -> Derivatives {
    let g = graph;
    let mut d = Differentiator::new();
    let (xs, vs) = (positions(dim), velocities(dim));
    let fx = jacobian(&mut d, g, &[root], &xs);
    let fv = jacobian(&mut d, g, &[root], &vs);
    let mut xx = vec![0; dim * dim];
    let mut vv = vec![0; dim * dim];
    let mut xv = vec![0; dim * dim];
    for i in 0..dim {
        for j in 0..dim {
            xv[i * dim + j] = d.diff(g, fx[i], Var::V(j));
            // Symmetric blocks: differentiate the upper triangle, mirror it.
            if i <= j {
                xx[i * dim + j] = d.diff(g, fx[i], Var::X(j));
                vv[i * dim + j] = d.diff(g, fv[i], Var::V(j));
                xx[j * dim + i] = xx[i * dim + j];
                vv[j * dim + i] = vv[i * dim + j];
            }
        }
    }
    let hessian_dependence = HessianDependence {
        xx: g.dependence(&xx),
        xv: g.dependence(&xv),
        vv: g.dependence(&vv),
    };
    Derivatives {
        fx,
        fv,
        xx,
        xv,
        vv,
        hessian_dependence,
        dependence: g.dependence(&[root]),
    }
}
