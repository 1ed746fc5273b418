//! The CSE stage: which nodes each generated method binds to temporaries ([`Plans`]).
//!
//! The DAG is hash-consed, so identical subexpressions are already one node. What remains is to
//! decide which nodes are bound to a `let` temporary: every non-leaf node that is used more than
//! once among the nodes an emitted method evaluates. A node used once is inlined into its only
//! user. Emitting temporaries in id order (a topological order) then evaluates every distinct
//! subexpression exactly once per method.

use crate::ir::{Derivatives, Graph, Id, Node};

/// One [`Plan`] per generated method.
#[derive(Clone, Debug)]
pub struct Plans {
    /// `value`: `L`.
    pub value: Plan,
    /// `gradient`: `∂L/∂x`, `∂L/∂v`.
    pub gradient: Plan,
    /// `hessian`: the nonzero entries of the three blocks.
    pub hessian: Plan,
    /// `value_and_gradient`: `L` and its gradient together.
    pub value_and_gradient: Plan,
    /// `gradient_and_hessian`: the gradient and the Hessian entries together, so that what
    /// they share (e.g. `sin`/`cos` of the same angle) is computed once.
    pub gradient_and_hessian: Plan,
}

/// Plans the methods that evaluate `L` (the node `root`) and its derivatives `d`.
pub fn plan(g: &Graph, root: Id, d: &Derivatives) -> Plans {
    let gradient = gradient_roots(d);
    let hessian = hessian_roots(g, d);
    let both: Vec<Id> = gradient.iter().chain(&hessian).copied().collect();
    let with_value: Vec<Id> = std::iter::once(root)
        .chain(gradient.iter().copied())
        .collect();
    Plans {
        value: Plan::new(g, &[root]),
        value_and_gradient: Plan::new(g, &with_value),
        gradient: Plan::new(g, &gradient),
        hessian: Plan::new(g, &hessian),
        gradient_and_hessian: Plan::new(g, &both),
    }
}

/// The gradient's entries, `∂L/∂x` then `∂L/∂v`.
pub fn gradient_roots(d: &Derivatives) -> Vec<Id> {
    d.fx.iter().chain(&d.fv).copied().collect()
}

/// The Hessian's roots, one per emitted (nonzero) entry: an off-diagonal entry of a symmetric
/// block is written twice, `(i, j)` and `(j, i)`, so it is listed twice and becomes a
/// temporary.
pub fn hessian_roots(g: &Graph, d: &Derivatives) -> Vec<Id> {
    [&d.xx, &d.xv, &d.vv]
        .into_iter()
        .flatten()
        .copied()
        .filter(|&id| !g.is_num(id, 0.0))
        .collect()
}

/// Which nodes of a method become temporaries.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The nodes bound to temporaries, in evaluation (id) order.
    pub temps: Vec<Id>,
    /// `temp_index[id]`: the temporary's number for nodes in `temps`.
    temp_index: Vec<Option<usize>>,
}

impl Plan {
    /// Plans the evaluation of `roots` (a root may be listed several times, e.g. the mirrored
    /// entry of a symmetric block; it then becomes a temporary).
    pub fn new(g: &Graph, roots: &[Id]) -> Self {
        let mut uses = vec![0usize; g.len()];
        for &r in roots {
            uses[r] += 1;
        }
        for id in g.reachable(roots) {
            let node = g.node(id);
            for c in node.children() {
                // `sign(a)` is emitted as an `if` that reads `a` twice, `1 − a²` as
                // `(1 − a)(1 + a)`: `a` must be a value.
                uses[c] += if matches!(node, Node::Call(f, _) if f.reads_argument_twice()) {
                    2
                } else {
                    1
                };
            }
        }
        let mut temp_index = vec![None; g.len()];
        let mut temps = Vec::new();
        for id in g.reachable(roots) {
            if uses[id] >= 2 && !g.node(id).is_leaf() {
                temp_index[id] = Some(temps.len());
                temps.push(id);
            }
        }
        Self { temps, temp_index }
    }

    /// A plan binding exactly `temps` (in id order).
    pub fn with_temps(g: &Graph, mut temps: Vec<Id>) -> Self {
        temps.sort_unstable();
        temps.dedup();
        let mut temp_index = vec![None; g.len()];
        for (k, &id) in temps.iter().enumerate() {
            temp_index[id] = Some(k);
        }
        Self { temps, temp_index }
    }

    /// A plan that binds nothing: every node is inlined at each use (a negative control for
    /// the CSE tests).
    #[cfg(test)]
    pub fn without_temps(g: &Graph) -> Self {
        Self {
            temps: Vec::new(),
            temp_index: vec![None; g.len()],
        }
    }

    /// The temporary bound to `id`, if any.
    pub fn temp(&self, id: Id) -> Option<usize> {
        self.temp_index.get(id).copied().flatten()
    }
}
