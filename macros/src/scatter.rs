//! The emitting stage for a Lagrangian with loops: each method is the loop nest of the
//! [`Assembly`]'s terms, adding every term's value or derivatives into its outputs
//! (`value += …`, `fx[i + 1] += …`, `xx[(i, i + 1)] += …`). The code has one loop per loop of
//! the user's fn, whatever the dimension.
//!
//! Temporaries are scoped: a node is bound inside the innermost loop whose variable it reads
//! (none: before every loop), so a value that does not change along a loop is computed once
//! outside it, and a node used twice in one iteration is computed once per iteration.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::quote;

use crate::assemble::{Assembly, Block, Term};
use crate::cse::Plan;
use crate::indices::Affine;
use crate::ir::{Graph, Id, IndexVar, Model, Node, Var};
use crate::names::Names;
use crate::render::Render;

/// What an output adds to.
#[derive(Clone, Copy)]
pub enum Target {
    Value,
    Gradient(Var),
    Hessian(Block, Var, Var),
}

/// One loop of the nest (the root scope has no variable).
#[derive(Default)]
struct Scope {
    var: Option<IndexVar>,
    outputs: Vec<(Target, Id)>,
    children: Vec<usize>,
    parent: Option<usize>,
    depth: usize,
}

/// The loop nest of one method.
struct Nest {
    scopes: Vec<Scope>,
}

impl Nest {
    /// The nest of `terms`, with the outputs `pick` gives for each.
    fn new(terms: &[Term], pick: &dyn Fn(&Term) -> Vec<(Target, Id)>) -> Self {
        let mut scopes = vec![Scope::default()];
        let mut by_path: HashMap<Vec<IndexVar>, usize> = HashMap::new();
        for term in terms {
            let outputs = pick(term);
            if outputs.is_empty() {
                // No loop for a term that adds nothing here.
                continue;
            }
            let mut at = 0;
            for (k, &var) in term.loops.iter().enumerate() {
                let path = term.loops[..=k].to_vec();
                at = *by_path.entry(path).or_insert_with(|| {
                    scopes.push(Scope {
                        var: Some(var),
                        parent: Some(at),
                        depth: k + 1,
                        ..Scope::default()
                    });
                    let new = scopes.len() - 1;
                    scopes[at].children.push(new);
                    new
                });
            }
            scopes[at].outputs.extend(outputs);
        }
        Self { scopes }
    }

    /// The loop variables from the root to scope `s`.
    fn path(&self, mut s: usize) -> Vec<IndexVar> {
        let mut path = Vec::new();
        while let Some(v) = self.scopes[s].var {
            path.push(v);
            s = self.scopes[s].parent.expect("a loop has a parent");
        }
        path.reverse();
        path
    }

    /// The ancestor of `s` at `depth`.
    fn ancestor(&self, mut s: usize, depth: usize) -> usize {
        while self.scopes[s].depth > depth {
            s = self.scopes[s].parent.expect("deeper than the root");
        }
        s
    }

    /// The temporaries of each scope, and the plan binding all of them.
    fn plan(&self, g: &Graph, free: &[Vec<IndexVar>]) -> (Plan, Vec<Vec<Id>>) {
        let n = self.scopes.len();
        let mut extra: Vec<Vec<Id>> = vec![Vec::new(); n];
        let mut expanded_in: Vec<Vec<Id>> = vec![Vec::new(); n];
        let mut bound = std::collections::HashSet::new();
        // Children have larger numbers than their parents: deepest first.
        for s in (0..n).rev() {
            let path = self.path(s);
            let home = |id: Id| {
                free[id]
                    .iter()
                    .map(|v| {
                        path.iter()
                            .position(|p| p == v)
                            .map_or(path.len(), |k| k + 1)
                    })
                    .max()
                    .unwrap_or(0)
            };
            let depth = self.scopes[s].depth;
            let mut uses: HashMap<Id, usize> = HashMap::new();
            let mut stack: Vec<Id> = self.scopes[s].outputs.iter().map(|o| o.1).collect();
            for (_, id) in &self.scopes[s].outputs {
                *uses.entry(*id).or_default() += 1;
            }
            let forced: Vec<Id> = extra[s].clone();
            stack.extend(&forced);
            let mut expanded = std::collections::HashSet::new();
            while let Some(id) = stack.pop() {
                let node = g.node(id);
                if node.is_leaf() {
                    continue;
                }
                let h = home(id);
                if h < depth {
                    // Computed outside this loop, once.
                    let a = self.ancestor(s, h);
                    if !extra[a].contains(&id) {
                        extra[a].push(id);
                    }
                    continue;
                }
                if !expanded.insert(id) {
                    continue;
                }
                let twice = matches!(node, Node::Call(f, _) if f.reads_argument_twice());
                for c in node.children() {
                    *uses.entry(c).or_default() += if twice { 2 } else { 1 };
                    stack.push(c);
                }
            }
            bound.extend(
                expanded
                    .iter()
                    .copied()
                    .filter(|id| uses.get(id).copied().unwrap_or(0) >= 2 || forced.contains(id)),
            );
            expanded_in[s] = expanded.into_iter().collect();
        }
        // A node bound in one loop is written by its name everywhere, so every loop that
        // evaluates it binds it.
        let temps: Vec<Vec<Id>> = expanded_in
            .into_iter()
            .map(|mut ids| {
                ids.retain(|id| bound.contains(id));
                ids.sort_unstable();
                ids
            })
            .collect();
        let all = bound.into_iter().collect();
        (Plan::with_temps(g, all), temps)
    }
}

