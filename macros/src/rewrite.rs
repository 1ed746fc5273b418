//! Rewrites of the expression graph that the assembly of a Lagrangian with loops needs:
//! which sums are used as values (and so lifted to leaves), replacing nodes, and renaming loop
//! variables so that two factors of a product never share an index.

use std::collections::{HashMap, HashSet};

use crate::ir::{Graph, Id, IndexVar, Node, Var};

/// Whether a node holds a `Sum`, for every node.
pub fn sum_inside(g: &Graph) -> Vec<bool> {
    let mut has = vec![false; g.len()];
    for id in 0..g.len() {
        let node = g.node(id);
        has[id] = matches!(node, Node::Sum(..)) || node.children().iter().any(|&c| has[c]);
    }
    has
}

/// The loop variables each node reads and does not bind, for every node.
pub fn free_vars(g: &Graph) -> Vec<Vec<IndexVar>> {
    let mut free: Vec<Vec<IndexVar>> = Vec::with_capacity(g.len());
    for id in 0..g.len() {
        let mut vars: Vec<IndexVar> = match g.node(id) {
            Node::Var(Var::XAt(c) | Var::VAt(c) | Var::FAt(c)) => c.at.var.into_iter().collect(),
            Node::Var(Var::Index(i)) => vec![i],
            Node::Sum(i, body) => {
                let r = &g.ranges[i.0 as usize];
                free[body]
                    .iter()
                    .copied()
                    .filter(|&v| v != i)
                    .chain(r.start.var)
                    .chain(r.end.var)
                    .collect()
            }
            node => node
                .children()
                .iter()
                .flat_map(|&c| free[c].clone())
                .collect(),
        };
        vars.sort_unstable();
        vars.dedup();
        free.push(vars);
    }
    free
}

/// The largest `powi` exponent expanded as a product of sums; a higher power of a sum is
/// lifted.
pub const MAX_EXPANDED_POWER: i32 = 4;

/// The sums `L` uses as values (inside a function, a divisor or a condition), in increasing
/// id (an inner sum before the sum whose body holds it), or a message naming one that reads
/// an enclosing loop's variable.
pub fn lifted_sums(g: &Graph, has: &[bool], root: Id) -> Result<Vec<Id>, String> {
    let free = free_vars(g);
    let mut lifted = HashSet::new();
    let mut seen = HashSet::new();
    let mut stack = vec![(root, false)];
    while let Some((id, inside)) = stack.pop() {
        if !has[id] || !seen.insert((id, inside)) {
            continue;
        }
        let node = g.node(id);
        if let Node::Sum(i, body) = node {
            if inside {
                if let Some(&outer) = free[id].first() {
                    let name = |v: IndexVar| g.ranges[v.0 as usize].name.clone();
                    return Err(format!(
                        "the sum over `{}` reads `{}`, the variable of an enclosing loop, and is \
                         used inside a function, a divisor or a condition: such a sum may only \
                         be added, multiplied or raised to a small power (`powi`); write the \
                         function of it outside that loop, or as a sum of its own",
                        name(i),
                        name(outer)
                    ));
                }
                lifted.insert(id);
            }
            // The body of a sum is a value of its own: what it does with further sums is
            // judged afresh.
            stack.push((body, false));
            continue;
        }
        let linear: Vec<bool> = match node {
            Node::Add(..) | Node::Sub(..) | Node::Neg(_) | Node::Mul(..) => {
                vec![inside; 2]
            }
            Node::Powi(_, n) if (1..=MAX_EXPANDED_POWER).contains(&n) => vec![inside],
            Node::Div(..) => vec![inside, true],
            Node::Select(..) => vec![true, true, inside, inside],
            _ => vec![true; 2],
        };
        for (k, c) in node.children().into_iter().enumerate() {
            stack.push((c, linear.get(k).copied().unwrap_or(true)));
        }
    }
    let mut out: Vec<Id> = lifted.into_iter().collect();
    out.sort_unstable();
    Ok(out)
}

