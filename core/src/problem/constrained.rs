//! [`Problem`]'s problems under holonomic constraints: initial and boundary value problems,
//! each handing the problem's parts and the constraint to its solver.

use super::Problem;
use crate::constraint::Constraint;
use crate::embedding::Scheme;
use crate::error::Result;
use crate::lagrangian::{IntoVector, Lagrangian, Vector};
use crate::solve::bvp;
use crate::solve::constrained::{self, ConstrainedSolution};
use crate::stack::with_room_for;

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// Solves the initial value problem `q(a) = q0`, `q̇(a) = v0` under the holonomic
    /// constraints `g(q) = 0` of `constraint`: the system
    /// `d/dt ∂L/∂v − ∂L/∂x = G(q)ᵀλ`, `g(q) = 0`, `G = ∂g/∂q`.
    ///
    /// Each step of `scheme` gains the constraint force `G(c)ᵀλ` at the node `c` where its row
    /// reads `∂L/∂x`, and the newest node satisfies `g(Q_n) = 0` (for the variational schemes,
    /// the constrained discrete Euler–Lagrange equations
    /// `D₂L_d(Q_{n−2}, Q_{n−1}) + D₁L_d(Q_{n−1}, Q_n) + h G(Q_{n−1})ᵀλ = 0`); each step is one
    /// Newton solve of the `D + M` unknowns `(Q_n, hλ)`, from the discrete Legendre start with
    /// the constraint force at `q(a)`. Every classical embedding, both schemes; Gauss–Legendre
    /// variational only, with the constraint at the nodes (its stages are not constrained, so
    /// it is order 2 for every `s`: see [forces and constraints](crate::guide::forces));
    /// combined with a [`Forced`](crate::Forced) model, forces and constraints together.
    ///
    /// Errors: [`Error::InconsistentInitialData`](crate::Error::InconsistentInitialData) when
    /// `g(q0) ≠ 0` or `G(q0) v0 ≠ 0` beyond `1e-10` relative (naming the constraint; see
    /// [`project_initial_data`](crate::project_initial_data)),
    /// [`Error::RankDeficientConstraints`](crate::Error::RankDeficientConstraints) where `G`
    /// has dependent rows, [`Error::Unsupported`](crate::Error::Unsupported) for the direct
    /// scheme of Gauss–Legendre and the fractional embeddings, and the step errors of
    /// [`solve_ivp`](Self::solve_ivp) (no blow-up guard, stability or resolution check runs).
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Holonomic, Problem, Scheme, lagrangian};
    ///
    /// /// A unit mass in the plane under gravity.
    /// #[lagrangian]
    /// fn mass(x: [f64; 2], v: [f64; 2]) -> f64 {
    ///     0.5 * (v[0] * v[0] + v[1] * v[1]) - x[1]
    /// }
    /// /// On a rod of unit length from the origin: a pendulum in Cartesian coordinates.
    /// #[lagrangian]
    /// fn rod(x: [f64; 2], _v: [f64; 2]) -> f64 {
    ///     0.5 * (x[0] * x[0] + x[1] * x[1] - 1.0)
    /// }
    ///
    /// let problem = Problem::new(&Mass, Grid::new(0.0, 10.0, 1000)?, Embedding::midpoint());
    /// let run = problem.solve_constrained_ivp(Scheme::Variational, &Holonomic(Rod), [1.0, 0.0], [0.0, 0.0])?;
    /// let on_rod = run.solution.q.iter().map(|q| (q.norm() - 1.0).abs()).fold(0.0, f64::max);
    /// assert!(on_rod < 1e-12);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_constrained_ivp<C: Constraint<D, M> + ?Sized, const M: usize>(
        &self,
        scheme: Scheme,
        constraint: &C,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<ConstrainedSolution<D, M>> {
        let (q0, v0) = (q0.into_vector(), v0.into_vector());
        with_room_for::<D, _>(|| constrained::solve(&self.ivp(), constraint, scheme, q0, v0))
    }

    /// Solves the boundary value problem `Q_0 = qa`, `Q_N = qb` under the holonomic constraints
    /// `g(q) = 0` of `constraint`, from the straight line between the ends with each interior
    /// node projected onto the constraints (see
    /// [`solve_constrained_bvp_from`](Self::solve_constrained_bvp_from)). Where that line
    /// crosses a singular point of the constraints (the centre of a sphere between antipodal
    /// ends), its projection fails with
    /// [`Error::RankDeficientConstraints`](crate::Error::RankDeficientConstraints) at that
    /// node: give a guess of the path with `solve_constrained_bvp_from`.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, Grid, Holonomic, Problem, Scheme, lagrangian};
    ///
    /// /// A unit mass in the plane under gravity.
    /// #[lagrangian]
    /// fn mass(x: [f64; 2], v: [f64; 2]) -> f64 {
    ///     0.5 * (v[0] * v[0] + v[1] * v[1]) - x[1]
    /// }
    /// /// On a rod of unit length from the origin: a pendulum in Cartesian coordinates.
    /// #[lagrangian]
    /// fn rod(x: [f64; 2], _v: [f64; 2]) -> f64 {
    ///     0.5 * (x[0] * x[0] + x[1] * x[1] - 1.0)
    /// }
    ///
    /// // From hanging straight down to a quarter turn, in one time unit.
    /// let problem = Problem::new(&Mass, Grid::new(0.0, 1.0, 200)?, Embedding::midpoint());
    /// let run = problem.solve_constrained_bvp(Scheme::Variational, &Holonomic(Rod), [0.0, -1.0], [1.0, 0.0])?;
    /// let on_rod = run.solution.q.iter().map(|q| (q.norm() - 1.0).abs()).fold(0.0, f64::max);
    /// assert!(on_rod < 1e-12);
    /// assert_eq!(run.multipliers.len(), 199);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn solve_constrained_bvp<C: Constraint<D, M> + ?Sized, const M: usize>(
        &self,
        scheme: Scheme,
        constraint: &C,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<ConstrainedSolution<D, M>> {
        let n = self.grid().n();
        let guess = bvp::straight_line(qa.into_vector(), qb.into_vector(), n)?;
        self.solve_constrained_bvp_from(scheme, constraint, &guess)
    }

    /// Solves the boundary value problem under the holonomic constraints of `constraint` from
    /// an initial guess of all `N + 1` nodes (its first and last nodes the end values, which
    /// must satisfy the constraints; its interior nodes are projected onto them first).
    ///
    /// Each row `k` of `scheme` (the rows of [`residual_rows`](Self::residual_rows)) gains the
    /// constraint force `G(Q_k)ᵀλ_k` at its own node, and every interior node satisfies
    /// `g(Q_j) = 0`: the rows of [`solve_constrained_ivp`](Self::solve_constrained_ivp)'s
    /// steps, so a boundary value problem with a constrained run's end values returns its nodes
    /// and multipliers (`multipliers[i]` is `λ` of row `residual_rows().start() + i`, as
    /// there). Newton's method on the whole system, with the line search of
    /// [`solve_bvp`](Self::solve_bvp); its Jacobian is block-tridiagonal with blocks of
    /// `D + M` and is factorised as a band matrix, `O(N (D + M)³)`. Every classical embedding
    /// but Gauss–Legendre, both schemes; with a [`Forced`](crate::Forced) model, forces and
    /// constraints together.
    ///
    /// Errors: [`Error::InconsistentBoundaryData`](crate::Error::InconsistentBoundaryData)
    /// when an end value violates a constraint beyond `1e-10` relative (naming the end and the
    /// constraint), [`Error::RankDeficientConstraints`](crate::Error::RankDeficientConstraints)
    /// where `G` has dependent rows, [`Error::InvalidModel`](crate::Error::InvalidModel) for a
    /// constraint that reads `v` or `t`, [`Error::Unsupported`](crate::Error::Unsupported) for
    /// Gauss–Legendre and the fractional embeddings, and the errors of
    /// [`solve_bvp_from`](Self::solve_bvp_from).
    pub fn solve_constrained_bvp_from<C: Constraint<D, M> + ?Sized, const M: usize>(
        &self,
        scheme: Scheme,
        constraint: &C,
        guess: &[Vector<D>],
    ) -> Result<ConstrainedSolution<D, M>> {
        with_room_for::<D, _>(|| {
            constrained::solve_bvp(
                &self.discretisation,
                &self.options,
                constraint,
                scheme,
                guess,
            )
        })
    }
}
