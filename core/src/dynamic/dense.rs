//! Dense output of a run-time-dimension solution: [`DynSolution::at`], [`at_into`]
//! (caller buffers) and [`state_at`] (with the momentum), by the same local Lagrange
//! polynomial as the const-generic path (`solve/dense.rs`) through the stored nodes.
//!
//! [`at_into`]: DynSolution::at_into
//! [`state_at`]: DynSolution::state_at

use crate::error::{Error, Result, check_len};
use crate::solve::dense::{check_time, interpolant, stencil};

use super::DynLagrangian;
use super::problem::DynSolution;

/// The state of a [`DynSolution`] at a time `t`: position, velocity, momentum and (for an
/// autonomous model) energy, each a vector of the model's dimension `d`.
///
/// Built by [`DynSolution::state_at`].
#[derive(Clone, Debug, PartialEq)]
pub struct DynState {
    /// The time.
    pub t: f64,
    /// The position `q(t)`.
    pub q: Vec<f64>,
    /// The velocity `v(t)`.
    pub v: Vec<f64>,
    /// The momentum `p = ∂L/∂v(q, v, t)`.
    pub p: Vec<f64>,
    /// `E = v·p − L(q, v, t)` when the model is autonomous (does not depend on `t`), `None`
    /// otherwise.
    pub energy: Option<f64>,
}

