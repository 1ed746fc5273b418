//! [`DynProblem`]'s comparisons of the two schemes, the run-time-dimension counterparts of
//! [`Problem`](crate::Problem)'s: the same columns, order rules and table, with the energy and
//! the other scheme's residual evaluated on the flat nodes by the residual rows the boundary
//! value problem solves.
//!
//! They live here rather than in `dynamic/` because the comparison is the layer above the
//! run-time-dimension solver: it reads the solver, never the other way round.

use super::{
    CompareOptions, Compares, Comparison, Reference, Study, compare, compare_runs, convergence,
};
use crate::dynamic::DynLagrangian;
use crate::dynamic::problem::{DynProblem, DynSolution};
use crate::dynamic::rows::DynRows;
use crate::embedding::{Embedding, Scheme};
use crate::error::{Result, check_len};
use crate::grid::Grid;
use crate::solve::start::Start;

/// The kinds of problem a comparison names.
const IVP: &str = "initial value problem";
const BVP: &str = "boundary value problem";

use super::convergence::Convergence;

/// A problem as the comparison sees it (a private type, so that what the comparison needs is
/// no part of `DynProblem`'s public interface).
struct Comparer<'p, 'l, L: ?Sized>(&'p DynProblem<'l, L>);

impl<L: DynLagrangian + ?Sized> Compares for Comparer<'_, '_, L> {
    type Solution = DynSolution;

    fn grid(&self) -> Grid {
        self.0.grid
    }

    fn embedding(&self) -> Embedding {
        self.0.embedding
    }

    fn depends_on_t(&self) -> bool {
        self.0.lagrangian.dependence().t
    }

    fn is_forced(&self) -> bool {
        self.0.lagrangian.is_forced()
    }

    /// One evaluation of `scheme`'s rows gives both: the rows need `V` and `p = ∂L/∂v` at the
    /// quadrature nodes, which is what the energy reads.
    fn energy_and_residual(
        &self,
        scheme: Scheme,
        solution: &DynSolution,
    ) -> Result<(Vec<f64>, f64)> {
        let DynProblem {
            lagrangian,
            grid,
            embedding,
            ..
        } = *self.0;
        let rows = DynRows::new(lagrangian, grid, embedding, scheme)?;
        let (n, d) = (grid.n(), rows.d);
        check_len("discrete curve Q", (n + 1) * d, solution.q.len())?;
        let mut values = rows.zero_values();
        rows.evaluate(&solution.q, &mut values)?;
        let energy = rows.energies(&solution.q, &values);
        Ok((energy, rows.relative_residual(&values)))
    }
}

