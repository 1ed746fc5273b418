//! The derivatives as text (`NAME::DERIVATIVES`): one `name = formula` per line, each formula
//! in Rust syntax with every shared node written out.

use std::collections::HashMap;

use crate::assemble::{Assembly, Block};
use crate::ir::{Affine, Derivatives, Func, Graph, Id, Model, Node, Prec, Var, constant_name};
use crate::readable::Poly;

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

/// The text of a Lagrangian with loops: `L` with its sums written `Σ_{i in a..b}`, then each
/// term's derivatives as the loop that adds them, `for i in a..b: ∂L/∂x[i + 1] += …`.
pub fn loops_text(model: &Model, a: &Assembly) -> String {
    let p = Printer {
        g: &model.graph,
        model,
    };
    // A force with loops: its components and Jacobian entries, without its virtual work.
    let force = model.attr == crate::ir::Attr::Force;
    let mut lines = if force {
        Vec::new()
    } else {
        vec![format!("L = {}", p.print(model.root))]
    };
    let head = |term: &crate::assemble::Term| -> String {
        term.loops
            .iter()
            .map(|&i| {
                let r = &p.g.ranges[i.0 as usize];
                format!(
                    "for {} in {}..{}: ",
                    r.name,
                    p.affine(r.start),
                    p.affine(r.end)
                )
            })
            .collect()
    };
    // The sums used as values, each computed first (`s0`, `s1`, …).
    for (k, terms) in a.sums.iter().enumerate() {
        for term in terms {
            lines.push(format!("{}s{k} += {}", head(term), p.print(term.value)));
        }
    }
    for term in &a.terms {
        let head = head(term);
        for &(u, id) in &term.gradient {
            let guard = p.guard(&[u]);
            let of = if force {
                String::new()
            } else {
                "∂L/∂".into()
            };
            lines.push(format!("{head}{guard}{of}{} += {}", p.var(u), p.print(id)));
        }
        for e in &term.hessian {
            let sym = if e.mirror {
                ", and at the mirrored entry"
            } else {
                ""
            };
            let _ = Block::Xx;
            let guard = p.guard(&[e.row, e.col]);
            let (row, col, id) = (p.var(e.row), p.var(e.col), p.print(e.id));
            lines.push(if force {
                format!("{head}{guard}∂{row}/∂{col} += {id}")
            } else {
                format!("{head}{guard}∂²L/∂{row}∂{col} += {id}{sym}")
            });
        }
    }
    lines.join("\n")
}

/// `label = formula` per line, for the nodes `lines` of the model's graph (a force's or a
/// constraint's components and derivatives, labelled by `vector.rs`).
pub fn lines_text(model: &Model, lines: &[(String, Id)]) -> String {
    let p = Printer {
        g: &model.graph,
        model,
    };
    let lines: Vec<String> = lines
        .iter()
        .map(|(label, id)| format!("{label} = {}", p.print(*id)))
        .collect();
    lines.join("\n")
}