impl DynSolution {
    /// The position and velocity `(q(t), v(t))` at any time `t` of `[a, b]`, interpolated from
    /// the stored nodes, as new vectors of length `d` ([`at_into`](Self::at_into) writes into
    /// the caller's).
    ///
    /// The interpolant is that of [`Solution::at`](crate::Solution::at): the cubic through the
    /// 4 stored nodes around `t` (one-sided near the ends) and its derivative, so on a model
    /// that implements both traits the two paths agree to round-off. With every node stored,
    /// `q(t)` and `v(t)` converge between the nodes at the order of the nodal positions: 1 for
    /// the Gauss-FDEσ embeddings and their asymmetric form, 2 where the nodes are
    /// (Störmer–Verlet on `L = ½vᵀMv − U` from the second-order start or as a boundary value
    /// problem). A run that stored every `s`-th node ([`DynProblem::solve_ivp_every`]) is
    /// interpolated through those alone: on top of the nodes' `O(h^r)`, the cubic's own error
    /// is `O(H⁴)` in `q` and `O(H³)` in `v` with `H = s h` the spacing of the stored nodes (the
    /// last node, closer to its neighbour when `N` is not a multiple of `s`, is read only for
    /// `t` in that last gap). At a stored node's time `q` is that node bit for bit.
    ///
    /// Errors: [`Error::TimeOutOfRange`] for `t` outside `[a, b]` or NaN;
    /// [`Error::Unsupported`] for an embedding without node values (as
    /// [`Solution::node_values`](crate::Solution::node_values)); [`Error::WrongLength`] when
    /// `q` does not hold the `indices` nodes of dimension `d`, or fewer than 2 are stored.
    ///
    /// [`DynProblem::solve_ivp_every`]: crate::DynProblem::solve_ivp_every
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, lagrangian};
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
    /// let grid = Grid::new(0.0, 1.0, 200)?;
    /// let problem = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward));
    /// let solution = problem.solve_ivp(Scheme::Variational, &[1.0; 3], &[0.0; 3])?;
    /// let (q, v) = solution.at(0.5025)?; // between t_100 and t_101: q = cos t, first order
    /// assert!((q[2] - 0.5025f64.cos()).abs() < 5e-3 && (v[2] + 0.5025f64.sin()).abs() < 5e-3);
    /// // The same into buffers the caller keeps.
    /// let (mut qb, mut vb) = (vec![0.0; 3], vec![0.0; 3]);
    /// solution.at_into(0.5025, &mut qb, &mut vb)?;
    /// assert_eq!((qb, vb), (q, v));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn at(&self, t: f64) -> Result<(Vec<f64>, Vec<f64>)> {
        let (mut q, mut v) = (vec![0.0; self.dimension], vec![0.0; self.dimension]);
        self.at_into(t, &mut q, &mut v)?;
        Ok((q, v))
    }

    /// [`at`](Self::at) into `q` and `v`, each of length `d` ([`Error::WrongLength`]
    /// otherwise): no allocation per call.
    pub fn at_into(&self, t: f64, q: &mut [f64], v: &mut [f64]) -> Result<()> {
        let d = self.dimension;
        let points = interpolant(&self.run.embedding, self.run.scheme, "DynSolution::at")?.points;
        check_time(&self.run.grid, t)?;
        check_len("the position buffer", d, q.len())?;
        check_len("the velocity buffer", d, v.len())?;
        let count = self.indices.len();
        if count < 2 {
            return Err(Error::WrongLength {
                what: "stored nodes (at least 2)",
                expected: 2,
                found: count,
            });
        }
        check_len("the stored nodes, flat", count * d, self.q.len())?;
        let grid = self.run.grid;
        let index = &self.indices;
        let short_last = count >= 3 && index[count - 1] - index[count - 2] < index[1] - index[0];
        let stencil = stencil(&|j| grid.t(index[j]), count, short_last, points, t);
        q.fill(0.0);
        v.fill(0.0);
        for i in 0..stencil.len {
            let node = self.node(stencil.first + i);
            let (value, slope) = (stencil.value[i], stencil.slope[i]);
            for ((q, v), x) in q.iter_mut().zip(v.iter_mut()).zip(node) {
                *q += x * value;
                *v += x * slope;
            }
        }
        if let Some(j) = stencil.node {
            q.copy_from_slice(self.node(j));
        }
        Ok(())
    }

    /// The state `(t, q, v, p)` at any time `t` of `[a, b]`: `q`, `v` of [`at`](Self::at),
    /// `p = ∂L/∂v(q, v, t)` from `lagrangian` (the model the solution was computed with), and
    /// for an autonomous model the energy. `p` has the order of `q` and `v`. A loop over many
    /// times that should not allocate calls [`at_into`](Self::at_into) and
    /// [`DynLagrangian::momentum`] with its own buffers.
    ///
    /// Errors: those of [`at`](Self::at); [`Error::WrongLength`] when the model's dimension is
    /// not the solution's; [`Error::OutsideDomain`] when `∂L/∂v` or the energy is not finite
    /// at the interpolated state.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{DynProblem, Embedding, Grid, Scheme, Side, lagrangian};
    ///
    /// /// `n` uncoupled oscillators of mass `m`, unit stiffness.
    /// #[lagrangian]
    /// fn oscillators(x: &[f64], v: &[f64], n: usize, m: f64) -> f64 {
    ///     let mut l = 0.0;
    ///     for i in 0..n {
    ///         l += 0.5 * (m * v[i] * v[i] - x[i] * x[i]);
    ///     }
    ///     l
    /// }
    ///
    /// let model = Oscillators { n: 2, m: 4.0 };
    /// let problem = DynProblem::new(&model, Grid::new(0.0, 1.0, 100)?, Embedding::asymmetric(Side::Forward));
    /// let solution = problem.solve_bvp(Scheme::Variational, &[0.0, 1.0], &[0.5, 0.0])?;
    /// let state = solution.state_at(0.3, &model)?;
    /// // q₀ = ½ sin(t/2)/sin(½), second order (Störmer–Verlet as a boundary value problem).
    /// let exact = |t: f64| 0.5 * (0.5 * t).sin() / 0.5f64.sin();
    /// let slope = |t: f64| 0.25 * (0.5 * t).cos() / 0.5f64.sin();
    /// assert!((state.q[0] - exact(0.3)).abs() < 1e-4 && (state.v[0] - slope(0.3)).abs() < 1e-4);
    /// assert_eq!(state.p, [4.0 * state.v[0], 4.0 * state.v[1]]); // p = m v
    /// assert!(state.energy.is_some()); // autonomous
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn state_at<L: DynLagrangian + ?Sized>(&self, t: f64, lagrangian: &L) -> Result<DynState> {
        check_len(
            "the model's dimension",
            self.dimension,
            lagrangian.dimension(),
        )?;
        let (q, v) = self.at(t)?;
        let mut p = vec![0.0; self.dimension];
        lagrangian.momentum(&q, &v, t, &mut p);
        let energy = (!lagrangian.dependence().t).then(|| {
            let kinetic: f64 = v.iter().zip(&p).map(|(v, p)| v * p).sum();
            kinetic - lagrangian.value(&q, &v, t)
        });
        if !(p.iter().all(|x| x.is_finite()) && energy.is_none_or(f64::is_finite)) {
            return Err(Error::OutsideDomain {
                what: format!("the interpolated state q = {q:?}, v = {v:?} at t = {t}"),
            });
        }
        Ok(DynState { t, q, v, p, energy })
    }
}
