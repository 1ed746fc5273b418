//! Initial value problems under holonomic constraints: each three-point step of a classical
//! scheme with the constraint force and the constraint at the newest node.
//!
//! The system `d/dt ∂L/∂v − ∂L/∂x = G(x)ᵀλ`, `g(x) = 0`. Each step of a classical scheme is the
//! equation `G_K(y) = π` of its kind (`G_K` and `π` of the step module) times `−h` of one row of
//! the scheme; that row gains the constraint force at the node where the row reads `∂L/∂x`, and
//! the newest node must satisfy the constraint:
//!
//! `G_K(y) − π − G(c)ᵀ μ = 0`, `g(y) = 0`, `μ = h λ`,
//!
//! with `c` the middle node `b` for the variational kinds and the direct kinds of the symmetric
//! embeddings (the constrained discrete Euler–Lagrange equations: `D₂L_d(a, b) + D₁L_d(b, y) +
//! h G(b)ᵀλ = 0`), the newest node `y` for the direct Gauss-FDE− step (its row reads `∂L/∂x` at
//! the right end) and the oldest node `a` for the direct Gauss-FDE+ step. Newton's method solves
//! for `(y, μ)` together, from the extrapolation `2b − a` and the previous `μ`; its Jacobian is
//! the saddle-point matrix `[[J − [c = y] Σ μ_i ∇²g_i, −G(c)ᵀ], [G(y), 0]]`. The first step is
//! the discrete Legendre start with the same constraint force at `q(a)`.

mod bvp;
mod gauss;

pub(crate) use bvp::solve as solve_bvp;

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use crate::constraint::{Constraint, check_consistent, check_rank};
use crate::embedding::{EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::solve_small;
use crate::memory::reserve;
use crate::options::NewtonOptions;
use crate::regularity::check_initial_data;
use crate::solve::ivp::Ivp;
use crate::solve::newton::at_round_off;
use crate::solve::nodes::{NodeValues, invert_momentum};
use crate::solve::solution::Solution;
use crate::stack::with_room_for;
use crate::step::{Step, StepKind, StepTimes, residual_and_terms};

/// A solution under holonomic constraints: the nodes, and the multipliers of each step.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstrainedSolution<const D: usize, const M: usize> {
    /// The nodes and the run's figures, as for an unconstrained run (its `node_values` are the
    /// unconstrained formulas at the nodes; [`ConstrainedSolution::node_values`] projects them
    /// onto the hidden constraint).
    pub solution: Solution<D>,
    /// `λ` of the row of the step that computed `Q_n`, for `n = 2..=N`, at index `n − 2`
    /// (`N − 1` entries): the multiplier of the constraint force `G(Q_c)ᵀλ` at the node `c`
    /// of that row, `c = n − 1` for the variational steps and the direct midpoint and
    /// trapezoidal steps, `n` for the direct Gauss-FDE− step, `n − 2` for the direct
    /// Gauss-FDE+ step: `λ(t_c)` to the scheme's order. (The start, the discrete Legendre
    /// transform at `q(a)`, takes the constraint's impulse over its first half-step, which is
    /// not a value of `λ`.)
    pub multipliers: Vec<SVector<f64, M>>,
}

impl<const D: usize, const M: usize> ConstrainedSolution<D, M> {
    /// Time, position, velocity, momentum and energy at every node, the momenta projected onto
    /// the hidden constraint `G(Q_k) v_k = 0`.
    ///
    /// From the unconstrained node values `(v_k, p_k)` of [`Solution::node_values`] (for a
    /// variational scheme the discrete Legendre transform `p_k^− = −D₁L_d(Q_k, Q_{k+1})`),
    /// `p̂_k = p_k − G(Q_k)ᵀν` with `ν = (G M⁻¹ Gᵀ)⁻¹ G v_k`, `M = ∂²L/∂v²` at the node, and
    /// `v̂_k` solving `∂L/∂v(Q_k, v̂_k, t_k) = p̂_k`. The correction lies along `Gᵀ`, so for a
    /// symmetry `ξ` the constraint respects (`G ξ = 0`) the Noether momentum `p̂_k·ξ` is
    /// `p_k·ξ`, conserved by the variational schemes; for `L` quadratic in `v`,
    /// `G(Q_k) v̂_k = 0` holds exactly (otherwise to second order in the correction). The
    /// energy is that of `(Q_k, v̂_k)`.
    ///
    /// `lagrangian` and `constraint` must be the ones the solution was computed with. Errors as
    /// [`Solution::node_values`], and [`Error::RankDeficientConstraints`] at a node where
    /// `G M⁻¹ Gᵀ` is singular.
    pub fn node_values<L, C>(&self, lagrangian: &L, constraint: &C) -> Result<NodeValues<D>>
    where
        L: Lagrangian<D> + ?Sized,
        C: Constraint<D, M> + ?Sized,
    {
        // Each node solves with `∂²L/∂v²` (see the stack module).
        with_room_for::<D, _>(|| self.project_node_values(lagrangian, constraint))
    }

