//! The Newton system of the fractional fast path at one iterate, known through products:
//! `J = L_xx + L_xv D + Dᵀ L_vx + Dᵀ L_vv D` on the interior unknowns, with `D = −σ Δ^α_σ`
//! applied by FFT, and the [`Preconditioner`] of its kinetic part. The corrected form adds its
//! starting columns ([`EndColumns`]) to `D` and to the momenta's operator, which for its
//! direct scheme is not `Dᵀ`; the preconditioner stays the paper's operator's.

use super::end_columns::EndColumns;
use super::preconditioner::{Preconditioner, extra_row};
use super::row_blocks::RowBlocks;
use crate::discretisation::Discretisation;
use crate::error::{Error, Location, Result};
use crate::fft_operator::FftOperator;
use crate::halves;
use crate::lagrangian::{Hessian, Lagrangian, Matrix, Vector};
use crate::linalg::{add_to_block, block, set_block, zeroed};
use crate::operator::Operator;
use crate::solve::krylov::{KrylovSystem, onto};

/// The Newton system at one iterate: Hessians at the quadrature rows, the preconditioner, and
/// the FFT operator whose workspace serves every product of the solve.
///
/// Memory (`d = 1`, per node): the Hessians (24 bytes; 8 for a constant `L_vv` and a zero
/// `L_xv`, which [`RowBlocks`] store once), `a = D x` on the rows (8, where a product forms it)
/// and the preconditioner's blocks (`L_vv⁻¹`, once where it is constant, and `U`: 16). The
/// other vectors of a
/// product (the nodes of `x`, `b = L_vx x + L_vv a`, `Dᵀ b`) are read and written by the
/// product's closures straight from and into the Krylov solver's vectors.
pub(super) struct FastSystem<'a, const D: usize> {
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
    pub(super) velocity: &'a mut FftOperator,
    /// The Hessians' blocks at the rows `first_row..first_row + N` (entry `i` at row
    /// `first_row + i`).
    pub(super) xx: RowBlocks<D>,
    pub(super) xv: RowBlocks<D>,
    pub(super) vv: RowBlocks<D>,
    pub(super) preconditioner: Preconditioner<'a, D>,
    /// `a = D x` on the rows (`N`, flat: component `c` of row `i` at `i D + c`) in a product:
    /// lent for a Newton step's Krylov solve where its products form it ([`forms_rows`]), or
    /// allocated by the first product that does (none does where the kinetic part comes from
    /// the preconditioner and no `L_xv` reads `D x`, as on the benchmark pendulum).
    ///
    /// [`forms_rows`]: Self::forms_rows
    rows: Vec<f64>,
    /// The corrected form's starting columns; `None` for the paper's operators.
    pub(super) columns: Option<EndColumns<'a>>,
    /// Whether the products leave the starting columns out: the paper's symmetric Jacobian at
    /// the same iterate, which the ill-posedness check's Lanczos process needs.
    pub(super) plain: bool,
    /// Whether some `L_xv` block is non-zero at the last linearisation.
    mixed: bool,
    /// Whether the Hessians held were set by [`keep_hessian`](Self::keep_hessian) for the
    /// next linearisation, which then does not evaluate them again.
    kept: bool,
    /// The Jacobian bound of the last linearisation, once its `L_xx` and `L_xv` are released
    /// ([`release_hessians`](Self::release_hessians)); `None` while they are held.
    released_bound: Option<f64>,
}

impl<'a, const D: usize> FastSystem<'a, D> {
    /// For `velocity = Δ^α_σ` on `N ≥ 2` steps, with its FFT form (of the plain operator), and
    /// the starting columns of a corrected form's `velocity` and momentum operator `adjoint`.
    pub(super) fn new(
        velocity: &'a Operator,
        columns: Option<EndColumns<'a>>,
        fft: &'a mut FftOperator,
    ) -> Self {
        let n = fft.n();
        let zero = RowBlocks::uniform(Matrix::<D>::zeros(), n);
        FastSystem {
            n,
            sigma: velocity.side().sign(),
            scale: velocity.scale(),
            first_row: velocity.first_row(),
            extra_row: extra_row(velocity.side(), n),
            preconditioner: Preconditioner::new(velocity, fft),
            velocity: fft,
            xx: zero.clone(),
            xv: zero.clone(),
            vv: zero,
            rows: Vec::new(),
            columns,
            plain: false,
            mixed: true,
            kept: false,
            released_bound: None,
        }
    }

