//! Initial value problems of the variational Gauss–Legendre integrators under holonomic
//! constraints, with the constraint at the nodes.
//!
//! The constrained discrete Euler–Lagrange equations of the Gauss–Legendre discrete Lagrangian
//! `L_d` (Marsden and West 2001, §3.5), `D₂L_d(q_{k−1}, q_k) + D₁L_d(q_k, q_{k+1}) +
//! G(q_k)ᵀμ_k = 0`, `g(q_{k+1}) = 0`, in the one-step form of the parent module's Gauss–Legendre
//! solver: the momentum `p_k` leaving the previous step gains the constraint impulse at the node,
//! `p_k⁺ = p_k + G(q_k)ᵀμ_k`, and the step from `(q_k, p_k⁺)` must land on the constraints:
//!
//! ```text
//! R_i(V) = ∂L/∂v(Q_i, V_i) − p_k − G(q_k)ᵀμ_k − h Σ_j a_ij Ṗ_j = 0,   i = 1..s,
//! g(q_k + h Σ_i b_i V_i) = 0,
//! ```
//!
//! one Newton solve of the `s·D + M` unknowns `(V, μ_k)` per step, then `q_{k+1} = q_k +
//! h Σ b_i V_i`, `p_{k+1} = p_k⁺ + h Σ b_i Ṗ_i`. The stages themselves are not constrained, so
//! this is not a SPARK method (Jay): its order is what the tests measure (stated in the guide to
//! forces and constraints), not `2s`. Its symplecticity and the exact conservation of the Noether
//! momenta of symmetries the constraint respects hold as for every constrained variational
//! scheme, since it is the constrained discrete Euler–Lagrange equation of a discrete Lagrangian.

use nalgebra::{DMatrix, DVector, SVector};

use super::ConstrainedSolution;
use crate::constraint::{Constraint, check_consistent, check_rank};
use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Location, Result};
use crate::gauss_legendre::GaussTableau;
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::memory::reserve;
use crate::options::NewtonOptions;
use crate::regularity::check_initial_data;
use crate::solve::gauss::StageSystem;
use crate::solve::newton::at_round_off;
use crate::solve::solution::Solution;

/// The run of the `stages`-stage variational Gauss–Legendre integrator from `q(a) = q0`,
/// `q̇(a) = v0` under `constraint` (module docs).
pub(crate) fn solve<L, C, const D: usize, const M: usize>(
    lagrangian: &L,
    constraint: &C,
    (grid, embedding, stages): (Grid, Embedding, usize),
    newton: &NewtonOptions,
    q0: Vector<D>,
    v0: Vector<D>,
) -> Result<ConstrainedSolution<D, M>>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    let (_, p0, _) = check_initial_data(lagrangian, &q0, &v0, grid.t(0))?;
    check_consistent(constraint, &q0, &v0)?;
    let n_steps = grid.n();
    let mut system = StageSystem::new(GaussTableau::new(stages), grid.h(), v0);
    let (mut q, mut p) = (
        reserve(n_steps + 1, "the nodes q_0..=q_N")?,
        reserve(n_steps + 1, "the momenta p_0..=p_N")?,
    );
    let mut multipliers = reserve(n_steps.saturating_sub(1), "the multipliers")?;
    q.push(q0);
    p.push(p0);
    let (mut qk, mut pk) = (q0, p0);
    let mut mu = SVector::<f64, M>::zeros();
    let mut iterations = 0;
    for n in 1..=n_steps {
        let from = (&qk, &pk, grid.t(n - 1));
        let (next_mu, used) =
            constrained_stages(&mut system, lagrangian, constraint, from, mu, n, newton)?;
        iterations += used;
        mu = next_mu;
        let kicked = pk + constraint.jacobian(&qk).transpose() * mu;
        (qk, pk) = system.advance(&qk, &kicked);
        if !qk.iter().chain(pk.iter()).all(|c| c.is_finite()) {
            return Err(Error::NotFinite {
                at: Location::Step(n),
            });
        }
        q.push(qk);
        p.push(pk);
        // The impulse at q_0 is the start's (as for the three-point schemes' starts).
        if n >= 2 {
            multipliers.push(mu / grid.h());
        }
        system.extrapolate_guess();
    }
    Ok(ConstrainedSolution {
        solution: Solution {
            scheme: Scheme::Variational,
            embedding,
            grid,
            q,
            momenta: p,
            newton_iterations: iterations,
            explicit_steps: 0,
            warnings: Vec::new(),
        },
        multipliers,
    })
}

