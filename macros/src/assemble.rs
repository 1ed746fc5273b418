//! The differentiation of a Lagrangian with loops: `L` written as a sum of *terms*, each a body
//! under a nest of loops, and every body differentiated with respect to the components it
//! reads ([`Assembly`]).
//!
//! `∂/∂x_k Σ_i f(x[i], x[i + 1])` is `Σ_i (∂₁f·[i = k] + ∂₂f·[i + 1 = k])`: the loop over `i`
//! adds `∂₁f` to entry `i` of the gradient and `∂₂f` to entry `i + 1`, and the Hessian gets
//! `∂²f/∂x[a]∂x[b]` at `(a, b)` for every pair of components the body reads — for a
//! nearest-neighbour chain the diagonal and the two next to it. The derivative of a loop is
//! that same loop, whatever `N`. Adding (rather than writing) each contribution also makes
//! two index expressions that name the same component at some `i` (`x[i]` and `x[j]` at
//! `i = j`) come out right: their contributions add up, as the chain rule says.
//!
//! Sums enter `L` linearly: through `+`, `−`, products (a factor is moved into the loop: `a ·
//! Σ_i b = Σ_i a·b`, and a product of two sums is a double sum), a division by a sum-free
//! divisor and either branch of an `if`. A sum inside a function (`sqrt`, `powi`, …) or a
//! divisor is rejected.

use std::collections::HashMap;

use crate::diff::Differentiator;
use crate::ir::{Dependence, Graph, HessianDependence, Id, IndexVar, Node, Var};

/// A Lagrangian with loops, as terms and their derivatives.
pub struct Assembly {
    pub terms: Vec<Term>,
    pub hessian_dependence: HessianDependence,
    pub dependence: Dependence,
}

/// One body under a nest of loops (outermost first), with its derivatives.
pub struct Term {
    pub loops: Vec<IndexVar>,
    pub value: Id,
    /// `(component, ∂value/∂component)`, nonzero ones.
    pub gradient: Vec<(Var, Id)>,
    /// The nonzero second derivatives.
    pub hessian: Vec<Entry>,
}

/// Which second-derivative block an entry is added to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Block {
    Xx,
    Xv,
    Vv,
}

/// `block[(row, col)] += id`, and `block[(col, row)] += id` too when `mirror`.
pub struct Entry {
    pub block: Block,
    pub row: Var,
    pub col: Var,
    pub id: Id,
    pub mirror: bool,
}

/// Whether a node holds a `Sum`, for every node.
fn sum_inside(g: &Graph) -> Vec<bool> {
    let mut has = vec![false; g.len()];
    for id in 0..g.len() {
        let node = g.node(id);
        has[id] = matches!(node, Node::Sum(..)) || node.children().iter().any(|&c| has[c]);
    }
    has
}

/// `L` as terms, or a message saying where a sum is used in a way that is not a sum of terms.
fn terms(g: &mut Graph, has: &[bool], id: Id) -> Result<Vec<(Vec<IndexVar>, Id)>, String> {
    if id >= has.len() || !has[id] {
        return Ok(vec![(Vec::new(), id)]);
    }
    let scale = |g: &mut Graph, ts: Vec<(Vec<IndexVar>, Id)>, f: &dyn Fn(&mut Graph, Id) -> Id| {
        ts.into_iter()
            .map(|(p, b)| (p, f(g, b)))
            .collect::<Vec<_>>()
    };
    Ok(match g.node(id) {
        Node::Add(a, b) => {
            let mut t = terms(g, has, a)?;
            t.extend(terms(g, has, b)?);
            t
        }
        Node::Sub(a, b) => {
            let mut t = terms(g, has, a)?;
            let tb = terms(g, has, b)?;
            t.extend(scale(g, tb, &|g, x| g.neg(x)));
            t
        }
        Node::Neg(a) => {
            let t = terms(g, has, a)?;
            scale(g, t, &|g, x| g.neg(x))
        }
        Node::Mul(a, b) => {
            let (ta, tb) = (terms(g, has, a)?, terms(g, has, b)?);
            let mut out = Vec::new();
            for (pa, ba) in &ta {
                for (pb, bb) in &tb {
                    let path = pa.iter().chain(pb).copied().collect();
                    out.push((path, g.mul(*ba, *bb)));
                }
            }
            out
        }
        Node::Div(a, b) if !has[b] => {
            let t = terms(g, has, a)?;
            scale(g, t, &|g, x| g.div(x, b))
        }
        Node::Select(op, l, r, a, b) if !has[l] && !has[r] => {
            let zero = g.num(0.0);
            let ta = terms(g, has, a)?;
            let tb = terms(g, has, b)?;
            let mut t = scale(g, ta, &|g, x| g.select(op, l, r, x, zero));
            t.extend(scale(g, tb, &|g, x| g.select(op, l, r, zero, x)));
            t
        }
        Node::Sum(i, body) => terms(g, has, body)?
            .into_iter()
            .map(|(p, b)| (std::iter::once(i).chain(p).collect(), b))
            .collect(),
        _ => {
            return Err(
                "a sum is used inside a function, a divisor or a condition: the \
                 Lagrangian must be a sum of terms, each a sum over indices of a formula \
                 (move the function inside the sum)"
                    .into(),
            );
        }
    })
}