    /// The values of [`node_values`](Self::node_values), which computes them where the stack
    /// has room for the blocks they solve with.
    fn project_node_values<L, C>(&self, lagrangian: &L, constraint: &C) -> Result<NodeValues<D>>
    where
        L: Lagrangian<D> + ?Sized,
        C: Constraint<D, M> + ?Sized,
    {
        let mut nodes = self.solution.node_values(lagrangian)?;
        for k in 0..nodes.len() {
            let (q, t) = (nodes.q[k], nodes.t[k]);
            let at = Location::Node(k);
            let mass = lagrangian.hessian(&q, &nodes.v[k], t).vv;
            let g = constraint.jacobian(&q);
            // M⁻¹ Gᵀ column by column, then the M × M system for ν.
            let mut spread = SMatrix::<f64, D, M>::zeros();
            for i in 0..M {
                let column = solve_small(&mass, &g.row(i).transpose())
                    .ok_or(Error::SingularJacobian { at })?;
                spread.set_column(i, &column);
            }
            let schur = g * spread;
            let rhs = g * nodes.v[k];
            let nu = DMatrix::from_column_slice(M, M, schur.as_slice())
                .lu()
                .solve(&DVector::from_column_slice(rhs.as_slice()))
                .filter(|nu| nu.iter().all(|c| c.is_finite()));
            let Some(nu) = nu else {
                check_rank(&g, at)?;
                return Err(Error::SingularJacobian { at });
            };
            let nu = SVector::<f64, M>::from_column_slice(nu.as_slice());
            let p = nodes.p[k] - g.transpose() * nu;
            let guess = nodes.v[k] - spread * nu;
            nodes.v[k] = invert_momentum(lagrangian, &q, t, &p, guess, k)?;
            nodes.p[k] = p;
        }
        if let Some(energy) = nodes.energy.as_mut() {
            for (k, e) in energy.iter_mut().enumerate() {
                let (q, v, t) = (&nodes.q[k], &nodes.v[k], nodes.t[k]);
                *e = v.dot(&nodes.p[k]) - lagrangian.value(q, v, t);
            }
        }
        Ok(nodes)
    }
}

/// Which node of a step's row carries the constraint force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RowNode {
    Oldest,
    Middle,
    Newest,
}

fn row_node(kind: StepKind) -> RowNode {
    match kind {
        StepKind::DirectBackward => RowNode::Newest,
        StepKind::DirectForward => RowNode::Oldest,
        _ => RowNode::Middle,
    }
}

/// The run of `scheme` from `q(a) = q0`, `q̇(a) = v0` under `constraint`.
pub(crate) fn solve<L, C, const D: usize, const M: usize>(
    ivp: &Ivp<'_, L, D>,
    constraint: &C,
    scheme: Scheme,
    q0: Vector<D>,
    v0: Vector<D>,
) -> Result<ConstrainedSolution<D, M>>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    if let EmbeddingKind::GaussLegendre { stages } = ivp.embedding.kind() {
        if scheme == Scheme::Direct {
            return Err(Error::Unsupported {
                operation: "the direct scheme (a Gauss–Legendre integrator is variational only)",
                embedding: ivp.embedding.to_string(),
            });
        }
        let run = (ivp.grid, ivp.embedding, stages);
        return gauss::solve(ivp.lagrangian, constraint, run, &ivp.newton, q0, v0);
    }
    let kind = ivp.step_kind(scheme)?;
    let (grid, lagrangian) = (ivp.grid, ivp.lagrangian);
    let (_, pi0, _) = check_initial_data(lagrangian, &q0, &v0, grid.t(0))?;
    check_consistent(constraint, &q0, &v0)?;
    let (n_steps, h) = (grid.n(), grid.h());
    let mut q = reserve(n_steps + 1, "the nodes Q_0..=Q_N")?;
    let mut multipliers = reserve(n_steps.saturating_sub(1), "the multipliers")?;
    q.push(q0);
    let mut iterations = 0;
    let mut mu = SVector::<f64, M>::zeros();
    for n in 1..=n_steps {
        let (step, guess) = if n == 1 {
            let start = Step {
                kind: kind.legendre_start(),
                a: q0 - v0 * h,
                b: q0,
                momentum: pi0,
                times: StepTimes::new(h, grid.t(0) - h, grid.t(0), grid.t(1)),
            };
            (start, q0 + v0 * h)
        } else {
            let (a, b) = (&q[n - 2], &q[n - 1]);
            let times = StepTimes::new(h, grid.t(n - 2), grid.t(n - 1), grid.t(n));
            (Step::new(lagrangian, kind, a, b, &times), b * 2.0 - a)
        };
        let (y, next_mu, used) =
            constrained_step(lagrangian, constraint, &step, guess, mu, &ivp.newton, n)?;
        iterations += used;
        mu = next_mu;
        q.push(y);
        if n >= 2 {
            multipliers.push(mu / h);
        }
    }
    Ok(ConstrainedSolution {
        solution: Solution {
            scheme,
            embedding: ivp.embedding,
            grid,
            q,
            momenta: Vec::new(),
            newton_iterations: iterations,
            explicit_steps: 0,
            warnings: Vec::new(),
        },
        multipliers,
    })
}

