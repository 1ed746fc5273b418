//! Code generation: the struct, the `Lagrangian<D>` impl with `value`, `gradient`, `hessian`
//! and the fused step kernels, and the derivatives as text.
//!
//! Each method evaluates one [`Plan`]: the shared nodes become `let eK = …;` temporaries in
//! topological order, everything else is inlined into its single user.

use std::collections::HashMap;

use proc_macro2::{Ident, Literal, Span, TokenStream, TokenTree};
use quote::{format_ident, quote};

use crate::cse::Plan;
use crate::diff::Derivatives;
use crate::expr::{Func, Graph, Id, Node, Var};
use crate::parse::Model;

/// The four classical step kinds, in `StepKind` order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    VariationalBackward,
    VariationalForward,
    DirectBackward,
    DirectForward,
}

impl Kind {
    /// All kinds.
    pub const ALL: [Kind; 4] = [
        Kind::VariationalBackward,
        Kind::VariationalForward,
        Kind::DirectBackward,
        Kind::DirectForward,
    ];

    fn path(self) -> TokenStream {
        let name = match self {
            Kind::VariationalBackward => "VariationalBackward",
            Kind::VariationalForward => "VariationalForward",
            Kind::DirectBackward => "DirectBackward",
            Kind::DirectForward => "DirectForward",
        };
        let name = Ident::new(name, Span::call_site());
        quote!(::varembed::StepKind::#name)
    }

    /// The equation for `y` is evaluated at `@right(b, y)` (position `y`, time `t_y`).
    fn right(self) -> bool {
        matches!(self, Kind::VariationalBackward | Kind::DirectBackward)
    }
}

/// Everything the generated code needs, as nodes of the model's graph.
pub struct Lowered {
    /// The derivatives of `L`.
    pub d: Derivatives,
    /// Per kind: the momentum `π` from `(a, b)` (`H` is the step size).
    pub momentum: Vec<Vec<Id>>,
    /// Per kind: residual (`D` entries) followed by the Jacobian (row-major) of the step
    /// equation, in terms of the evaluation point's `X`, `V`, `T`, `H` and `M`.
    pub residual: Vec<Vec<Id>>,
    /// Per kind: whether the step is affine in `y` with a constant Jacobian.
    pub affine: Vec<bool>,
    /// Per affine kind: how its closed-form update is computed.
    pub explicit: Vec<Option<Explicit>>,
}

/// The closed-form update `y = b − J⁻¹ G(b)` of an affine step (`G`, `J` at `y = b`, i.e. with
/// `V = 0`). `J` has the form `M/h` with `M = L_vv + h K` (`K` the other blocks of the row of
/// the module docs of `varembed::lagrangian`), so `J⁻¹ = h M⁻¹`: written that way the `1/h`
/// cancels symbolically and no division is left on the step's critical path.
pub enum Explicit {
    /// `dy = (h M⁻¹) G(b)` entry by entry (`M⁻¹` folded when `M` is a constant matrix, `h/m`
    /// when `d = 1`). With `check`, a non-finite `dy` gives `None` (the scalar case of
    /// `solve_small`: `m = 0` shows as an infinite or NaN `dy`).
    ClosedForm { dy: Vec<Id>, check: bool },
    /// `G(b)` (`D` entries) and `J` (row-major), solved at run time by `solve_small`: `M`
    /// depends on the model's constants or on `b`, and `d > 1`.
    Solve(Vec<Id>),
    /// `M` is a constant singular matrix (by the `solve_small` criterion): no closed form, so
    /// the solver runs Newton, which reports the singular Jacobian.
    Singular,
}

/// Ratio below which a pivot of a constant step matrix counts as zero: the criterion of
/// `varembed::solve::linear::solve_small` (relative to the largest entry, same pivot order), so
/// a matrix is singular here when `J = M/h` would be singular there, up to the rounding of the
/// division by `h`.
const SINGULAR_RATIO: f64 = 1e-14;

/// The inverse of the row-major `dim × dim` matrix `m` by Gauss–Jordan elimination with partial
/// pivoting; `None` when it is not finite or singular by [`SINGULAR_RATIO`].
pub fn invert(m: &[f64], dim: usize) -> Option<Vec<f64>> {
    let norm = m.iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
    if m.iter().any(|x| !x.is_finite()) || norm == 0.0 {
        return None;
    }
    let mut a = m.to_vec();
    let mut inv: Vec<f64> = (0..dim * dim)
        .map(|k| if k / dim == k % dim { 1.0 } else { 0.0 })
        .collect();
    for col in 0..dim {
        // The first row of largest magnitude, as in `solve_small`.
        let piv = (col..dim).fold(col, |best, r| {
            if a[r * dim + col].abs() > a[best * dim + col].abs() {
                r
            } else {
                best
            }
        });
        if a[piv * dim + col].abs() <= SINGULAR_RATIO * norm {
            return None;
        }
        for c in 0..dim {
            a.swap(piv * dim + c, col * dim + c);
            inv.swap(piv * dim + c, col * dim + c);
        }
        let p = a[col * dim + col];
        for c in 0..dim {
            a[col * dim + c] /= p;
            inv[col * dim + c] /= p;
        }
        for r in (0..dim).filter(|&r| r != col) {
            let l = a[r * dim + col];
            for c in 0..dim {
                a[r * dim + c] -= l * a[col * dim + c];
                inv[r * dim + c] -= l * inv[col * dim + c];
            }
        }
    }
    Some(inv)
}

/// Builds the derivatives and the step-kernel expressions.
pub fn lower(model: &mut Model) -> Lowered {
    let dim = model.dim;
    let g = &mut model.graph;
    let d = Derivatives::new(g, model.root, dim);
    let h = g.var(Var::H);
    let mut momentum = Vec::new();
    let mut residual = Vec::new();
    for kind in Kind::ALL {
        // (p + h f) for VariationalBackward and DirectForward, p otherwise.
        let mom = (0..dim)
            .map(|i| match kind {
                Kind::VariationalBackward | Kind::DirectForward => {
                    let fh = g.mul(d.fx[i], h);
                    g.add(d.fv[i], fh)
                }
                _ => d.fv[i],
            })
            .collect();
        momentum.push(mom);
        // Same operation order as the trait's generic kernels.
        let mut out = Vec::new();
        for i in 0..dim {
            let m = g.var(Var::M(i));
            let lhs = match kind {
                Kind::VariationalBackward | Kind::DirectForward => d.fv[i],
                _ => {
                    let fh = g.mul(d.fx[i], h);
                    g.sub(d.fv[i], fh)
                }
            };
            out.push(g.sub(lhs, m));
        }
        for i in 0..dim {
            for j in 0..dim {
                let (xx, xv, vv, vx) = (
                    d.xx[i * dim + j],
                    d.xv[i * dim + j],
                    d.vv[i * dim + j],
                    d.xv[j * dim + i],
                );
                let vvh = g.div(vv, h);
                let jac = match kind {
                    Kind::VariationalBackward => g.add(vx, vvh),
                    Kind::VariationalForward => g.sub(vvh, xv),
                    Kind::DirectBackward => {
                        let s = g.add(vx, vvh);
                        let xxh = g.mul(xx, h);
                        let s = g.sub(s, xxh);
                        g.sub(s, xv)
                    }
                    Kind::DirectForward => vvh,
                };
                out.push(jac);
            }
        }
        residual.push(out);
    }

    // Affinity, decided on the second-derivative blocks (DESIGN "Solving"): the Jacobian of
    // the step equation must not depend on y, through the position (when the equation is
    // evaluated at `y`) or the velocity `(y − b)/h` (always).
    let dep_x = g.depends(|v| matches!(v, Var::X(_)));
    let dep_v = g.depends(|v| matches!(v, Var::V(_)));
    let free_of = |ids: &[Id], x: bool| ids.iter().all(|&i| !(dep_v[i] || (x && dep_x[i])));
    let affine: Vec<bool> = Kind::ALL
        .iter()
        .map(|kind| match kind {
            Kind::VariationalBackward => free_of(&d.xv, true) && free_of(&d.vv, true),
            Kind::VariationalForward => free_of(&d.xv, false) && free_of(&d.vv, false),
            Kind::DirectBackward => {
                free_of(&d.xx, true) && free_of(&d.xv, true) && free_of(&d.vv, true)
            }
            Kind::DirectForward => free_of(&d.vv, false),
        })
        .collect();

    let mut explicit = Vec::new();
    for (k, roots) in residual.iter().enumerate() {
        if !affine[k] {
            explicit.push(None);
            continue;
        }
        let mut memo = HashMap::new();
        let zero_v = |v: Var| matches!(v, Var::V(_)).then_some(0.0);
        let at_b: Vec<Id> = roots
            .iter()
            .map(|&r| g.substitute(r, &zero_v, &mut memo))
            .collect();
        // M = h J, from the blocks (the Jacobian rows of `residual` above, times h).
        let m: Vec<Id> = (0..dim * dim)
            .map(|e| {
                let (i, j) = (e / dim, e % dim);
                let (xx, xv, vv, vx) = (
                    d.xx[i * dim + j],
                    d.xv[i * dim + j],
                    d.vv[i * dim + j],
                    d.xv[j * dim + i],
                );
                let rest = match Kind::ALL[k] {
                    Kind::VariationalBackward => vx,
                    Kind::VariationalForward => g.neg(xv),
                    Kind::DirectBackward => {
                        let xxh = g.mul(xx, h);
                        let s = g.sub(vx, xxh);
                        g.sub(s, xv)
                    }
                    Kind::DirectForward => g.num(0.0),
                };
                let h_rest = g.mul(h, rest);
                let entry = g.add(vv, h_rest);
                g.substitute(entry, &zero_v, &mut memo)
            })
            .collect();
        let constant: Option<Vec<f64>> = m.iter().map(|&e| g.num_value(e)).collect();
        let dy = |g: &mut Graph, factor: &dyn Fn(&mut Graph, usize, usize) -> Id| -> Vec<Id> {
            (0..dim)
                .map(|i| {
                    (0..dim).fold(g.num(0.0), |acc, j| {
                        let f = factor(g, i, j);
                        let term = g.mul(f, at_b[j]);
                        g.add(acc, term)
                    })
                })
                .collect()
        };
        let update = match constant {
            Some(values) => match invert(&values, dim) {
                // h M⁻¹ is loop-invariant: the step is a product with the residual.
                Some(inv) => Explicit::ClosedForm {
                    dy: dy(g, &|g, i, j| {
                        let c = g.num(inv[i * dim + j]);
                        g.mul(h, c)
                    }),
                    check: dim == 1,
                },
                None => Explicit::Singular,
            },
            None if dim == 1 => Explicit::ClosedForm {
                dy: dy(g, &|g, _, _| g.div(h, m[0])),
                check: true,
            },
            None => Explicit::Solve(at_b),
        };
        explicit.push(Some(update));
    }
    Lowered {
        d,
        momentum,
        residual,
        affine,
        explicit,
    }
}

const P_IF: u8 = 0;
const P_ADD: u8 = 1;
const P_MUL: u8 = 2;
const P_NEG: u8 = 3;
const P_MAX: u8 = 4;

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

