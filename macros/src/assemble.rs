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
//! Sums are values. Where a sum enters polynomially — through `+`, `−`, products, `powi` with
//! a small positive exponent, a division by a sum-free divisor and either branch of an `if` —
//! `L` is expanded into terms by the distributive law: `(Σ_i a_i)·(Σ_i b_i)` is the double sum
//! `Σ_i Σ_j a_i·b_j`, and the second factor's loop variables are renamed so that the two
//! factors never share an index (a sum squared is a double sum, not `Σ_i a_i²`). A sum inside
//! a function, a divisor or a condition is *lifted*: replaced by a leaf `s_k`
//! ([`Var::Lifted`]), its value computed first by its own loop, and `L` differentiated
//! through it by the chain rule in reverse mode: with the adjoints `s̄_k = ∂L/∂s_k` (each the
//! partial of `L`'s terms plus the adjoints of the later sums that read `s_k`),
//! `∇L = ∂F/∂z + Σ_k s̄_k ∇s_k`, which is the gradient of the assembled function
//! `Φ = F + Σ_k s̄_k·(the terms of s_k)` with the adjoints held fixed. Its Hessian is
//! `Φ_zz + Σ_k (U_k W_kᵀ + W_k U_kᵀ)`, where `W_k = ds_k/dz` (forward: `∂s_k/∂z` plus the
//! earlier sums it reads) and `U_k = Φ_{z s_k} + ½ Σ_l Φ_{s_k s_l} W_l`: the sparse part of
//! the terms and a dense part of rank `2m`, which is why such a model claims no band.
//! A lifted sum must not read an enclosing loop's variable (it is then one value per
//! iteration, an array the scheme does not hold): that is a compile error naming the sum.

use std::collections::HashMap;

use crate::diff::Differentiator;
use crate::ir::{Dependence, Graph, HessianDependence, Id, IndexVar, Node, Var};
use crate::rewrite::{MAX_EXPANDED_POWER, fresh_copy, lifted_sums, replace, sum_inside};

/// A Lagrangian with loops, as terms and their derivatives.
pub struct Assembly {
    /// The terms of `Φ`: those of `L` (its lifted sums as leaves), then each lifted sum's terms
    /// weighted by its adjoint.
    pub terms: Vec<Term>,
    /// The terms of each lifted sum `s_k`, unweighted, in the order they are computed.
    pub sums: Vec<Vec<Term>>,
    /// Which blocks (`xx`, `xv`, `vv`) get the dense part of the lifted sums' Hessian.
    pub dense_blocks: [bool; 3],
    pub hessian_dependence: HessianDependence,
    pub dependence: Dependence,
}

/// One body under a nest of loops (outermost first), with its derivatives.
pub struct Term {
    pub loops: Vec<IndexVar>,
    pub value: Id,
    /// `(component, ∂value/∂component)`, nonzero ones; the components are `x`, `v` and the
    /// lifted sums the body reads.
    pub gradient: Vec<(Var, Id)>,
    /// The nonzero second derivatives.
    pub hessian: Vec<Entry>,
    /// `Some(k)`: a term of lifted sum `k`, weighted by its adjoint (it adds to the derivatives
    /// of `L`, not to its value).
    pub weighted: Option<usize>,
}

/// Which second-derivative block an entry is added to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Block {
    Xx,
    Xv,
    Vv,
    /// A state component (row) and a lifted sum (column).
    Zs,
    /// Two lifted sums.
    Ss,
    /// `∂f/∂x` of a force with loops: a weight of its virtual work (row) and a position.
    Fx,
    /// `∂f/∂v` of a force with loops: a weight (row) and a velocity.
    Fv,
}

/// `block[(row, col)] += id`, and `block[(col, row)] += id` too when `mirror`.
pub struct Entry {
    pub block: Block,
    pub row: Var,
    pub col: Var,
    pub id: Id,
    pub mirror: bool,
}

type Terms = Vec<(Vec<IndexVar>, Id)>;

/// The product of two term lists; the second factor's loop variables are renamed where they
/// meet the first's, so that two sums never share an index.
fn product(g: &mut Graph, ta: &Terms, tb: &Terms) -> Terms {
    let mut out = Vec::new();
    for (pa, ba) in ta {
        for (pb, bb) in tb {
            let (pb, bb) = if pb.iter().any(|v| pa.contains(v)) {
                fresh_copy(g, pb, *bb)
            } else {
                (pb.clone(), *bb)
            };
            let path = pa.iter().chain(&pb).copied().collect();
            out.push((path, g.mul(*ba, bb)));
        }
    }
    out
}