/// The value a term adds (a lifted sum's weighted term adds to the derivatives only).
pub fn value_out(t: &Term) -> Vec<(Target, Id)> {
    match t.weighted {
        None => vec![(Target::Value, t.value)],
        Some(_) => Vec::new(),
    }
}

/// What a term adds to the gradient with respect to the state.
pub fn gradient_out(t: &Term) -> Vec<(Target, Id)> {
    t.gradient
        .iter()
        .filter(|(u, _)| !matches!(u, Var::Lifted(_)))
        .map(|&(u, id)| (Target::Gradient(u), id))
        .collect()
}

/// What a term adds to the Hessian blocks of the state, the mirrored entries of the
/// symmetric blocks too.
pub fn hessian_out(t: &Term) -> Vec<(Target, Id)> {
    let mut out = Vec::new();
    for e in t
        .hessian
        .iter()
        .filter(|e| matches!(e.block, Block::Xx | Block::Xv | Block::Vv))
    {
        out.push((Target::Hessian(e.block, e.row, e.col), e.id));
        if e.mirror {
            out.push((Target::Hessian(e.block, e.col, e.row), e.id));
        }
    }
    out
}

/// How the Hessian entries are written: into dense matrices `xx[(i, j)] += e;` or as the
/// entries of core's `SparseHessian`, `out.xx.add(i, j, e);`.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Dense,
    Sparse,
}

/// The loop nests of one model, rendered method by method.
pub struct Loops<'a> {
    model: &'a Model,
    a: &'a Assembly,
    pub names: Names<'a>,
    free: Vec<Vec<IndexVar>>,
}

impl<'a> Loops<'a> {
    pub fn new(model: &'a Model, a: &'a Assembly) -> Self {
        Self {
            model,
            a,
            names: Names::new(model, a),
            free: crate::rewrite::free_vars(&model.graph),
        }
    }

    /// The assembly the nests are made of.
    pub fn assembly(&self) -> &Assembly {
        self.a
    }

    /// The loop nest adding the outputs `pick` gives for each term, and which of `value`,
    /// `fx`, `fv`, `xx`, `xv`, `vv` it writes.
    pub fn body(
        &self,
        pick: &dyn Fn(&Term) -> Vec<(Target, Id)>,
        style: Style,
    ) -> (TokenStream, [bool; 6]) {
        self.body_of(&self.a.terms, pick, style)
    }

    /// [`Loops::body`] over `terms` (a lifted sum's).
    pub fn body_of(
        &self,
        terms: &[Term],
        pick: &dyn Fn(&Term) -> Vec<(Target, Id)>,
        style: Style,
    ) -> (TokenStream, [bool; 6]) {
        let g = &self.model.graph;
        let nest = Nest::new(terms, pick);
        let (plan, temps) = nest.plan(g, &self.free);
        let leaf = |v: Var| self.names.leaf(&self.model.consts, v);
        let r = Render::new(g, &plan, &leaf);
        let mut used = [false; 6];
        let code = scope(&nest, 0, &temps, &r, &self.names, style, &mut used);
        (code, used)
    }
}

