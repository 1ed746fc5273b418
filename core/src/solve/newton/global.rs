//! The Newton iteration of the global (boundary value) systems, written once for every
//! storage and linear solver ([`solve_global`] over [`GlobalSystem`]), and its line search.

use super::at_round_off;
use crate::error::{Error, Location, Result};
use crate::lagrangian::Vector;
use crate::linalg::max_norm;
use crate::options::NewtonOptions;
use std::ops::ControlFlow;

/// A global (boundary value) system as Newton's method sees it, in any storage and with any
/// linear solver: its evaluation at an iterate, its linearisation, the Newton direction, and
/// what it returns at convergence. The iteration itself ([`solve_global`]: the stopping rule,
/// its round-off floor, the line search, the errors) is written once for all of them.
pub(crate) trait GlobalSystem {
    /// The unknowns: what the line search moves.
    type Iterate: Iterate;
    /// The residual at an iterate, with what the linearisation reads there.
    type Evaluation;
    /// What the iteration returns: at convergence, or where a hook stops it early (a linear
    /// solver that gives way to another, with its reason).
    type Output;

    /// The evaluation at `q` for Newton iteration `iteration`, the residual's max-norm and its
    /// 2-norm (the line search's merit); [`Error::NotFinite`] at that iteration when any value
    /// is not finite.
    fn evaluate(
        &mut self,
        q: &Self::Iterate,
        iteration: usize,
    ) -> Result<(Self::Evaluation, f64, f64)>;

    /// Whether the residual at `e` (max-norm `residual`) is within `tolerance` of the scale of
    /// the terms its rows sum (relative only, so that `c L` stops where `L` does).
    fn within(&self, e: &Self::Evaluation, residual: f64, tolerance: f64) -> bool;

    /// Linearises at `q` for Newton iteration `iteration`: `‖J‖∞`, for the round-off floor; or
    /// an early stop. Where the Jacobian is applied by products and formed only when a
    /// direction needs it (the fractional fast path), this only returns a bound of `‖J‖∞` at
    /// the last linearisation, or at the second derivatives held for the first (0 before
    /// either).
    fn linearise(
        &mut self,
        q: &Self::Iterate,
        e: &Self::Evaluation,
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output, f64>>;

    /// At an iterate that meets the stopping rule: the checks of the solution (an isolated
    /// solution: a Jacobian not singular to working precision; the ill-posedness measure) and
    /// the output. `scratch` is a vector of the unknowns' length, free for the checks.
    fn converged(&mut self, at: Converging<'_, Self>) -> Result<Self::Output>;

    /// The Newton direction `δ = J⁻¹ r` at the linearisation of the `current` iterate and
    /// evaluation, to the linear solver's accuracy, into `delta`; or an early stop. `residual`
    /// holds the max-norm and the 2-norm of the evaluation's residual. The evaluation is not
    /// read after this call (only [`recycle`](Self::recycle)d): the system may take its
    /// vectors for the linear solve.
    fn direction(
        &mut self,
        current: (&Self::Iterate, &mut Self::Evaluation),
        residual: (f64, f64),
        delta: &mut [f64],
        iteration: usize,
    ) -> Result<ControlFlow<Self::Output>>;

    /// An evaluation the iteration has left behind (before the line search, which evaluates
    /// trials without it): its allocations, for the next.
    fn recycle(&mut self, _e: Self::Evaluation) {}
}

/// What [`GlobalSystem::converged`] receives: the converged iterate, its evaluation and
/// residual max-norm, the Newton iteration, and a free vector of the unknowns' length.
pub(crate) struct Converging<'a, S: GlobalSystem + ?Sized> {
    pub(crate) q: S::Iterate,
    pub(crate) evaluation: S::Evaluation,
    pub(crate) residual: f64,
    pub(crate) iteration: usize,
    pub(crate) scratch: &'a mut [f64],
}

impl<S: GlobalSystem + ?Sized> Converging<'_, S> {
    /// Where the iteration converged.
    pub(crate) fn at(&self) -> Location {
        Location::Newton(self.iteration)
    }
}

