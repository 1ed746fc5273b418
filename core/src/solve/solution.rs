//! [`Solution`]: what every solver returns.

use crate::embedding::{Embedding, Scheme};
use crate::grid::Grid;
use crate::lagrangian::Vector;
use std::fmt;

/// Something a caller should know about a returned solution that is not an error: the solve
/// succeeded, but the numbers may not mean what they seem.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// A fractional boundary value problem of order `α ≤ 1/2` with values imposed at both ends.
    ///
    /// The action's natural space is `H^α`, whose curves have point values only for
    /// `α > 1/2`: the end value `q(b)` cannot be imposed on the continuous problem, which in
    /// general has no solution. The discrete system is still solvable, but its solutions need
    /// not converge as `N` grows (a boundary layer forms at `t = b`; on the pendulum
    /// `L = ½v² + cos x` at `α = 1/2` on `[0, 1]`, `Q_0 = 0`, `Q_N = 1`, `Q(1/2)` is 0.466,
    /// 0.426, 0.392 at `N` = 250, 1000, 4000 and still 0.332 at `N = 10⁵`). With compatible data — end values the problem without the
    /// condition at `b` reaches by itself — they do converge; deciding that would take another
    /// solve, so every such problem carries the warning.
    IllPosedFractional {
        /// The order α of the Grünwald–Letnikov embedding.
        alpha: f64,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::IllPosedFractional { alpha } => write!(
                f,
                "ill-posed: a fractional boundary value problem of order α = {alpha} ≤ 1/2 with \
                 both end values imposed has no continuous solution for generic data; the \
                 discrete solutions need not converge as N grows"
            ),
        }
    }
}

/// A discrete curve computed by a solver, with how it was computed.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution<const D: usize> {
    /// The scheme solved.
    pub scheme: Scheme,
    /// The embedding.
    pub embedding: Embedding,
    /// The grid.
    pub grid: Grid,
    /// The nodes `Q_0..=Q_N`.
    pub q: Vec<Vector<D>>,
    /// The discrete momenta `p_0..=p_N` at the nodes, for the schemes that carry them as their
    /// state (the Gauss–Legendre integrators, one-step maps of `(q_k, p_k)`); empty otherwise.
    pub momenta: Vec<Vector<D>>,
    /// Newton iterations, summed over the steps (IVP) or of the global system (BVP).
    pub newton_iterations: usize,
    /// Steps taken by the closed-form update, with no Newton iteration (IVP).
    pub explicit_steps: usize,
    /// What the caller should know about this solution (empty when nothing): e.g.
    /// [`Warning::IllPosedFractional`].
    pub warnings: Vec<Warning>,
}

impl<const D: usize> Solution<D> {
    /// Component `i` of every node, `None` when `i ≥ D`.
    pub fn component(&self, i: usize) -> Option<Vec<f64>> {
        (i < D).then(|| self.q.iter().map(|x| x[i]).collect())
    }
    /// The last node `Q_N`.
    pub fn last(&self) -> Vector<D> {
        *self.q.last().expect("a solution has N + 1 ≥ 2 nodes")
    }
    /// Max over nodes of `|Q_k − other_k|∞`; `None` when the lengths differ.
    pub fn max_distance(&self, other: &[Vector<D>]) -> Option<f64> {
        (other.len() == self.q.len()).then(|| {
            self.q
                .iter()
                .zip(other)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).amax()))
        })
    }
}
