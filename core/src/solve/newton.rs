//! Newton's method: the `d`-dimensional step solve of the initial value problems, and the
//! stopping rule and line search of the global systems.

use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::solve_small;
use crate::options::NewtonOptions;
use crate::step::{Step, residual as step_residual};

/// Whether Newton has stagnated at round-off: `residual` is within the round-off level of a
/// system with Jacobian max-norm `jacobian` at unknowns of max-norm `unknowns`, *and* the last
/// iteration did not halve it (`previous` is the residual before it; `∞` at the start). While
/// the residual still falls, iterating goes on: the solution error is `cond(J)` times the
/// residual, so stopping early at the floor would cost accuracy.
pub(crate) fn at_round_off(residual: f64, previous: f64, jacobian: f64, unknowns: f64) -> bool {
    residual <= NewtonOptions::ROUND_OFF_FLOOR * f64::EPSILON * jacobian * unknowns
        && residual > 0.5 * previous
}

/// Newton's method on the step equation `G(y) = π` for the newest node `Q_n` (index `n`, for
/// the error), from the initial guess `guess`, with the analytic Jacobian.
///
/// Returns the node and the number of iterations (0 when `guess` already solves the step).
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
    let scale = 1.0 + momentum.amax();
    let mut y = guess;
    let mut residual = f64::INFINITY;
    // Failures at the initial guess belong to the problem (a Lagrangian undefined there, a
    // degenerate ∂²L/∂v²); failures after Newton has moved belong to the iteration.
    let diverged = |iterations, residual| Error::NewtonDidNotConverge {
        at,
        iterations,
        residual,
    };
    for iteration in 0..=options.max_iterations {
        let (r, j) = step_residual(lagrangian, step, &y);
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
        let converged = residual <= options.tolerance * scale
            || at_round_off(residual, previous, j_norm, y.amax());
        // The step is well defined only where its Jacobian is invertible (implicit function
        // theorem): a singular J at a zero residual means every nearby y solves it, so it is an
        // error even then, never a silently returned guess.
        let Some(delta) = solve_small(&j, &r) else {
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