/// `L` as terms, or a message saying where a sum is used in a way that is not a sum of terms.
fn terms(g: &mut Graph, has: &[bool], id: Id) -> Result<Terms, String> {
    if id >= has.len() || !has[id] {
        return Ok(vec![(Vec::new(), id)]);
    }
    let scale = |g: &mut Graph, ts: Terms, f: &dyn Fn(&mut Graph, Id) -> Id| {
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
            product(g, &ta, &tb)
        }
        Node::Powi(a, n) if (1..=MAX_EXPANDED_POWER).contains(&n) => {
            let ta = terms(g, has, a)?;
            let mut t = ta.clone();
            for _ in 1..n {
                t = product(g, &t, &ta);
            }
            t
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
                "a sum is used inside a function, a divisor or a condition where the macro \
                 cannot lift it"
                    .into(),
            );
        }
    })
}

/// The components a body reads: positions, velocities and lifted sums, each in id order.
fn components(g: &Graph, body: Id) -> [Vec<Var>; 3] {
    let (mut xs, mut vs, mut ss) = (Vec::new(), Vec::new(), Vec::new());
    for id in g.reachable(&[body]) {
        match g.node(id) {
            Node::Var(w @ (Var::X(_) | Var::XAt(_))) => xs.push(w),
            Node::Var(w @ (Var::V(_) | Var::VAt(_))) => vs.push(w),
            Node::Var(w @ Var::Lifted(_)) => ss.push(w),
            _ => {}
        }
    }
    [xs, vs, ss]
}

/// Terms with the same loops, merged into one body each, in first-seen order.
fn merged(g: &mut Graph, ts: Terms) -> Terms {
    let mut by_path: Terms = Vec::new();
    let mut index: HashMap<Vec<IndexVar>, usize> = HashMap::new();
    for (path, body) in ts {
        match index.get(&path) {
            Some(&k) => by_path[k].1 = g.add(by_path[k].1, body),
            None => {
                index.insert(path.clone(), by_path.len());
                by_path.push((path, body));
            }
        }
    }
    by_path
}

/// Differentiates each term twice.
fn differentiate(g: &mut Graph, d: &mut Differentiator, ts: Terms) -> Vec<Term> {
    let mut out = Vec::new();
    for (loops, value) in ts {
        if g.is_num(value, 0.0) {
            continue;
        }
        let [xs, vs, ss] = components(g, value);
        let states: Vec<Var> = xs.iter().chain(&vs).copied().collect();
        let mut gradient = Vec::new();
        let mut first = HashMap::new();
        for &u in states.iter().chain(&ss) {
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
            (Block::Zs, &states, &ss, false),
            (Block::Ss, &ss, &ss, true),
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
            weighted: None,
        });
    }
    out
}

/// `term` weighted by the adjoint of lifted sum `k`.
fn weighted(g: &mut Graph, term: &Term, k: usize) -> Term {
    let adjoint = g.var(Var::Adjoint(k));
    let w = |g: &mut Graph, id: Id| g.mul(adjoint, id);
    Term {
        loops: term.loops.clone(),
        value: w(g, term.value),
        gradient: term.gradient.iter().map(|&(u, id)| (u, w(g, id))).collect(),
        hessian: term
            .hessian
            .iter()
            .map(|e| Entry {
                id: w(g, e.id),
                ..*e
            })
            .collect(),
        weighted: Some(k),
    }
}

