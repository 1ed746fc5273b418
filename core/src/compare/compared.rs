//! [`ComparedSolution`]: what a [`Comparison`](crate::Comparison) and a
//! [`Convergence`](crate::Convergence) run read off a solution, so that one comparison serves
//! the const-generic [`Solution`] and the run-time-dimension [`DynSolution`].

use crate::dynamic::problem::DynSolution;
use crate::dynamic::slices::max_norm as flat_max_norm;
use crate::embedding::Embedding;
use crate::grid::Grid;
use crate::lagrangian::Vector;
use crate::linalg::max_norm;
use crate::solve::solution::{Solution, Warning};

/// A solution that a [`Comparison`](crate::Comparison) and a
/// [`Convergence`](crate::Convergence) run can report on: [`Solution<D>`] of a
/// [`Problem`](crate::Problem), whose reference curves return a [`Vector<D>`], and
/// [`DynSolution`] of a [`DynProblem`](crate::DynProblem), whose reference curves return a
/// `Vec<f64>` of length `d`.
///
/// Every measure is a max-norm over the stored nodes; a comparison stores every node, so
/// these are the nodes `Q_0, …, Q_N`.
///
/// ```
/// use varembed::{ComparedSolution, Embedding, Grid, Problem, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let solution = problem.solve_ivp(Scheme::Variational, 1.0, 0.0)?;
/// assert_eq!(solution.size(), 1.0);
/// assert!(solution.max_error(&|t| Vector::<1>::new(t.cos())) < 0.05);
/// # Ok::<(), varembed::Error>(())
/// ```
pub trait ComparedSolution: Clone + std::fmt::Debug {
    /// The value `q(t)` of a reference curve of this solution's problem.
    type Value;

    /// The grid the solution is on.
    fn grid(&self) -> &Grid;

    /// The embedding it was solved under.
    fn embedding(&self) -> &Embedding;

    /// Newton iterations of the solve.
    fn newton_iterations(&self) -> usize;

    /// What the solver warns about the solution.
    fn warnings(&self) -> &[Warning];

    /// `max_k |Q_k|∞`, the scale of the solution's round-off.
    fn size(&self) -> f64;

    /// `max_k |Q_k − q(t_k)|∞` against the curve `reference`.
    fn max_error(&self, reference: &dyn Fn(f64) -> Self::Value) -> f64;

    /// `max_k |Q_k − R_k|∞` to the solution `other`; `None` when they do not store the same
    /// number of nodes.
    fn distance_to(&self, other: &Self) -> Option<f64>;

    /// `max_k |Q_k − F_{k·s}|∞` over the nodes of this (coarse) solution, `F` the nodes of
    /// `fine` and `s` the refinement factor; `None` when the fine grid is not a refinement of
    /// this one.
    fn distance_on_coarse_nodes(&self, fine: &Self) -> Option<f64>;
}

/// The refinement factor `s` from `coarse` to `fine` nodes (counts `n + 1`, `m + 1`): `None`
/// unless `m` is a positive multiple of `n`.
fn stride(coarse: usize, fine: usize) -> Option<usize> {
    let (n, m) = (coarse.checked_sub(1)?, fine.checked_sub(1)?);
    (n > 0 && m % n == 0).then_some(m / n)
}

impl<const D: usize> ComparedSolution for Solution<D> {
    type Value = Vector<D>;

    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn embedding(&self) -> &Embedding {
        &self.embedding
    }

    fn newton_iterations(&self) -> usize {
        self.newton_iterations
    }

    fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    fn size(&self) -> f64 {
        max_norm(&self.q)
    }

    fn max_error(&self, reference: &dyn Fn(f64) -> Vector<D>) -> f64 {
        super::max_error(&self.grid, &self.q, reference)
    }

    fn distance_to(&self, other: &Self) -> Option<f64> {
        self.max_distance(&other.q)
    }

    fn distance_on_coarse_nodes(&self, fine: &Self) -> Option<f64> {
        let s = stride(self.q.len(), fine.q.len())?;
        Some(
            self.q
                .iter()
                .enumerate()
                .map(|(k, x)| (x - fine.q[k * s]).amax())
                .fold(0.0, f64::max),
        )
    }
}

/// `|x − y|∞` of two nodes.
fn gap(x: &[f64], y: &[f64]) -> f64 {
    x.iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
}

/// `max_j |A_j − B_{j·s}|∞` over the stored nodes `A_j` of `a`, node `j` of `a` against node
/// `j s` of `b`.
fn flat_distance(a: &DynSolution, b: &DynSolution, s: usize) -> f64 {
    (0..a.len())
        .map(|j| gap(a.node(j), b.node(j * s)))
        .fold(0.0, f64::max)
}

impl ComparedSolution for DynSolution {
    type Value = Vec<f64>;

    fn grid(&self) -> &Grid {
        &self.run.grid
    }

    fn embedding(&self) -> &Embedding {
        &self.run.embedding
    }

    fn newton_iterations(&self) -> usize {
        self.run.newton_iterations
    }

    fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    fn size(&self) -> f64 {
        flat_max_norm(&self.q)
    }

    /// A reference value of another length than `d` compares as far as the shorter reaches;
    /// the comparisons check the length once, before they solve.
    fn max_error(&self, reference: &dyn Fn(f64) -> Vec<f64>) -> f64 {
        self.indices
            .iter()
            .enumerate()
            .map(|(j, &k)| gap(self.node(j), &reference(self.run.grid.t(k))))
            .fold(0.0, f64::max)
    }

    fn distance_to(&self, other: &Self) -> Option<f64> {
        (self.indices == other.indices && self.dimension == other.dimension)
            .then(|| flat_distance(self, other, 1))
    }

    fn distance_on_coarse_nodes(&self, fine: &Self) -> Option<f64> {
        let complete = |s: &Self| s.len() == s.run.grid.n() + 1;
        if !complete(self) || !complete(fine) || self.dimension != fine.dimension {
            return None;
        }
        let s = stride(self.len(), fine.len())?;
        Some(flat_distance(self, fine, s))
    }
}
