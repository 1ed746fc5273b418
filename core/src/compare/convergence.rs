//! [`Convergence`]: one scheme of one problem solved on `N, 2N, 4N, …`, and its [`Level`]s.

use super::compared::ComparedSolution;
use super::order::{OrderStatus, observed_order, observed_orders, order_statuses};
use crate::embedding::Scheme;
use crate::error::Error;
use std::time::Duration;

/// One solved grid of a [`Convergence`] run.
///
/// ```
/// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let exact = |t: f64| Vector::<1>::new(t.cos());
/// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
/// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
/// let level = run.level(40).expect("solved");
/// assert!(level.error.unwrap() < 0.05 && level.wall_time.unwrap().as_secs() < 1);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Level<S> {
    /// The solution ([`Solution<D>`](crate::Solution) or [`DynSolution`](crate::DynSolution));
    /// its grid has the level's `N`.
    pub solution: S,
    /// Wall time of the solve (measured once: each grid is solved once); `None` when the run
    /// was not timed ([`CompareOptions::timing`](crate::CompareOptions::timing) off, the grids
    /// solved in parallel).
    pub wall_time: Option<Duration>,
    /// `max_k |Q_k − q(t_k)|∞` against the reference, if there is one.
    pub error: Option<f64>,
}

impl<S: ComparedSolution> Level<S> {
    /// The number of steps `N`.
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// assert_eq!(run.levels[2].n(), 80);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn n(&self) -> usize {
        self.solution.grid().n()
    }
}

/// One scheme of one problem solved on `N, 2N, 4N, …` steps over the same interval
/// ([`Problem::convergence_ivp`](crate::Problem::convergence_ivp), [`Problem::convergence_bvp`](crate::Problem::convergence_bvp);
/// [`DynProblem::convergence_ivp`](crate::DynProblem::convergence_ivp),
/// [`DynProblem::convergence_bvp`](crate::DynProblem::convergence_bvp) for a run-time
/// dimension, `S` = [`DynSolution`](crate::DynSolution)): every solution with its error and
/// wall time, and the [`observed_order`] between successive grids.
///
/// ```
/// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let exact = |t: f64| Vector::<1>::new(t.cos());
/// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
/// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
/// assert!(run.failures.is_empty());
/// assert_eq!(run.orders().len(), 2);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Convergence<S> {
    /// What was solved: "initial value problem" or "boundary value problem".
    pub kind: &'static str,
    /// The scheme.
    pub scheme: Scheme,
    /// Which reference the errors are against ("none" without one).
    pub reference: String,
    /// The grids that solved, by increasing `N`.
    pub levels: Vec<Level<S>>,
    /// The sizes whose solve failed, with the error (e.g. Newton not converging on a coarse
    /// grid): reported, not hidden. The orders skip them.
    pub failures: Vec<(usize, Error)>,
}

impl<S: ComparedSolution> Convergence<S> {
    /// The level on `n` steps, if it solved.
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// assert!(run.level(40).is_some() && run.level(30).is_none());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn level(&self, n: usize) -> Option<&Level<S>> {
        self.levels.iter().find(|level| level.n() == n)
    }

    /// `(N, e_N)` per level, the errors the orders are computed from: the error against the
    /// reference, or without one the self-convergence estimate `‖Q_N − Q_{N'}‖` on the nodes
    /// of the `N` grid, `N'` the next level (so the last level has none).
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// let errors = run.error_estimates();
    /// assert_eq!(errors[0].0, 20);
    /// assert!(errors[1].1 < errors[0].1);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn error_estimates(&self) -> Vec<(usize, f64)> {
        self.scaled_estimates()
            .into_iter()
            .map(|(n, e, _)| (n, e))
            .collect()
    }

    /// [`error_estimates`](Self::error_estimates) with the size of the solutions each is
    /// measured on (`max_k |Q_k|∞`), the scale of its round-off.
    fn scaled_estimates(&self) -> Vec<(usize, f64, f64)> {
        let size = |level: &Level<S>| level.solution.size();
        self.levels
            .iter()
            .enumerate()
            .filter_map(|(i, level)| match level.error {
                Some(e) => Some((level.n(), e, size(level))),
                None => {
                    let next = self.levels.get(i + 1)?;
                    level
                        .solution
                        .distance_on_coarse_nodes(&next.solution)
                        .map(|e| (level.n(), e, size(level).max(size(next))))
                }
            })
            .collect()
    }

    /// The [`OrderStatus`] of each of the [`orders`](Self::orders).
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// // The last order has no next one to be checked against.
    /// assert_eq!(run.order_statuses().last(), Some(&varembed::OrderStatus::Unchecked));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn order_statuses(&self) -> Vec<OrderStatus> {
        order_statuses(&self.scaled_estimates())
    }

    /// The [`OrderStatus`] of [`order_at`](Self::order_at)`(n)`, if there is that order.
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// assert_eq!(run.order_status_at(40), Some(varembed::OrderStatus::Unchecked));
    /// assert_eq!(run.order_status_at(80), None);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn order_status_at(&self, n: usize) -> Option<OrderStatus> {
        let errors = self.scaled_estimates();
        let i = errors.iter().position(|&(m, _, _)| m == n)?;
        order_statuses(&errors[i..]).first().copied()
    }

    /// The [`observed_order`] between each pair of successive [`error_estimates`]
    /// (`log₂(e_N / e_{2N})` on a run without failures).
    ///
    /// [`error_estimates`]: Self::error_estimates
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// assert!(run.orders().iter().all(|p| (p - 1.0).abs() < 0.2)); // first order
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn orders(&self) -> Vec<f64> {
        observed_orders(&self.error_estimates())
    }

    /// The [`observed_order`] from the level on `n` steps to the next one, if both have an
    /// error estimate: entry `i` of [`orders`](Self::orders) when `n` is the `i`-th.
    ///
    /// ```
    /// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3); // N = 20, 40, 80
    /// assert_eq!(run.order_at(40), Some(run.orders()[1]));
    /// assert_eq!(run.order_at(80), None);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn order_at(&self, n: usize) -> Option<f64> {
        let errors = self.error_estimates();
        let i = errors.iter().position(|&(m, _)| m == n)?;
        errors
            .get(i + 1)
            .map(|&fine| observed_order(errors[i], fine))
    }
}
