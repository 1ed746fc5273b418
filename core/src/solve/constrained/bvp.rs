//! Boundary value problems under holonomic constraints: Newton on the whole system of the
//! scheme's rows with their constraint forces and the constraints at the interior nodes.
//!
//! Every row `r_k` of a classical scheme reads `∂L/∂x` at its own node `k` (the rows of
//! [`Discretisation::rows`]: `1..=N−1`, or `2..=N` and `0..=N−2` for the direct Gauss-FDE∓
//! schemes), and gains the constraint force there: the unknowns `Q_1..Q_{N−1}` and one
//! multiplier `λ_k` per row solve
//!
//! `r_k + G(Q_k)ᵀ λ_k = 0` for every row `k`, `g(Q_j) = 0` for `j = 1..=N−1`,
//!
//! `(N − 1)(D + M)` equations in as many unknowns: the rows of the initial value problem's steps
//! (see the parent module), so a boundary value problem whose ends come from a constrained run
//! returns that run's nodes and multipliers. Node `j`'s unknowns and equations form one block
//! `[Q_j, λ of row j − 1]`, `[row j − 1, g(Q_j)]` (row counted from the first), so the Jacobian
//! is block-tridiagonal with blocks of `D + M` (half-bandwidth `2D + M − 1`), factorised as a
//! band matrix in `O(N (D + M)³)`. The constraint rows are weighted, and the multipliers measured, in units of
//! the scheme's rows (`w` below), so that the system scales with `L` as a whole: `c L` gives the
//! same Newton iterates and multipliers `c λ`.

use std::marker::PhantomData;

use nalgebra::SVector;

use super::ConstrainedSolution;
use crate::constraint::{Constraint, check_end_value, check_rank, project_position};
use crate::discretisation::{Discretisation, Pointwise};
use crate::embedding::Scheme;
use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::{BandNorms, BandedMatrix};
use crate::options::SolverOptions;
use crate::solve::bvp::checks::{check_input, check_nodes};
use crate::solve::conditioning::{NUMERICALLY_SINGULAR, condition_bound, inverse_iteration};
use crate::solve::newton::{Converging, GlobalSystem, Iterate, solve_global};
use crate::solve::solution::Solution;
use std::ops::ControlFlow;

/// The iterate: the nodes (ends included, which stay) and the scaled multipliers `μ = λ / w`,
/// one per row.
#[derive(Clone)]
struct Unknowns<const D: usize, const M: usize> {
    q: Vec<Vector<D>>,
    mu: Vec<SVector<f64, M>>,
}

impl<const D: usize, const M: usize> Iterate for Unknowns<D, M> {
    fn along(&self, delta: &[f64], lambda: f64) -> Self {
        let block = D + M;
        let n = self.q.len() - 1;
        let mut next = self.clone();
        for j in 1..n {
            let at = (j - 1) * block;
            next.q[j] -= Vector::<D>::from_column_slice(&delta[at..at + D]) * lambda;
            next.mu[j - 1] -=
                SVector::<f64, M>::from_column_slice(&delta[at + D..at + block]) * lambda;
        }
        next
    }

    fn size(&self) -> f64 {
        let q = self.q.iter().map(|q| q.amax());
        q.chain(self.mu.iter().map(|m| m.amax()))
            .fold(0.0f64, f64::max)
    }
}

/// The system at one iterate: its rows flat in block order, the pointwise values they came
/// from, and the largest residual and the scale of each kind of row.
struct Evaluation<const D: usize> {
    rows: Vec<f64>,
    pointwise: Pointwise<D>,
    /// The scheme's rows with their constraint forces: `max |r_k + G(Q_k)ᵀλ_k|` and the row
    /// scale plus the largest constraint force.
    scheme: (f64, f64),
    /// The weighted constraints: `max |w g(Q_j)|` and `w · max ‖G(Q_j)‖∞ · max ‖Q_j‖∞`.
    constraints: (f64, f64),
}

