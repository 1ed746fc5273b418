//! The expression IR: a hash-consed DAG of scalar operations.
//!
//! Every node lives once in a [`Graph`]; building a node that already exists returns the
//! existing [`Id`], so identical subexpressions are shared by construction. Children are always
//! created before their parents, hence `Id` order is a topological order — the code generator
//! emits temporaries in `Id` order.

use std::collections::HashMap;

/// Index of a node in its [`Graph`].
pub type Id = usize;

/// A leaf variable of the Lagrangian or of a step kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    /// Position component `x_i`.
    X(usize),
    /// Velocity component `v_i`.
    V(usize),
    /// Time `t`.
    T,
    /// Model constant number `k` (a field of the generated struct).
    Const(usize),
    /// Step size `h` (step kernels only).
    H,
    /// Momentum component `π_i` (step kernels only).
    M(usize),
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
    Ln,
    Log10,
    Sqrt,
    Cbrt,
    Recip,
    Abs,
    /// `sign(a)` with `sign(0) = 0` (and `sign(NaN) = 0`): the derivative of `abs`.
    Sign,
}

impl Func {
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
            Func::Ln => "ln",
            Func::Log10 => "log10",
            Func::Sqrt => "sqrt",
            Func::Cbrt => "cbrt",
            Func::Recip => "recip",
            Func::Abs => "abs",
            Func::Sign => "sign",
        }
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
            Func::Ln => a.ln(),
            Func::Log10 => a.log10(),
            Func::Sqrt => a.sqrt(),
            Func::Cbrt => a.cbrt(),
            Func::Recip => a.recip(),
            Func::Abs => a.abs(),
            Func::Sign => sign(a),
        }
    }
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
}

impl Node {
    /// The children of the node, in order.
    pub fn children(&self) -> Vec<Id> {
        match *self {
            Node::Num(_) | Node::Var(_) => vec![],
            Node::Neg(a) | Node::Call(_, a) | Node::Powi(a, _) => vec![a],
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Powf(a, b)
            | Node::Hypot(a, b) => vec![a, b],
        }
    }

    /// A leaf (a number or a variable) is never bound to a temporary.
    pub fn is_leaf(&self) -> bool {
        matches!(self, Node::Num(_) | Node::Var(_))
    }
}

/// The hash-consed node store.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Returns the id of `node`, creating it if it is new. No simplification happens here
    /// (see `simplify.rs` for the smart constructors).
    pub fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = self.nodes.len();
        self.nodes.push(node);
        self.index.insert(node, id);
        id
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

    /// Whether `id` is the constant `c` (bitwise, so `-0.0` is not `0.0`).
    pub fn is_num(&self, id: Id, c: f64) -> bool {
        self.num_value(id) == Some(c) || (c == 0.0 && self.num_value(id) == Some(-0.0))
    }

    /// For every node: does it depend on a variable accepted by `pred`? Uses the topological
    /// order of ids.
    pub fn depends(&self, pred: impl Fn(Var) -> bool) -> Vec<bool> {
        let mut out = vec![false; self.nodes.len()];
        for (id, node) in self.nodes.iter().enumerate() {
            out[id] = match *node {
                Node::Var(var) => pred(var),
                Node::Num(_) => false,
                _ => node.children().iter().any(|&c| out[c]),
            };
        }
        out
    }

    #[cfg(test)]
    /// Evaluates `roots` with variable values from `env`, sharing the work over the DAG.
    pub fn eval_many(&self, roots: &[Id], env: &dyn Fn(Var) -> f64) -> Vec<f64> {
        let mut memo: HashMap<Id, f64> = HashMap::new();
        roots
            .iter()
            .map(|&r| self.eval_memo(r, env, &mut memo))
            .collect()
    }

    /// Evaluates one node.
    #[cfg(test)]
    pub fn eval(&self, root: Id, env: &dyn Fn(Var) -> f64) -> f64 {
        self.eval_many(&[root], env)[0]
    }

    #[cfg(test)]
    fn eval_memo(&self, root: Id, env: &dyn Fn(Var) -> f64, memo: &mut HashMap<Id, f64>) -> f64 {
        // Children have smaller ids, so evaluating the reachable nodes in increasing id order
        // needs no recursion (and cannot overflow the stack on deep expressions).
        let mut order = self.reachable(&[root]);
        order.retain(|id| !memo.contains_key(id));
        for id in order {
            let val = |i: Id| memo[&i];
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
            };
            memo.insert(id, x);
        }
        memo[&root]
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
}
