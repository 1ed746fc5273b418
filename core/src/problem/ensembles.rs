//! [`Problem`]'s ensembles: one problem solved from many initial conditions, or its grid,
//! embedding and options applied to many models, the members run by an [`Ensemble`].

use super::Problem;
use crate::embedding::Scheme;
use crate::ensemble::Ensemble;
use crate::error::Result;
use crate::lagrangian::{IntoVector, Lagrangian};
use crate::solve::solution::Solution;

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// [`solve_ivp`](Self::solve_ivp) from each member's initial data `(q(a), q̇(a))`, the
    /// members run by `ensemble` (in parallel by default), the results in input order. A member
    /// that fails is its own `Err`; the others are solved all the same.
    ///
    /// Each solution equals, bit for bit, the one [`solve_ivp`](Self::solve_ivp) returns for
    /// the same data, whichever thread solved it ([`Ensemble`]). The Lagrangian is shared by
    /// the threads, hence `L: Sync` (every `#[lagrangian]` model is).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Ensemble, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// #[lagrangian]
    /// fn pendulum(x: f64, v: f64) -> f64 {
    ///     0.5 * v * v + x.cos()
    /// }
    ///
    /// let problem = Problem::new(&Pendulum, Grid::new(0.0, 10.0, 1000)?, Embedding::midpoint());
    /// // Amplitudes 0.1 to 3.0 from rest.
    /// let members: Vec<(f64, f64)> = (1..=30).map(|i| (0.1 * i as f64, 0.0)).collect();
    /// let runs = problem.solve_ivp_ensemble(Scheme::Variational, &members, &Ensemble::new());
    /// assert_eq!(runs.len(), 30);
    /// let (q0, v0) = members[6];
    /// let one = problem.solve_ivp(Scheme::Variational, q0, v0)?;
    /// assert_eq!(runs[6].as_ref().unwrap().q, one.q); // input order, bit for bit
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_ensemble<Q, V>(
        &self,
        scheme: Scheme,
        members: &[(Q, V)],
        ensemble: &Ensemble<'_>,
    ) -> Vec<Result<Solution<D>>>
    where
        L: Sync,
        Q: IntoVector<D> + Copy + Sync,
        V: IntoVector<D> + Copy + Sync,
    {
        ensemble.map(members, |&(q0, v0)| self.solve_ivp(scheme, q0, v0))
    }

    /// [`solve_ivp`](Self::solve_ivp) of one model per member, each built by `model` from the
    /// member's parameters on the thread that solves it, with this problem's grid, embedding
    /// and options (its own Lagrangian is not used) and the same initial data `(q0, v0)`; the
    /// members run by `ensemble`, the results in input order. For a slice of models, `model` is
    /// `|m| m` (a reference to a Lagrangian is one).
    ///
    /// Each solution equals, bit for bit, `Problem::new(&model(p), grid, embedding)` with this
    /// problem's options solving `solve_ivp(scheme, q0, v0)` on its own.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Ensemble, Grid, Problem, Scheme, Side, lagrangian};
    ///
    /// /// A pendulum of length `l` under gravity `g`.
    /// #[lagrangian]
    /// fn pendulum(x: f64, v: f64, g: f64, l: f64) -> f64 {
    ///     0.5 * l * l * v * v + g * l * x.cos()
    /// }
    ///
    /// let problem = Problem::new(
    ///     &Pendulum { g: 9.81, l: 1.0 },
    ///     Grid::new(0.0, 2.0, 2000)?,
    ///     Embedding::midpoint(),
    /// );
    /// // One model per length, built from its parameter.
    /// let lengths = [0.25, 0.5, 1.0, 2.0];
    /// let build = |&l: &f64| Pendulum { g: 9.81, l };
    /// let runs = problem.solve_ivp_models(Scheme::Variational, &lengths, build, 0.1, 0.0, &Ensemble::new());
    /// // Small swings: q(2) ≈ 0.1 cos(2 √(g/l)) for each length.
    /// for (run, l) in runs.iter().zip(lengths) {
    ///     let small = 0.1 * (2.0 * (9.81f64 / l).sqrt()).cos();
    ///     assert!((run.as_ref().unwrap().last()[0] - small).abs() < 2e-3);
    /// }
    ///
    /// // A slice of models: `|m| m`.
    /// let models = lengths.map(|l| Pendulum { g: 9.81, l });
    /// let same = problem.solve_ivp_models(Scheme::Variational, &models, |m| m, 0.1, 0.0, &Ensemble::serial());
    /// assert_eq!(same[2].as_ref().unwrap().q, runs[2].as_ref().unwrap().q);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_models<'p, P, M>(
        &self,
        scheme: Scheme,
        members: &'p [P],
        model: impl Fn(&'p P) -> M + Sync,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        ensemble: &Ensemble<'_>,
    ) -> Vec<Result<Solution<D>>>
    where
        P: Sync,
        M: Lagrangian<D>,
    {
        let (q0, v0) = (q0.into_vector(), v0.into_vector());
        // Only plain data crosses to the threads: this problem's Lagrangian need not be `Sync`.
        let (grid, embedding, options) = (*self.grid(), *self.embedding(), self.options);
        let start = self.start;
        ensemble.map(members, |p| {
            let model = model(p);
            // The member's own problem with these options: a large model is handed to the
            // run-time engine as its own `solve_ivp` would hand it.
            let mut problem = Problem::new(&model, grid, embedding).with_start(start);
            problem.options = options;
            problem.solve_ivp(scheme, q0, v0)
        })
    }
}