/// The constrained boundary value problem of `scheme` from `guess` (its first and last nodes
/// the end values): see the module docs.
pub(crate) fn solve<L, C, const D: usize, const M: usize>(
    disc: &Discretisation<'_, L, D>,
    options: &SolverOptions,
    constraint: &C,
    scheme: Scheme,
    guess: &[Vector<D>],
) -> Result<ConstrainedSolution<D, M>>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    let embedding = *disc.embedding();
    if embedding.is_one_step() || embedding.is_fractional() {
        // Gauss–Legendre has no rows on the nodes; a fractional row reads every node, so its
        // constrained system would be dense.
        return Err(Error::Unsupported {
            operation: "a boundary value problem under constraints",
            embedding: embedding.to_string(),
        });
    }
    if let Some(reason) = constraint.not_holonomic() {
        return Err(Error::InvalidModel { reason });
    }
    check_input(disc, guess)?;
    let grid = *disc.grid();
    let n = grid.n();
    check_end_value(constraint, &guess[0], "a", Location::Node(0))?;
    check_end_value(constraint, &guess[n], "b", Location::Node(n))?;
    let mut q = guess.to_vec();
    for (j, node) in q.iter_mut().enumerate().take(n).skip(1) {
        *node = project_position(constraint, *node, Location::Node(j))?;
    }
    let system = System {
        disc,
        constraint,
        scheme,
        start: *disc.rows(scheme).start(),
        weight: weight(disc, constraint, scheme, &q)?,
        dimension: PhantomData,
    };
    let x = Unknowns {
        q,
        mu: vec![SVector::<f64, M>::zeros(); n - 1],
    };
    let (q, mu, iterations) = system.newton(x, options)?;
    check_nodes(disc, &q, false)?;
    let solution = Solution {
        scheme,
        embedding,
        grid,
        q,
        momenta: Vec::new(),
        newton_iterations: iterations,
        explicit_steps: 0,
        warnings: Vec::new(),
    };
    let multipliers = mu.iter().map(|m| m * system.weight).collect();
    Ok(ConstrainedSolution {
        solution,
        multipliers,
    })
}

/// The constrained system of one scheme: what evaluates its rows and Jacobian.
struct System<'s, 'l, L: ?Sized, C: ?Sized, const D: usize, const M: usize> {
    disc: &'s Discretisation<'l, L, D>,
    constraint: &'s C,
    scheme: Scheme,
    /// The first row's node: row `i` is node `start + i`.
    start: usize,
    /// `w`: the constraint rows are `w g`, the multipliers `λ = w μ`. The scale of the scheme's
    /// rows over that of the constraints (`max ‖G‖∞ · max ‖Q‖∞`) at the initial iterate; it
    /// scales with `L`, so the whole system does.
    weight: f64,
    /// The multipliers' dimension, which the constraint fixes.
    dimension: PhantomData<[f64; M]>,
}

