//! The residual of the fractional fast path at an iterate, `r_j = f_j + (Dᵀ p)_j` on the
//! interior nodes (`(B p)_j` with the corrected form's starting columns), by FFT in the
//! workspace of the [`FastSystem`], into reused buffers.

use super::system::FastSystem;
use crate::discretisation::Discretisation;
use crate::error::{Error, Location, Result, check_len};
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::{add_to_block, block, set_block, zeroed};

/// The residual at an iterate, with what the Jacobian needs. Its buffers are reused from one
/// evaluation to the next (at `N = 10⁷` a fresh `N`-vector costs its page faults: tens of
/// milliseconds).
pub(super) struct Evaluation<const D: usize> {
    /// `r_j`, `j = 1..N−1`, flat: component `c` of `r_j` at `(j − 1) D + c`, as the Krylov
    /// solvers read a right-hand side.
    pub(super) r: Vec<f64>,
    /// `V` on the rows, flat as `r`: component `c` of `V_i` at `i D + c`.
    pub(super) v: Vec<f64>,
    /// `p = ∂L/∂v` on the rows, flat as `V`: read by the residual's product and spent after
    /// it (the Newton direction hands its vector to the Krylov solver).
    pub(super) p: Vec<f64>,
    /// `max|f| + h^{−α} max|p|` over what the rows read: `f` on the interior nodes, `p` on
    /// the quadrature nodes (the scale of the rows, as the dense path's).
    pub(super) scale: f64,
    /// `max|r|` and `‖r‖₂`, measured by [`residual`] in the sweep that checks `r`.
    norms: (f64, f64),
}

impl<const D: usize> Evaluation<D> {
    /// Buffers for `N` steps.
    pub(super) fn new(n: usize) -> Self {
        Self::from_buffers(n, [Vec::new(), Vec::new(), Vec::new()])
    }

    /// Buffers for `N` steps in the allocations of three vectors (the Krylov solver's, idle
    /// while a trial iterate is evaluated), for `r`, `V` and `p` (the last sized by
    /// [`residual`], which alone uses it).
    pub(super) fn from_buffers(n: usize, [mut r, mut v, p]: [Vec<f64>; 3]) -> Self {
        zeroed(&mut r, (n - 1) * D);
        zeroed(&mut v, n * D);
        Evaluation {
            r,
            v,
            p,
            scale: 0.0,
            norms: (0.0, 0.0),
        }
    }

    /// The allocations back, for [`from_buffers`](Self::from_buffers) or the Krylov solver.
    pub(super) fn into_buffers(self) -> [Vec<f64>; 3] {
        [self.r, self.v, self.p]
    }

    /// `max|r|` and `‖r‖₂` of the last [`residual`].
    pub(super) fn norms(&self) -> (f64, f64) {
        self.norms
    }
}

/// The residual at `q` into `eval` (a non-finite value anywhere is [`Error::NotFinite`] at
/// Newton iteration `iteration`).
#[cfg(test)]
pub(super) fn evaluate<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    system: &mut FastSystem<'_, D>,
    q: &[Vector<D>],
    iteration: usize,
    eval: &mut Evaluation<D>,
) -> Result<()> {
    velocities(disc, system, q, iteration, eval)?;
    residual(disc, system, q, iteration, eval)
}

/// The first part of an evaluation at `q`: `V` on the rows into `eval.v`.
pub(super) fn velocities<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    system: &mut FastSystem<'_, D>,
    q: &[Vector<D>],
    iteration: usize,
    eval: &mut Evaluation<D>,
) -> Result<()> {
    let not_finite = Error::NotFinite {
        at: Location::Newton(iteration),
    };
    let n = system.n;
    check_len("curve", n + 1, q.len())?;
    if !q.iter().all(|x| x.iter().all(|c| c.is_finite())) {
        return Err(not_finite);
    }
    let minus_sigma = -system.sigma;
    // Through the differences of the curve (see `FftOperator`): the residual's accuracy rests
    // on V's, whose error the rows amplify by h^{−α}.
    let v = &mut eval.v;
    // The Caputo form applies the operator to `Q − Q_e`, `Q_e` the end node's value (a shift
    // of the curve the differences do not see but the end's term does).
    let end = disc.embedding().caputo_end(n);
    for c in 0..D {
        let base = end.map_or(0.0, |e| q[e][c]);
        system
            .velocity
            .apply_by_differences_with(|k| q[k][c] - base, |i, y| v[i * D + c] = y * minus_sigma);
    }
    if let Some(columns) = &system.columns {
        // The starting columns read the same shifted curve.
        let base = end.map_or(Vector::<D>::zeros(), |e| q[e]);
        columns.add_velocity(
            |j| q[j] - base,
            system.first_row,
            |i, a| add_to_block(v, i, &a),
        );
    }
    Ok(())
}

/// The second part of an evaluation, after [`velocities`]: the residual from `eval.v` (a
/// non-finite value anywhere is [`Error::NotFinite`] at Newton iteration `iteration`).
pub(super) fn residual<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    system: &mut FastSystem<'_, D>,
    q: &[Vector<D>],
    iteration: usize,
    eval: &mut Evaluation<D>,
) -> Result<()> {
    let not_finite = Error::NotFinite {
        at: Location::Newton(iteration),
    };
    let (lagrangian, grid) = (disc.lagrangian(), disc.grid());
    let (n, minus_sigma) = (system.n, -system.sigma);
    // r starts as f on the interior nodes; p goes in its own buffer.
    zeroed(&mut eval.p, n * D);
    let (mut f_max, mut p_max) = (0.0f64, 0.0f64);
    for i in 0..n {
        let k = i + system.first_row;
        let (fk, pk) = lagrangian.gradient(&q[k], &block(&eval.v, i), grid.t(k));
        // The end node's force is read by no row: it plays no part in the scale, and may be
        // infinite (a forcing singular at that end).
        let row = (1..n).contains(&k);
        if !pk.iter().all(|c| c.is_finite()) || (row && !fk.iter().all(|c| c.is_finite())) {
            return Err(not_finite);
        }
        if row {
            f_max = f_max.max(fk.amax());
            set_block(&mut eval.r, k - 1, &fk);
        }
        p_max = p_max.max(pk.amax());
        set_block(&mut eval.p, i, &pk);
    }
    let (p, r) = (&eval.p, &mut eval.r);
    for c in 0..D {
        system.velocity.apply_transpose_with(
            |i| p[i * D + c],
            |j, y| {
                if (1..n).contains(&j) {
                    r[(j - 1) * D + c] += y * minus_sigma;
                }
            },
        );
    }
    if let Some(columns) = &system.columns {
        columns.add_momentum(
            |i| block::<D>(p, i),
            system.first_row,
            |j, e| add_to_block(r, j - 1, &e),
        );
    }
    eval.scale = f_max + system.scale * p_max;
    // One sweep checks r and measures it (at N = 10⁷ each sweep is milliseconds).
    let (mut finite, mut max, mut squares) = (true, 0.0f64, 0.0);
    for x in &eval.r {
        finite &= x.is_finite();
        max = max.max(x.abs());
        squares += x * x;
    }
    if !finite {
        return Err(not_finite);
    }
    eval.norms = (max, squares.sqrt());
    Ok(())
}