impl<L: DynLagrangian + ?Sized> DynProblem<'_, L> {
    /// This problem on `grid`: same model, embedding and solver settings.
    fn on(&self, grid: Grid) -> Self {
        DynProblem {
            lagrangian: self.lagrangian,
            grid,
            embedding: self.embedding,
            newton: self.newton,
            blow_up_guard: self.blow_up_guard,
            bvp_solver: self.bvp_solver,
            start: self.start,
            resolution_check: self.resolution_check,
            posedness_check: self.posedness_check,
        }
    }

    /// Solves the initial value problem `(q0, v0)` from `start` with a scheme on a grid.
    fn ivp_solver<'s>(
        &'s self,
        q0: &'s [f64],
        v0: &'s [f64],
        start: Start,
    ) -> impl Fn(Scheme, Grid) -> Result<DynSolution> + 's {
        move |scheme, grid| self.on(grid).with_start(start).solve_ivp(scheme, q0, v0)
    }

    /// Solves the boundary value problem `(qa, qb)` with a scheme on a grid.
    fn bvp_solver<'s>(
        &'s self,
        qa: &'s [f64],
        qb: &'s [f64],
    ) -> impl Fn(Scheme, Grid) -> Result<DynSolution> + 's {
        move |scheme, grid| self.on(grid).solve_bvp(scheme, qa, qb)
    }

    /// The study of `levels` grids from this problem's, as `options` time it.
    fn study(
        &self,
        kind: &'static str,
        options: &CompareOptions<'_, Vec<f64>>,
        levels: usize,
    ) -> Study {
        Study {
            kind,
            grid: self.grid,
            levels,
            timing: options.timing,
        }
    }

    /// [`Error::WrongLength`](crate::Error::WrongLength) when the reference's value at `a` is not of length `d`: the
    /// error column compares node by node.
    fn check_reference(&self, reference: &Reference<'_, Vec<f64>>) -> Result<()> {
        match reference.curve() {
            Some(q) => check_len(
                "reference value q(a)",
                self.lagrangian.dimension(),
                q(self.grid.a()).len(),
            ),
            None => Ok(()),
        }
    }

    /// Compares both schemes on the initial value problem `q(a) = q0`, `q̇(a) = v0`
    /// (discrete Legendre start, no reference, observed order by self-convergence): the
    /// run-time-dimension [`Problem::compare_ivp`](crate::Problem::compare_ivp), with the same
    /// columns and rules, for the embeddings [`solve_ivp`](Self::solve_ivp) offers.
    ///
    /// A comparison stores every node of every solve (its own and the finer grids' of the
    /// order), `O(N d)` memory per solve; a long run that only needs a few quantities along
    /// the way is [`run_ivp`](Self::run_ivp)'s.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    ///
    /// /// `n` uncoupled unit oscillators.
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// let model = Oscillators { n: 3 };
    /// let grid = Grid::new(0.0, 1.0, 20)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_ivp(&[1.0; 3], &[0.0; 3])?;
    /// assert!(comparison.max_distance > 0.0); // Gauss-FDE− is not coherent
    /// assert_eq!(comparison.direct.solution.len(), 21);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_ivp(&self, q0: &[f64], v0: &[f64]) -> Result<Comparison<DynSolution>>
    where
        L: Sync,
    {
        self.compare_ivp_with(q0, v0, &CompareOptions::default())
    }

    /// [`compare_ivp`](Self::compare_ivp) with options; the reference returns `Vec<f64>` of
    /// length `d` ([`Error::WrongLength`](crate::Error::WrongLength) otherwise); `options.start` is the start of every
    /// solve (see [`with_start`](Self::with_start)).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    /// #     let mut l = 0.0;
    /// #     for i in 0..n { l += 0.5 * (v[i] * v[i] - x[i] * x[i]); }
    /// #     l
    /// # }
    /// use varembed::{CompareOptions, Reference};
    /// let model = Oscillators { n: 3 };
    /// let grid = Grid::new(0.0, 1.0, 20)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| vec![t.cos(); 3];
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let comparison = problem.compare_ivp_with(&[1.0; 3], &[0.0; 3], &options)?;
    /// assert!(comparison.variational.error.unwrap() < 0.05);
    /// assert_eq!(comparison.order_grids, [40, 80]);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_ivp_with(
        &self,
        q0: &[f64],
        v0: &[f64],
        options: &CompareOptions<'_, Vec<f64>>,
    ) -> Result<Comparison<DynSolution>>
    where
        L: Sync,
    {
        self.check_reference(&options.reference)?;
        let solve = self.ivp_solver(q0, v0, options.start);
        compare(&Comparer(self), IVP, options, solve)
    }

    /// Compares both schemes on the boundary value problem `Q_0 = qa`, `Q_N = qb`
    /// ([`solve_bvp`](Self::solve_bvp)): the run-time-dimension
    /// [`Problem::compare_bvp`](crate::Problem::compare_bvp). Every node of every solve is
    /// stored, as [`solve_bvp`](Self::solve_bvp) does anyway.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    /// #     let mut l = 0.0;
    /// #     for i in 0..n { l += 0.5 * (v[i] * v[i] - x[i] * x[i]); }
    /// #     l
    /// # }
    /// let model = Oscillators { n: 2 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_bvp(&[0.0; 2], &[1.0; 2])?;
    /// assert!(comparison.direct.residual_of_other > 0.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_bvp(&self, qa: &[f64], qb: &[f64]) -> Result<Comparison<DynSolution>>
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
    /// # use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    /// #     let mut l = 0.0;
    /// #     for i in 0..n { l += 0.5 * (v[i] * v[i] - x[i] * x[i]); }
    /// #     l
    /// # }
    /// let model = Oscillators { n: 2 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::asymmetric(Side::Backward));
    /// let options = varembed::CompareOptions { order: false, ..Default::default() };
    /// let comparison = problem.compare_bvp_with(&[0.0; 2], &[1.0; 2], &options)?;
    /// assert_eq!(comparison.extra_solves, 0);
    /// // The asymmetric embedding is coherent: each scheme solves the other's equations.
    /// assert!(comparison.direct.residual_of_other < 1e-12);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_bvp_with(
        &self,
        qa: &[f64],
        qb: &[f64],
        options: &CompareOptions<'_, Vec<f64>>,
    ) -> Result<Comparison<DynSolution>>
    where
        L: Sync,
    {
        self.check_reference(&options.reference)?;
        let solve = self.bvp_solver(qa, qb);
        compare(&Comparer(self), BVP, options, solve)
    }

    /// Solves the initial value problem `q(a) = q0`, `q̇(a) = v0` with `scheme` on
    /// `N, 2N, …, 2^{levels−1} N` steps (`N` this problem's), storing every node, timing each
    /// solve and measuring its error against `options.reference`. A size that fails is
    /// recorded in [`Convergence::failures`] and the run goes on. The run-time-dimension
    /// [`Problem::convergence_ivp`](crate::Problem::convergence_ivp): timed, its grids are
    /// solved one after the other, untimed in parallel ([`CompareOptions::timing`]), hence
    /// `L: Sync`.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    /// #     let mut l = 0.0;
    /// #     for i in 0..n { l += 0.5 * (v[i] * v[i] - x[i] * x[i]); }
    /// #     l
    /// # }
    /// use varembed::{CompareOptions, Reference, Scheme};
    /// let model = Oscillators { n: 3 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let exact = |t: f64| vec![t.cos(); 3];
    /// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
    /// let run = problem.convergence_ivp(Scheme::Direct, &[1.0; 3], &[0.0; 3], &options, 3);
    /// assert_eq!(run.levels.len(), 3);
    /// assert!((run.orders()[1] - 1.0).abs() < 0.2);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn convergence_ivp(
        &self,
        scheme: Scheme,
        q0: &[f64],
        v0: &[f64],
        options: &CompareOptions<'_, Vec<f64>>,
        levels: usize,
    ) -> Convergence<DynSolution>
    where
        L: Sync,
    {
        // Checked once, here, where the reference is: the solves may run on other threads.
        let checked = self.check_reference(&options.reference);
        let solve = self.ivp_solver(q0, v0, options.start);
        let study = self.study(IVP, options, levels);
        convergence(&study, scheme, &options.reference, |grid| {
            checked.clone()?;
            solve(scheme, grid)
        })
    }

    /// [`convergence_ivp`](Self::convergence_ivp) for the boundary value problem `Q_0 = qa`,
    /// `Q_N = qb` (the start is not used).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    /// #     let mut l = 0.0;
    /// #     for i in 0..n { l += 0.5 * (v[i] * v[i] - x[i] * x[i]); }
    /// #     l
    /// # }
    /// use varembed::Scheme;
    /// let model = Oscillators { n: 2 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let options = varembed::CompareOptions::default();
    /// let run = problem.convergence_bvp(Scheme::Variational, &[0.0; 2], &[1.0; 2], &options, 2);
    /// assert_eq!(run.levels[1].n(), 20);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn convergence_bvp(
        &self,
        scheme: Scheme,
        qa: &[f64],
        qb: &[f64],
        options: &CompareOptions<'_, Vec<f64>>,
        levels: usize,
    ) -> Convergence<DynSolution>
    where
        L: Sync,
    {
        let checked = self.check_reference(&options.reference);
        let solve = self.bvp_solver(qa, qb);
        let study = self.study(BVP, options, levels);
        convergence(&study, scheme, &options.reference, |grid| {
            checked.clone()?;
            solve(scheme, grid)
        })
    }

    /// The comparison at this problem's grid from a run of each scheme that solved it (same
    /// data and options): nothing is solved again. The run-time-dimension
    /// [`Problem::compare_runs`](crate::Problem::compare_runs), with its errors.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{DynProblem, Embedding, Grid, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillators(x: &[f64], v: &[f64], n: usize) -> f64 {
    /// #     let mut l = 0.0;
    /// #     for i in 0..n { l += 0.5 * (v[i] * v[i] - x[i] * x[i]); }
    /// #     l
    /// # }
    /// use varembed::Scheme;
    /// let model = Oscillators { n: 2 };
    /// let grid = Grid::new(0.0, 1.0, 10)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let options = varembed::CompareOptions::default();
    /// let (q0, v0) = ([1.0; 2], [0.0; 2]);
    /// let direct = problem.convergence_ivp(Scheme::Direct, &q0, &v0, &options, 2);
    /// let variational = problem.convergence_ivp(Scheme::Variational, &q0, &v0, &options, 2);
    /// let comparison = problem.compare_runs(&direct, &variational)?;
    /// assert_eq!((comparison.grid.n(), comparison.extra_solves), (10, 0));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn compare_runs(
        &self,
        direct: &Convergence<DynSolution>,
        variational: &Convergence<DynSolution>,
    ) -> Result<Comparison<DynSolution>> {
        compare_runs(&Comparer(self), direct, variational)
    }
}
