//! [`Discretisation`]: a Lagrangian on a grid under a discrete embedding, with what every solver
//! evaluates on it: the discrete velocity, the residuals of the two schemes (computed by
//! separate code, so that comparing them is the coherence test), the action and energy, and the
//! Jacobian of the global system.
//!
//! The Grünwald–Letnikov operators are dense: on grids of more than
//! [`FFT_OPERATOR_THRESHOLD`] steps they are applied by FFT ([`FftOperator`], `O(N log N)`)
//! instead of the `O(N²)` loops of [`Operator`]. The FFT forms are built on first use and kept,
//! so repeated evaluations (a comparison, the dense-LU Newton's residuals) plan and transform
//! the weights once. The two routes agree to round-off (tested below).

use crate::embedding::{Embedding, EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result, check_len};
use crate::fft_operator::FftOperator;
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::operator::Operator;
use crate::options::FFT_OPERATOR_THRESHOLD;
use std::ops::RangeInclusive;
use std::sync::{Mutex, OnceLock, PoisonError, TryLockError};

/// An operator's FFT form, built on first use. Its products need scratch buffers, so it sits
/// behind a lock: a discretisation shared between threads stays usable, its FFT products
/// taking turns.
#[derive(Default)]
struct FftCache(OnceLock<Mutex<FftOperator>>);

impl FftCache {
    fn with<R>(&self, op: &Operator, f: impl FnOnce(&mut FftOperator) -> R) -> R {
        let cell = self.0.get_or_init(|| Mutex::new(FftOperator::new(op)));
        // The buffers carry nothing from one product to the next, so a product that panicked
        // leaves nothing behind to distrust.
        let mut fft = cell.lock().unwrap_or_else(PoisonError::into_inner);
        f(&mut fft)
    }

    /// Like [`with`](Self::with), for a long use: when another thread holds the lock, `f`
    /// works on a copy instead of waiting for it.
    fn with_exclusive<R>(&self, op: &Operator, f: impl FnOnce(&mut FftOperator) -> R) -> R {
        let cell = self.0.get_or_init(|| Mutex::new(FftOperator::new(op)));
        match cell.try_lock() {
            Ok(mut fft) => f(&mut fft),
            Err(TryLockError::Poisoned(poisoned)) => f(&mut poisoned.into_inner()),
            Err(TryLockError::WouldBlock) => {
                let mut copy = self.with(op, |fft| fft.clone());
                f(&mut copy)
            }
        }
    }
}

/// A Lagrangian on a grid under an embedding, with the embedding's two operators.
pub(crate) struct Discretisation<'l, L: ?Sized, const D: usize> {
    lagrangian: &'l L,
    grid: Grid,
    embedding: Embedding,
    /// `Δ_σ` (or `Δ^α_σ`).
    velocity: Operator,
    /// `Δ_{−σ}` (or `Δ^α_{−σ}`).
    adjoint: Operator,
    velocity_fft: FftCache,
    adjoint_fft: FftCache,
    /// [`FFT_OPERATOR_THRESHOLD`] (tests raise it to force the dense loops).
    fft_threshold: usize,
    /// Unknown nodes per panel of the kinetic term's products ([`kinetic::PANEL`]; tests
    /// narrow it to cross panel borders).
    kinetic_panel: usize,
}

/// `V`, `f = ∂L/∂x`, `p = ∂L/∂v` at the quadrature nodes, stored by node index `0..=N` (the one
/// node outside `I_σ` holds zeros and is never read by a valid row).
///
/// For the symmetric embeddings entry `k ∈ 1..=N` belongs to the interval `[t_{k−1}, t_k]`:
/// `v` its velocity, `p` its momentum `P`, `f` its force `F_w` and `f_left` its force `F_u`
/// (see the interval module); `f_node[k]`, `k ∈ 1..=N−1`, is the force of the direct scheme at
/// node `k` with the centred velocity. Both extra vectors are empty for the other embeddings.
pub(crate) struct Pointwise<const D: usize> {
    pub v: Vec<Vector<D>>,
    pub f: Vec<Vector<D>>,
    pub p: Vec<Vector<D>>,
    pub f_left: Vec<Vector<D>>,
    pub f_node: Vec<Vector<D>>,
}