/// Writes `L` (the node `root`) as terms and differentiates each twice.
pub fn assemble(g: &mut Graph, root: Id) -> Result<Assembly, String> {
    let has = sum_inside(g);
    let lifted = lifted_sums(g, &has, root)?;
    // Each lifted sum becomes a leaf; its own body reads the leaves of the sums lifted
    // inside it (smaller ids, so lower numbers: computed before it).
    let mut map: HashMap<Id, Id> = HashMap::new();
    let mut definitions = Vec::new();
    for (k, &s) in lifted.iter().enumerate() {
        definitions.push(replace(g, s, &map));
        let leaf = g.var(Var::Lifted(k));
        map.insert(s, leaf);
    }
    let top = replace(g, root, &map);
    let has = sum_inside(g);
    let mut d = Differentiator::new();
    let top_terms = terms(g, &has, top)?;
    let top_terms = merged(g, top_terms);
    let mut out = differentiate(g, &mut d, top_terms);
    let mut sums = Vec::new();
    for (k, &def) in definitions.iter().enumerate() {
        let ts = terms(g, &has, def)?;
        let ts = merged(g, ts);
        let own = differentiate(g, &mut d, ts);
        for t in &own {
            let w = weighted(g, t, k);
            out.push(w);
        }
        sums.push(own);
    }
    let deep = Deep::new(g, &out, &sums);
    let dense_blocks = dense_blocks(&out, &sums);
    let block_ids = |b: Block| -> Vec<Id> {
        out.iter()
            .flat_map(|t| t.hessian.iter().filter(|e| e.block == b).map(|e| e.id))
            .collect()
    };
    // The dense part of block `b` reads every derivative of the lifted sums and the
    // lifted blocks of `Φ`.
    let rank_ids: Vec<Id> = sums
        .iter()
        .flatten()
        .flat_map(|t| t.gradient.iter().map(|e| e.1))
        .chain(out.iter().flat_map(|t| {
            t.hessian
                .iter()
                .filter(|e| matches!(e.block, Block::Zs | Block::Ss))
                .map(|e| e.id)
        }))
        .collect();
    let block_dependence = |b: Block, k: usize| {
        let mut ids = block_ids(b);
        if dense_blocks[k] {
            ids.extend(&rank_ids);
        }
        deep.dependence(g, &ids)
    };
    let hessian_dependence = HessianDependence {
        xx: block_dependence(Block::Xx, 0),
        xv: block_dependence(Block::Xv, 1),
        vv: block_dependence(Block::Vv, 2),
    };
    Ok(Assembly {
        dependence: g.dependence(&[root]),
        terms: out,
        sums,
        dense_blocks,
        hessian_dependence,
    })
}

/// What the lifted sums and their adjoints depend on, so that the dependence of a node that
/// reads their leaves is known.
struct Deep {
    lifted: Vec<Dependence>,
    adjoint: Vec<Dependence>,
}

impl Deep {
    fn new(g: &Graph, terms: &[Term], sums: &[Vec<Term>]) -> Self {
        let mut deep = Deep {
            lifted: Vec::new(),
            adjoint: vec![Dependence::NONE; sums.len()],
        };
        for s in sums {
            let ids: Vec<Id> = s.iter().map(|t| t.value).collect();
            let dep = deep.dependence(g, &ids);
            deep.lifted.push(dep);
        }
        // The adjoint of sum `k` reads the adjoints of later sums only.
        for k in (0..sums.len()).rev() {
            let ids: Vec<Id> = terms
                .iter()
                .flat_map(|t| t.gradient.iter())
                .filter(|e| e.0 == Var::Lifted(k))
                .map(|e| e.1)
                .collect();
            deep.adjoint[k] = deep.dependence(g, &ids);
        }
        deep
    }

    /// On which of `x`, `v`, `t` the nodes `ids` depend, through the leaves of lifted sums
    /// and adjoints too.
    fn dependence(&self, g: &Graph, ids: &[Id]) -> Dependence {
        let mut dep = g.dependence(ids);
        for id in g.reachable(ids) {
            let other = match g.node(id) {
                Node::Var(Var::Lifted(k)) => self.lifted.get(k),
                Node::Var(Var::Adjoint(k)) => self.adjoint.get(k),
                _ => None,
            };
            if let Some(o) = other {
                dep.x |= o.x;
                dep.v |= o.v;
                dep.t |= o.t;
            }
        }
        dep
    }
}

/// Which of the blocks `xx`, `xv`, `vv` the dense part `Σ_k (U_k W_kᵀ + W_k U_kᵀ)` can
/// reach: where some `W_k` or `U_k` has entries on each side.
fn dense_blocks(terms: &[Term], sums: &[Vec<Term>]) -> [bool; 3] {
    let is_x = |u: &Var| matches!(u, Var::X(_) | Var::XAt(_));
    let is_v = |u: &Var| matches!(u, Var::V(_) | Var::VAt(_));
    // `W_k` has `x` (`v`) entries when sum `k` reads positions (velocities), directly or
    // through an earlier sum.
    let mut w: Vec<[bool; 2]> = Vec::new();
    for s in sums {
        let mut side = [false; 2];
        for (u, _) in s.iter().flat_map(|t| &t.gradient) {
            side[0] |= is_x(u);
            side[1] |= is_v(u);
            if let Var::Lifted(j) = u {
                side[0] |= w[*j][0];
                side[1] |= w[*j][1];
            }
        }
        w.push(side);
    }
    // `U_k` has entries where `Φ_{z s_k}` has, or where a `W_l` with `Φ_{s_k s_l} ≠ 0` has.
    let mut u = vec![[false; 2]; sums.len()];
    for e in terms.iter().flat_map(|t| &t.hessian) {
        match (e.block, e.row, e.col) {
            (Block::Zs, row, Var::Lifted(k)) => {
                u[k][0] |= is_x(&row);
                u[k][1] |= is_v(&row);
            }
            (Block::Ss, Var::Lifted(j), Var::Lifted(l)) => {
                for (a, b) in [(j, l), (l, j)] {
                    u[a][0] |= w[b][0];
                    u[a][1] |= w[b][1];
                }
            }
            _ => {}
        }
    }
    let pair =
        |r: usize, c: usize| (0..sums.len()).any(|k| (u[k][r] && w[k][c]) || (w[k][r] && u[k][c]));
    [pair(0, 0), pair(0, 1), pair(1, 1)]
}