    /// The expression of a root (a temporary's name when it is one).
    pub fn root(&self, id: Id) -> TokenStream {
        self.operand(id).0
    }

    fn operand(&self, id: Id) -> (TokenStream, u8) {
        match self.plan.temp(id) {
            Some(k) => {
                let name = temp_ident(k);
                (quote!(#name), P_MAX)
            }
            None => self.define(id),
        }
    }

    fn wrapped(&self, id: Id, need: u8) -> TokenStream {
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
            _ => self.wrapped(id, P_MAX),
        }
    }

    fn define(&self, id: Id) -> (TokenStream, u8) {
        let binary = |a: Id, b: Id, op: TokenStream, p: u8| {
            let (l, r) = (self.wrapped(a, p), self.wrapped(b, p + 1));
            (quote!(#l #op #r), p)
        };
        match self.g.node(id) {
            Node::Num(bits) => number(f64::from_bits(bits), false),
            Node::Var(v) => ((self.leaf)(v), P_MAX),
            Node::Add(a, b) => binary(a, b, quote!(+), P_ADD),
            Node::Sub(a, b) => binary(a, b, quote!(-), P_ADD),
            Node::Mul(a, b) => binary(a, b, quote!(*), P_MUL),
            Node::Div(a, b) => binary(a, b, quote!(/), P_MUL),
            Node::Neg(a) => {
                let a = self.wrapped(a, P_MAX);
                (quote!(-#a), P_NEG)
            }
            Node::Call(Func::Sign, a) => {
                // `a` is a temporary or a leaf (see `cse.rs`), so it is read, not recomputed.
                let a = self.wrapped(a, P_MAX);
                (
                    quote!(if #a > 0.0 { 1.0 } else if #a < 0.0 { -1.0 } else { 0.0 }),
                    P_IF,
                )
            }
            Node::Call(f, a) => {
                let a = self.receiver(a);
                let m = Ident::new(f.name(), Span::call_site());
                (quote!(#a.#m()), P_MAX)
            }
            Node::Powi(a, n) => {
                let a = self.receiver(a);
                let n = Literal::i32_unsuffixed(n);
                (quote!(#a.powi(#n)), P_MAX)
            }
            Node::Powf(a, b) => {
                let (a, b) = (self.receiver(a), self.root(b));
                (quote!(#a.powf(#b)), P_MAX)
            }
            Node::Hypot(a, b) => {
                let (a, b) = (self.receiver(a), self.root(b));
                (quote!(#a.hypot(#b)), P_MAX)
            }
        }
    }
}

fn temp_ident(k: usize) -> Ident {
    format_ident!("e{}", k)
}

/// A float as tokens; non-finite values (from folding, e.g. `1.0 / 0.0`) become the `f64`
/// constants, since a literal cannot express them.
fn number(c: f64, suffixed: bool) -> (TokenStream, u8) {
    if c.is_nan() {
        return (quote!(f64::NAN), P_MAX);
    }
    if c.is_infinite() {
        return if c > 0.0 {
            (quote!(f64::INFINITY), P_MAX)
        } else {
            (quote!(-f64::INFINITY), P_NEG)
        };
    }
    if let Some(name) = named_constant(c.abs()) {
        let name = Ident::new(name, Span::call_site());
        return if c.is_sign_negative() {
            (quote!(-::core::f64::consts::#name), P_NEG)
        } else {
            (quote!(::core::f64::consts::#name), P_MAX)
        };
    }
    let lit = if suffixed {
        Literal::f64_suffixed(c.abs())
    } else {
        Literal::f64_unsuffixed(c.abs())
    };
    if c.is_sign_negative() {
        (quote!(-#lit), P_NEG)
    } else {
        (quote!(#lit), P_MAX)
    }
}

/// The `std::f64::consts` name of `c`, if `c` is one of them exactly: emitted by name, which
/// reads better than 17 digits (and is what clippy's `approx_constant` asks of the user's
/// crate, where this code lands).
pub fn named_constant(c: f64) -> Option<&'static str> {
    use std::f64::consts::*;
    const TABLE: [(f64, &str); 19] = [
        (PI, "PI"),
        (TAU, "TAU"),
        (E, "E"),
        (SQRT_2, "SQRT_2"),
        (FRAC_1_SQRT_2, "FRAC_1_SQRT_2"),
        (LN_2, "LN_2"),
        (LN_10, "LN_10"),
        (LOG2_E, "LOG2_E"),
        (LOG10_E, "LOG10_E"),
        (LOG2_10, "LOG2_10"),
        (LOG10_2, "LOG10_2"),
        (FRAC_PI_2, "FRAC_PI_2"),
        (FRAC_PI_3, "FRAC_PI_3"),
        (FRAC_PI_4, "FRAC_PI_4"),
        (FRAC_PI_6, "FRAC_PI_6"),
        (FRAC_PI_8, "FRAC_PI_8"),
        (FRAC_1_PI, "FRAC_1_PI"),
        (FRAC_2_PI, "FRAC_2_PI"),
        (FRAC_2_SQRT_PI, "FRAC_2_SQRT_PI"),
    ];
    TABLE
        .iter()
        .find(|(v, _)| v.to_bits() == c.to_bits())
        .map(|&(_, name)| name)
}

fn index(i: usize) -> Literal {
    Literal::usize_unsuffixed(i)
}

/// Whether `ts` mentions the identifier `name` (to name unused parameters `_name`).
fn mentions(ts: &TokenStream, name: &str) -> bool {
    ts.clone().into_iter().any(|tt| match tt {
        TokenTree::Ident(i) => i == name,
        TokenTree::Group(g) => mentions(&g.stream(), name),
        _ => false,
    })
}

/// `name` if the body uses it, `_name` otherwise.
fn param(body: &TokenStream, name: &str) -> Ident {
    if mentions(body, name) {
        Ident::new(name, Span::call_site())
    } else {
        format_ident!("_{}", name)
    }
}

/// The variables reachable from `roots`.
fn vars_used(g: &Graph, roots: &[Id]) -> Vec<Var> {
    let mut vars: Vec<Var> = g
        .reachable(roots)
        .into_iter()
        .filter_map(|id| match g.node(id) {
            Node::Var(v) => Some(v),
            _ => None,
        })
        .collect();
    vars.sort();
    vars
}

/// Leaves of `value`, `gradient`, `hessian`: the method's own arguments and the fields.
fn point_leaf(consts: &[Ident]) -> impl Fn(Var) -> TokenStream + '_ {
    move |v| match v {
        Var::X(i) => {
            let i = index(i);
            quote!(x[#i])
        }
        Var::V(i) => {
            let i = index(i);
            quote!(v[#i])
        }
        Var::T => quote!(t),
        Var::Const(k) => {
            let c = &consts[k];
            quote!(self.#c)
        }
        // Not reachable from `L` and its derivatives; rendered anyway so that this is total.
        Var::H => quote!(times.h),
        Var::M(i) => {
            let i = index(i);
            quote!(momentum[#i])
        }
    }
}

/// Leaves of a step kernel evaluated at position `x`, time `times.<t>`, with the velocity in
/// the locals `v0, v1, …`.
fn step_leaf<'a>(
    consts: &'a [Ident],
    x: &'a Ident,
    t: &'a Ident,
) -> impl Fn(Var) -> TokenStream + 'a {
    move |v| match v {
        Var::X(i) => {
            let i = index(i);
            quote!(#x[#i])
        }
        Var::V(i) => {
            let name = format_ident!("v{}", i);
            quote!(#name)
        }
        Var::T => quote!(times.#t),
        Var::Const(k) => {
            let c = &consts[k];
            quote!(self.#c)
        }
        Var::H => quote!(h),
        Var::M(i) => {
            let i = index(i);
            quote!(momentum[#i])
        }
    }
}

/// `let h = times.h;` when the roots use `h`, and `let inv_h = times.inv_h;
/// let v0 = (new[0] - old[0]) * inv_h; …` for the velocities they use (a product: a division
/// by `h` would sit on the critical path of every step).
fn velocity_lets(g: &Graph, roots: &[Id], old: &Ident, new: &Ident) -> TokenStream {
    let vars = vars_used(g, roots);
    let vs: Vec<usize> = vars
        .iter()
        .filter_map(|v| match v {
            Var::V(i) => Some(*i),
            _ => None,
        })
        .collect();
    let h = vars.contains(&Var::H).then(|| quote!(let h = times.h;));
    let inv_h = (!vs.is_empty()).then(|| quote!(let inv_h = times.inv_h;));
    let lets = vs.iter().map(|&i| {
        let name = format_ident!("v{}", i);
        let i = index(i);
        quote!(let #name = (#new[#i] - #old[#i]) * inv_h;)
    });
    quote!(#h #inv_h #(#lets)*)
}

/// A `Vector<D>` from its entries.
fn vector(dim: usize, entries: &[TokenStream]) -> TokenStream {
    let dim = index(dim);
    quote!(::varembed::Vector::<#dim>::from([#(#entries),*]))
}

/// `let [mut] name = Matrix::zeros(); name[(i, j)] = …;` for the nonzero entries.
fn matrix(g: &Graph, r: &Render<'_>, name: &Ident, dim: usize, entries: &[Id]) -> TokenStream {
    let d = index(dim);
    let sets: Vec<TokenStream> = entries
        .iter()
        .enumerate()
        .filter(|&(_, &id)| !g.is_num(id, 0.0))
        .map(|(k, &id)| {
            let (i, j) = (index(k / dim), index(k % dim));
            let e = r.root(id);
            quote!(#name[(#i, #j)] = #e;)
        })
        .collect();
    if sets.is_empty() {
        quote!(let #name = ::varembed::Matrix::<#d>::zeros();)
    } else {
        quote!(let mut #name = ::varembed::Matrix::<#d>::zeros(); #(#sets)*)
    }
}

/// The hessian's roots, one per emitted (nonzero) entry: an off-diagonal entry of a symmetric
/// block is the same node twice, so the plan binds it to a temporary.
pub fn hessian_roots(g: &Graph, d: &Derivatives) -> Vec<Id> {
    [&d.xx, &d.xv, &d.vv]
        .into_iter()
        .flatten()
        .copied()
        .filter(|&id| !g.is_num(id, 0.0))
        .collect()
}

/// Emits the struct, its impls and the user's fn.
pub fn emit(model: &mut Model) -> TokenStream {
    let lowered = lower(model);
    let model = &*model;
    let g = &model.graph;
    let dim = model.dim;
    let d = &lowered.d;
    let dlit = index(dim);
    let consts = &model.consts;
    let name = &model.struct_name;
    let vis = &model.vis;
    let item = &model.item;
    let fn_name = &item.sig.ident;

    // The struct.
    let docs = &model.docs;
    let generated_doc = format!(
        "Lagrangian generated by `#[lagrangian]` from the fn [`{fn_name}`]; its derivatives are \
         listed in [`{name}::DERIVATIVES`]."
    );
    let fields = consts.iter().map(|c| {
        let doc = format!("Model constant `{c}` of [`{fn_name}`].");
        quote!(#[doc = #doc] pub #c: f64)
    });
    let body = if consts.is_empty() {
        quote!(;)
    } else {
        quote!({ #(#fields),* })
    };
    let strukt = quote! {
        #(#docs)*
        #[doc = ""]
        #[doc = #generated_doc]
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #vis struct #name #body
    };

    let leaf = point_leaf(consts);
    let vec_ty = quote!(::varembed::Vector<#dlit>);

    // value
    let plan = Plan::new(g, &[model.root]);
    let r = Render::new(g, &plan, &leaf);
    let (temps, out) = (r.temps(), r.root(model.root));
    let value_body = quote!(#temps #out);
    let value = method_point(quote!(value), quote!(f64), value_body, &vec_ty);

    // gradient
    let roots: Vec<Id> = d.fx.iter().chain(&d.fv).copied().collect();
    let plan = Plan::new(g, &roots);
    let r = Render::new(g, &plan, &leaf);
    let temps = r.temps();
    let fx: Vec<TokenStream> = d.fx.iter().map(|&i| r.root(i)).collect();
    let fv: Vec<TokenStream> = d.fv.iter().map(|&i| r.root(i)).collect();
    let (fx, fv) = (vector(dim, &fx), vector(dim, &fv));
    let gradient = method_point(
        quote!(gradient),
        quote!((#vec_ty, #vec_ty)),
        quote!(#temps (#fx, #fv)),
        &vec_ty,
    );

    // hessian
    let roots = hessian_roots(g, d);
    let plan = Plan::new(g, &roots);
    let r = Render::new(g, &plan, &leaf);
    let temps = r.temps();
    let (xx, xv, vv) = (
        Ident::new("xx", Span::call_site()),
        Ident::new("xv", Span::call_site()),
        Ident::new("vv", Span::call_site()),
    );
    let mxx = matrix(g, &r, &xx, dim, &d.xx);
    let mxv = matrix(g, &r, &xv, dim, &d.xv);
    let mvv = matrix(g, &r, &vv, dim, &d.vv);
    let hessian = method_point(
        quote!(hessian),
        quote!(::varembed::Hessian<#dlit>),
        quote!(#temps #mxx #mxv #mvv ::varembed::Hessian { xx, xv, vv }),
        &vec_ty,
    );

    let kernels = step_kernels(model, &lowered);
    let text = derivatives_text(model, d);

    quote! {
        // The fn stays callable, but the generated struct is the usual entry point: a program
        // that only uses the struct has not made a mistake worth a `dead_code` warning.
        #[allow(dead_code)]
        #item

        #strukt

        impl #name {
            /// The derivatives of `L` computed by `#[lagrangian]`, one per line (zero entries
            /// omitted; symmetric blocks listed once, `i ≤ j`).
            pub const DERIVATIVES: &str = #text;
        }

        impl ::varembed::Lagrangian<#dlit> for #name {
            #value
            #gradient
            #hessian
            #kernels
        }
    }
}

/// A method on a point `(x, v, t)`, with unused parameters named `_x` etc.
fn method_point(
    name: TokenStream,
    ret: TokenStream,
    body: TokenStream,
    vec_ty: &TokenStream,
) -> TokenStream {
    let (x, v, t) = (param(&body, "x"), param(&body, "v"), param(&body, "t"));
    quote! {
        #[inline]
        fn #name(&self, #x: &#vec_ty, #v: &#vec_ty, #t: f64) -> #ret {
            #body
        }
    }
}

fn step_kernels(model: &Model, low: &Lowered) -> TokenStream {
    let g = &model.graph;
    let dim = model.dim;
    let dlit = index(dim);
    let consts = &model.consts;
    let vec_ty = quote!(::varembed::Vector<#dlit>);
    let mat_ty = quote!(::varembed::Matrix<#dlit>);
    let id = |s: &str| Ident::new(s, Span::call_site());
    let (a, b, y) = (id("a"), id("b"), id("y"));
    let (t_a, t_b, t_y) = (id("t_a"), id("t_b"), id("t_y"));

    // step_momentum: from (a, b); @right = (b, t_b), @left = (a, t_a).
    let arms = Kind::ALL.iter().enumerate().map(|(k, kind)| {
        let roots = &low.momentum[k];
        let (x, t) = if matches!(kind, Kind::VariationalBackward | Kind::DirectBackward) {
            (&b, &t_b)
        } else {
            (&a, &t_a)
        };
        let leaf = step_leaf(consts, x, t);
        let plan = Plan::new(g, roots);
        let r = Render::new(g, &plan, &leaf);
        let lets = velocity_lets(g, roots, &a, &b);
        let temps = r.temps();
        let entries: Vec<TokenStream> = roots.iter().map(|&i| r.root(i)).collect();
        let out = vector(dim, &entries);
        let path = kind.path();
        quote!(#path => { #lets #temps #out })
    });
    let body = quote!(match kind { #(#arms)* });
    let (pa, pb, pt) = (param(&body, "a"), param(&body, "b"), param(&body, "times"));
    let momentum = quote! {
        #[inline]
        fn step_momentum(
            &self,
            kind: ::varembed::StepKind,
            #pa: &#vec_ty,
            #pb: &#vec_ty,
            #pt: &::varembed::StepTimes,
        ) -> #vec_ty {
            #body
        }
    };

    // step_residual: from (b, y); @right = (y, t_y), @left = (b, t_b).
    let jac = id("jac");
    let arms = Kind::ALL.iter().enumerate().map(|(k, kind)| {
        let roots = &low.residual[k];
        let (x, t) = if kind.right() { (&y, &t_y) } else { (&b, &t_b) };
        let leaf = step_leaf(consts, x, t);
        let plan = Plan::new(g, roots);
        let r = Render::new(g, &plan, &leaf);
        let lets = velocity_lets(g, roots, &b, &y);
        let temps = r.temps();
        let res: Vec<TokenStream> = roots[..dim].iter().map(|&i| r.root(i)).collect();
        let res = vector(dim, &res);
        let m = matrix(g, &r, &jac, dim, &roots[dim..]);
        let path = kind.path();
        quote!(#path => { #lets #temps #m (#res, #jac) })
    });
    let body = quote!(match kind { #(#arms)* });
    let (pb, py, pm, pt) = (
        param(&body, "b"),
        param(&body, "y"),
        param(&body, "momentum"),
        param(&body, "times"),
    );
    let residual = quote! {
        #[inline]
        fn step_residual(
            &self,
            kind: ::varembed::StepKind,
            #pb: &#vec_ty,
            #py: &#vec_ty,
            #pm: &#vec_ty,
            #pt: &::varembed::StepTimes,
        ) -> (#vec_ty, #mat_ty) {
            #body
        }
    };

    // step_is_affine and step_explicit, only when some kind is affine.
    let affine_kinds: Vec<TokenStream> = Kind::ALL
        .iter()
        .zip(&low.affine)
        .filter(|&(_, &aff)| aff)
        .map(|(k, _)| k.path())
        .collect();
    if affine_kinds.is_empty() {
        return quote!(#momentum #residual);
    }
    let is_affine = if affine_kinds.len() == Kind::ALL.len() {
        quote! {
            #[inline]
            fn step_is_affine(&self, _kind: ::varembed::StepKind) -> bool {
                true
            }
        }
    } else {
        quote! {
            #[inline]
            fn step_is_affine(&self, kind: ::varembed::StepKind) -> bool {
                matches!(kind, #(#affine_kinds)|*)
            }
        }
    };

    // step_explicit: y = b − J⁻¹ G(b), with G and J evaluated at y = b (so v = 0).
    let arms = Kind::ALL.iter().enumerate().map(|(k, kind)| {
        let path = kind.path();
        let roots = match &low.explicit[k] {
            None | Some(Explicit::Singular) => {
                return quote!(#path => ::core::option::Option::None,);
            }
            Some(Explicit::ClosedForm { dy, .. }) => dy,
            Some(Explicit::Solve(at_b)) => at_b,
        };
        let t = if kind.right() { &t_y } else { &t_b };
        let leaf = step_leaf(consts, &b, t);
        let plan = Plan::new(g, roots);
        let r = Render::new(g, &plan, &leaf);
        let lets = velocity_lets(g, roots, &b, &b);
        let temps = r.temps();
        match &low.explicit[k] {
            Some(Explicit::ClosedForm { check, .. }) => {
                let names: Vec<Ident> = (0..dim).map(|i| format_ident!("dy{}", i)).collect();
                let values = roots.iter().map(|&i| r.root(i));
                let ys: Vec<TokenStream> = names
                    .iter()
                    .enumerate()
                    .map(|(i, dy)| {
                        let i = index(i);
                        quote!(#b[#i] - #dy)
                    })
                    .collect();
                let some = vector(dim, &ys);
                let some = quote!(::core::option::Option::Some(#some));
                let out = if *check {
                    quote! {
                        if #(#names.is_finite())&&* {
                            #some
                        } else {
                            ::core::option::Option::None
                        }
                    }
                } else {
                    some
                };
                quote!(#path => {
                    #lets #temps
                    #(let #names: f64 = #values;)*
                    #out
                })
            }
            _ => {
                let res: Vec<TokenStream> = roots[..dim].iter().map(|&i| r.root(i)).collect();
                let res = vector(dim, &res);
                let m = matrix(g, &r, &jac, dim, &roots[dim..]);
                quote!(#path => {
                    #lets #temps #m
                    let r = #res;
                    ::varembed::solve::linear::solve_small(&#jac, &r).map(|dy| b - dy)
                })
            }
        }
    });
    let body = quote!(match kind { #(#arms)* });
    let (pb, pm, pt) = (
        param(&body, "b"),
        param(&body, "momentum"),
        param(&body, "times"),
    );
    let explicit = quote! {
        #[inline]
        fn step_explicit(
            &self,
            kind: ::varembed::StepKind,
            #pb: &#vec_ty,
            #pm: &#vec_ty,
            #pt: &::varembed::StepTimes,
        ) -> ::core::option::Option<#vec_ty> {
            #body
        }
    };
    quote!(#momentum #residual #is_affine #explicit)
}

/// The derivatives as text, one `name = formula` per line.
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

/// Formulas longer than this are not spelled out (the expansion of a DAG can be exponential).
const MAX_TEXT_NODES: usize = 4000;

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

    fn wrap(&self, id: Id, need: u8) -> String {
        let (s, p) = self.go(id);
        if p < need { format!("({s})") } else { s }
    }

    fn go(&self, id: Id) -> (String, u8) {
        let bin = |a: Id, b: Id, op: &str, p: u8| {
            (
                format!("{} {op} {}", self.wrap(a, p), self.wrap(b, p + 1)),
                p,
            )
        };
        match self.g.node(id) {
            Node::Num(bits) => {
                let c = f64::from_bits(bits);
                let s = match named_constant(c.abs()) {
                    Some(name) if c < 0.0 => format!("-{name}"),
                    Some(name) => name.to_string(),
                    None => format!("{c:?}"),
                };
                (s, if c.is_sign_negative() { P_NEG } else { P_MAX })
            }
            Node::Var(v) => {
                let s = match v {
                    Var::X(_) if self.model.scalar => "x".into(),
                    Var::V(_) if self.model.scalar => "v".into(),
                    Var::X(i) => format!("x[{i}]"),
                    Var::V(i) => format!("v[{i}]"),
                    Var::T => "t".into(),
                    Var::Const(k) => self.model.consts[k].to_string(),
                    Var::H => "h".into(),
                    Var::M(i) => format!("π[{i}]"),
                };
                (s, P_MAX)
            }
            Node::Add(a, b) => bin(a, b, "+", P_ADD),
            Node::Sub(a, b) => bin(a, b, "-", P_ADD),
            Node::Mul(a, b) => bin(a, b, "*", P_MUL),
            Node::Div(a, b) => bin(a, b, "/", P_MUL),
            Node::Neg(a) => (format!("-{}", self.wrap(a, P_MAX)), P_NEG),
            Node::Call(Func::Sign, a) => (format!("sign({})", self.go(a).0), P_MAX),
            Node::Call(f, a) => (format!("{}.{}()", self.wrap(a, P_MAX), f.name()), P_MAX),
            Node::Powi(a, n) => (format!("{}.powi({n})", self.wrap(a, P_MAX)), P_MAX),
            Node::Powf(a, b) => (
                format!("{}.powf({})", self.wrap(a, P_MAX), self.go(b).0),
                P_MAX,
            ),
            Node::Hypot(a, b) => (
                format!("{}.hypot({})", self.wrap(a, P_MAX), self.go(b).0),
                P_MAX,
            ),
        }
    }
}