    /// The starting columns, unless the products leave them out.
    fn active_columns(&self) -> Option<&EndColumns<'a>> {
        self.columns.as_ref().filter(|_| !self.plain)
    }

    /// Whether `J` is symmetric (the momenta's operator is `Dᵀ`).
    pub(super) fn symmetric(&self) -> bool {
        self.active_columns().is_none_or(EndColumns::symmetric)
    }

    /// A bound on `‖J‖∞` from the last linearisation: with `‖D‖∞ ≤ 2h^{−α}` (the
    /// Grünwald–Letnikov weights have `Σ|α_r| ≤ 2`),
    /// `‖J‖∞ ≤ max‖L_xx‖ + 4h^{−α} max‖L_xv‖ + 4h^{−2α} max‖L_vv‖`, or at the Hessians kept for the
    /// next one ([`keep_hessian`](Self::keep_hessian)); zero before either.
    /// The starting columns add their row sums to the bounds of `D` and of the momenta's
    /// operator. After [`release_hessians`](Self::release_hessians), the bound they gave.
    pub(super) fn jacobian_bound(&self) -> f64 {
        if let Some(bound) = self.released_bound {
            return bound;
        }
        let norm = |m: &Matrix<D>| {
            m.row_iter()
                .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let (c, e) = self
            .columns
            .as_ref()
            .map_or((0.0, 0.0), EndColumns::row_sums);
        let (d, b) = (2.0 * self.scale + c, 2.0 * self.scale + e);
        (0..self.n)
            .map(|i| {
                let (xx, xv, vv) = (self.xx.get(i), self.xv.get(i), self.vv.get(i));
                norm(xx) + (d + b) * norm(xv) + b * d * norm(vv)
            })
            .fold(0.0, f64::max)
    }

    /// Hessians and preconditioner blocks at `q` (with `v` the velocities on the rows, flat:
    /// component `c` of `V_i` at `i D + c`).
    pub(super) fn linearize<L: Lagrangian<D> + ?Sized>(
        &mut self,
        disc: &Discretisation<'_, L, D>,
        q: &[Vector<D>],
        v: &[f64],
        at: Location,
    ) -> Result<()> {
        let (lagrangian, grid) = (disc.lagrangian(), disc.grid());
        self.released_bound = None;
        if !std::mem::take(&mut self.kept) {
            for i in 0..grid.n() {
                let k = i + self.first_row;
                let h = lagrangian.hessian(&q[k], &block(v, i), grid.t(k));
                if !self.set_hessian(i, h) {
                    return Err(Error::NotFinite { at });
                }
            }
        }
        let zero = Matrix::<D>::zeros();
        self.mixed = self.xv.distinct().iter().any(|xv| *xv != zero);
        let ws = self.velocity.workspace_mut();
        self.preconditioner.update(&self.vv, self.first_row, ws);
        Ok(())
    }

    /// Frees the `L_xx` and `L_xv` blocks (`L_vv` stays with the preconditioner built on it),
    /// keeping the Jacobian bound they give: between a Newton step's Krylov solve and the next
    /// linearisation, which sets them again, nothing reads them, and at `d = 1` a varying
    /// `L_xx` is 8 bytes a node beside the line search's vectors. Products need a
    /// [`linearize`](Self::linearize) first.
    pub(super) fn release_hessians(&mut self) {
        self.released_bound = Some(self.jacobian_bound());
        let zero = RowBlocks::uniform(Matrix::<D>::zeros(), self.n);
        (self.xx, self.xv) = (zero.clone(), zero);
    }

    /// Row `i`'s second derivatives, evaluated at the iterate and velocities the next
    /// [`linearize`](Self::linearize) is called with (the input checks' at the guess), which
    /// then reads them instead of evaluating them again; rows are handed in order from 0.
    /// `false` where a block is not finite: nothing is kept then.
    pub(super) fn keep_hessian(&mut self, i: usize, h: &Hessian<D>) -> bool {
        self.released_bound = None;
        self.kept = self.set_hessian(i, *h) && (i == 0 || self.kept);
        self.kept
    }

    /// Sets row `i`'s blocks; `false` (the blocks left as they were) where one is not finite.
    fn set_hessian(&mut self, i: usize, mut h: Hessian<D>) -> bool {
        // At the fixed end node only L_vv acts on the unknowns (through D); its L_xx and L_xv
        // multiply that node's zero correction or feed a row no one solves, and may be
        // infinite there (a forcing singular at that end).
        let k = i + self.first_row;
        if !(1..self.n).contains(&k) {
            h.xx = Matrix::<D>::zeros();
            h.xv = Matrix::<D>::zeros();
        }
        let finite = h.xx.iter().chain(h.xv.iter()).chain(h.vv.iter());
        if !finite.into_iter().all(|c| c.is_finite()) {
            return false;
        }
        self.xx.set(i, h.xx);
        self.xv.set(i, h.xv);
        self.vv.set(i, h.vv);
        true
    }

    /// Whether the Krylov solver's products form `a = D x` on the rows: all but those that take
    /// the kinetic part from the preconditioner where no `L_xv` reads `D x`.
    pub(super) fn forms_rows(&self) -> bool {
        !self.kinetic_known() || self.mixed
    }

    /// Lends a vector for the rows of `a = D x` (module docs of [`FastSystem::rows`]).
    pub(super) fn lend_rows(&mut self, rows: Vec<f64>) {
        self.rows = rows;
    }

    /// The rows' vector back (empty when there is none), for the Krylov solver: it is not read
    /// again before the next linearisation.
    pub(super) fn take_rows(&mut self) -> Vec<f64> {
        std::mem::take(&mut self.rows)
    }

    /// Whether `J x = P' x + (J − P') x` may be formed from `P' x` given: the preconditioner
    /// inverts `P'` exactly and the products leave out no term of `P'` it does not hold (the
    /// starting columns).
    pub(super) fn kinetic_known(&self) -> bool {
        self.preconditioner.is_exact() && self.active_columns().is_none()
    }

    /// `y ← c · J x + β y` (`y` only written where `β = 0`); `a = D x` by FFT, or, given
    /// `image = D_a x`, from it and the one extra row. Given `kinetic = P' x` (as
    /// `factor · r`, from `x = factor · P'⁻¹ r`), the kinetic part `Dᵀ L_vv D x` is taken from
    /// it: `J x = P' x + L_xx x + L_xv a + Dᵀ L_vx x`, no FFT product at all when every `L_xv`
    /// is zero.
    fn jacobian_product(
        &mut self,
        x: &[f64],
        image: Option<&[f64]>,
        kinetic: Option<(&[f64], f64)>,
        (scale, beta): (f64, f64),
        y: &mut [f64],
    ) {
        debug_assert!(
            self.released_bound.is_none(),
            "a product with released Hessians"
        );
        let n = self.n;
        let combine = |y: f64, jx: f64| onto(y, jx, (scale, beta));
        if let Some((r, factor)) = kinetic.filter(|_| !self.mixed) {
            // Row j − 1 of the unknowns is node j, whose Hessians are at j − first_row.
            let (xx, shift) = (&self.xx, 1 - self.first_row);
            halves::each((n - 1, D), (&mut y[..], r, x), |first, (y, r, x)| {
                for i in 0..y.len() / D {
                    let xx = xx.get(first + i + shift);
                    let jx = block::<D>(r, i) * factor + xx * block::<D>(x, i);
                    for (c, jx) in jx.iter().enumerate() {
                        y[i * D + c] = combine(y[i * D + c], *jx);
                    }
                }
            });
            return;
        }
        if self.rows.len() != n * D {
            zeroed(&mut self.rows, n * D);
        }
        // Node k of x (zero at the fixed ends), component c.
        let node = |k: usize, c: usize| {
            if (1..n).contains(&k) {
                x[(k - 1) * D + c]
            } else {
                0.0
            }
        };
        let minus_sigma = -self.sigma;
        match image {
            Some(image) => {
                // Rows 1..N−1 are the square block; the extra row is N (σ = −) or 0 (σ = +).
                let mut extra = Vector::<D>::zeros();
                for j in 1..n {
                    extra += block::<D>(x, j - 1) * self.preconditioner.extra(j - 1);
                }
                for j in 1..n {
                    set_block(
                        &mut self.rows,
                        j - self.first_row,
                        &block::<D>(image, j - 1),
                    );
                }
                set_block(&mut self.rows, self.extra_row, &extra);
            }
            None => {
                let rows = &mut self.rows;
                for c in 0..D {
                    self.velocity
                        .apply_with(|k| node(k, c), |i, a| rows[i * D + c] = a * minus_sigma);
                }
            }
        }
        let node_vector = |k: usize| {
            if (1..n).contains(&k) {
                block::<D>(x, k - 1)
            } else {
                Vector::<D>::zeros()
            }
        };
        let first_row = self.first_row;
        if let Some(columns) = self.columns.as_ref().filter(|_| !self.plain) {
            let rows = &mut self.rows;
            columns.add_velocity(node_vector, first_row, |i, a| add_to_block(rows, i, &a));
        }
        let (xx, xv, vv) = (&self.xx, &self.xv, &self.vv);
        let rows = |i: usize| block::<D>(&self.rows, i);
        // Where every `L_xv` is zero its terms are left out: two products of blocks fewer a
        // row on each side of the transform, read one row at a time.
        let mixed = self.mixed;
        for c in 0..D {
            // b_i = L_vx δ + L_vv a on the rows, component c, formed as the product reads it;
            // y_j = L_xx δ + L_xv a + (Dᵀ b)_j written as the product yields it.
            // Without the kinetic part, b_i = L_vx δ and y_j gains (P' x)_j instead.
            let with_vv = if kinetic.is_some() { 0.0 } else { 1.0 };
            let b = |i: usize| {
                let kinetic = with_vv * vv.get(i).row(c).tr_dot(&rows(i));
                if mixed {
                    xv.get(i).column(c).dot(&node_vector(i + first_row)) + kinetic
                } else {
                    kinetic
                }
            };
            self.velocity.apply_transpose_with(b, |j, dt_b| {
                if (1..n).contains(&j) {
                    let i = j - first_row;
                    let known = kinetic.map_or(0.0, |(r, factor)| r[(j - 1) * D + c] * factor);
                    let mixed_term = if mixed {
                        xv.get(i).row(c).tr_dot(&rows(i))
                    } else {
                        0.0
                    };
                    let jx = xx.get(i).row(c).tr_dot(&node_vector(j))
                        + mixed_term
                        + dt_b * minus_sigma
                        + known;
                    let at = (j - 1) * D + c;
                    y[at] = combine(y[at], jx);
                }
            });
        }
        if let Some(columns) = self.active_columns() {
            let b =
                |i: usize| xv.get(i).transpose() * node_vector(i + first_row) + vv.get(i) * rows(i);
            columns.add_momentum(b, first_row, |j, e| add_to_block(y, j - 1, &(e * scale)));
        }
    }
}