/// Newton's method on a global system of `unknowns` unknowns from `q`, globalised by
/// [`LineSearch`]. It stops when [`GlobalSystem::within`] the tolerance of `options`, or at
/// round-off ([`at_round_off`], with the linearisation's `‖J‖∞` and the iterate's size);
/// [`Error::NewtonDidNotConverge`] with the last residual when `options.max_iterations`
/// iterations did not get there. The linearisation comes before the test, so that a Jacobian
/// that is not finite is reported even at a converged iterate, and the converged hook's
/// checks read the Jacobian there.
pub(crate) fn solve_global<S: GlobalSystem>(
    system: &mut S,
    mut q: S::Iterate,
    unknowns: usize,
    options: &NewtonOptions,
) -> Result<S::Output> {
    let (mut current, mut res, mut merit) = system.evaluate(&q, 0)?;
    let mut line_search = LineSearch::new(merit);
    let mut previous = f64::INFINITY;
    let mut delta = vec![0.0; unknowns];
    for iteration in 0..=options.max_iterations {
        let j_norm = match system.linearise(&q, &current, iteration)? {
            ControlFlow::Continue(j_norm) => j_norm,
            ControlFlow::Break(output) => return Ok(output),
        };
        if system.within(&current, res, options.tolerance)
            || at_round_off(res, previous, j_norm, q.size())
        {
            return system.converged(Converging {
                q,
                evaluation: current,
                residual: res,
                iteration,
                scratch: &mut delta,
            });
        }
        if iteration == options.max_iterations {
            break;
        }
        let residual = (res, merit);
        if let ControlFlow::Break(output) =
            system.direction((&q, &mut current), residual, &mut delta, iteration)?
        {
            return Ok(output);
        }
        // The line search reads only the current merit: the current evaluation is spent
        // before the trials are evaluated, so that its memory is not held beside theirs.
        system.recycle(current);
        let next_res;
        (q, current, next_res, merit) = line_search.step(&q, merit, &delta, |trial| {
            system.evaluate(trial, iteration + 1)
        })?;
        (previous, res) = (res, next_res);
    }
    Err(Error::NewtonDidNotConverge {
        at: Location::Newton(options.max_iterations),
        iterations: options.max_iterations,
        residual: res,
    })
}

/// Sufficient decrease of a damped step: `‖r(q − λδ)‖₂ ≤ (1 − ARMIJO λ) ‖r(q)‖₂`.
const ARMIJO: f64 = 1e-4;

/// Full Newton steps taken in a row without improving on the best residual before the line
/// search returns to the best iterate and damps from there.
const WATCHDOG: usize = 8;

/// A full step is never taken when its residual exceeds the best one by more than this
/// factor: far outside the region where Newton converges, damping is the better bet.
const GROWTH: f64 = 1e8;

/// The shortest damped step: below it the line search takes the best trial it saw.
const SHORTEST: f64 = 1.0 / 64.0;

/// The globalisation of the boundary value Newton iterations: a line search in the 2-norm of
/// the residual with a watchdog (Chamberlain, Powell, Lemaréchal and Pedersen, 1982).
///
/// Each iteration first tries the full Newton step `q − δ` (`δ` flat over the unknowns, as
/// [`Iterate::along`] reads it) and takes it when it decreases the residual's 2-norm
/// sufficiently. It also takes it when it does not, up to [`WATCHDOG`] times in a row and
/// within [`GROWTH`] of the best residual so far: Newton's full steps often pass through a
/// larger residual on their way into the region of quadratic convergence, and a line search
/// that insists on decrease at every step stalls there, in a valley of the merit function,
/// with steps of `1/32` that lead nowhere. When the watchdog runs out, the iteration returns
/// to the best iterate and damps from there: `λ = ½, ¼, …` until `‖r‖₂` decreases by the
/// Armijo factor, or, below `λ = 1/64`, the best trial seen. The merit is the 2-norm, not the
/// max-norm of the stopping rule: the Newton direction (exact, or inexact within a forcing
/// term `η < 1` in the 2-norm) is a descent direction of `‖r‖₂²`, of no other norm.
pub(crate) struct LineSearch<X> {
    /// The iterate of the smallest merit so far; `None` while that is the current iterate
    /// (every step that improved on it), so that the common case keeps no copy of the nodes.
    best: Option<X>,
    best_merit: f64,
    /// Full steps taken since the best iterate improved.
    free: usize,
}

/// An accepted iterate: nodes, evaluation, residual max-norm and 2-norm.
pub(crate) type Accepted<X, E> = (X, E, f64, f64);

/// The nodes of a boundary value iteration, in either storage: what the line search moves
/// along a Newton direction `δ`, flat over the interior nodes (the end nodes stay).
pub(crate) trait Iterate: Clone {
    /// `q − λ δ` on the interior nodes.
    fn along(&self, delta: &[f64], lambda: f64) -> Self;

    /// The max-norm of every value (the round-off floor's size of the unknowns).
    fn size(&self) -> f64;
}

/// Nodes of a fixed dimension, node `k`'s correction at `δ[(k−1)D..kD]`.
impl<const D: usize> Iterate for Vec<Vector<D>> {
    fn along(&self, delta: &[f64], lambda: f64) -> Self {
        let n = self.len() - 1;
        (0..=n)
            .map(|k| {
                if k == 0 || k == n {
                    self[k]
                } else {
                    self[k] - Vector::<D>::from_column_slice(&delta[(k - 1) * D..k * D]) * lambda
                }
            })
            .collect()
    }
    fn size(&self) -> f64 {
        max_norm(self)
    }
}

