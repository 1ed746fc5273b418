//! The default initial guess of a boundary value problem: the straight line between the ends.
//! Its own module so that the fractional fast path, which `bvp` calls, can tell that line
//! from a guess of the caller's ([`is_straight_line`]).

use crate::error::Result;
use crate::lagrangian::Vector;
use crate::memory::reserve;

/// The straight line from `qa` to `qb` on `n` steps: the default initial guess.
pub(crate) fn straight_line<const D: usize>(
    qa: Vector<D>,
    qb: Vector<D>,
    n: usize,
) -> Result<Vec<Vector<D>>> {
    let mut line = reserve(n + 1, "the nodes Q_0..=Q_N of the initial guess")?;
    line.extend((0..=n).map(|k| line_node(&qa, &qb, k, n)));
    Ok(line)
}

/// Whether `q` is the straight line between its ends, node for node as [`straight_line`]
/// makes it: the guess of [`Problem::solve_bvp`](crate::Problem::solve_bvp).
pub(crate) fn is_straight_line<const D: usize>(q: &[Vector<D>]) -> bool {
    let n = q.len() - 1;
    q.iter()
        .enumerate()
        .all(|(k, x)| *x == line_node(&q[0], &q[n], k, n))
}

/// Node `k` of the straight line from `qa` to `qb` on `n` steps. The ends exactly
/// (`qa + (qb − qa)·1` need not round to `qb`), so that a non-finite end stays where it was
/// given and is reported as that end.
fn line_node<const D: usize>(qa: &Vector<D>, qb: &Vector<D>, k: usize, n: usize) -> Vector<D> {
    match k {
        0 => *qa,
        k if k == n => *qb,
        k => qa + (qb - qa) * (k as f64 / n as f64),
    }
}
