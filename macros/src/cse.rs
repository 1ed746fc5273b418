//! Common-subexpression elimination.
//!
//! The DAG is hash-consed, so identical subexpressions are already one node. What remains is to
//! decide which nodes are bound to a `let` temporary: every non-leaf node that is used more than
//! once among the nodes an emitted method evaluates. A node used once is inlined into its only
//! user. Emitting temporaries in id order (a topological order) then evaluates every distinct
//! subexpression exactly once per method.

use crate::expr::{Func, Graph, Id, Node};

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
                // `sign(a)` is emitted as an `if` that reads `a` twice: `a` must be a value.
                uses[c] += if matches!(node, Node::Call(Func::Sign, _)) {
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