/// Flat nodes of a run-time dimension `d`, node `k` at `q[kd..(k+1)d]`: `δ` covers all but
/// the first and last `d` entries, which gives `d`.
impl Iterate for Vec<f64> {
    fn along(&self, delta: &[f64], lambda: f64) -> Self {
        let d = (self.len() - delta.len()) / 2;
        let mut q = self.clone();
        for (q, delta) in q[d..d + delta.len()].iter_mut().zip(delta) {
            *q -= delta * lambda;
        }
        q
    }
    fn size(&self) -> f64 {
        self.iter().fold(0.0, |m, x| m.max(x.abs()))
    }
}

impl<X: Iterate> LineSearch<X> {
    /// From the initial iterate `q` with residual 2-norm `merit`.
    pub(crate) fn new(merit: f64) -> Self {
        LineSearch {
            best: None,
            best_merit: merit,
            free: 0,
        }
    }

    /// Takes `accepted` as the next iterate after `q`, keeping `q` as the best where it was
    /// and the next one is not better.
    fn accept<E>(&mut self, q: &X, accepted: Accepted<X, E>) -> Accepted<X, E> {
        if accepted.3 < self.best_merit {
            self.best = None;
            self.best_merit = accepted.3;
            self.free = 0;
        } else if self.best.is_none() {
            self.best = Some(q.clone());
        }
        accepted
    }

    /// The next iterate from `q` (residual 2-norm `merit`) along the Newton direction `delta`;
    /// `evaluate` gives a trial's evaluation, its residual max-norm and 2-norm. An error
    /// evaluating a trial rejects it; an error at the last trial, with none better, is returned.
    pub(crate) fn step<E>(
        &mut self,
        q: &X,
        merit: f64,
        delta: &[f64],
        mut evaluate: impl FnMut(&X) -> Result<(E, f64, f64)>,
    ) -> Result<Accepted<X, E>> {
        let full = q.along(delta, 1.0);
        let mut best_trial = None;
        if let Ok((e, max, m)) = evaluate(&full) {
            let decrease = m <= (1.0 - ARMIJO) * merit;
            let free = self.free < WATCHDOG && m <= GROWTH * self.best_merit;
            if decrease || free {
                if !decrease {
                    self.free += 1;
                }
                return Ok(self.accept(q, (full, e, max, m)));
            }
            best_trial = Some((full, e, max, m));
        }
        // Damping from an iterate worse than the best would follow a valley away from it:
        // return to the best, damp from there next time.
        if merit > self.best_merit {
            self.free = WATCHDOG;
            let (e, max, m) = evaluate(self.best.as_ref().unwrap_or(q))?;
            let best = self.best.take().unwrap_or_else(|| q.clone());
            return Ok((best, e, max, m));
        }
        let mut lambda = 0.5;
        loop {
            let q_lambda = q.along(delta, lambda);
            match evaluate(&q_lambda) {
                Ok((e, max, m)) => {
                    if m <= (1.0 - ARMIJO * lambda) * merit {
                        return Ok(self.accept(q, (q_lambda, e, max, m)));
                    }
                    if best_trial.as_ref().is_none_or(|b| m < b.3) {
                        best_trial = Some((q_lambda, e, max, m));
                    }
                }
                Err(error) if lambda < SHORTEST => {
                    return match best_trial {
                        Some(b) => Ok(self.accept(q, b)),
                        None => Err(error),
                    };
                }
                Err(_) => {}
            }
            if lambda < SHORTEST {
                let b = best_trial.expect("the last trial was evaluated");
                return Ok(self.accept(q, b));
            }
            lambda *= 0.5;
        }
    }
}

