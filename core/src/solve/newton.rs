//! Newton's method: the `d`-dimensional step solve of the initial value problems, and the
//! stopping rule and line search of the global systems.

use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::linalg::{BandedMatrix, solve_small};
use crate::options::NewtonOptions;
use crate::step::{Step, residual_and_terms};

/// Whether Newton has stagnated at round-off: `residual` is within the round-off level of a
/// system with Jacobian max-norm `jacobian` at unknowns of max-norm `unknowns`, *and* the last
/// iteration did not halve it (`previous` is the residual before it; `∞` at the start). While
/// the residual still falls, iterating goes on: the solution error is `cond(J)` times the
/// residual, so stopping early at the floor would cost accuracy.
pub(crate) fn at_round_off(residual: f64, previous: f64, jacobian: f64, unknowns: f64) -> bool {
    residual <= NewtonOptions::ROUND_OFF_FLOOR * f64::EPSILON * jacobian * unknowns
        && residual > 0.5 * previous
}

/// The smallest dimension at which a step Jacobian with a narrow band is factorised as a band
/// matrix (measured 1.5–1.6× faster than the dense path at `D = 16`, BENCHMARKS.md; smaller
/// models keep the dense elimination on the stack, which allocates nothing).
const BANDED_FROM: usize = 16;

/// The half-bandwidth the step Jacobians of `lagrangian` are factorised with, or `None` for
/// the dense path. Every step kind's Jacobian is a linear combination of the blocks `xx`,
/// `xv`, `xvᵀ`, `vv` (at one point, or at the points of an interval's quadrature), so it has
/// the Hessian's band.
fn step_band<const D: usize, L: Lagrangian<D> + ?Sized>(lagrangian: &L) -> Option<usize> {
    if D < BANDED_FROM {
        return None;
    }
    lagrangian.hessian_bandwidth().filter(|&b| 2 * b + 1 < D)
}

/// Solves `J δ = r`: by banded LU with half-bandwidth `band` (`O(D b²)`), or densely
/// (`O(D³)`). `None` when `J` is singular, to the same relative threshold either way. A
/// Jacobian with an entry outside the claimed band (a Lagrangian whose bandwidth promise is
/// wrong) takes the dense path, so a wrong claim costs speed, never the answer.
fn solve_step<const D: usize>(
    j: &Matrix<D>,
    r: &Vector<D>,
    band: Option<usize>,
) -> Option<Vector<D>> {
    let Some(b) = band else {
        return solve_small(j, r);
    };
    let outside = (0..D).any(|i| (0..D).any(|c| i.abs_diff(c) > b && j[(i, c)] != 0.0));
    if outside {
        return solve_small(j, r);
    }
    let mut banded = BandedMatrix::zeros(D, b, b);
    for i in 0..D {
        for c in i.saturating_sub(b)..(i + b + 1).min(D) {
            banded.add(i, c, j[(i, c)]);
        }
    }
    banded.factorize().ok()?;
    let mut x = *r;
    banded.solve_inplace(x.as_mut_slice());
    Some(x)
}

/// Newton's method on the step equation `G(y) = π` for the newest node `Q_n` (index `n`, for
/// the error), from the initial guess `guess`, with the analytic Jacobian.
///
/// Returns the node and the number of iterations (0 when `guess` already solves the step).
/// A large model with a narrow [`Lagrangian::hessian_bandwidth`] has its Jacobian factorised
/// as a band matrix; the Jacobian itself, its norm and every error are the dense path's.
pub(crate) fn newton_step<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    step: &Step<D>,
    guess: Vector<D>,
    n: usize,
    options: &NewtonOptions,
) -> Result<(Vector<D>, usize)> {
    let momentum = &step.momentum;
    let at = Location::Step(n);
    if !momentum.iter().all(|c| c.is_finite()) {
        return Err(Error::NotFinite { at });
    }
    let momentum_size = momentum.amax();
    let mut y = guess;
    let mut residual = f64::INFINITY;
    let band = step_band(lagrangian);
    // Failures at the initial guess belong to the problem (a Lagrangian undefined there, a
    // degenerate ∂²L/∂v²); failures after Newton has moved belong to the iteration.
    let diverged = |iterations, residual| Error::NewtonDidNotConverge {
        at,
        iterations,
        residual,
    };
    for iteration in 0..=options.max_iterations {
        let (r, j, terms) = residual_and_terms(lagrangian, step, &y);
        if !r.iter().chain(j.iter()).all(|c| c.is_finite()) {
            return Err(if iteration == 0 {
                Error::NotFinite { at }
            } else {
                diverged(iteration, residual)
            });
        }
        let previous = residual;
        residual = r.amax();
        let j_norm = j
            .row_iter()
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        // The scale of the equation: the terms it balances, `π` and those of `G(y)`. No
        // absolute part, so that `c L` stops where `L` does.
        let scale = momentum_size.max(terms);
        let converged = residual <= options.tolerance * scale
            || at_round_off(residual, previous, j_norm, y.amax());
        // The step is well defined only where its Jacobian is invertible (implicit function
        // theorem): a singular J at a zero residual means every nearby y solves it, so it is an
        // error even then, never a silently returned guess.
        let Some(delta) = solve_step(&j, &r, band) else {
            return Err(if iteration == 0 || converged {
                Error::SingularJacobian { at }
            } else {
                diverged(iteration, residual)
            });
        };
        if converged {
            return Ok((y, iteration));
        }
        if iteration == options.max_iterations {
            break;
        }
        y -= delta;
        if !y.iter().all(|c| c.is_finite()) {
            return Err(diverged(iteration + 1, residual));
        }
    }
    Err(diverged(options.max_iterations, residual))
}

/// The line search of the global (boundary value) Newton iterations: tries `q − λ δ` on the
/// interior nodes (`δ` flattened, node `k` at `δ[(k−1)d..kd]`) for `λ = 1, ½, ¼, …` and accepts
/// the first trial whose max-norm residual is below `residual`. Below `λ = 1/32` it takes the
/// shortest step anyway and lets the iteration count decide (an error evaluating that last trial
/// is returned). `evaluate` gives a trial's evaluation and its residual max-norm.
pub(crate) fn backtrack<const D: usize, E>(
    q: &[Vector<D>],
    delta: &[f64],
    residual: f64,
    mut evaluate: impl FnMut(&[Vector<D>]) -> Result<(E, f64)>,
) -> Result<(Vec<Vector<D>>, E, f64)> {
    let n = q.len() - 1;
    let mut lambda = 1.0;
    loop {
        let trial: Vec<Vector<D>> = (0..=n)
            .map(|k| {
                if k == 0 || k == n {
                    q[k]
                } else {
                    q[k] - Vector::<D>::from_column_slice(&delta[(k - 1) * D..k * D]) * lambda
                }
            })
            .collect();
        let last = lambda < 1.0 / 32.0;
        match evaluate(&trial) {
            Ok((eval, res)) if res < residual || last => return Ok((trial, eval, res)),
            Err(e) if last => return Err(e),
            _ => lambda *= 0.5,
        }
    }
}
