//! [`Problem`]'s boundary value problems: the global Newton solve of the discretisation, or,
//! for a large model under an embedding the run-time engine solves, that engine's sparse LU.

use super::Problem;
use crate::dynamic::problem::DynProblem;
use crate::embedding::{EmbeddingKind, Scheme};
use crate::error::{Result, check_len};
use crate::lagrangian::run_time::FixedDimension;
use crate::lagrangian::{IntoVector, Lagrangian, Vector};
use crate::options::RUN_TIME_FROM;
use crate::solve::bvp;
use crate::solve::solution::Solution;
use crate::stack::with_room_for;
use std::borrow::Cow;

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// Solves the boundary value problem `Q_0 = qa`, `Q_N = qb` for `scheme`, from the straight
    /// line between them (on the fractional fast path from `2¹⁹` steps on, from the solution on
    /// a grid 32 times coarser, interpolated: one Newton step fewer on large grids, see
    /// [solvers](crate::guide::solvers)). Works for every embedding.
    ///
    /// Newton's method on the rows of [`residual`](Self::residual), full steps first, damped by
    /// a line search on the residual's 2-norm with a watchdog (see
    /// [solvers](crate::guide::solvers)). Errors: [`Error::SingularJacobian`],
    /// [`Error::NewtonDidNotConverge`] (iterations, last residual) and [`Error::NotFinite`],
    /// located at the global Newton iteration; on the fractional fast path (see
    /// [`FractionalSolver`]) also [`Error::KrylovDidNotConverge`].
    ///
    /// [`Error::SingularJacobian`]: crate::Error::SingularJacobian
    /// [`Error::NewtonDidNotConverge`]: crate::Error::NewtonDidNotConverge
    /// [`Error::NotFinite`]: crate::Error::NotFinite
    /// [`Error::KrylovDidNotConverge`]: crate::Error::KrylovDidNotConverge
    /// [`FractionalSolver`]: crate::FractionalSolver
    ///
    /// A model that is also a [`DynLagrangian`](crate::DynLagrangian) (every `#[lagrangian]`
    /// model with loops over `[f64; N]`, see [`Lagrangian::run_time`]) with [`RUN_TIME_FROM`]
    /// or more degrees of freedom is solved, under every classical embedding, by the run-time
    /// engine
    /// ([`DynProblem::solve_bvp`](crate::DynProblem::solve_bvp): sparse LU, or MINRES for a
    /// variational scheme of many unknowns, the same rows, stopping rule and errors), with no
    /// `D × D` block on the stack.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// // q = sin t / sin 1 from q(0) = 0 to q(1) = 1.
    /// let solution = problem.solve_bvp(Scheme::Variational, 0.0, 1.0)?;
    /// assert!((solution.q[5][0] - 0.5f64.sin() / 1f64.sin()).abs() < 1e-3);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_bvp(
        &self,
        scheme: Scheme,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        let guess = bvp::straight_line(qa.into_vector(), qb.into_vector(), self.grid().n())?;
        self.solve_bvp_guess(scheme, Cow::Owned(guess))
    }

    /// Solves the boundary value problem from an initial guess of all `N + 1` nodes; its first
    /// and last nodes are the boundary values. (A guess that is the straight line between
    /// them, node for node, is treated as [`solve_bvp`](Self::solve_bvp)'s: on the fractional
    /// fast path from `2¹⁹` steps on, Newton starts from a coarser grid's solution instead.)
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let guess = vec![Vector::<1>::new(1.0); 11];
    /// let solution = problem.solve_bvp_from(Scheme::Variational, &guess)?;
    /// assert_eq!((solution.q[0][0], solution.q[10][0]), (1.0, 1.0));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_bvp_from(&self, scheme: Scheme, guess: &[Vector<D>]) -> Result<Solution<D>> {
        self.solve_bvp_guess(scheme, Cow::Borrowed(guess))
    }

    /// [`solve_bvp_from`](Self::solve_bvp_from), with a guess the solver may take as its first
    /// iterate when it is owned (the straight line of [`solve_bvp`](Self::solve_bvp)) instead
    /// of copying it: at `N = 10⁷` nodes each copy is 80 MB a coordinate.
    fn solve_bvp_guess(&self, scheme: Scheme, guess: Cow<'_, [Vector<D>]>) -> Result<Solution<D>> {
        if let Some(solved) = self.bvp_on_run_time_engine(scheme, &guess) {
            return solved;
        }
        with_room_for::<D, _>(|| {
            if self.discretisation.embedding().is_one_step() {
                return self.gauss_legendre_bvp(scheme, &guess);
            }
            bvp::solve(
                &self.discretisation,
                &self.options,
                scheme,
                guess.into_owned(),
            )
        })
    }

    /// The boundary value problem of a Gauss–Legendre integrator: the run-time engine's global
    /// collocation system ([`DynProblem::solve_bvp_from`]), on this model's dense blocks seen
    /// as sparse ones (one solver for both paths), with this problem's Newton options.
    fn gauss_legendre_bvp(&self, scheme: Scheme, guess: &[Vector<D>]) -> Result<Solution<D>> {
        check_len("discrete curve Q", self.grid().n() + 1, guess.len())?;
        let model = FixedDimension::<L, D>(self.discretisation.lagrangian());
        let embedding = *self.discretisation.embedding();
        let problem =
            DynProblem::new(&model, *self.grid(), embedding).with_newton(self.options.newton);
        let flat: Vec<f64> = guess.iter().flat_map(|q| q.iter().copied()).collect();
        problem
            .solve_bvp_from(scheme, &flat)
            .map(|solution| solution.into_nodes())
    }

    /// The boundary value problem of a model that is also a
    /// [`DynLagrangian`](crate::DynLagrangian) (see [`Lagrangian::run_time`]) with
    /// [`RUN_TIME_FROM`] or more degrees of freedom, under an embedding whose boundary value
    /// problems the run-time engine solves (every classical one): by that engine's solvers,
    /// with this problem's Newton options and posedness check, no `D × D` block on the stack;
    /// `None` for any other problem, which stays on this path.
    fn bvp_on_run_time_engine(
        &self,
        scheme: Scheme,
        guess: &[Vector<D>],
    ) -> Option<Result<Solution<D>>> {
        if D < RUN_TIME_FROM {
            return None;
        }
        let model = self.discretisation.lagrangian().run_time()?;
        let embedding = *self.discretisation.embedding();
        let solved_there = matches!(
            embedding.kind(),
            EmbeddingKind::FiniteDifference
                | EmbeddingKind::Asymmetric
                | EmbeddingKind::Midpoint
                | EmbeddingKind::Trapezoidal
                | EmbeddingKind::GaussLegendre { .. }
        );
        // A guess of the wrong length gets this path's error, naming it in nodes.
        if model.dimension() != D || !solved_there || guess.len() != self.grid().n() + 1 {
            return None;
        }
        let problem = DynProblem::new(model, *self.grid(), embedding)
            .with_newton(self.options.newton)
            .with_posedness_check(self.options.posedness_check);
        let flat: Vec<f64> = guess.iter().flat_map(|q| q.iter().copied()).collect();
        let solved = problem.solve_bvp_from(scheme, &flat);
        Some(solved.map(|solution| solution.into_nodes()))
    }
}
