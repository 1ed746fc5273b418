//! [`Problem`]'s comparisons of the two schemes: the problem tells the comparison what it
//! needs ([`Compares`]) and solves each grid of a run.

use super::Problem;
use crate::compare::convergence::Convergence;
use crate::compare::{self, CompareOptions, Compares, Comparison, Study};
use crate::discretisation::Discretisation;
use crate::embedding::{Embedding, Scheme};
use crate::error::Result;
use crate::grid::Grid;
use crate::lagrangian::{IntoVector, Lagrangian, Vector};
use crate::solve::bvp;
use crate::solve::ivp::Ivp;
use crate::solve::solution::Solution;
use crate::solve::start::Start;
use crate::stack::with_room_for;

/// The kinds of problem a comparison names.
const IVP: &str = "initial value problem";
const BVP: &str = "boundary value problem";

/// A problem as the comparison sees it (a private type, so that what the comparison needs is
/// no part of `Problem`'s public interface).
struct Comparer<'p, 'l, L: ?Sized, const D: usize>(&'p Problem<'l, L, D>);

impl<L: Lagrangian<D> + ?Sized, const D: usize> Compares for Comparer<'_, '_, L, D> {
    type Solution = Solution<D>;

    fn grid(&self) -> Grid {
        *self.0.discretisation.grid()
    }

    fn embedding(&self) -> Embedding {
        *self.0.discretisation.embedding()
    }

    fn depends_on_t(&self) -> bool {
        self.0.discretisation.lagrangian().dependence().t
    }

    fn is_forced(&self) -> bool {
        self.0.discretisation.lagrangian().is_forced()
    }