/// `id` with the nodes of `map` replaced (rebuilt through the smart constructors above them).
pub fn replace(g: &mut Graph, id: Id, map: &HashMap<Id, Id>) -> Id {
    let mut memo: HashMap<Id, Id> = HashMap::new();
    for n in g.reachable(&[id]) {
        if let Some(&r) = map.get(&n) {
            memo.insert(n, r);
            continue;
        }
        let m = |c: Id| memo[&c];
        let new = match g.node(n) {
            Node::Num(_) | Node::Var(_) => n,
            Node::Add(a, b) => g.add(m(a), m(b)),
            Node::Sub(a, b) => g.sub(m(a), m(b)),
            Node::Mul(a, b) => g.mul(m(a), m(b)),
            Node::Div(a, b) => g.div(m(a), m(b)),
            Node::Neg(a) => g.neg(m(a)),
            Node::Call(f, a) => g.call(f, m(a)),
            Node::Powi(a, k) => g.powi(m(a), k),
            Node::Powf(a, b) => g.powf(m(a), m(b)),
            Node::Hypot(a, b) => g.hypot(m(a), m(b)),
            Node::Atan2(a, b) => g.atan2(m(a), m(b)),
            Node::Select(op, l, r, a, b) => g.select(op, m(l), m(r), m(a), m(b)),
            Node::Sum(i, body) => g.sum(i, m(body)),
        };
        memo.insert(n, new);
    }
    memo[&id]
}

/// `id` with the loop variables of `map` renamed (their ranges are copied for the new
/// variables beforehand). A renaming keeps the shape of every node, so nodes are interned as
/// they are.
pub fn rename(g: &mut Graph, id: Id, map: &HashMap<IndexVar, IndexVar>) -> Id {
    let at = |c: crate::ir::Component| crate::ir::Component {
        at: crate::ir::Affine {
            var: c.at.var.map(|v| *map.get(&v).unwrap_or(&v)),
            ..c.at
        },
        ..c
    };
    let mut memo: HashMap<Id, Id> = HashMap::new();
    for n in g.reachable(&[id]) {
        let m = |c: Id| memo[&c];
        let node = match g.node(n) {
            Node::Var(Var::XAt(c)) => Node::Var(Var::XAt(at(c))),
            Node::Var(Var::VAt(c)) => Node::Var(Var::VAt(at(c))),
            Node::Var(Var::FAt(c)) => Node::Var(Var::FAt(at(c))),
            Node::Var(Var::Index(i)) => Node::Var(Var::Index(*map.get(&i).unwrap_or(&i))),
            node @ (Node::Num(_) | Node::Var(_)) => node,
            Node::Add(a, b) => Node::Add(m(a), m(b)),
            Node::Sub(a, b) => Node::Sub(m(a), m(b)),
            Node::Mul(a, b) => Node::Mul(m(a), m(b)),
            Node::Div(a, b) => Node::Div(m(a), m(b)),
            Node::Neg(a) => Node::Neg(m(a)),
            Node::Call(f, a) => Node::Call(f, m(a)),
            Node::Powi(a, k) => Node::Powi(m(a), k),
            Node::Powf(a, b) => Node::Powf(m(a), m(b)),
            Node::Hypot(a, b) => Node::Hypot(m(a), m(b)),
            Node::Atan2(a, b) => Node::Atan2(m(a), m(b)),
            Node::Select(op, l, r, a, b) => Node::Select(op, m(l), m(r), m(a), m(b)),
            Node::Sum(i, body) => Node::Sum(*map.get(&i).unwrap_or(&i), m(body)),
        };
        let new = g.intern(node);
        memo.insert(n, new);
    }
    memo[&id]
}

/// Fresh copies of the loop variables `path` (outermost first), each range rewritten in the
/// copies of the variables before it, with `body` renamed to them.
pub fn fresh_copy(g: &mut Graph, path: &[IndexVar], body: Id) -> (Vec<IndexVar>, Id) {
    let mut map: HashMap<IndexVar, IndexVar> = HashMap::new();
    let mut new_path = Vec::with_capacity(path.len());
    for &i in path {
        let mut r = g.ranges[i.0 as usize].clone();
        for end in [&mut r.start, &mut r.end] {
            if let Some(v) = end.var {
                end.var = Some(*map.get(&v).unwrap_or(&v));
            }
        }
        let new = IndexVar(g.ranges.len() as u32);
        g.ranges.push(r);
        map.insert(i, new);
        new_path.push(new);
    }
    (new_path, rename(g, body, &map))
}
