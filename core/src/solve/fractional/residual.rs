//! The residual of the fractional fast path at an iterate, `r_j = f_j + (Dᵀ p)_j` on the
//! interior nodes, by FFT in the buffers of the [`FastSystem`].

use super::system::FastSystem;
use crate::discretisation::Discretisation;
use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Vector};
use crate::linalg::max_norm;

/// The residual at an iterate, with what the Jacobian needs.
pub(super) struct Evaluation<const D: usize> {
    /// `r_j`, `j = 1..N−1`.
    pub(super) r: Vec<Vector<D>>,
    /// `V` on the rows.
    pub(super) v: Vec<Vector<D>>,
    /// `max|f| + h^{−α} max|p|` over what the rows read: `f` on the interior nodes, `p` on
    /// the quadrature nodes (the scale of the rows, as the dense path's).
    pub(super) scale: f64,
}

/// The residual at `q` (a non-finite value anywhere is [`Error::NotFinite`] at Newton
/// iteration `iteration`).
pub(super) fn evaluate<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    system: &mut FastSystem<D>,
    q: &[Vector<D>],
    iteration: usize,
) -> Result<Evaluation<D>> {
    let not_finite = Error::NotFinite {
        at: Location::Newton(iteration),
    };
    if !q.iter().all(|x| x.iter().all(|c| c.is_finite())) {
        return Err(not_finite);
    }
    let (lagrangian, grid) = (disc.lagrangian(), disc.grid());
    let n = system.n;
    let mut v = vec![Vector::<D>::zeros(); n];
    // Through the differences of the curve (see `FftOperator`): the residual's accuracy rests
    // on V's, whose error the rows amplify by h^{−α}.
    system.velocity.apply_by_differences_inplace(q, &mut v)?;
    if let Some(end) = disc.embedding().caputo_end(n) {
        // The Caputo form: the end node's term taken out (a rank-one correction, no copy).
        disc.velocity_operator().remove_end_term(q[end], &mut v);
    }
    let minus_sigma = -system.sigma;
    // r starts as f on the interior nodes; p goes in the rows' buffer (no allocation per call).
    let mut r = vec![Vector::<D>::zeros(); n - 1];
    let mut p = std::mem::take(&mut system.rows_b);
    let mut f_max = 0.0f64;
    for i in 0..n {
        let k = i + system.first_row;
        v[i] *= minus_sigma;
        let (fk, pk) = lagrangian.gradient(&q[k], &v[i], grid.t(k));
        if !fk.iter().chain(pk.iter()).all(|c| c.is_finite()) {
            system.rows_b = p;
            return Err(not_finite);
        }
        // The end node's force is read by no row: it plays no part in the scale.
        if (1..n).contains(&k) {
            f_max = f_max.max(fk.amax());
            r[k - 1] = fk;
        }
        p[i] = pk;
    }
    let mut dt_p = std::mem::take(&mut system.nodes);
    let applied = system.velocity.apply_transpose_inplace(&p, &mut dt_p);
    for (j, rj) in r.iter_mut().enumerate() {
        *rj += dt_p[j + 1] * minus_sigma;
    }
    let scale = f_max + system.scale * max_norm(&p);
    system.rows_b = p;
    system.nodes = dt_p;
    applied?;
    if !r.iter().all(|x| x.iter().all(|c| c.is_finite())) {
        return Err(not_finite);
    }
    Ok(Evaluation { r, v, scale })
}
