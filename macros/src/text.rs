//! The derivatives as text (`NAME::DERIVATIVES`): one `name = formula` per line, each formula
//! in Rust syntax with every shared node written out.

use std::collections::HashMap;

use crate::ir::{Derivatives, Func, Graph, Id, Model, Node, Prec, Var, constant_name};

/// Formulas longer than this are not spelled out (the expansion of a DAG can be exponential).
const MAX_TEXT_NODES: usize = 4000;

/// `L` and its nonzero derivatives, one per line (symmetric blocks listed once, `i ≤ j`).
pub fn derivatives_text(model: &Model, d: &Derivatives) -> String {
    let g = &model.graph;
    let dim = model.dim;
    let var = |x: bool, i: usize| {
        let n = if x { "x" } else { "v" };
        if model.scalar {
            n.to_string()
        } else {
            format!("{n}[{i}]")
        }
    };
    let p = Printer { g, model };
    let mut lines = vec![format!("L = {}", p.print(model.root))];
    for (x, ids) in [(true, &d.fx), (false, &d.fv)] {
        for (i, &id) in ids.iter().enumerate() {
            lines.push(format!("∂L/∂{} = {}", var(x, i), p.print(id)));
        }
    }
    for (bx, by, block, sym) in [
        (true, true, &d.xx, true),
        (true, false, &d.xv, false),
        (false, false, &d.vv, true),
    ] {
        for i in 0..dim {
            for j in 0..dim {
                let id = block[i * dim + j];
                if (sym && j < i) || g.is_num(id, 0.0) {
                    continue;
                }
                lines.push(format!(
                    "∂²L/∂{}∂{} = {}",
                    var(bx, i),
                    var(by, j),
                    p.print(id)
                ));
            }
        }
    }
    lines.join("\n")
}

/// Prints a node as a formula in Rust syntax, expanding shared nodes.
struct Printer<'a> {
    g: &'a Graph,
    model: &'a Model,
}

impl Printer<'_> {
    fn print(&self, id: Id) -> String {
        // Size of the expanded tree, saturating, over the topological order.
        let order = self.g.reachable(&[id]);
        let mut size: HashMap<Id, usize> = HashMap::new();
        for &n in &order {
            let s = self
                .g
                .node(n)
                .children()
                .iter()
                .fold(1usize, |acc, c| acc.saturating_add(size[c]));
            size.insert(n, s);
        }
        if size[&id] > MAX_TEXT_NODES {
            return format!("(formula of {}+ operations, not printed)", MAX_TEXT_NODES);
        }
        self.go(id).0
    }

    fn wrap(&self, id: Id, need: Prec) -> String {
        let (s, p) = self.go(id);
        if p < need { format!("({s})") } else { s }
    }

    fn go(&self, id: Id) -> (String, Prec) {
        let bin = |a: Id, b: Id, op: &str, p: Prec| {
            (
                format!(
                    "{} {op} {}",
                    self.wrap(a, p),
                    self.wrap(b, p.right_operand())
                ),
                p,
            )
        };
        match self.g.node(id) {
            Node::Num(bits) => {
                let c = f64::from_bits(bits);
                let s = match constant_name(c.abs()) {
                    Some(name) if c < 0.0 => format!("-{name}"),
                    Some(name) => name.to_string(),
                    None => format!("{c:?}"),
                };
                let p = if c.is_sign_negative() {
                    Prec::Neg
                } else {
                    Prec::Atom
                };
                (s, p)
            }
            Node::Var(v) => {
                let s = match v {
                    Var::X(_) if self.model.scalar => "x".into(),
                    Var::V(_) if self.model.scalar => "v".into(),
                    Var::X(i) => format!("x[{i}]"),
                    Var::V(i) => format!("v[{i}]"),
                    Var::T => "t".into(),
                    Var::Const(k) => self.model.consts[k].to_string(),
                };
                (s, Prec::Atom)
            }
            Node::Add(a, b) => bin(a, b, "+", Prec::Add),
            Node::Sub(a, b) => bin(a, b, "-", Prec::Add),
            Node::Mul(a, b) => bin(a, b, "*", Prec::Mul),
            Node::Div(a, b) => bin(a, b, "/", Prec::Mul),
            Node::Neg(a) => (format!("-{}", self.wrap(a, Prec::Atom)), Prec::Neg),
            Node::Call(Func::Sign, a) => (format!("sign({})", self.go(a).0), Prec::Atom),
            Node::Call(f, a) => (
                format!("{}.{}()", self.wrap(a, Prec::Atom), f.name()),
                Prec::Atom,
            ),
            Node::Powi(a, n) => (
                format!("{}.powi({n})", self.wrap(a, Prec::Atom)),
                Prec::Atom,
            ),
            Node::Powf(a, b) => (
                format!("{}.powf({})", self.wrap(a, Prec::Atom), self.go(b).0),
                Prec::Atom,
            ),
            Node::Hypot(a, b) => (
                format!("{}.hypot({})", self.wrap(a, Prec::Atom), self.go(b).0),
                Prec::Atom,
            ),
        }
    }
}
