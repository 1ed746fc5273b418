//! [`Solution`]: what every solver returns.

use crate::embedding::{Embedding, Scheme};
use crate::grid::Grid;
use crate::lagrangian::Vector;

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
    /// Newton iterations, summed over the steps (IVP) or of the global system (BVP).
    pub newton_iterations: usize,
    /// Steps taken by the closed-form update, with no Newton iteration (IVP).
    pub explicit_steps: usize,
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
