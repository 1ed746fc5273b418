//! The Newton system of the fractional fast path at one iterate, known through products:
//! `J = L_xx + L_xv D + Dᵀ L_vx + Dᵀ L_vv D` on the interior unknowns, with `D = −σ Δ^α_σ`
//! applied by FFT, and the [`Preconditioner`] of its kinetic part.

use super::preconditioner::{Preconditioner, extra_row};
use crate::discretisation::Discretisation;
use crate::error::{Error, Location, Result};
use crate::fft_operator::FftOperator;
use crate::lagrangian::{Hessian, Lagrangian, Matrix, Vector};
use crate::linalg::{block, set_block};
use crate::operator::Operator;
use crate::solve::krylov::KrylovSystem;

/// The Newton system at one iterate: Hessians at the quadrature rows, the preconditioner, and
/// the FFT machinery with its buffers (allocated once per solve).
pub(super) struct FastSystem<const D: usize> {
    /// The number of steps `N`.
    pub(super) n: usize,
    pub(super) sigma: f64,
    /// `h^{−α}`.
    pub(super) scale: f64,
    /// The first quadrature row (1 for σ = −, 0 for σ = +).
    pub(super) first_row: usize,
    /// Where the row of `D` outside its square block sits among the rows.
    extra_row: usize,
    /// `Δ^α_σ` by FFT; its workspace serves every product of the solve.
    pub(super) velocity: FftOperator,
    /// Hessians at the rows `first_row..first_row + N`.
    pub(super) hessians: Vec<Hessian<D>>,
    pub(super) preconditioner: Preconditioner<D>,
    full: Vec<Vector<D>>,
    rows: Vec<Vector<D>>,
    /// Values on the rows (`N`): `L_vx δ + L_vv a` in a product, `p` in an evaluation.
    pub(super) rows_b: Vec<Vector<D>>,
    /// Values at the nodes (`N + 1`): `Dᵀ b` in a product, `Dᵀ p` in an evaluation.
    pub(super) nodes: Vec<Vector<D>>,
}

impl<const D: usize> FastSystem<D> {
    /// For `velocity = Δ^α_σ` on `N ≥ 2` steps, with its FFT form.
    pub(super) fn new(velocity: &Operator, fft: FftOperator) -> Self {
        let n = fft.n();
        let zero = Hessian {
            xx: Matrix::<D>::zeros(),
            xv: Matrix::<D>::zeros(),
            vv: Matrix::<D>::zeros(),
        };
        FastSystem {
            n,
            sigma: velocity.side().sign(),
            scale: velocity.scale(),
            first_row: velocity.first_row(),
            extra_row: extra_row(velocity.side(), n),
            preconditioner: Preconditioner::new(velocity, &fft),
            velocity: fft,
            hessians: vec![zero; n],
            full: vec![Vector::<D>::zeros(); n + 1],
            rows: vec![Vector::<D>::zeros(); n],
            rows_b: vec![Vector::<D>::zeros(); n],
            nodes: vec![Vector::<D>::zeros(); n + 1],
        }
    }