impl<L, C, const D: usize, const M: usize> System<'_, '_, L, C, D, M>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    /// The rows at `x`; [`Error::NotFinite`] at Newton iteration `iteration` when they are not
    /// finite.
    fn evaluate(&self, x: &Unknowns<D, M>, iteration: usize) -> Result<Evaluation<D>> {
        let not_finite = Error::NotFinite {
            at: Location::Newton(iteration),
        };
        if !x.q.iter().all(|q| q.iter().all(|c| c.is_finite())) {
            return Err(not_finite);
        }
        let pointwise = self.disc.pointwise(&x.q).map_err(|_| not_finite.clone())?;
        let r = self.disc.residual_from(self.scheme, &pointwise);
        let block = D + M;
        let mut rows = vec![0.0; r.len() * block];
        let (mut forces, mut scheme, mut constraints) = (0.0f64, 0.0f64, 0.0f64);
        let (mut gradients, mut size) = (0.0f64, 0.0f64);
        for (i, (row, mu)) in r.iter().zip(&x.mu).enumerate() {
            let force =
                self.constraint.jacobian(&x.q[self.start + i]).transpose() * (mu * self.weight);
            forces = forces.max(force.amax());
            let node = &x.q[i + 1];
            let g = self.constraint.value(node) * self.weight;
            gradients = gradients.max(self.constraint.jacobian(node).amax());
            size = size.max(node.amax());
            let row = row + force;
            scheme = scheme.max(row.amax());
            constraints = constraints.max(g.amax());
            rows[i * block..i * block + D].copy_from_slice(row.as_slice());
            rows[i * block + D..(i + 1) * block].copy_from_slice(g.as_slice());
        }
        if !rows.iter().all(|c| c.is_finite()) {
            return Err(not_finite);
        }
        let scale = self.disc.row_scale(self.scheme, &pointwise) + forces;
        Ok(Evaluation {
            rows,
            pointwise,
            scheme: (scheme, scale),
            constraints: (constraints, self.weight * gradients * size),
        })
    }

    /// The Jacobian at `x` in the block order of the module docs.
    fn jacobian(&self, x: &Unknowns<D, M>, pointwise: &Pointwise<D>) -> BandedMatrix {
        let block = D + M;
        let n = x.q.len() - 1;
        // A scheme row of block i reaches `Q` of blocks i ± 1; a constraint row, block i alone.
        let band = 2 * D + M - 1;
        let mut jac = BandedMatrix::zeros((n - 1) * block, band, band);
        self.disc
            .assemble_jacobian(self.scheme, &x.q, pointwise, |i, j, b| {
                for r in 0..D {
                    for c in 0..D {
                        jac.add(i * block + r, j * block + c, b[(r, c)]);
                    }
                }
            });
        for (i, mu) in x.mu.iter().enumerate() {
            let node = self.start + i;
            let lambda = mu * self.weight;
            // The constraint force `G(Q_k)ᵀ λ` of row i: in `λ` (scaled by `w`), and in `Q_k`
            // where that node is an unknown.
            let g = self.constraint.jacobian(&x.q[node]);
            for r in 0..D {
                for m in 0..M {
                    jac.add(i * block + r, i * block + D + m, g[(m, r)] * self.weight);
                }
            }
            if (1..n).contains(&node) {
                let curvature = self.constraint.weighted_hessian(&x.q[node], &lambda);
                for r in 0..D {
                    for c in 0..D {
                        jac.add(i * block + r, (node - 1) * block + c, curvature[(r, c)]);
                    }
                }
            }
            // `w g(Q_{i+1})`.
            let g = self.constraint.jacobian(&x.q[i + 1]);
            for m in 0..M {
                for c in 0..D {
                    jac.add(i * block + D + m, i * block + c, g[(m, c)] * self.weight);
                }
            }
        }
        jac
    }

    /// Newton's method ([`solve_global`]) as the unconstrained boundary value problems run it;
    /// the nodes, the scaled multipliers and the iterations used.
    fn newton(
        &self,
        x: Unknowns<D, M>,
        options: &SolverOptions,
    ) -> Result<(Vec<Vector<D>>, Vec<SVector<f64, M>>, usize)> {
        let n = x.q.len() - 1;
        let unknowns = (n - 1) * (D + M);
        if unknowns == 0 {
            return Ok((x.q, x.mu, 0));
        }
        let mut by_lu = ByBandedLu {
            system: self,
            jacobian: None,
        };
        solve_global(&mut by_lu, x, unknowns, &options.newton)
    }
}

/// The constrained system with its Newton systems solved by banded LU.
struct ByBandedLu<'a, 's, 'l, L: ?Sized, C: ?Sized, const D: usize, const M: usize> {
    system: &'a System<'s, 'l, L, C, D, M>,
    /// The last linearisation and its norms.
    jacobian: Option<(BandedMatrix, BandNorms)>,
}

