//! Nodes as Rust tokens, following one [`Plan`]: the shared nodes become `let eK = …;`
//! temporaries in topological order, everything else is inlined into its single user.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use crate::cse::Plan;
use crate::ir::{Func, Graph, Id, Node, Prec, Var, constant_name};

/// `::varembed::__private::<name>`: the one path by which generated code reaches core.
pub fn private(name: &str) -> TokenStream {
    let name = Ident::new(name, Span::call_site());
    quote!(::varembed::__private::#name)
}

/// Renders the nodes of one [`Plan`] as Rust tokens.
pub struct Render<'a> {
    g: &'a Graph,
    plan: &'a Plan,
    leaf: &'a dyn Fn(Var) -> TokenStream,
}

impl<'a> Render<'a> {
    /// A renderer; `leaf` gives the tokens of each variable in this method.
    pub fn new(g: &'a Graph, plan: &'a Plan, leaf: &'a dyn Fn(Var) -> TokenStream) -> Self {
        Self { g, plan, leaf }
    }

    /// The `let` statements of the temporaries.
    pub fn temps(&self) -> TokenStream {
        let lets = self.plan.temps.iter().enumerate().map(|(k, &id)| {
            let name = temp_ident(k);
            let value = self.define(id).0;
            quote!(let #name = #value;)
        });
        quote!(#(#lets)*)
    }

    /// The `let` statements of the temporaries `ids` (a subset of the plan's, in its order).
    pub fn lets(&self, ids: &[Id]) -> TokenStream {
        let lets = ids.iter().map(|&id| {
            let name = temp_ident(self.plan.temp(id).expect("a temporary of the plan"));
            let value = self.define(id).0;
            quote!(let #name = #value;)
        });
        quote!(#(#lets)*)
    }

    /// The expression of a root (a temporary's name when it is one).
    pub fn root(&self, id: Id) -> TokenStream {
        self.operand(id).0
    }

    fn operand(&self, id: Id) -> (TokenStream, Prec) {
        match self.plan.temp(id) {
            Some(k) => {
                let name = temp_ident(k);
                (quote!(#name), Prec::Atom)
            }
            None => self.define(id),
        }
    }

    /// The expression of `id`, parenthesised if it binds less tightly than `need`.
    pub fn wrapped(&self, id: Id, need: Prec) -> TokenStream {
        let (ts, prec) = self.operand(id);
        if prec < need { quote!((#ts)) } else { ts }
    }

    /// A method receiver: a number needs a type suffix there (`2.0f64.powf(x)`).
    fn receiver(&self, id: Id) -> TokenStream {
        match (self.plan.temp(id), self.g.num_value(id)) {
            (None, Some(c)) => {
                let lit = number(c, true).0;
                quote!((#lit))
            }
            _ => self.wrapped(id, Prec::Atom),
        }
    }

    fn define(&self, id: Id) -> (TokenStream, Prec) {
        let binary = |a: Id, b: Id, op: TokenStream, p: Prec| {
            let (l, r) = (self.wrapped(a, p), self.wrapped(b, p.right_operand()));
            (quote!(#l #op #r), p)
        };
        match self.g.node(id) {
            Node::Num(bits) => number(f64::from_bits(bits), false),
            Node::Var(v) => ((self.leaf)(v), Prec::Atom),
            Node::Add(a, b) => binary(a, b, quote!(+), Prec::Add),
            Node::Sub(a, b) => binary(a, b, quote!(-), Prec::Add),
            Node::Mul(a, b) => binary(a, b, quote!(*), Prec::Mul),
            Node::Div(a, b) => binary(a, b, quote!(/), Prec::Mul),
            Node::Neg(a) => {
                let a = self.wrapped(a, Prec::Atom);
                (quote!(-#a), Prec::Neg)
            }
            Node::Call(Func::Sign, a) => {
                // `a` is a temporary or a leaf (see `cse.rs`), so it is read, not recomputed.
                let a = self.wrapped(a, Prec::Atom);
                (
                    quote!(if #a > 0.0 { 1.0 } else if #a < 0.0 { -1.0 } else { 0.0 }),
                    Prec::If,
                )
            }
            Node::Call(Func::Sech2, a) => {
                let f = private("sech2");
                let a = self.root(a);
                (quote!(#f(#a)), Prec::Atom)
            }
            Node::Call(Func::OneMinusSquare, a) => {
                // `a` is a temporary or a leaf (see `cse.rs`), so it is read, not recomputed.
                let a = self.wrapped(a, Prec::Atom);
                (quote!((1.0 - #a) * (1.0 + #a)), Prec::Mul)
            }
            Node::Call(f, a) => {
                let a = self.receiver(a);
                let m = Ident::new(f.name(), Span::call_site());
                (quote!(#a.#m()), Prec::Atom)
            }
            Node::Powi(a, n) => {
                let a = self.receiver(a);
                let n = Literal::i32_unsuffixed(n);
                (quote!(#a.powi(#n)), Prec::Atom)
            }
            Node::Powf(a, b) => {
                let (a, b) = (self.receiver(a), self.root(b));
                (quote!(#a.powf(#b)), Prec::Atom)
            }
            Node::Hypot(a, b) => {
                let (a, b) = (self.receiver(a), self.root(b));
                (quote!(#a.hypot(#b)), Prec::Atom)
            }
            Node::Atan2(a, b) => {
                let (a, b) = (self.receiver(a), self.root(b));
                (quote!(#a.atan2(#b)), Prec::Atom)
            }
            Node::Select(op, l, r, a, b) => {
                let (l, r) = (self.wrapped(l, Prec::Add), self.wrapped(r, Prec::Add));
                let (a, b) = (self.root(a), self.root(b));
                let op: TokenStream = op.symbol().parse().expect("an operator");
                (quote!(if #l #op #r { #a } else { #b }), Prec::If)
            }
            Node::Sum(..) => unreachable!("sums are emitted as loops by scatter.rs"),
        }
    }
}

fn temp_ident(k: usize) -> Ident {
    format_ident!("e{}", k)
}

/// A float as tokens; non-finite values (from folding, e.g. `1.0 / 0.0`) become the `f64`
/// constants, since a literal cannot express them.
fn number(c: f64, suffixed: bool) -> (TokenStream, Prec) {
    if c.is_nan() {
        return (quote!(f64::NAN), Prec::Atom);
    }
    if c.is_infinite() {
        return if c > 0.0 {
            (quote!(f64::INFINITY), Prec::Atom)
        } else {
            (quote!(-f64::INFINITY), Prec::Neg)
        };
    }
    if let Some(name) = constant_name(c.abs()) {
        let name = Ident::new(name, Span::call_site());
        return if c.is_sign_negative() {
            (quote!(-::core::f64::consts::#name), Prec::Neg)
        } else {
            (quote!(::core::f64::consts::#name), Prec::Atom)
        };
    }
    let lit = if suffixed {
        Literal::f64_suffixed(c.abs())
    } else {
        Literal::f64_unsuffixed(c.abs())
    };
    if c.is_sign_negative() {
        (quote!(-#lit), Prec::Neg)
    } else {
        (quote!(#lit), Prec::Atom)
    }
}
