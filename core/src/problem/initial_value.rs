//! [`Problem`]'s initial value problems: each method hands the problem's parts to the IVP
//! solver.

use super::Problem;
use crate::dynamic::ivp::SecondNode;
use crate::dynamic::problem::DynProblem;
use crate::embedding::Scheme;
use crate::error::Result;
use crate::lagrangian::{IntoVector, Lagrangian, Vector};
use crate::options::RUN_TIME_FROM;
use crate::solve::ivp::Ivp;
use crate::solve::solution::Solution;
use crate::solve::start::Start;
use crate::stack::with_room_for;

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// The parts of this problem an initial value problem needs.
    pub(super) fn ivp(&self) -> Ivp<'_, L, D> {
        Ivp::new(&self.discretisation, &self.options)
    }

    /// The run of a model that is also a [`DynLagrangian`](crate::DynLagrangian) (see
    /// [`Lagrangian::run_time`]) with [`RUN_TIME_FROM`] or more degrees of freedom, by the
    /// run-time engine with this problem's options; `None` for any other run, which stays on
    /// the const-generic path (a fractional embedding, a model whose run-time form has
    /// another dimension than `D`, and a Gauss–Legendre run from given nodes, which has none).
    /// `second` is how `Q_1` is had: by a start from `v0`, or given (`v0` then unread).
    fn on_run_time_engine(
        &self,
        scheme: Scheme,
        (q0, v0): (&Vector<D>, &Vector<D>),
        second: SecondNode<'_>,
    ) -> Option<Result<Solution<D>>> {
        if D < RUN_TIME_FROM {
            return None;
        }
        let model = self.discretisation.lagrangian().run_time()?;
        if model.dimension() != D {
            // A run-time form of another dimension is not this model's: the const-generic path
            // solves what the `Lagrangian<D>` methods say.
            return None;
        }
        let embedding = *self.discretisation.embedding();
        if embedding.is_fractional() {
            return None;
        }
        let problem = DynProblem::new(model, *self.discretisation.grid(), embedding)
            .with_newton(self.options.newton)
            .with_blow_up_guard(self.options.blow_up_guard)
            .with_resolution_check(self.options.resolution_check);
        let run = match second {
            SecondNode::Start(start) => {
                problem
                    .with_start(start)
                    .solve_ivp(scheme, q0.as_slice(), v0.as_slice())
            }
            SecondNode::Given(_) if embedding.is_one_step() => return None,
            SecondNode::Given(q1) => problem.solve_ivp_from_nodes(scheme, q0.as_slice(), q1),
        };
        Some(run.map(|solution| solution.into_nodes()))
    }

    /// The discrete Legendre start: `Q_1` from `Q_0 = q(a)` and `π_0 = ∂L/∂v(q(a), q̇(a), a)`,
    /// by the variational step equation of this side (σ=−: `∂L/∂v(Q_1, (Q_1−Q_0)/h, t_1) = π_0`;
    /// σ=+: `p_0 − h f_0 = π_0` at `(Q_0, (Q_1−Q_0)/h, t_0)`; midpoint and trapezoidal:
    /// `−D₁L_d(Q_0, Q_1) = π_0`). [`Error::Unsupported`](crate::Error::Unsupported) for an
    /// embedding without a three-point recurrence (Gauss–Legendre, whose runs start from
    /// `q(a)`, `q̇(a)` themselves, and the fractional ones).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// // σ = −: (Q_1 − Q_0)/h = q̇(0) for L = ½v² − ½x².
    /// assert!((problem.legendre_start(1.0, 0.5)?[0] - 1.05).abs() < 1e-12);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn legendre_start(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Vector<D>> {
        let (q0, v0) = (q0.into_vector(), v0.into_vector());
        with_room_for::<D, _>(|| self.ivp().legendre_start(q0, v0))
    }

    /// The second-order start `Q_1 = Q_0 + h q̇(a) + ½h² q̈(a)`, with `q̈(a)` solved from the
    /// Euler–Lagrange equation at `a`: `L_vv q̈ = ∂L/∂x − L_vx q̇ − ∂²L/∂v∂t`.
    ///
    /// `∂²L/∂v∂t` is not among the Hessian blocks; it is taken by a central difference of
    /// `∂L/∂v` in `t` with step `10⁻⁵ (1 + |a|)` (error `O(10⁻¹⁰)`, far below the `O(h³)` of the
    /// start itself; exactly zero for a Lagrangian that does not depend on `t`).
    /// Errors with [`Error::SingularJacobian`](crate::Error::SingularJacobian) at step 1 when `L_vv` is singular.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// // Q_1 = Q_0 + h q̇ + ½h² q̈ with q̈ = −q.
    /// assert!((problem.second_order_start(1.0, 0.0)?[0] - 0.995).abs() < 1e-12);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn second_order_start(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Vector<D>> {
        let (q0, v0) = (q0.into_vector(), v0.into_vector());
        with_room_for::<D, _>(|| self.ivp().second_order_start(q0, v0))
    }

    /// Solves the initial value problem with the chosen [`Start`] for `Q_1`, whatever
    /// [`with_start`](Self::with_start) set (ignored by the one-step Gauss–Legendre
    /// integrators); [`DynProblem::solve_ivp_with`](crate::DynProblem::solve_ivp_with) on the
    /// run-time path.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_ivp_with(Scheme::Variational, 1.0, 0.0, varembed::Start::SecondOrder)?;
    /// assert!((run.last()[0] - 1f64.cos()).abs() < 1e-2);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_with(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        start: Start,
    ) -> Result<Solution<D>> {
        let (q0, v0) = (q0.into_vector(), v0.into_vector());
        if let Some(run) = self.on_run_time_engine(scheme, (&q0, &v0), SecondNode::Start(start)) {
            return run;
        }
        with_room_for::<D, _>(|| self.ivp().solve(scheme, q0, v0, start))
    }

    /// Solves the initial value problem `q(a) = q0`, `q̇(a) = v0` with `scheme`, from the start
    /// of [`with_start`](Self::with_start): by default the discrete Legendre start (the same
    /// `Q_1` for both schemes).
    ///
    /// A step whose equation is affine in the newest node (as declared by
    /// [`Lagrangian::hessian_dependence`]) is taken in closed form, with no Newton iteration.
    ///
    /// A model that is also a [`DynLagrangian`](crate::DynLagrangian) (every `#[lagrangian]`
    /// model with loops over `[f64; N]`, see [`Lagrangian::run_time`]) with
    /// [`RUN_TIME_FROM`] or more degrees of freedom is run by the
    /// run-time-dimension engine: the same steps (Gauss–Legendre's too), with no `D × D` block
    /// on the stack, and without the eigenvalue stability check.
    ///
    /// Under [`Embedding::gauss_legendre`](crate::Embedding::gauss_legendre) the run is the
    /// one-step Gauss–Legendre map of `(q_k, p_k)` from `p_0 = ∂L/∂v(q(a), q̇(a), a)` (no start;
    /// the momenta are in [`Solution::momenta`]), each step a Newton solve of its stage
    /// velocities; it has no eigenvalue check (A-stable on the oscillator, see
    /// [solvers](crate::guide::solvers)), the rest applies.
    ///
    /// Errors: [`Error::Unsupported`](crate::Error::Unsupported) for Gauss-GLEσ and for the
    /// direct scheme of Gauss–Legendre; at step `n`,
    /// [`Error::SingularJacobian`](crate::Error::SingularJacobian), [`Error::NewtonDidNotConverge`](crate::Error::NewtonDidNotConverge) (with the last residual) or
    /// [`Error::Unstable`](crate::Error::Unstable) (the linearised step map, checked at step 2 and every 1024 steps, has
    /// a real eigenvalue below −1 or one of modulus ≥ 2: the step is too large for the scheme;
    /// on a run handed to the run-time engine, at its initial data and where the model's modes
    /// decouple, see [`DynProblem`])
    /// or [`Error::NotFinite`](crate::Error::NotFinite) (e.g. a recurrence overflowing between two checks); for a
    /// Lagrangian that does not depend on `t`, [`Error::BlowUp`](crate::Error::BlowUp) over a window of steps where the
    /// energy grew far beyond the early run's (see
    /// [`with_blow_up_guard`](Self::with_blow_up_guard)).
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_ivp(Scheme::Direct, 1.0, 0.0)?;
    /// assert_eq!(run.q.len(), 11);
    /// assert!((run.last()[0] - 1f64.cos()).abs() < 0.1);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        self.solve_ivp_with(scheme, q0, v0, self.start)
    }

    /// Runs the recurrence of `scheme` from given first nodes `Q_0`, `Q_1`.
    ///
    /// A model that is also a [`DynLagrangian`](crate::DynLagrangian) with
    /// [`RUN_TIME_FROM`] or more degrees of freedom is run by the
    /// run-time-dimension engine, as in [`solve_ivp`](Self::solve_ivp)
    /// ([`DynProblem::solve_ivp_from_nodes`](crate::DynProblem::solve_ivp_from_nodes)). Both
    /// paths check the first nodes alike, with the same errors: finite, and `∂²L/∂v²` and the
    /// domain at `Q_1` with the velocity `(Q_1 − Q_0)/h`, at step 1. The run-time engine also
    /// gives its stability verdict ([`Error::Unstable`](crate::Error::Unstable)) at `Q_0` with
    /// that velocity; this path checks the degeneracy again at the last nodes.
    ///
    /// # Example
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, NewtonOptions, Problem, Scheme, Side, Vector, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 10)?, Embedding::finite_difference(Side::Backward));
    /// let run = problem.solve_ivp_from_nodes(Scheme::Variational, 1.0, 0.1f64.cos())?;
    /// assert!((run.last()[0] - 1f64.cos()).abs() < 1e-2);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_ivp_from_nodes(
        &self,
        scheme: Scheme,
        q0: impl IntoVector<D>,
        q1: impl IntoVector<D>,
    ) -> Result<Solution<D>> {
        let (q0, q1) = (q0.into_vector(), q1.into_vector());
        let given = SecondNode::Given(q1.as_slice());
        // v0 is not read when Q_1 is given.
        if let Some(run) = self.on_run_time_engine(scheme, (&q0, &Vector::<D>::zeros()), given) {
            return run;
        }
        with_room_for::<D, _>(|| self.ivp().solve_from_nodes(scheme, q0, q1))
    }
}