impl<L, C, const D: usize, const M: usize> ByBandedLu<'_, '_, '_, L, C, D, M>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    /// `δ = J⁻¹ r` into `delta` at the last linearisation, at the nodes `x`, factorised here:
    /// where it is singular, a rank-deficient `G` at some node is the cause to name
    /// ([`check_rank`]); otherwise the scheme's own system is singular.
    fn solve(
        &mut self,
        x: &Unknowns<D, M>,
        rows: &[f64],
        delta: &mut [f64],
        at: Location,
    ) -> Result<&mut BandedMatrix> {
        let (jac, norms) = self.jacobian.as_mut().expect("linearised before");
        if jac.factorize_scaled(norms.largest).is_err() {
            for (k, q) in x.q.iter().enumerate() {
                check_rank(&self.system.constraint.jacobian(q), Location::Node(k))?;
            }
            return Err(Error::SingularJacobian { at });
        }
        delta.copy_from_slice(rows);
        jac.solve_inplace(delta);
        Ok(jac)
    }
}

impl<L, C, const D: usize, const M: usize> GlobalSystem for ByBandedLu<'_, '_, '_, L, C, D, M>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    type Iterate = Unknowns<D, M>;
    type Evaluation = Evaluation<D>;
    type Output = (Vec<Vector<D>>, Vec<SVector<f64, M>>, usize);

    fn evaluate(
        &mut self,
        x: &Unknowns<D, M>,
        iteration: usize,
    ) -> Result<(Evaluation<D>, f64, f64)> {
        let e = self.system.evaluate(x, iteration)?;
        let res = e.rows.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let merit = e.rows.iter().map(|c| c * c).sum::<f64>().sqrt();
        Ok((e, res, merit))
    }

    fn within(&self, e: &Evaluation<D>, _: f64, tolerance: f64) -> bool {
        let within = |(residual, scale): (f64, f64)| residual <= tolerance * scale;
        within(e.scheme) && within(e.constraints)
    }

    fn linearise(
        &mut self,
        x: &Unknowns<D, M>,
        e: &Evaluation<D>,
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output, f64>> {
        let jac = self.system.jacobian(x, &e.pointwise);
        let norms = jac.norms();
        if !norms.is_finite() {
            let at = Location::Newton(iteration);
            return Err(Error::NotFinite { at });
        }
        self.jacobian = Some((jac, norms));
        Ok(ControlFlow::Continue(norms.inf))
    }

    fn converged(&mut self, c: Converging<'_, Self>) -> Result<Self::Output> {
        // As for the unconstrained problems: a solution whose Newton system is singular to
        // working precision is round-off, not an answer.
        let at = c.at();
        let jac = self.solve(&c.q, &c.evaluation.rows, c.scratch, at)?;
        let step = c.scratch.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        let correction = if c.residual > 0.0 {
            step / c.residual
        } else {
            0.0
        };
        let unknowns = c.scratch.len();
        let inverse = inverse_iteration(unknowns, |v| jac.solve_inplace(v));
        let inf = self.jacobian.as_ref().map_or(0.0, |(_, norms)| norms.inf);
        let condition = condition_bound(inf, inverse, unknowns, correction);
        if condition >= NUMERICALLY_SINGULAR {
            return Err(Error::IllConditioned { at, condition });
        }
        Ok((c.q.q, c.q.mu, c.iteration))
    }

    fn direction(
        &mut self,
        (x, e): (&Unknowns<D, M>, &mut Evaluation<D>),
        _: (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output>> {
        self.solve(x, &e.rows, delta, Location::Newton(iteration))?;
        Ok(ControlFlow::Continue(()))
    }
}

/// `w` at the initial nodes `q` (see [`System`]); 1 where either scale is zero or not finite.
fn weight<L, C, const D: usize, const M: usize>(
    disc: &Discretisation<'_, L, D>,
    constraint: &C,
    scheme: Scheme,
    q: &[Vector<D>],
) -> Result<f64>
where
    L: Lagrangian<D> + ?Sized,
    C: Constraint<D, M> + ?Sized,
{
    let pointwise = disc.pointwise(q).map_err(|_| Error::NotFinite {
        at: Location::Newton(0),
    })?;
    let rows = disc.row_scale(scheme, &pointwise);
    let g = q
        .iter()
        .fold(0.0f64, |m, x| m.max(constraint.jacobian(x).amax()));
    let size = q.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let weight = rows / (g * if size > 0.0 { size } else { 1.0 });
    Ok(if weight.is_finite() && weight > 0.0 {
        weight
    } else {
        1.0
    })
}