/// Newton's method on `(y, μ)` for one constrained step (module docs); the iterations used.
///
/// The unknowns are `y` and `ν = μ / w`, and the constraint rows are `w g(y)`, with `w` the
/// scale of the step's rows over that of the constraint (`‖G(y)‖∞ ‖y‖∞`) at the guess: the
/// whole system then scales with `L`, so `c L` takes the same iterates, and partial pivoting
/// compares entries of one unit. It stops when the step's rows are within the tolerance of their
/// terms (`‖π‖∞`, the terms of `G_K(y)`, `‖G(c)ᵀμ‖∞`) and the constraint within the tolerance
/// of `‖G(y)‖∞ ‖y‖∞`, or at the round-off floor of the unconstrained steps (`at_round_off`:
/// within `64 ε` of the system's terms and no longer halving).
fn constrained_step<L, C, const D: usize, const M: usize>(
    lagrangian: &L,
    constraint: &C,
    step: &Step<D>,
    mut y: Vector<D>,
    mu: SVector<f64, M>,
    newton: &NewtonOptions,
    n: usize,
) -> Result<(Vector<D>, SVector<f64, M>, usize)>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    let at = Location::Step(n);
    let node = row_node(step.kind);
    // `G` at a row node other than the newest is the same at every iteration.
    let fixed = match node {
        RowNode::Oldest => Some(constraint.jacobian(&step.a)),
        RowNode::Middle => Some(constraint.jacobian(&step.b)),
        RowNode::Newest => None,
    };
    let (mut weight, mut nu) = (1.0, mu);
    let mut last = f64::INFINITY;
    for iteration in 0..=newton.max_iterations {
        let (r, j, size) = residual_and_terms(lagrangian, step, &y);
        let jacobian_y = constraint.jacobian(&y);
        // `‖G(y)‖∞ ‖y‖∞`, the scale of the constraint's terms.
        let terms_of_g = jacobian_y.amax() * y.amax();
        if iteration == 0 {
            let w = size.max(step.momentum.amax()) / terms_of_g;
            weight = if w.is_finite() && w > 0.0 { w } else { 1.0 };
            nu = mu / weight;
        }
        let mu = nu * weight;
        let g_c = fixed.unwrap_or(jacobian_y);
        let force = g_c.transpose() * mu;
        let r = r - force;
        let (g, g_y) = (constraint.value(&y) * weight, jacobian_y * weight);
        let residual = r.amax().max(g.amax());
        if !residual.is_finite() || !j.iter().all(|c| c.is_finite()) {
            return Err(if iteration == 0 {
                Error::NotFinite { at }
            } else {
                Error::NewtonDidNotConverge {
                    at,
                    iterations: iteration,
                    residual: last,
                }
            });
        }
        let previous = std::mem::replace(&mut last, residual);
        let row_scale = size.max(step.momentum.amax()).max(force.amax());
        let constraint_scale = weight * terms_of_g;
        let within = r.amax() <= newton.tolerance * row_scale
            && g.amax() <= newton.tolerance * constraint_scale;
        // The floor of the unconstrained steps, with the saddle-point system's scale: each
        // row's terms, and the Jacobian's blocks times the unknowns they multiply.
        let terms =
            row_scale + constraint_scale + j.amax() * y.amax() + weight * g_c.amax() * nu.amax();
        if within || at_round_off(residual, previous, 1.0, terms) {
            return Ok((y, mu, iteration));
        }
        if iteration == newton.max_iterations {
            break;
        }
        let mut kkt = DMatrix::<f64>::zeros(D + M, D + M);
        let mut top_left = j;
        if node == RowNode::Newest {
            top_left -= constraint.weighted_hessian(&y, &mu);
        }
        kkt.view_mut((0, 0), (D, D)).copy_from(&top_left);
        kkt.view_mut((0, D), (D, M))
            .copy_from(&(-g_c.transpose() * weight));
        kkt.view_mut((D, 0), (M, D)).copy_from(&g_y);
        let mut rhs = DVector::<f64>::zeros(D + M);
        rhs.rows_mut(0, D).copy_from(&(-r));
        rhs.rows_mut(D, M).copy_from(&(-g));
        let solved = kkt.lu().solve(&rhs);
        let Some(update) = solved.filter(|u| u.iter().all(|c| c.is_finite())) else {
            check_rank(&g_y, at)?;
            check_rank(&g_c, at)?;
            return Err(Error::SingularJacobian { at });
        };
        let (dy, dnu) = (update.rows(0, D), update.rows(D, M));
        y += dy;
        nu += dnu;
    }
    Err(Error::NewtonDidNotConverge {
        at,
        iterations: newton.max_iterations,
        residual: last,
    })
}