impl<'l, L: Lagrangian<D> + ?Sized, const D: usize> Discretisation<'l, L, D> {
    /// `lagrangian` on `grid` under `embedding`.
    pub(crate) fn new(lagrangian: &'l L, grid: Grid, embedding: Embedding) -> Self {
        let (velocity, adjoint) = embedding.operators(&grid);
        Discretisation {
            lagrangian,
            grid,
            embedding,
            velocity,
            adjoint,
            velocity_fft: FftCache::default(),
            adjoint_fft: FftCache::default(),
            fft_threshold: FFT_OPERATOR_THRESHOLD,
            kinetic_panel: kinetic::PANEL,
        }
    }

    pub(crate) fn lagrangian(&self) -> &'l L {
        self.lagrangian
    }
    pub(crate) fn grid(&self) -> &Grid {
        &self.grid
    }
    pub(crate) fn embedding(&self) -> &Embedding {
        &self.embedding
    }
    /// `Δ_σ` (or `Δ^α_σ`), whose rows give `V = −σ Δ_σ Q`.
    pub(crate) fn velocity_operator(&self) -> &Operator {
        &self.velocity
    }

    /// The momenta's operator of the direct scheme: `Δ_{−σ}`, or the corrected form's with its
    /// starting columns.
    pub(crate) fn adjoint_operator(&self) -> &Operator {
        &self.adjoint
    }

    /// Runs `f` with the FFT form of `Δ_σ` (planned and transformed once per discretisation; a
    /// fast solve frees its spectrum while it needs none, and computes it again),
    /// for a solver that uses it for a whole solve: the kept one itself, so that its spectra
    /// and buffers are not copied (at `N = 10⁷` they are about 60 bytes a node), or a copy
    /// when another thread is using the kept one.
    pub(crate) fn with_velocity_fft<R>(&self, f: impl FnOnce(&mut FftOperator) -> R) -> R {
        self.velocity_fft.with_exclusive(&self.velocity, f)
    }

    /// The nodes `k` of the equations of `scheme`; entry `i` of a residual is row
    /// `rows.start() + i`.
    pub(crate) fn rows(&self, scheme: Scheme) -> RangeInclusive<usize> {
        self.embedding.scheme_rows(scheme, self.grid.n())
    }

    /// `N + 1` finite nodes, or the typed error; [`Error::Unsupported`] for a one-step
    /// embedding (Gauss–Legendre), which has no operator on the nodes to evaluate a curve with.
    pub(crate) fn check_curve(&self, q: &[Vector<D>]) -> Result<()> {
        if self.embedding.is_one_step() {
            return Err(Error::Unsupported {
                operation: "an evaluation on a whole curve (quadrature_velocities, residual, \
                            action, quadrature_energies, boundary value problem)",
                embedding: self.embedding.to_string(),
            });
        }
        check_len("discrete curve Q", self.grid.n() + 1, q.len())?;
        match q.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            Some(k) => Err(Error::NonFiniteInput {
                what: format!("Q_{k} = {:?}", q[k].as_slice()),
            }),
            None => Ok(()),
        }
    }

    /// Whether the operators are applied by FFT: fractional (dense) operators on a grid of more
    /// than [`FFT_OPERATOR_THRESHOLD`] steps. The FFT forms are of the Toeplitz parts; the
    /// corrected form's starting columns are added beside them (`O(N)`).
    fn by_fft(&self) -> bool {
        self.embedding.is_fractional() && self.grid.n() > self.fft_threshold
    }

    /// The discrete velocity `V = −σ Δ_σ Q` (or `−σ Δ^α_σ Q`, `−σ Δ^α_σ (Q − Q_e)` for the
    /// Caputo form) on the quadrature rows `I_σ`.
    pub(crate) fn velocity(&self, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        self.check_curve(q)?;
        let sign = -self.embedding.side().sign();
        // The Caputo form: the operator applied to the shifted curve itself, whose end node is
        // then exactly zero (the dense loops sum smaller terms, the FFT route's end term
        // vanishes), rather than a correction subtracted afterwards.
        let shifted: Vec<Vector<D>>;
        let q = match self.embedding.caputo_end(self.grid.n()) {
            Some(end) => {
                shifted = q.iter().map(|x| x - q[end]).collect();
                &shifted
            }
            None => q,
        };
        // By FFT, through the curve's differences: as accurate as the dense loops, where the
        // plain FFT product's error would be amplified into the residual rows (see
        // `FftOperator`'s docs, "the difference form").
        let v = if self.by_fft() {
            let mut v = self
                .velocity_fft
                .with(&self.velocity, |fft| fft.apply_by_differences(q))?;
            self.velocity.add_end_columns(q, &mut v);
            v
        } else {
            self.velocity.apply(q)?
        };
        Ok(v.into_iter().map(|v| v * sign).collect())
    }

    /// `Δ_{−σ} p` on all `N + 1` nodes' values, by FFT when [`by_fft`](Self::by_fft).
    fn apply_adjoint(&self, p: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        if self.by_fft() {
            let mut out = self.adjoint_fft.with(&self.adjoint, |fft| fft.apply(p))?;
            self.adjoint.add_end_columns(p, &mut out);
            Ok(out)
        } else {
            self.adjoint.apply(p)
        }
    }

    /// `Δ_σᵀ w` for values `w` on the rows, by FFT when [`by_fft`](Self::by_fft).
    fn apply_velocity_transpose(&self, w: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        if self.by_fft() {
            let mut out = self
                .velocity_fft
                .with(&self.velocity, |fft| fft.apply_transpose(w))?;
            self.velocity.add_end_columns_transpose(w, &mut out);
            Ok(out)
        } else {
            self.velocity.apply_transpose(w)
        }
    }

    /// The residual of `scheme` at `Q` (`N + 1` nodes), one entry per row of
    /// [`rows`](Self::rows).
    pub(crate) fn residual(&self, scheme: Scheme, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        let pw = self.pointwise(q)?;
        Ok(self.residual_from(scheme, &pw))
    }

    /// The residual of `scheme` from the values at the nodes.
    pub(crate) fn residual_from(&self, scheme: Scheme, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        match scheme {
            Scheme::Direct => self.direct_residual(pw),
            Scheme::Variational => self.variational_residual(pw),
        }
    }

    /// The discrete action `S_h(Q) = h Σ_{k∈I_σ} L(Q_k, V_k, t_k)`.
    pub(crate) fn action(&self, q: &[Vector<D>]) -> Result<f64> {
        if self.embedding.is_symmetric() {
            return self.symmetric_action(q);
        }
        let v = self.velocity(q)?;
        let mut s = 0.0;
        for (k, vk) in self.embedding.quadrature_rows(self.grid.n()).zip(&v) {
            s += self.lagrangian.value(&q[k], vk, self.grid.t(k));
        }
        let s = s * self.grid.h();
        if s.is_finite() {
            Ok(s)
        } else {
            Err(self.first_non_finite(q, &v))
        }
    }

    /// `E_k = V_k·∂L/∂v(Q_k, V_k, t_k) − L(Q_k, V_k, t_k)` on the quadrature nodes `I_σ`.
    pub(crate) fn energy(&self, q: &[Vector<D>]) -> Result<Vec<f64>> {
        if self.embedding.is_symmetric() {
            return self.symmetric_energy(q);
        }
        let v = self.velocity(q)?;
        Ok(self
            .embedding
            .quadrature_rows(self.grid.n())
            .zip(&v)
            .map(|(k, vk)| self.lagrangian.energy(&q[k], vk, self.grid.t(k)))
            .collect())
    }

    /// Which node made the Lagrangian non-finite (for the error message).
    fn first_non_finite(&self, q: &[Vector<D>], v: &[Vector<D>]) -> Error {
        let rows = self.embedding.quadrature_rows(self.grid.n());
        let k = rows
            .clone()
            .zip(v)
            .find(|(k, vk)| {
                !self
                    .lagrangian
                    .value(&q[*k], vk, self.grid.t(*k))
                    .is_finite()
            })
            .map_or(*rows.start(), |(k, _)| k);
        Error::NotFinite {
            at: Location::Node(k),
        }
    }

    /// `V`, `f` and `p` at the quadrature nodes of `Q`.
    pub(crate) fn pointwise(&self, q: &[Vector<D>]) -> Result<Pointwise<D>> {
        if self.embedding.is_symmetric() {
            return self.symmetric_pointwise(q);
        }
        let v_rows = self.velocity(q)?;
        let n = self.grid.n();
        let mut pw = Pointwise {
            v: vec![Vector::<D>::zeros(); n + 1],
            f: vec![Vector::<D>::zeros(); n + 1],
            p: vec![Vector::<D>::zeros(); n + 1],
            f_left: Vec::new(),
            f_node: Vec::new(),
        };
        // The force no row reads is stored as zero, and may be infinite (a forcing singular at
        // that end).
        let unread = self.embedding.unread_force_end(n);
        for (k, vk) in self.embedding.quadrature_rows(n).zip(v_rows) {
            let (mut f, p) = self.lagrangian.gradient(&q[k], &vk, self.grid.t(k));
            if unread == Some(k) {
                f = Vector::<D>::zeros();
            }
            if !(f.iter().chain(p.iter()).all(|c| c.is_finite())) {
                return Err(Error::NotFinite {
                    at: Location::Node(k),
                });
            }
            pw.v[k] = vk;
            pw.f[k] = f;
            pw.p[k] = p;
        }
        Ok(pw)
    }

    /// The scale of the rows of `scheme` at the values `pw`, which Newton's tolerance is
    /// measured against: the largest force a row reads plus `h^{−α}` times the largest
    /// momentum (each row is a force plus momenta weighted by `h^{−α}`). Values no row reads
    /// — the force at the end node outside the rows, `∂L/∂x` at `t = a` or `t = b` — play no
    /// part. It scales with `L`: `c L` has `c` times the scale, so its solve stops where `L`'s
    /// does.
    pub(crate) fn row_scale(&self, scheme: Scheme, pw: &Pointwise<D>) -> f64 {
        let h_alpha = self.grid.h().powf(-self.embedding.alpha());
        let rows = self.rows(scheme);
        let forces = if self.embedding.is_symmetric() {
            rows.fold(0.0f64, |m, k| match scheme {
                Scheme::Variational => m
                    .max(0.5 * pw.f[k].amax())
                    .max(0.5 * pw.f_left[k + 1].amax()),
                Scheme::Direct => m.max(pw.f_node[k].amax()),
            })
        } else {
            rows.fold(0.0f64, |m, k| m.max(pw.f[k].amax()))
        };
        // Every momentum stored is read by a row (the node outside `I_σ`, or the symmetric
        // embeddings' entry 0, holds zeros).
        let momenta = pw.p.iter().fold(0.0f64, |m, p| m.max(p.amax()));
        forces + h_alpha * momenta
    }

    /// The direct path: the embedding's operators applied to `p` row by row.
    fn direct_residual(&self, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        let sigma = self.embedding.side().sign();
        let rows = self.rows(Scheme::Direct);
        match self.embedding.kind() {
            // d/dt ↦ −σΔ_σ in ∂_x L − d/dt ∂_v L.
            EmbeddingKind::FiniteDifference => rows
                .map(|k| pw.f[k] + self.velocity.apply_row(&pw.p, k) * sigma)
                .collect(),
            // −σ d_{−σ} ↦ −σ Δ_{−σ} (Δ^α_{−σ}) in the asymmetric / fractional Euler–Lagrange.
            EmbeddingKind::Asymmetric => rows
                .map(|k| pw.f[k] - self.adjoint.apply_row(&pw.p, k) * sigma)
                .collect(),
            // The same for all rows at once (the rows 1..=N−1 are rows of Δ^α_{−σ} either way).
            EmbeddingKind::GrunwaldLetnikov { .. }
            | EmbeddingKind::Caputo { .. }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { .. }
            | EmbeddingKind::CorrectedCaputo { .. } => {
                let first = self.adjoint.first_row();
                let adjoint_p = self.apply_adjoint(&pw.p).expect("p has one value per node");
                rows.map(|k| pw.f[k] - adjoint_p[k - first] * sigma)
                    .collect()
            }
            // The force at the node, the momenta of the two intervals differenced.
            EmbeddingKind::Midpoint | EmbeddingKind::Trapezoidal => {
                self.symmetric_residual(Scheme::Direct, pw)
            }
            // `check_curve` refuses a one-step embedding before any pointwise value exists.
            EmbeddingKind::GaussLegendre { .. } => {
                unreachable!("Gauss–Legendre has no values on the nodes")
            }
        }
    }

    /// The variational path: `f + Dᵀ p` on the interior nodes, `D = −σ Δ_σ`.
    fn variational_residual(&self, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        if self.embedding.is_symmetric() {
            return self.symmetric_residual(Scheme::Variational, pw);
        }
        let sigma = self.embedding.side().sign();
        let n = self.grid.n();
        let p_rows: Vec<Vector<D>> = self.embedding.quadrature_rows(n).map(|k| pw.p[k]).collect();
        let dt_p = self
            .apply_velocity_transpose(&p_rows)
            .expect("p has one value per quadrature row");
        self.rows(Scheme::Variational)
            .map(|j| pw.f[j] - dt_p[j] * sigma)
            .collect()
    }

    /// The Jacobian of [`residual`](Self::residual) with respect to the interior nodes
    /// `Q_1..Q_{N−1}`, block by block: `add(i, j − 1, block)` adds `block` to
    /// `∂r_{rows[i]}/∂Q_j` (a block may come in several parts).
    ///
    /// Every scheme's row is `r_k = f_k + Σ_m B[k, m] p_m` with `V = D Q`, `D = −σΔ_σ`, so
    /// `∂r_k/∂Q_j = δ_kj L_xx + L_xv D[k, j] + Σ_m B[k, m] (δ_mj L_vx + L_vv D[m, j])`.
    /// For the variational scheme `B = Dᵀ`, read by columns of `Δ_σ`; this gives the symmetric
    /// `L_xx + L_xv D + Dᵀ L_vx + Dᵀ L_vv D`.
    pub(crate) fn assemble_jacobian(
        &self,
        scheme: Scheme,
        q: &[Vector<D>],
        pw: &Pointwise<D>,
        mut add: impl FnMut(usize, usize, &Matrix<D>),
    ) {
        if self.embedding.is_symmetric() {
            return self.assemble_symmetric_jacobian(scheme, q, add);
        }
        let n = self.grid.n();
        let sigma = self.embedding.side().sign();
        let hess: Vec<Option<_>> = (0..=n)
            .map(|k| {
                self.embedding.quadrature_rows(n).contains(&k).then(|| {
                    let (x, v, t) = (&q[k], &pw.v[k], self.grid.t(k));
                    let hs = self.lagrangian.hessian(x, v, t);
                    // ∂f/∂x, ∂f/∂v of the row's force: L_xx, L_xv and a generalised
                    // force's blocks; the momentum's blocks are L's alone.
                    let (f_x, f_v) = match self.lagrangian.force_jacobian(x, v, t) {
                        Some(force) => (hs.xx + force.x, hs.xv + force.v),
                        None => (hs.xx, hs.xv),
                    };
                    (hs, f_x, f_v)
                })
            })
            .collect();
        let unknown = |j: usize| (1..n).contains(&j);
        // D[m, j] = −σ Δ_σ[m, j].
        let d_row = |m: usize| {
            self.velocity
                .row_entries(m)
                .map(move |(j, c)| (j, -sigma * c))
        };
        // A fractional B and D are dense: their kinetic product goes by matrix products.
        let dense = self.embedding.is_fractional();
        for (i, k) in self.rows(scheme).enumerate() {
            let (_, f_x, f_v) = hess[k].as_ref().expect("rows lie in I_σ");
            if unknown(k) {
                add(i, k - 1, f_x);
            }
            for (j, c) in d_row(k) {
                if unknown(j) {
                    add(i, j - 1, &(f_v * c));
                }
            }
            let operators = (&self.velocity, &self.adjoint);
            for (m, b) in self.embedding.momentum_row(scheme, operators, k) {
                let (hm, _, _) = hess[m].as_ref().expect("B only reaches nodes of I_σ");
                if unknown(m) {
                    add(i, m - 1, &(hm.xv.transpose() * b));
                }
                if !dense {
                    for (j, c) in d_row(m) {
                        if unknown(j) {
                            add(i, j - 1, &(hm.vv * (b * c)));
                        }
                    }
                }
            }
        }
        if dense {
            let vv: Vec<_> = hess.iter().map(|h| h.as_ref().map(|h| h.0.vv)).collect();
            self.add_kinetic_term(scheme, &vv, &mut add);
        }
    }

    /// The Jacobian of [`assemble_jacobian`](Self::assemble_jacobian) as a dense matrix.
    #[cfg(test)]
    pub(crate) fn dense_jacobian(
        &self,
        scheme: Scheme,
        q: &[Vector<D>],
        pw: &Pointwise<D>,
    ) -> nalgebra::DMatrix<f64> {
        let size = (self.grid.n() - 1) * D;
        let mut jac = nalgebra::DMatrix::<f64>::zeros(size, size);
        self.assemble_jacobian(scheme, q, pw, |i, j, block| {
            let mut view = jac.view_mut((i * D, j * D), (D, D));
            view += block;
        });
        jac
    }
}

mod kinetic;
mod symmetric;
mod term_sizes;
pub(crate) use term_sizes::relative;

#[cfg(test)]
mod tests;