    /// A bound on `‖J‖∞` from the last linearisation: with `‖D‖∞ ≤ 2h^{−α}` (the
    /// Grünwald–Letnikov weights have `Σ|α_r| ≤ 2`),
    /// `‖J‖∞ ≤ max‖L_xx‖ + 4h^{−α} max‖L_xv‖ + 4h^{−2α} max‖L_vv‖`. Zero before the first one.
    pub(super) fn jacobian_bound(&self) -> f64 {
        let norm = |m: &Matrix<D>| {
            m.row_iter()
                .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let s = self.scale;
        self.hessians
            .iter()
            .map(|h| norm(&h.xx) + 4.0 * s * norm(&h.xv) + 4.0 * s * s * norm(&h.vv))
            .fold(0.0, f64::max)
    }

    /// Hessians and preconditioner blocks at `q` (with `v` the velocities on the rows).
    pub(super) fn linearize<L: Lagrangian<D> + ?Sized>(
        &mut self,
        disc: &Discretisation<'_, L, D>,
        q: &[Vector<D>],
        v: &[Vector<D>],
        at: Location,
    ) -> Result<()> {
        let (lagrangian, grid) = (disc.lagrangian(), disc.grid());
        for (i, h) in self.hessians.iter_mut().enumerate() {
            let k = i + self.first_row;
            *h = lagrangian.hessian(&q[k], &v[i], grid.t(k));
            let finite = h.xx.iter().chain(h.xv.iter()).chain(h.vv.iter());
            if !finite.into_iter().all(|c| c.is_finite()) {
                return Err(Error::NotFinite { at });
            }
        }
        self.preconditioner.update(
            &self.hessians,
            self.first_row,
            self.velocity.workspace_mut(),
        );
        Ok(())
    }

    /// `y = J x`; `a = D x` by FFT, or, given `image = D_a x`, from it and the one extra row.
    fn jacobian_product(&mut self, x: &[f64], image: Option<&[f64]>, y: &mut [f64]) {
        let n = self.n;
        self.full[0] = Vector::<D>::zeros();
        self.full[n] = Vector::<D>::zeros();
        for j in 1..n {
            self.full[j] = block(x, j - 1);
        }
        let minus_sigma = -self.sigma;
        match image {
            Some(image) => {
                // Rows 1..N−1 are the square block; the extra row is N (σ = −) or 0 (σ = +).
                let mut extra = Vector::<D>::zeros();
                for j in 1..n {
                    extra += self.full[j] * self.preconditioner.extra[j - 1];
                }
                for j in 1..n {
                    self.rows[j - self.first_row] = block(image, j - 1);
                }
                self.rows[self.extra_row] = extra;
            }
            None => {
                self.velocity
                    .apply_inplace(&self.full, &mut self.rows)
                    .expect("buffers sized for the grid");
                for a in self.rows.iter_mut() {
                    *a *= minus_sigma;
                }
            }
        }
        for i in 0..n {
            let k = i + self.first_row;
            let h = &self.hessians[i];
            self.rows_b[i] = h.xv.transpose() * self.full[k] + h.vv * self.rows[i];
        }
        self.velocity
            .apply_transpose_inplace(&self.rows_b, &mut self.nodes)
            .expect("buffers sized for the grid");
        for j in 1..n {
            let i = j - self.first_row;
            let h = &self.hessians[i];
            let yj = h.xx * self.full[j] + h.xv * self.rows[i] + self.nodes[j] * minus_sigma;
            set_block(y, j - 1, &yj);
        }
    }
}

impl<const D: usize> KrylovSystem for FastSystem<D> {
    fn len(&self) -> usize {
        (self.n - 1) * D
    }

    /// `J δ` with `a = D δ`, `b = L_vx δ + L_vv a` (on the rows), `J δ = L_xx δ + L_xv a + Dᵀ b`.
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.jacobian_product(x, None, y);
    }

    /// `z = P'⁻¹ r` ([`Preconditioner`]).
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        let ws = self.velocity.workspace_mut();
        self.preconditioner.apply(r, z, None, ws);
    }

    /// The images are `D_a x` (`N − 1` interior rows).
    fn image_len(&self) -> usize {
        self.len()
    }

    /// `P'⁻¹ r`, whose middle vector yields `D_a z` on the way.
    fn precondition_with_image(&mut self, r: &[f64], z: &mut [f64], image: &mut [f64]) {
        let ws = self.velocity.workspace_mut();
        self.preconditioner.apply(r, z, Some(image), ws);
    }

    /// `J x` with the interior rows of `a = D x` taken from `image` (one FFT product, `Dᵀ b`).
    fn apply_with_image(&mut self, x: &[f64], image: &[f64], y: &mut [f64]) {
        self.jacobian_product(x, Some(image), y);
    }
}