/// The components a body reads, positions then velocities, each in id order.
fn components(g: &Graph, body: Id) -> (Vec<Var>, Vec<Var>) {
    let (mut xs, mut vs) = (Vec::new(), Vec::new());
    for id in g.reachable(&[body]) {
        match g.node(id) {
            Node::Var(w @ (Var::X(_) | Var::XAt(_))) => xs.push(w),
            Node::Var(w @ (Var::V(_) | Var::VAt(_))) => vs.push(w),
            _ => {}
        }
    }
    (xs, vs)
}

/// Writes `L` (the node `root`) as terms and differentiates each twice.
pub fn assemble(g: &mut Graph, root: Id) -> Result<Assembly, String> {
    let has = sum_inside(g);
    let mut by_path: Vec<(Vec<IndexVar>, Id)> = Vec::new();
    let mut index: HashMap<Vec<IndexVar>, usize> = HashMap::new();
    for (path, body) in terms(g, &has, root)? {
        match index.get(&path) {
            Some(&k) => by_path[k].1 = g.add(by_path[k].1, body),
            None => {
                index.insert(path.clone(), by_path.len());
                by_path.push((path, body));
            }
        }
    }
    let mut d = Differentiator::new();
    let mut out = Vec::new();
    for (loops, value) in by_path {
        if g.is_num(value, 0.0) {
            continue;
        }
        let (xs, vs) = components(g, value);
        let mut gradient = Vec::new();
        let mut first = HashMap::new();
        for &u in xs.iter().chain(&vs) {
            let du = d.diff(g, value, u);
            first.insert(u, du);
            if !g.is_num(du, 0.0) {
                gradient.push((u, du));
            }
        }
        let mut hessian = Vec::new();
        let blocks = [
            (Block::Xx, &xs, &xs, true),
            (Block::Xv, &xs, &vs, false),
            (Block::Vv, &vs, &vs, true),
        ];
        for (block, rows, cols, symmetric) in blocks {
            for (a, &row) in rows.iter().enumerate() {
                for (b, &col) in cols.iter().enumerate() {
                    if symmetric && b < a {
                        continue;
                    }
                    let id = d.diff(g, first[&row], col);
                    if !g.is_num(id, 0.0) {
                        let mirror = symmetric && a != b;
                        hessian.push(Entry {
                            block,
                            row,
                            col,
                            id,
                            mirror,
                        });
                    }
                }
            }
        }
        out.push(Term {
            loops,
            value,
            gradient,
            hessian,
        });
    }
    let block_ids = |b: Block| -> Vec<Id> {
        out.iter()
            .flat_map(|t| t.hessian.iter().filter(|e| e.block == b).map(|e| e.id))
            .collect()
    };
    let hessian_dependence = HessianDependence {
        xx: g.dependence(&block_ids(Block::Xx)),
        xv: g.dependence(&block_ids(Block::Xv)),
        vv: g.dependence(&block_ids(Block::Vv)),
    };
    Ok(Assembly {
        dependence: g.dependence(&[root]),
        terms: out,
        hessian_dependence,
    })
}