/// The name of a state variable in the text: `x[i]`, or `x` for a model on `x: f64`.
pub fn state_name(model: &Model, v: Var) -> String {
    Printer {
        g: &model.graph,
        model,
    }
    .var(v)
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
        self.normal(id).print().0
    }

    /// The node in the normal form for reading ([`crate::readable`]).
    fn normal(&self, id: Id) -> Poly {
        let atom = |p: Poly| {
            let (s, prec) = p.print();
            if prec < Prec::Atom {
                format!("({s})")
            } else {
                s
            }
        };
        let plain = |p: Poly| p.print().0;
        match self.g.node(id) {
            Node::Num(bits) => Poly::number(f64::from_bits(bits)),
            Node::Var(v) => Poly::atom(self.var(v), Prec::Atom),
            Node::Add(a, b) => self.normal(a).add(self.normal(b)),
            Node::Sub(a, b) => self.normal(a).add(self.normal(b).scale(-1.0)),
            Node::Neg(a) => self.normal(a).scale(-1.0),
            Node::Mul(a, b) => self.normal(a).mul(self.normal(b)),
            Node::Div(a, b) => self.normal(a).div(self.normal(b)),
            Node::Powi(a, n) => self.normal(a).powi(n),
            Node::Call(Func::Recip, a) => self.normal(a).powi(-1),
            Node::Call(Func::Sign, a) => {
                Poly::atom(format!("sign({})", plain(self.normal(a))), Prec::Atom)
            }
            Node::Call(Func::Sech2, a) => {
                Poly::atom(format!("sech2({})", plain(self.normal(a))), Prec::Atom)
            }
            Node::Call(Func::OneMinusSquare, a) => {
                let a = self.normal(a);
                Poly::number(1.0).add(a.clone().mul(a).scale(-1.0))
            }
            Node::Call(f, a) => Poly::atom(
                format!("{}.{}()", atom(self.normal(a)), f.name()),
                Prec::Atom,
            ),
            Node::Select(op, l, r, a, b) => {
                let side = |x: Id| {
                    let (s, p) = self.normal(x).print();
                    if p < Prec::Add { format!("({s})") } else { s }
                };
                Poly::atom(
                    format!(
                        "if {} {} {} {{ {} }} else {{ {} }}",
                        side(l),
                        op.symbol(),
                        side(r),
                        plain(self.normal(a)),
                        plain(self.normal(b))
                    ),
                    Prec::If,
                )
            }
            Node::Sum(i, body) => {
                let r = &self.g.ranges[i.0 as usize];
                Poly::atom(
                    format!(
                        "Σ_{{{} in {}..{}}} {}",
                        r.name,
                        self.affine(r.start),
                        self.affine(r.end),
                        atom(self.normal(body))
                    ),
                    Prec::Neg,
                )
            }
            _ => {
                let (s, p) = self.go(id);
                Poly::atom(s, p)
            }
        }
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
            Node::Var(v) => (self.var(v), Prec::Atom),
            Node::Add(a, b) => bin(a, b, "+", Prec::Add),
            Node::Sub(a, b) => bin(a, b, "-", Prec::Add),
            Node::Mul(a, b) => bin(a, b, "*", Prec::Mul),
            Node::Div(a, b) => bin(a, b, "/", Prec::Mul),
            Node::Neg(a) => (format!("-{}", self.wrap(a, Prec::Atom)), Prec::Neg),
            Node::Call(Func::Sign, a) => (format!("sign({})", self.go(a).0), Prec::Atom),
            Node::Call(Func::Sech2, a) => (format!("sech2({})", self.go(a).0), Prec::Atom),
            Node::Call(Func::OneMinusSquare, a) => {
                let a = self.wrap(a, Prec::Atom);
                (format!("(1.0 - {a}) * (1.0 + {a})"), Prec::Mul)
            }
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
            Node::Atan2(a, b) => (
                format!("{}.atan2({})", self.wrap(a, Prec::Atom), self.go(b).0),
                Prec::Atom,
            ),
            Node::Select(op, l, r, a, b) => (
                format!(
                    "if {} {} {} {{ {} }} else {{ {} }}",
                    self.wrap(l, Prec::Add),
                    op.symbol(),
                    self.wrap(r, Prec::Add),
                    self.go(a).0,
                    self.go(b).0
                ),
                Prec::If,
            ),
            Node::Sum(i, body) => {
                let r = &self.g.ranges[i.0 as usize];
                (
                    format!(
                        "Σ_{{{} in {}..{}}} {}",
                        r.name,
                        self.affine(r.start),
                        self.affine(r.end),
                        self.wrap(body, Prec::Atom)
                    ),
                    Prec::Neg,
                )
            }
        }
    }

    /// `if i >= 1: ` for derivatives with respect to guarded components (added only where
    /// the guard holds), nothing for the others.
    fn guard(&self, vars: &[Var]) -> String {
        let mut conds: Vec<String> = Vec::new();
        for &v in vars {
            let (Var::XAt(c) | Var::VAt(c) | Var::FAt(c)) = v else {
                continue;
            };
            let (Some(i), false) = (c.at.var, c.guard.is_none()) else {
                continue;
            };
            let name = &self.g.ranges[i.0 as usize].name;
            let low = c.guard.low.map(|l| format!("{name} >= {}", self.affine(l)));
            let high = c.guard.high.map(|h| format!("{name} < {}", self.affine(h)));
            for cond in [low, high].into_iter().flatten() {
                if !conds.contains(&cond) {
                    conds.push(cond);
                }
            }
        }
        if conds.is_empty() {
            String::new()
        } else {
            format!("if {}: ", conds.join(" && "))
        }
    }

    /// The name of a variable.
    fn var(&self, v: Var) -> String {
        match v {
            Var::X(_) if self.model.scalar => "x".into(),
            Var::V(_) if self.model.scalar => "v".into(),
            Var::X(i) => format!("x[{i}]"),
            Var::V(i) => format!("v[{i}]"),
            Var::F(i) => format!("f[{i}]"),
            Var::XAt(c) | Var::VAt(c) | Var::FAt(c) => {
                let n = match v {
                    Var::XAt(_) => "x",
                    Var::VAt(_) => "v",
                    _ => "f",
                };
                let at = self.affine(c.at);
                if c.wrap {
                    format!("{n}[({at}) % {}]", self.dim())
                } else {
                    format!("{n}[{at}]")
                }
            }
            Var::T => "t".into(),
            Var::Const(k) => self.model.consts[k].to_string(),
            Var::Index(i) => format!("({} as f64)", self.g.ranges[i.0 as usize].name),
            Var::Dim => format!("({} as f64)", self.dim()),
            Var::Sym(s) => format!("({} as f64)", self.sym(s)),
            Var::Lifted(k) => format!("s{k}"),
            Var::Adjoint(k) => format!("∂L/∂s{k}"),
        }
    }

    /// A constant the macro does not know: `M`, `(N / 2)`.
    fn sym(&self, s: crate::ir::SymId) -> String {
        match &self.g.syms[s.0 as usize] {
            crate::ir::Sym::Named(name) => name.to_string(),
            crate::ir::Sym::Div(a, d) => {
                let a = self.affine(*a);
                if a.contains(' ') {
                    format!("(({a}) / {d})")
                } else {
                    format!("({a} / {d})")
                }
            }
        }
    }

    fn dim(&self) -> String {
        match (&self.model.dim_name, &self.model.runtime_dim) {
            (Some(p), _) => quote::ToTokens::to_token_stream(p).to_string(),
            (None, Some(n)) => n.to_string(),
            (None, None) => self.model.dim.to_string(),
        }
    }

    /// An index, `2 * i + N - 1`.
    fn affine(&self, a: Affine) -> String {
        let mut parts: Vec<(i64, String)> = Vec::new();
        if let Some(i) = a.var {
            parts.push((a.scale, self.g.ranges[i.0 as usize].name.clone()));
        }
        parts.push((a.n, self.dim()));
        if let Some(s) = a.sym {
            parts.push((a.k, self.sym(s)));
        }
        parts.push((a.c, String::new()));
        let mut out = String::new();
        for (k, what) in parts.into_iter().filter(|p| p.0 != 0) {
            let mag = k.unsigned_abs();
            let term = match (what.is_empty(), mag) {
                (true, _) => mag.to_string(),
                (false, 1) => what,
                (false, _) => format!("{mag} * {what}"),
            };
            if out.is_empty() {
                out = if k < 0 { format!("-{term}") } else { term };
            } else {
                out.push_str(if k < 0 { " - " } else { " + " });
                out.push_str(&term);
            }
        }
        if out.is_empty() { "0".into() } else { out }
    }
}