    fn energy_and_residual(
        &self,
        scheme: Scheme,
        solution: &Solution<D>,
    ) -> Result<(Vec<f64>, f64)> {
        let energy = self.0.discretisation.energy(&solution.q)?;
        let residual = self
            .0
            .discretisation
            .relative_residual(scheme, &solution.q)?;
        Ok((energy, residual))
    }
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// This problem's Lagrangian, embedding and options on `grid`.
    fn on_grid(&self, grid: Grid) -> Discretisation<'_, L, D> {
        let d = &self.discretisation;
        Discretisation::new(d.lagrangian(), grid, *d.embedding())
    }

    /// Solves the initial value problem `(q0, v0)` from `start` with a scheme on a grid.
    fn ivp_solver(
        &self,
        q0: Vector<D>,
        v0: Vector<D>,
        start: Start,
    ) -> impl Fn(Scheme, Grid) -> Result<Solution<D>> {
        move |scheme, grid| {
            with_room_for::<D, _>(|| {
                Ivp::new(&self.on_grid(grid), &self.options).solve(scheme, q0, v0, start)
            })
        }
    }

    /// Solves the boundary value problem `(qa, qb)` from the straight line with a scheme on a
    /// grid.
    fn bvp_solver(
        &self,
        qa: Vector<D>,
        qb: Vector<D>,
    ) -> impl Fn(Scheme, Grid) -> Result<Solution<D>> {
        move |scheme, grid| {
            let guess = bvp::straight_line(qa, qb, grid.n())?;
            with_room_for::<D, _>(|| bvp::solve(&self.on_grid(grid), &self.options, scheme, guess))
        }
    }

    /// The study of `levels` grids from this problem's, as `options` time it.
    fn study(
        &self,
        kind: &'static str,
        options: &CompareOptions<'_, Vector<D>>,
        levels: usize,
    ) -> Study {
        Study {
            kind,
            grid: *self.discretisation.grid(),
            levels,
            timing: options.timing,
        }
    }

    /// Compares both schemes on the initial value problem `q(a) = q0`, `q̇(a) = v0` (discrete
    /// Legendre start, no reference, observed order by self-convergence).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_ivp(1.0, 0.0)?;
    /// assert!(comparison.max_distance > 0.0); // Gauss-FDE− is not coherent
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_ivp(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Comparison<Solution<D>>>
    where
        L: Sync,
    {
        self.compare_ivp_with(q0, v0, &CompareOptions::default())
    }

    /// [`compare_ivp`](Self::compare_ivp) with options.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = varembed::CompareOptions { reference: varembed::Reference::Exact(&exact), ..Default::default() };
    /// let comparison = problem.compare_ivp_with(1.0, 0.0, &options)?;
    /// assert!(comparison.variational.error.unwrap() < 0.1);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_ivp_with(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        options: &CompareOptions<'_, Vector<D>>,
    ) -> Result<Comparison<Solution<D>>>
    where
        L: Sync,
    {
        let solve = self.ivp_solver(q0.into_vector(), v0.into_vector(), options.start);
        compare::compare(&Comparer(self), IVP, options, solve)
    }

    /// Compares both schemes on the boundary value problem `Q_0 = qa`, `Q_N = qb`.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_bvp(0.0, 1.0)?;
    /// assert!(comparison.direct.residual_of_other > 0.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_bvp(
        &self,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<Comparison<Solution<D>>>
    where
        L: Sync,
    {
        self.compare_bvp_with(qa, qb, &CompareOptions::default())
    }

    /// [`compare_bvp`](Self::compare_bvp) with options (the start is not used).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let options = varembed::CompareOptions { order: false, ..Default::default() };
    /// let comparison = problem.compare_bvp_with(0.0, 1.0, &options)?;
    /// assert_eq!(comparison.extra_solves, 0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_bvp_with(
        &self,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
        options: &CompareOptions<'_, Vector<D>>,
    ) -> Result<Comparison<Solution<D>>>
    where
        L: Sync,
    {
        let solve = self.bvp_solver(qa.into_vector(), qb.into_vector());
        compare::compare(&Comparer(self), BVP, options, solve)
    }

    /// Solves the initial value problem `q(a) = q0`, `q̇(a) = v0` with `scheme` on
    /// `N, 2N, …, 2^{levels−1} N` steps (`N` this problem's), with `options.start`, timing each
    /// solve and measuring its error against `options.reference`. A size that fails is recorded
    /// in [`Convergence::failures`] and the run goes on.
    ///
    /// Timed ([`CompareOptions::timing`], the default), the grids are solved one after the
    /// other; untimed, in parallel, with the same solutions bit for bit and no wall times. The
    /// solves may share the Lagrangian between threads, hence `L: Sync`; so do the
    /// comparisons'.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| Vector::<1>::new(t.cos());
    /// let options = varembed::CompareOptions { reference: varembed::Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 3);
    /// assert_eq!(run.levels.len(), 3);
    /// assert!((run.orders()[1] - 1.0).abs() < 0.2);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn convergence_ivp(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        options: &CompareOptions<'_, Vector<D>>,
        levels: usize,
    ) -> Convergence<Solution<D>>
    where
        L: Sync,
    {
        let solve = self.ivp_solver(q0.into_vector(), v0.into_vector(), options.start);
        let study = self.study(IVP, options, levels);
        compare::convergence(&study, scheme, &options.reference, |grid| {
            solve(scheme, grid)
        })
    }

    /// [`convergence_ivp`](Self::convergence_ivp) for the boundary value problem `Q_0 = qa`,
    /// `Q_N = qb` (the start is not used).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let options = varembed::CompareOptions::default();
    /// let run = problem.convergence_bvp(Scheme::Variational, 0.0, 1.0, &options, 2);
    /// assert_eq!(run.levels[1].n(), 20);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn convergence_bvp(
        &self,
        scheme: Scheme,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
        options: &CompareOptions<'_, Vector<D>>,
        levels: usize,
    ) -> Convergence<Solution<D>>
    where
        L: Sync,
    {
        let solve = self.bvp_solver(qa.into_vector(), qb.into_vector());
        let study = self.study(BVP, options, levels);
        compare::convergence(&study, scheme, &options.reference, |grid| {
            solve(scheme, grid)
        })
    }

    /// The comparison at this problem's grid from a run of each scheme that solved it (same
    /// data and options, e.g. the sweeps of a work–precision report): nothing is solved again,
    /// the solutions, errors and wall times are the runs', and each order is
    /// [`Convergence::order_at`] this `N`. Errors if a run failed at this `N` (that failure), or
    /// is of the wrong scheme, or did not solve this problem's grid and embedding.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let options = varembed::CompareOptions::default();
    /// let direct = problem.convergence_ivp(Scheme::Direct, 1.0, 0.0, &options, 2);
    /// let variational = problem.convergence_ivp(Scheme::Variational, 1.0, 0.0, &options, 2);
    /// let comparison = problem.compare_runs(&direct, &variational)?;
    /// assert_eq!(comparison.grid.n(), 10);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_runs(
        &self,
        direct: &Convergence<Solution<D>>,
        variational: &Convergence<Solution<D>>,
    ) -> Result<Comparison<Solution<D>>> {
        compare::compare_runs(&Comparer(self), direct, variational)
    }
}