/// Newton's method on the constrained stage equations of the step from `(q_k, p_k)` at `t_k`
/// (step `n`), from the stage velocities in `system` and the previous step's `μ`: the unknowns
/// `(V, ν)` with `μ_k = w ν` and the constraint rows `w g(q_{k+1})`, `w` the scale of the stage
/// rows over that of the constraint at the guess, so that the system scales with `L` (as the
/// three-point constrained steps). The stopping rule of the unconstrained stages, with the
/// constraint within the tolerance of `‖G‖∞ ‖q_{k+1}‖∞`. Returns `μ_k` and the iterations.
fn constrained_stages<L, C, const D: usize, const M: usize>(
    system: &mut StageSystem<D>,
    lagrangian: &L,
    constraint: &C,
    (qk, pk, tk): (&Vector<D>, &Vector<D>, f64),
    mu: SVector<f64, M>,
    n: usize,
    options: &NewtonOptions,
) -> Result<(SVector<f64, M>, usize)>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    let at = Location::Step(n);
    let s = system.tableau.stages();
    let (h, width) = (system.h, s * D);
    let g_k = constraint.jacobian(qk);
    let largest = |x: &[Vector<D>]| x.iter().fold(0.0f64, |m, y| m.max(y.amax()));
    let landing = |system: &StageSystem<D>| {
        let mut q = *qk;
        for (i, b) in system.tableau.b.iter().enumerate() {
            q += system.v[i] * (h * b);
        }
        q
    };
    let (mut w, mut nu) = (1.0, mu);
    let mut residual = f64::INFINITY;
    for iteration in 0..=options.max_iterations {
        let finite = system.evaluate(lagrangian, qk, tk);
        let stage_rows = pk.amax() + largest(&system.p) + h * largest(&system.f);
        let next = landing(system);
        let g_next = constraint.jacobian(&next);
        let constraint_scale = g_next.amax() * next.amax();
        if iteration == 0 {
            let scale = stage_rows / constraint_scale;
            w = if scale.is_finite() && scale > 0.0 {
                scale
            } else {
                1.0
            };
            nu = mu / w;
        }
        let impulse = g_k.transpose() * (nu * w);
        let stage_residual = system.residual(&(pk + impulse));
        let g = constraint.value(&next) * w;
        let previous = residual;
        residual = stage_residual.max(g.amax());
        if !finite || !residual.is_finite() {
            return Err(if iteration == 0 {
                Error::NotFinite { at }
            } else {
                Error::NewtonDidNotConverge {
                    at,
                    iterations: iteration,
                    residual: previous,
                }
            });
        }
        let j_norm = system.assemble_jacobian();
        let rows = stage_rows + impulse.amax();
        let constraint_scale = w * constraint_scale;
        let terms =
            rows + constraint_scale + j_norm * largest(&system.v) + w * g_k.amax() * nu.amax();
        let converged = (stage_residual <= options.tolerance * rows
            && g.amax() <= options.tolerance * constraint_scale)
            || at_round_off(residual, previous, 1.0, terms);
        // The bordered system `[[J, −w G(q_k)ᵀ per stage], [w h b_m G(q_{k+1}), 0]]`.
        let size = width + M;
        let mut kkt = DMatrix::<f64>::zeros(size, size);
        for r in 0..width {
            for c in 0..width {
                kkt[(r, c)] = system.jacobian[r * width + c];
            }
        }
        for i in 0..s {
            for d in 0..D {
                for m in 0..M {
                    kkt[(i * D + d, width + m)] = -w * g_k[(m, d)];
                    kkt[(width + m, i * D + d)] = w * h * system.tableau.b[i] * g_next[(m, d)];
                }
            }
        }
        let mut rhs = DVector::<f64>::zeros(size);
        rhs.rows_mut(0, width).copy_from_slice(&system.rhs);
        rhs.rows_mut(width, M).copy_from(&g);
        let solved = kkt.lu().solve(&rhs);
        let Some(update) = solved.filter(|u| u.iter().all(|c| c.is_finite())) else {
            check_rank(&g_next, at)?;
            check_rank(&g_k, at)?;
            return Err(Error::SingularJacobian { at });
        };
        if converged {
            return Ok((nu * w, iteration));
        }
        if iteration == options.max_iterations {
            break;
        }
        for (i, v) in system.v.iter_mut().enumerate() {
            *v -= Vector::<D>::from_column_slice(&update.as_slice()[i * D..(i + 1) * D]);
        }
        nu -= SVector::<f64, M>::from_column_slice(&update.as_slice()[width..]);
    }
    Err(Error::NewtonDidNotConverge {
        at,
        iterations: options.max_iterations,
        residual,
    })
}