/// The largest `|i − j|` over the Hessian entries of every term, read off their index
/// expressions: a row and a column that differ by a constant (the same loop variable with the
/// same scale, or two literals) bound it; a periodic index (`% N`), two different loop
/// variables (a double sum), different scales or a difference naming `N` or another const
/// leave it unbounded: `None`.
pub fn bandwidth(a: &Assembly) -> Option<usize> {
    if a.dense_blocks.iter().any(|&d| d) {
        return None;
    }
    let state = |e: &&crate::assemble::Entry| matches!(e.block, Block::Xx | Block::Xv | Block::Vv);
    band(a.terms.iter().flat_map(|t| &t.hessian).filter(state))
}

/// [`bandwidth`] of a force with loops: over the entries of its Jacobian.
pub fn force_bandwidth(terms: &[Term]) -> Option<usize> {
    band(terms.iter().flat_map(|t| &t.hessian))
}

/// The largest `|row − col|` over `entries`, `None` when one is not a constant.
fn band<'e>(entries: impl Iterator<Item = &'e crate::assemble::Entry>) -> Option<usize> {
    let at = |u: Var| match u {
        Var::X(k) | Var::V(k) | Var::F(k) => Some(Affine::constant(k as i64)),
        Var::XAt(c) | Var::VAt(c) | Var::FAt(c) if !c.wrap => Some(c.at),
        _ => None,
    };
    let mut band = 0;
    for e in entries {
        let (row, col) = (at(e.row)?, at(e.col)?);
        let difference = row.add_scaled(col, -1)?.as_constant()?;
        band = band.max(difference.unsigned_abs() as usize);
    }
    Some(band)
}

/// The code of scope `s`: its temporaries, its outputs, then its inner loops.
fn scope(
    nest: &Nest,
    s: usize,
    temps: &[Vec<Id>],
    r: &Render<'_>,
    names: &Names<'_>,
    style: Style,
    used: &mut [bool; 6],
) -> TokenStream {
    let lets = r.lets(&temps[s]);
    let outputs: Vec<TokenStream> = nest.scopes[s]
        .outputs
        .iter()
        .map(|&(target, id)| {
            let e = r.root(id);
            // A guarded component's entry exists only where its guard holds.
            let guard = match target {
                Target::Value => None,
                Target::Gradient(u) => names.guard(&[u]),
                Target::Hessian(_, row, col) => names.guard(&[row, col]),
            };
            let add = match target {
                Target::Value => {
                    used[0] = true;
                    quote!(value += #e;)
                }
                Target::Gradient(u) => {
                    let i = names.position(u);
                    // A force's component goes where `∂L/∂x` would (`used[1]`).
                    let (k, name) = match u {
                        Var::X(_) | Var::XAt(_) => (1, quote!(fx)),
                        Var::F(_) | Var::FAt(_) => (1, quote!(f)),
                        _ => (2, quote!(fv)),
                    };
                    used[k] = true;
                    quote!(#name[#i] += #e;)
                }
                Target::Hessian(block, row, col) => {
                    let (i, j) = (names.position(row), names.position(col));
                    // A force's Jacobian blocks go where `xx` and `xv` would (`used[3]`, `[4]`),
                    // into `out.x`, `out.v` of a `SparseForceJacobian`.
                    let (k, name, field) = match block {
                        Block::Xx => (3, quote!(xx), quote!(xx)),
                        Block::Xv => (4, quote!(xv), quote!(xv)),
                        Block::Vv => (5, quote!(vv), quote!(vv)),
                        Block::Fx => (3, quote!(jx), quote!(x)),
                        Block::Fv => (4, quote!(jv), quote!(v)),
                        Block::Zs | Block::Ss => {
                            unreachable!("the lifted sums' blocks are picked into vectors")
                        }
                    };
                    used[k] = true;
                    match style {
                        Style::Dense => quote!(#name[(#i, #j)] += #e;),
                        Style::Sparse => quote!(out.#field.add(#i, #j, #e);),
                    }
                }
            };
            match guard {
                Some(g) => quote!(if #g { #add }),
                None => add,
            }
        })
        .collect();
    let children: Vec<TokenStream> = nest.scopes[s]
        .children
        .iter()
        .map(|&c| scope(nest, c, temps, r, names, style, used))
        .collect();
    let inner = quote!(#lets #(#outputs)* #(#children)*);
    match nest.scopes[s].var {
        None => inner,
        Some(i) => {
            let var = &names.vars[i.0 as usize];
            let range = names.range(i);
            quote!(for #var in #range { #inner })
        }
    }
}
