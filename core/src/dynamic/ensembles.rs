//! [`DynProblem`]'s ensembles: the run-time-dimension counterparts of
//! [`Problem::solve_ivp_ensemble`](crate::Problem::solve_ivp_ensemble) and
//! [`Problem::solve_ivp_models`](crate::Problem::solve_ivp_models).

use super::DynLagrangian;
use super::problem::{DynProblem, DynSolution};
use crate::embedding::Scheme;
use crate::ensemble::Ensemble;
use crate::error::Result;

impl<L: DynLagrangian + ?Sized> DynProblem<'_, L> {
    /// [`solve_ivp`](Self::solve_ivp) from each member's initial data `(q(a), q̇(a))` (each
    /// of length `d`), the members run by `ensemble` (in parallel by default), the results in
    /// input order and bit for bit those of [`solve_ivp`](Self::solve_ivp) on the same data.
    /// A member that fails is its own `Err`.
    ///
    /// Each member stores every node, `O(N d)` memory, and the members running at once hold
    /// theirs together: for long runs of large models, map [`run_ivp`](Self::run_ivp) with an
    /// observer over the members with [`Ensemble::map`] instead.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Ensemble, Grid, Scheme, Side, lagrangian};
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
    /// let model = Oscillators { n: 8 };
    /// let grid = Grid::new(0.0, 1.0, 100)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let members: Vec<(Vec<f64>, Vec<f64>)> =
    ///     (1..=4).map(|i| (vec![i as f64; 8], vec![0.0; 8])).collect();
    /// let runs = problem.solve_ivp_ensemble(Scheme::Variational, &members, &Ensemble::new());
    /// let third = problem.solve_ivp(Scheme::Variational, &[3.0; 8], &[0.0; 8])?;
    /// assert_eq!(runs[2].as_ref().unwrap().q, third.q);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_ensemble<Q, V>(
        &self,
        scheme: Scheme,
        members: &[(Q, V)],
        ensemble: &Ensemble<'_>,
    ) -> Vec<Result<DynSolution>>
    where
        L: Sync,
        Q: AsRef<[f64]> + Sync,
        V: AsRef<[f64]> + Sync,
    {
        ensemble.map(members, |(q0, v0)| {
            self.solve_ivp(scheme, q0.as_ref(), v0.as_ref())
        })
    }

    /// [`solve_ivp`](Self::solve_ivp) of one model per member, each built by `model` from the
    /// member's parameters on the thread that solves it, with this problem's grid, embedding,
    /// start and solver settings (its own model is not used) and the same initial data; the
    /// members run by `ensemble`, the results in input order. For a slice of models, `model`
    /// is `|m| m`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Ensemble, Grid, Scheme, Side, lagrangian};
    ///
    /// /// `n` uncoupled oscillators of frequency `w`.
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize, w: f64) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (v[i] * v[i] - w * w * x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// let grid = Grid::new(0.0, 1.0, 1000)?;
    /// let first = Oscillators { n: 4, w: 1.0 };
    /// let problem = DynProblem::new(&first, grid, Embedding::finite_difference(Side::Backward));
    /// let frequencies = [1.0, 2.0, 3.0];
    /// let build = |&w: &f64| Oscillators { n: 4, w };
    /// let runs = problem.solve_ivp_models(Scheme::Variational, &frequencies, build, &[1.0; 4], &[0.0; 4], &Ensemble::new());
    /// for (run, w) in runs.iter().zip(frequencies) {
    ///     assert!((run.as_ref().unwrap().node(1000)[0] - w.cos()).abs() < 0.02);
    /// }
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_models<'p, P, M>(
        &self,
        scheme: Scheme,
        members: &'p [P],
        model: impl Fn(&'p P) -> M + Sync,
        q0: &[f64],
        v0: &[f64],
        ensemble: &Ensemble<'_>,
    ) -> Vec<Result<DynSolution>>
    where
        P: Sync,
        M: DynLagrangian,
    {
        // Only plain data crosses to the threads: this problem's model need not be `Sync`.
        let (grid, embedding, newton) = (self.grid, self.embedding, self.newton);
        let (guard, start) = (self.blow_up_guard, self.start);
        ensemble.map(members, |p| {
            let model = model(p);
            DynProblem::new(&model, grid, embedding)
                .with_newton(newton)
                .with_blow_up_guard(guard)
                .with_start(start)
                .solve_ivp(scheme, q0, v0)
        })
    }
}