/// A `#[force]` with loops, read as its virtual work `W = Σ_k w_k f_k` (see
/// `parse/looped_force.rs`): each term's force entries `(w_k, ∂W/∂w_k)` in `gradient`, its
/// Jacobian entries `∂²W/∂w_k∂x_j`, `∂²W/∂w_k∂v_j` in `hessian` (blocks [`Block::Fx`],
/// [`Block::Fv`], never mirrored: a force's Jacobian is in general not symmetric).
pub struct ForceAssembly {
    /// The terms, as an [`Assembly`] without lifted sums, for the loop path's emitters.
    pub assembly: Assembly,
    /// What `∂f/∂x` and `∂f/∂v` depend on.
    pub dependence: [Dependence; 2],
}

/// Writes the virtual work `root` as terms and differentiates each with respect to its
/// weights, then each force entry with respect to the state.
pub fn assemble_force(g: &mut Graph, root: Id) -> Result<ForceAssembly, String> {
    let has = sum_inside(g);
    if !lifted_sums(g, &has, root)?.is_empty() {
        return Err(
            "a sum inside a function, a divisor or a condition is not supported in a \
                    #[force]: a force component may hold sums only through `+`, `−`, products \
                    and small powers (`powi`), which give its Jacobian's entries term by term"
                .into(),
        );
    }
    let ts = terms(g, &has, root)?;
    let ts = merged(g, ts);
    let mut d = Differentiator::new();
    let mut out = Vec::new();
    let (mut on_x, mut on_v) = (Vec::new(), Vec::new());
    for (loops, value) in ts {
        let mut weights = Vec::new();
        for id in g.reachable(&[value]) {
            if let Node::Var(w @ (Var::F(_) | Var::FAt(_))) = g.node(id) {
                weights.push(w);
            }
        }
        let [xs, vs, _] = components(g, value);
        let mut gradient = Vec::new();
        let mut hessian = Vec::new();
        let (one, zero) = (g.num(1.0), g.num(0.0));
        for &w in &weights {
            // `W` is linear in the weights, so `∂W/∂w_k` is `W` at `w_k = 1` and every other
            // weight 0: substituted rather than differentiated, it holds no weight by
            // construction (a derivative's unsimplified zeros could keep one).
            let map: HashMap<Id, Id> = weights
                .iter()
                .map(|&u| (g.var(u), if u == w { one } else { zero }))
                .collect();
            let f = replace(g, value, &map);
            if g.is_num(f, 0.0) {
                continue;
            }
            gradient.push((w, f));
            for (block, states) in [(Block::Fx, &xs), (Block::Fv, &vs)] {
                for &col in states {
                    let id = d.diff(g, f, col);
                    if !g.is_num(id, 0.0) {
                        match block {
                            Block::Fx => on_x.push(id),
                            _ => on_v.push(id),
                        }
                        hessian.push(Entry {
                            block,
                            row: w,
                            col,
                            id,
                            mirror: false,
                        });
                    }
                }
            }
        }
        if !gradient.is_empty() {
            out.push(Term {
                loops,
                value,
                gradient,
                hessian,
                weighted: None,
            });
        }
    }
    let none = Dependence::NONE;
    Ok(ForceAssembly {
        assembly: Assembly {
            terms: out,
            sums: Vec::new(),
            dense_blocks: [false; 3],
            hessian_dependence: HessianDependence {
                xx: none,
                xv: none,
                vv: none,
            },
            dependence: g.dependence(&[root]),
        },
        dependence: [g.dependence(&on_x), g.dependence(&on_v)],
    })
}