impl<const D: usize> KrylovSystem for FastSystem<'_, D> {
    fn len(&self) -> usize {
        (self.n - 1) * D
    }

    /// `J δ` with `a = D δ`, `b = L_vx δ + L_vv a` (on the rows), `J δ = L_xx δ + L_xv a + Dᵀ b`.
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.jacobian_product(x, None, None, (1.0, 0.0), y);
    }

    /// `z = P'⁻¹ r` ([`Preconditioner`]).
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        let ws = self.velocity.workspace_mut();
        self.preconditioner.apply(r, z, None, ws);
    }

    /// The images are `D_a x` (`N − 1` interior rows); none where the products take the
    /// kinetic part from the preconditioner's input and no `L_xv` reads `D x` (two vectors of
    /// MINRES fewer, 16 bytes a node at `d = 1`).
    fn image_len(&self) -> usize {
        if self.forms_rows() { self.len() } else { 0 }
    }

    /// `P'⁻¹ r`, whose middle vector yields `D_a z` on the way (into `image` unless it is
    /// empty).
    fn precondition_with_image(&mut self, r: &[f64], z: &mut [f64], image: &mut [f64]) {
        let ws = self.velocity.workspace_mut();
        let image = Some(image).filter(|image| !image.is_empty());
        self.preconditioner.apply(r, z, image, ws);
    }

    /// `J x` with the interior rows of `a = D x` taken from `image` (one FFT product, `Dᵀ b`).
    fn apply_with_image(&mut self, x: &[f64], image: &[f64], y: &mut [f64]) {
        // No image where none is kept (`image_len`): `D x` by FFT.
        let image = Some(image).filter(|image| !image.is_empty());
        self.jacobian_product(x, image, None, (1.0, 0.0), y);
    }

    /// `y ← c · J x + β y` for `x = factor · P'⁻¹ r`: `factor · r` stands for `P' x` when
    /// the preconditioner is exact, sparing the product `Dᵀ L_vv D x`.
    fn apply_preconditioned(
        &mut self,
        x: &[f64],
        image: &[f64],
        preconditioned: (&[f64], f64),
        onto: (f64, f64),
        y: &mut [f64],
    ) {
        let kinetic = Some(preconditioned).filter(|_| self.kinetic_known());
        let image = Some(image).filter(|image| !image.is_empty());
        self.jacobian_product(x, image, kinetic, onto, y);
    }
}
