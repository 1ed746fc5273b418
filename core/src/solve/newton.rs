//! Newton's method: the `d`-dimensional step solve of the initial value problems, and (in
//! `global`) the iteration and line search of the global systems.

mod global;

pub(crate) use global::{Converging, GlobalSystem, Iterate, solve_global, two_norm};

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

/// One step equation `G(y) = π` as Newton's method sees it, in either storage: the residual
/// at the current iterate, the solve for the correction, and the update. The iteration itself
/// ([`newton`]: its stopping rule, its round-off floor, the choice of its errors) is written
/// once for both.
pub(crate) trait StepIteration {
    /// Evaluates the residual at the current iterate: its max-norm (NaN when any entry, or the
    /// Jacobian where it comes with the residual, is not finite) and the scale of the
    /// equation's terms (`‖π‖∞` and the sizes of the terms `G(y)` sums).
    fn residual(&mut self) -> (f64, f64);

    /// Linearises at the current iterate and solves for the correction: `‖J‖∞` (NaN when
    /// the Jacobian is not finite) and whether `J` is regular.
    fn solve(&mut self) -> (f64, bool);

    /// `‖y‖∞` of the current iterate.
    fn size(&self) -> f64;

    /// Moves the iterate by the correction; `false` when the new iterate is not finite.
    fn update(&mut self) -> bool;
}

/// Newton's method on a step equation from its initial iterate, for the step at `at`: the
/// number of iterations (0 when the initial iterate already solves it).
///
/// It stops when the residual is within `tolerance` of the scale of the equation's terms (no
/// absolute part, so that `c L` stops where `L` does), or at round-off ([`at_round_off`]).
/// Failures at the initial iterate belong to the problem (a Lagrangian undefined there:
/// [`Error::NotFinite`]; a degenerate `∂²L/∂v²`: [`Error::SingularJacobian`]), failures after
/// Newton has moved belong to the iteration ([`Error::NewtonDidNotConverge`] with the last
/// residual). The step is well defined only where its Jacobian is invertible (implicit
/// function theorem): a singular `J` at a zero residual means every nearby `y` solves it, so
/// it is an error even then, never a silently returned guess. After a step from a regular
/// Jacobian, a converged iterate is `O(|δ|)` from where that Jacobian was formed: its own is
/// not formed again (a third of the linearisations of a step that converges in two
/// iterations).
#[inline]
pub(crate) fn newton(
    system: &mut impl StepIteration,
    options: &NewtonOptions,
    at: Location,
) -> Result<usize> {
    let diverged = |iterations, residual| Error::NewtonDidNotConverge {
        at,
        iterations,
        residual,
    };
    let mut residual = f64::INFINITY;
    for iteration in 0..=options.max_iterations {
        let previous = residual;
        let scale;
        (residual, scale) = system.residual();
        let within = residual <= options.tolerance * scale;
        if residual.is_finite() && iteration > 0 && within {
            return Ok(iteration);
        }
        let (j_norm, regular) = if residual.is_finite() {
            system.solve()
        } else {
            (f64::NAN, false)
        };
        if !j_norm.is_finite() {
            return Err(if iteration == 0 {
                Error::NotFinite { at }
            } else {
                diverged(iteration, previous)
            });
        }
        // `‖y‖∞` only where the floor can apply (the residual did not halve): a pass saved
        // at every iteration of a converging Newton.
        let converged = within
            || (residual > 0.5 * previous
                && at_round_off(residual, previous, j_norm, system.size()));
        if !regular {
            return Err(if iteration == 0 || converged {
                Error::SingularJacobian { at }
            } else {
                diverged(iteration, residual)
            });
        }
        if converged {
            return Ok(iteration);
        }
        if iteration == options.max_iterations {
            break;
        }
        if !system.update() {
            return Err(diverged(iteration + 1, residual));
        }
    }
    Err(diverged(options.max_iterations, residual))
}

/// A step of the const-generic path at its current iterate `y`.
struct FixedStep<'a, L: ?Sized, const D: usize> {
    lagrangian: &'a L,
    step: &'a Step<D>,
    momentum_size: f64,
    band: Option<usize>,
    y: Vector<D>,
    r: Vector<D>,
    j: Matrix<D>,
    delta: Vector<D>,
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> StepIteration for FixedStep<'_, L, D> {
    #[inline(always)]
    fn residual(&mut self) -> (f64, f64) {
        let (r, j, terms) = residual_and_terms(self.lagrangian, self.step, &self.y);
        (self.r, self.j) = (r, j);
        let finite = r.iter().chain(j.iter()).all(|c| c.is_finite());
        let residual = if finite { r.amax() } else { f64::NAN };
        (residual, self.momentum_size.max(terms))
    }

    #[inline(always)]
    fn solve(&mut self) -> (f64, bool) {
        let j_norm = self
            .j
            .row_iter()
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        match solve_step(&self.j, &self.r, self.band) {
            Some(delta) => {
                self.delta = delta;
                (j_norm, true)
            }
            None => (j_norm, false),
        }
    }

    fn size(&self) -> f64 {
        self.y.amax()
    }

    #[inline(always)]
    fn update(&mut self) -> bool {
        self.y -= self.delta;
        self.y.iter().all(|c| c.is_finite())
    }
}

/// Newton's method ([`newton`]) on the step equation `G(y) = π` for the newest node `Q_n`
/// (index `n`, for the error), from the initial guess `guess`, with the analytic Jacobian.
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
    let at = Location::Step(n);
    if !step.momentum.iter().all(|c| c.is_finite()) {
        return Err(Error::NotFinite { at });
    }
    let mut system = FixedStep {
        lagrangian,
        step,
        momentum_size: step.momentum.amax(),
        band: step_band(lagrangian),
        y: guess,
        r: Vector::<D>::zeros(),
        j: Matrix::<D>::zeros(),
        delta: Vector::<D>::zeros(),
    };
    let iterations = newton(&mut system, options, at)?;
    Ok((system.y, iterations))
}