/// The 2-norm of a residual of nodes.
pub(crate) fn two_norm<const D: usize>(r: &[Vector<D>]) -> f64 {
    r.iter().map(|x| x.norm_squared()).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `c (q_k³ + q_k − b_k) = 0` on the interior entries of `q` (one coordinate a node, the
    /// ends fixed): an independent root per node, the scale `c` of the whole system free.
    struct Cubics {
        b: Vec<f64>,
        c: f64,
        /// The Newton iteration at which [`direction`](GlobalSystem::direction) stops early.
        stop_at: Option<usize>,
    }

    impl GlobalSystem for Cubics {
        type Iterate = Vec<f64>;
        type Evaluation = Vec<f64>;
        type Output = (Vec<f64>, usize);

        fn evaluate(&mut self, q: &Vec<f64>, iteration: usize) -> Result<(Vec<f64>, f64, f64)> {
            let interior = &q[1..q.len() - 1];
            let r: Vec<f64> = interior
                .iter()
                .zip(&self.b)
                .map(|(x, b)| self.c * (x * x * x + x - b))
                .collect();
            if !r.iter().all(|x| x.is_finite()) {
                let at = Location::Newton(iteration);
                return Err(Error::NotFinite { at });
            }
            let max = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let merit = r.iter().map(|x| x * x).sum::<f64>().sqrt();
            Ok((r, max, merit))
        }

        fn within(&self, _: &Vec<f64>, residual: f64, tolerance: f64) -> bool {
            let scale = self.c * self.b.iter().fold(0.0f64, |m, b| m.max(b.abs()));
            residual <= tolerance * scale
        }

        fn linearise(
            &mut self,
            q: &Vec<f64>,
            _: &Vec<f64>,
            _: usize,
        ) -> Result<ControlFlow<Self::Output, f64>> {
            let largest = q.iter().fold(0.0f64, |m, x| m.max(3.0 * x * x + 1.0));
            Ok(ControlFlow::Continue(self.c * largest))
        }

        fn converged(&mut self, c: Converging<'_, Self>) -> Result<Self::Output> {
            assert_eq!(c.scratch.len(), self.b.len());
            Ok((c.q, c.iteration))
        }

        fn direction(
            &mut self,
            (q, r): (&Vec<f64>, &mut Vec<f64>),
            _: (f64, f64),
            delta: &mut [f64],
            iteration: usize,
        ) -> Result<ControlFlow<Self::Output>> {
            if self.stop_at == Some(iteration) {
                return Ok(ControlFlow::Break((Vec::new(), iteration)));
            }
            for ((d, x), r) in delta.iter_mut().zip(&q[1..]).zip(r.iter()) {
                *d = r / (self.c * (3.0 * x * x + 1.0));
            }
            Ok(ControlFlow::Continue(()))
        }
    }

    fn start(b: &[f64]) -> Vec<f64> {
        let mut q = vec![0.0; b.len() + 2];
        q[0] = 7.0;
        q[b.len() + 1] = -7.0;
        q
    }

    #[test]
    fn the_global_iteration_finds_the_roots_and_does_not_depend_on_the_scale() {
        let b = vec![0.5, -3.0, 10.0, 1e-3, 2.0];
        let options = NewtonOptions::default();
        let mut runs = Vec::new();
        for c in [1e-9, 1.0, 1e9] {
            let mut system = Cubics {
                b: b.clone(),
                c,
                stop_at: None,
            };
            let (q, iterations) = solve_global(&mut system, start(&b), b.len(), &options).unwrap();
            // The ends stay; each interior entry is the real root of x³ + x = b.
            assert_eq!((q[0], q[b.len() + 1]), (7.0, -7.0));
            for (x, b) in q[1..=b.len()].iter().zip(&b) {
                assert!((x * x * x + x - b).abs() <= 1e-12 * 10.0, "{x} for {b}");
            }
            assert!(iterations > 2 && iterations < 20, "{iterations}");
            runs.push((q, iterations));
        }
        // `c L` runs the same iterates as `L`: the stopping rule is relative.
        assert!(runs.windows(2).all(|w| w[0].1 == w[1].1));
        for w in runs.windows(2) {
            let gap = w[0]
                .0
                .iter()
                .zip(&w[1].0)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(gap <= 1e-13, "{gap}");
        }
    }

    #[test]
    fn an_iteration_that_runs_out_reports_its_last_residual_and_a_hook_may_stop_it() {
        let b = vec![10.0, -20.0];
        let options = NewtonOptions {
            max_iterations: 2,
            ..NewtonOptions::default()
        };
        let mut system = Cubics {
            b: b.clone(),
            c: 1.0,
            stop_at: None,
        };
        match solve_global(&mut system, start(&b), b.len(), &options) {
            Err(Error::NewtonDidNotConverge {
                at,
                iterations,
                residual,
            }) => {
                assert_eq!((at, iterations), (Location::Newton(2), 2));
                assert!(residual > 1e-3 && residual.is_finite(), "{residual}");
            }
            other => panic!("expected NewtonDidNotConverge, got {other:?}"),
        }
        let mut system = Cubics {
            b: b.clone(),
            c: 1.0,
            stop_at: Some(1),
        };
        let (q, iteration) =
            solve_global(&mut system, start(&b), b.len(), &NewtonOptions::default()).unwrap();
        assert_eq!((q.len(), iteration), (0, 1));
        // An evaluation that fails at the start is the problem's error, at iteration 0.
        let mut system = Cubics {
            b: vec![f64::INFINITY],
            c: 1.0,
            stop_at: None,
        };
        let error = solve_global(&mut system, start(&[0.0]), 1, &NewtonOptions::default());
        assert!(
            matches!(
                error,
                Err(Error::NotFinite {
                    at: Location::Newton(0)
                })
            ),
            "{error:?}"
        );
    }
}
