//! The fast path for the boundary value problems of Gauss-GLEσ: Newton–Krylov with the
//! operators applied by FFT, `O(N log N)` per iteration and `O(N)` memory.
//!
//! Gauss-GLEσ is coherent, so its direct and variational schemes are the same equations; the
//! fast path solves the variational form `r_j = f_j + (Dᵀ p)_j = 0` on the interior nodes
//! `j = 1..N−1`, with `D = −σ Δ^α_σ` and `V = D Q`. Its Jacobian, restricted to the interior
//! unknowns (the boundary nodes are fixed), is the symmetric
//!
//! `J = L_xx + L_xv D + Dᵀ L_vx + Dᵀ L_vv D`,
//!
//! never formed: `J δ` costs two FFT products (`a = D δ`, then `Dᵀ(L_vx δ + L_vv a)`), and
//! inside CG only one (below).
//!
//! **Preconditioner.** On the interior columns, the rows of `D` that belong to interior nodes
//! form a square triangular Toeplitz matrix `D_a = s·T` (σ = −: `T` lower-triangular with the
//! Grünwald–Letnikov weights `w`, `s = h^{−α}`; σ = +: `D_a = −s Tᵀ`); `D` has one row more, `E`
//! (row `N` for σ = −, row `0` for σ = +, with `L_vv` block `H_e` there). With `V` the block
//! diagonal of the `L_vv` at the interior nodes, the whole `L_vv` part of `J` is
//!
//! `P' = Dᵀ L_vv D = P + Eᵀ H_e E`,  `P = D_aᵀ V D_a`.
//!
//! The inverse of `T` is the lower-triangular Toeplitz matrix `G` of the weights
//! `g_r = Γ(r+α)/(Γ(α) r!)` ([`grunwald_letnikov_inverse`]), so
//!
//! `P⁻¹ = s⁻² G V⁻¹ Gᵀ` (σ = −),  `P⁻¹ = s⁻² Gᵀ V⁻¹ G` (σ = +),
//!
//! two triangular Toeplitz products by FFT, and the rank-`d` row is added by Woodbury:
//!
//! `P'⁻¹ = P⁻¹ − U (I + H_e E U)⁻¹ H_e E P⁻¹`,  `U = P⁻¹ Eᵀ`,
//!
//! `O(N d²)` per application once `U` is known. `U` costs `d²` products per Newton step, since
//! `D_a⁻ᵀ Eᵀ` has a closed form: `T G = I` makes it `−(g_{N−1}, …, g_1)` for σ = − and
//! `−(g_1, …, g_{N−1})` for σ = +. Without this term `P⁻¹J` had one outlying eigenvalue
//! `E P⁻¹ Eᵀ ≈ Σ_{r<N} g_r² ∝ N^{2α−1}` (about 350 at `N = 10⁶`, α = 0.7), which CG resolves
//! with extra iterations that grew with `N`. Now `P'` is symmetric positive definite when every
//! `L_vv` is, `P'⁻¹ J = I + P'⁻¹(L_xx + L_xv D + Dᵀ L_vx)`, and since `D_a` grows like `h^{−α}`
//! the remainder is a compact perturbation: the iteration counts stay flat as `N` grows (on the
//! benchmark pendulum: 1, 2, 4 and 2–3 CG iterations in the four Newton steps at every
//! `N = 10⁴ … 10⁶`).
//!
//! **One FFT product less per CG iteration.** The preconditioner's middle vector
//! `V⁻¹ D_a⁻ᵀ r` is `D_a` of `P⁻¹ r`, and `D_a U` is known, so the preconditioner yields `D_a z`
//! for its output `z`; CG's directions are `p = z + β p`, so the square-block rows of `D p` are
//! carried along the recurrence (`D_a p = D_a z + β D_a p`, [`KrylovSystem::image_len`]); the
//! extra row is one dot product. A CG iteration then costs
//! three FFT products (`Dᵀ b`, and the two of `P⁻¹`) instead of four, with the same iterates.
//!
//! **Linear solves.** Conjugate gradients first (`J` is symmetric); when `J` is indefinite
//! (a potential whose `L_xx` outweighs the kinetic term), CG breaks down and GMRES(m) takes
//! over. Each Newton system is solved to the Eisenstat–Walker forcing tolerance `η_k`, never
//! below what the Newton tolerance needs. When neither solver gets below `η_k` — and not even
//! below `0.1`, which still gives a usable inexact Newton step — the solve fails with
//! [`Error::KrylovDidNotConverge`]; with [`FractionalSolver::Auto`] a small system then falls back
//! to dense LU.
//!
//! **Stopping rule.** The same as the dense path: `max|r| ≤ tol · (1 + max|f| + h^{−α} max|p|)`,
//! or a residual that has stopped falling at round-off ([`NewtonOptions`]). The residual is
//! computed by FFT, with `V = D Q` taken through the differences of the curve
//! ([`FftOperator`], "the difference form"), so that its own error stays below the floor of
//! double precision: the residual of the exact discrete solution rounded to doubles, of size
//! `ε h^{−2α}` since `J` has norm about `4h^{−2α}` (1.51e-9 at `N = 10⁵` on the benchmark
//! pendulum, measured with a double-double oracle in `tests/residual_floor.rs`; random roundings
//! do no better). A tolerance below that floor runs Newton down to it (the oracle puts the
//! solution there at 1.50e-9).
//!
//! [`NewtonOptions`]: crate::NewtonOptions
//!
//! ## Reference
//!
//! S. C. Eisenstat and H. F. Walker, *Choosing the forcing terms in an inexact Newton method*,
//! SIAM J. Sci. Comput. 17 (1996) (choice 2). Triangular Toeplitz inverses: D. Bini,
//! *Parallel solution of certain Toeplitz linear systems*, SIAM J. Comput. 13 (1984). Woodbury:
//! G. H. Golub and C. F. Van Loan, *Matrix Computations*, 4th ed., §2.1.4.

use crate::embedding::Side;
use crate::error::{Error, Location, Result};
use crate::fft_operator::FftOperator;
use crate::lagrangian::{Hessian, Lagrangian, Matrix, Vector};
use crate::problem::{Problem, Scheme};
use crate::solve::Solution;
use crate::solve::krylov::{KrylovFailure, KrylovOptions, KrylovSystem, conjugate_gradient, gmres};
use crate::solve::max_norm;
use crate::solve::newton::{at_round_off, backtrack};
use crate::toeplitz::TriangularToeplitz;
use crate::weights::grunwald_letnikov_inverse;

/// Which linear algebra solves the Newton systems of a fractional (Gauss-GLEσ) boundary value
/// problem. Set with [`Problem::with_fractional_solver`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FractionalSolver {
    /// Dense LU when the system is small (`(N − 1)·d ≤` [`DENSE_LIMIT`]), the fast path
    /// otherwise; when the fast path's Krylov solver fails on a system of at most
    /// [`DENSE_FALLBACK_LIMIT`] unknowns, the problem is solved again by dense LU.
    #[default]
    Auto,
    /// Always dense LU: `O((N d)²)` memory and `O((N d)³)` time per Newton iteration (its
    /// residual, like [`Problem::residual`], goes by FFT above
    /// [`FFT_OPERATOR_THRESHOLD`](crate::problem::FFT_OPERATOR_THRESHOLD)). The reference the
    /// fast path is tested against: the assembled Jacobian and LU share nothing with it.
    Dense,
    /// Always the FFT Newton–Krylov path (module docs), without dense fallback.
    Fast,
}

/// Unknowns `(N − 1)·d` up to which [`FractionalSolver::Auto`] uses dense LU.
pub const DENSE_LIMIT: usize = 400;

/// Unknowns up to which [`FractionalSolver::Auto`] falls back to dense LU when the Krylov
/// solver fails.
pub const DENSE_FALLBACK_LIMIT: usize = 1500;

/// Iteration budgets of the Krylov solvers (per Newton system).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct KrylovBudget {
    pub cg_iterations: usize,
    pub gmres_iterations: usize,
    pub restart: usize,
}

impl Default for KrylovBudget {
    fn default() -> Self {
        KrylovBudget {
            cg_iterations: 300,
            gmres_iterations: 300,
            restart: 30,
        }
    }
}

/// The largest forcing term: a step whose linear residual is below this fraction of the
/// nonlinear one is still a descent step of an inexact Newton method.
const ETA_MAX: f64 = 0.1;

/// `P'⁻¹ = P⁻¹ − U K (E P⁻¹)` for `P' = P + Eᵀ H_e E` (Woodbury), `E` the extra row of `D`
/// (`e_j I` blocks), `H_e` its `L_vv`: `U = P⁻¹ Eᵀ` (blocks `u_j`), `K = (I + H_e E U)⁻¹ H_e`.
struct Correction<const D: usize> {
    u: Vec<Matrix<D>>,
    /// `D_a U`, for the images.
    du: Vec<Matrix<D>>,
    k: Matrix<D>,
}

/// The Newton system at one iterate: Hessians at the quadrature rows, the preconditioner's
/// blocks, and the FFT machinery with its buffers (allocated once per solve).
struct FastSystem<const D: usize> {
    n: usize,
    sigma: f64,
    side: Side,
    /// `h^{−α}`.
    scale: f64,
    /// The first quadrature row (1 for σ = −, 0 for σ = +).
    first_row: usize,
    velocity: FftOperator,
    /// `G`, the inverse of the lower-triangular GL Toeplitz matrix, order `N − 1`.
    inverse: TriangularToeplitz,
    /// `D_a⁻ᵀ e` in closed form (module docs): `−g_{N−1−p}` (σ = −) or `−g_{p+1}` (σ = +) at
    /// position `p = j − 1`.
    extra_solved: Vec<f64>,
    /// Hessians at the rows `first_row..first_row + N`.
    hessians: Vec<Hessian<D>>,
    /// `L_vv⁻¹` at the interior nodes `1..N−1` (entry `j − 1`).
    vv_inverse: Vec<Matrix<D>>,
    /// The row of `D` outside the square block `D_a`, on the interior columns: `e_j` at entry
    /// `j − 1` (`e_j = h^{−α} w_{N−j}` for σ = −, row `N`; `e_j = −h^{−α} w_j` for σ = +, row 0).
    extra: Vec<f64>,
    /// The extra row's term in the preconditioner (module docs), when it can be formed.
    correction: Option<Correction<D>>,
    full: Vec<Vector<D>>,
    rows: Vec<Vector<D>>,
    rows_b: Vec<Vector<D>>,
    nodes: Vec<Vector<D>>,
    interior: Vec<Vector<D>>,
}

impl<const D: usize> FastSystem<D> {
    fn new<L: Lagrangian<D> + ?Sized>(problem: &Problem<'_, L, D>) -> Self {
        let n = problem.grid.n();
        let velocity = FftOperator::new(&problem.velocity);
        // g_0..g_{N−1}: G (order N − 1) uses the first N − 1, D_a⁻ᵀ e also g_{N−1}.
        let g_all = grunwald_letnikov_inverse(problem.velocity.alpha(), n);
        let g = &g_all[..n - 1];
        let extra_solved = match problem.embedding.side() {
            Side::Backward => (0..n - 1).map(|p| -g_all[n - 1 - p]).collect(),
            Side::Forward => (0..n - 1).map(|p| -g_all[p + 1]).collect(),
        };
        // Same FFT length and plans as the operator (order N + 1 ≥ N − 1), so both share one
        // workspace and one set of twiddle tables.
        let inverse = velocity.toeplitz().with_same_plans(g);
        let zero = Hessian {
            xx: Matrix::<D>::zeros(),
            xv: Matrix::<D>::zeros(),
            vv: Matrix::<D>::zeros(),
        };
        let scale = problem.velocity.scale();
        let w = problem.velocity.weights();
        let extra = match problem.embedding.side() {
            Side::Backward => (1..n).map(|j| scale * w[n - j]).collect(),
            Side::Forward => (1..n).map(|j| -scale * w[j]).collect(),
        };
        FastSystem {
            n,
            sigma: problem.embedding.side().sign(),
            side: problem.embedding.side(),
            scale: problem.velocity.scale(),
            first_row: problem.velocity.first_row(),
            velocity,
            inverse,
            extra_solved,
            hessians: vec![zero; n],
            vv_inverse: vec![Matrix::<D>::identity(); n - 1],
            extra,
            correction: None,
            full: vec![Vector::<D>::zeros(); n + 1],
            rows: vec![Vector::<D>::zeros(); n],
            rows_b: vec![Vector::<D>::zeros(); n],
            nodes: vec![Vector::<D>::zeros(); n + 1],
            interior: vec![Vector::<D>::zeros(); n - 1],
        }
    }

    /// A bound on `‖J‖∞` from the last linearisation: with `‖D‖∞ ≤ 2h^{−α}` (the
    /// Grünwald–Letnikov weights have `Σ|α_r| ≤ 2`),
    /// `‖J‖∞ ≤ max‖L_xx‖ + 4h^{−α} max‖L_xv‖ + 4h^{−2α} max‖L_vv‖`. Zero before the first one.
    fn jacobian_bound(&self) -> f64 {
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
    fn linearize<L: Lagrangian<D> + ?Sized>(
        &mut self,
        problem: &Problem<'_, L, D>,
        q: &[Vector<D>],
        v: &[Vector<D>],
        at: Location,
    ) -> Result<()> {
        for (i, h) in self.hessians.iter_mut().enumerate() {
            let k = i + self.first_row;
            *h = problem.lagrangian.hessian(&q[k], &v[i], problem.grid.t(k));
            let finite = h.xx.iter().chain(h.xv.iter()).chain(h.vv.iter());
            if !finite.into_iter().all(|c| c.is_finite()) {
                return Err(Error::NotFinite { at });
            }
        }
        // Where an L_vv block cannot be inverted the preconditioner keeps the identity there:
        // it only has to be good, and the Krylov solver reports what it cannot solve.
        for j in 1..self.n {
            let vv = &self.hessians[j - self.first_row].vv;
            let inv = vv.try_inverse().filter(|m| m.iter().all(|c| c.is_finite()));
            let size = vv.amax();
            self.vv_inverse[j - 1] = inv.unwrap_or_else(|| {
                if size > 0.0 {
                    Matrix::<D>::identity() / size
                } else {
                    Matrix::<D>::identity()
                }
            });
        }
        self.update_correction();
        Ok(())
    }

    /// [`Correction`] at the current linearisation: `U = P⁻¹Eᵀ = D_a⁻¹ V⁻¹ (D_a⁻ᵀ Eᵀ)`, with
    /// `D_a⁻ᵀ Eᵀ` in closed form, so `d²` FFT products; `D_a U = V⁻¹ D_a⁻ᵀ Eᵀ` comes free.
    fn update_correction(&mut self) {
        self.correction = None;
        let m = self.n - 1;
        let mut u = vec![Matrix::<D>::zeros(); m];
        let mut du = vec![Matrix::<D>::zeros(); m];
        let mut middle = vec![Vector::<D>::zeros(); m];
        let mut solved = vec![Vector::<D>::zeros(); m];
        let g_transposed = self.side == Side::Forward;
        let factor = -self.sigma / self.scale;
        for c in 0..D {
            for j in 0..m {
                middle[j] = self.vv_inverse[j].column(c) * self.extra_solved[j];
                du[j].set_column(c, &middle[j]);
            }
            self.mul_inverse(g_transposed, &middle, &mut solved);
            for j in 0..m {
                u[j].set_column(c, &(solved[j] * factor));
            }
        }
        let mut eu = Matrix::<D>::zeros();
        for (e, uj) in self.extra.iter().zip(&u) {
            eu += uj * *e;
        }
        let extra_row = if self.first_row == 1 { self.n - 1 } else { 0 };
        let h_e = self.hessians[extra_row].vv;
        let k = (Matrix::<D>::identity() + h_e * eu)
            .try_inverse()
            .map(|inv| inv * h_e)
            .filter(|k| k.iter().all(|c| c.is_finite()));
        if let Some(k) = k {
            self.correction = Some(Correction { u, du, k });
        }
    }

    /// `out = Gᵀ x` (transpose) or `G x`, one real product per component.
    fn mul_inverse(&mut self, transpose: bool, x: &[Vector<D>], out: &mut [Vector<D>]) {
        for c in 0..D {
            self.inverse.mul_with(
                transpose,
                self.velocity.workspace_mut(),
                |k| x[k][c],
                |k, y| out[k][c] = y,
            );
        }
    }
}

fn read<const D: usize>(x: &[f64], j: usize) -> Vector<D> {
    Vector::<D>::from_column_slice(&x[j * D..(j + 1) * D])
}

impl<const D: usize> KrylovSystem for FastSystem<D> {
    fn len(&self) -> usize {
        (self.n - 1) * D
    }

    /// `J δ` with `a = D δ`, `b = L_vx δ + L_vv a` (on the rows), `J δ = L_xx δ + L_xv a + Dᵀ b`.
    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.jacobian_product(x, None, y);
    }

    /// `z = P⁻¹ r = s⁻² G V⁻¹ Gᵀ r` (σ = −) or `s⁻² Gᵀ V⁻¹ G r` (σ = +).
    fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        self.precondition_into(r, z, None);
    }

    /// The images are `D_a x` (`N − 1` interior rows).
    fn image_len(&self) -> usize {
        self.len()
    }

    /// `P⁻¹ r = D_a⁻¹ V⁻¹ D_a⁻ᵀ r`: the middle vector `V⁻¹ D_a⁻ᵀ r` is `D_a z`.
    fn precondition_with_image(&mut self, r: &[f64], z: &mut [f64], image: &mut [f64]) {
        self.precondition_into(r, z, Some(image));
    }

    /// `J x` with the interior rows of `a = D x` taken from `image` (one FFT product, `Dᵀ b`).
    fn apply_with_image(&mut self, x: &[f64], image: &[f64], y: &mut [f64]) {
        self.jacobian_product(x, Some(image), y);
    }
}

impl<const D: usize> FastSystem<D> {
    /// `y = J x`; `a = D x` by FFT, or, given `image = D_a x`, from it and the one extra row.
    fn jacobian_product(&mut self, x: &[f64], image: Option<&[f64]>, y: &mut [f64]) {
        let n = self.n;
        self.full[0] = Vector::<D>::zeros();
        self.full[n] = Vector::<D>::zeros();
        for j in 1..n {
            self.full[j] = read(x, j - 1);
        }
        let minus_sigma = -self.sigma;
        match image {
            Some(image) => {
                // Rows 1..N−1 are the square block; the extra row is N (σ = −) or 0 (σ = +).
                let mut extra = Vector::<D>::zeros();
                for j in 1..n {
                    extra += self.full[j] * self.extra[j - 1];
                }
                let extra_row = if self.first_row == 1 { n - 1 } else { 0 };
                for j in 1..n {
                    self.rows[j - self.first_row] = read(image, j - 1);
                }
                self.rows[extra_row] = extra;
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
            y[(j - 1) * D..j * D].copy_from_slice(yj.as_slice());
        }
    }

    /// `z = P⁻¹ r`, and `D_a z` into `image` if asked. With `D_a = −σ s A` (`A = T` for σ = −,
    /// `Tᵀ` for σ = +) and `A⁻¹ = G` or `Gᵀ`: `middle = s⁻² V⁻¹ A⁻ᵀ r`, `z = A⁻¹ middle`, and
    /// `D_a z = −σ s · middle`.
    fn precondition_into(&mut self, r: &[f64], z: &mut [f64], mut image: Option<&mut [f64]>) {
        let m = self.n - 1;
        let mut input = std::mem::take(&mut self.interior);
        for j in 0..m {
            input[j] = read(r, j);
        }
        let mut middle = std::mem::take(&mut self.nodes);
        let first_transposed = self.side == Side::Backward;
        self.mul_inverse(first_transposed, &input, &mut middle[..m]);
        let s2 = 1.0 / (self.scale * self.scale);
        for j in 0..m {
            middle[j] = self.vv_inverse[j] * middle[j] * s2;
        }
        if let Some(image) = image.as_deref_mut() {
            let factor = -self.sigma * self.scale;
            for j in 0..m {
                let v = middle[j] * factor;
                image[j * D..(j + 1) * D].copy_from_slice(v.as_slice());
            }
        }
        self.mul_inverse(!first_transposed, &middle[..m], &mut input);
        for j in 0..m {
            z[j * D..(j + 1) * D].copy_from_slice(input[j].as_slice());
        }
        if let Some(corr) = &self.correction {
            let mut ez = Vector::<D>::zeros();
            for (e, zj) in self.extra.iter().zip(&input[..m]) {
                ez += zj * *e;
            }
            let c = corr.k * ez;
            for j in 0..m {
                let zj = input[j] - corr.u[j] * c;
                z[j * D..(j + 1) * D].copy_from_slice(zj.as_slice());
            }
            if let Some(image) = image {
                for j in 0..m {
                    let v = read::<D>(image, j) - corr.du[j] * c;
                    image[j * D..(j + 1) * D].copy_from_slice(v.as_slice());
                }
            }
        }
        self.interior = input;
        self.nodes = middle;
    }
}

/// The residual at an iterate, with what the Jacobian needs.
struct Evaluation<const D: usize> {
    /// `r_j`, `j = 1..N−1`.
    r: Vec<Vector<D>>,
    /// `V` on the rows.
    v: Vec<Vector<D>>,
    /// `1 + max|f| + h^{−α} max|p|`.
    scale: f64,
}

fn evaluate<L: Lagrangian<D> + ?Sized, const D: usize>(
    problem: &Problem<'_, L, D>,
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
    let n = system.n;
    let mut v = vec![Vector::<D>::zeros(); n];
    // Through the differences of the curve (see `FftOperator`): the residual's accuracy rests
    // on V's, whose error the rows amplify by h^{−α}.
    system.velocity.apply_by_differences_inplace(q, &mut v)?;
    let minus_sigma = -system.sigma;
    // r starts as f on the interior nodes; p goes in the rows' buffer (no allocation per call).
    let mut r = vec![Vector::<D>::zeros(); n - 1];
    let mut p = std::mem::take(&mut system.rows_b);
    let mut f_max = 0.0f64;
    for i in 0..n {
        let k = i + system.first_row;
        v[i] *= minus_sigma;
        let (fk, pk) = problem.lagrangian.gradient(&q[k], &v[i], problem.grid.t(k));
        if !fk.iter().chain(pk.iter()).all(|c| c.is_finite()) {
            system.rows_b = p;
            return Err(not_finite);
        }
        f_max = f_max.max(fk.amax());
        if (1..n).contains(&k) {
            r[k - 1] = fk;
        }
        p[i] = pk;
    }
    let mut dt_p = std::mem::take(&mut system.nodes);
    let applied = system.velocity.apply_transpose_inplace(&p, &mut dt_p);
    for (j, rj) in r.iter_mut().enumerate() {
        *rj += dt_p[j + 1] * minus_sigma;
    }
    let scale = 1.0 + f_max + system.scale * max_norm(&p);
    system.rows_b = p;
    system.nodes = dt_p;
    applied?;
    if !r.iter().all(|x| x.iter().all(|c| c.is_finite())) {
        return Err(not_finite);
    }
    Ok(Evaluation { r, v, scale })
}

/// Solves `J δ = rhs` to the relative tolerance `eta`: CG, then GMRES when CG breaks down or
/// runs out of iterations. Accepts a GMRES iterate below [`ETA_MAX`] as an inexact step.
fn solve_newton_system<const D: usize>(
    system: &mut FastSystem<D>,
    rhs: &[f64],
    delta: &mut [f64],
    eta: f64,
    budget: &KrylovBudget,
    at: Location,
) -> Result<usize> {
    let mut options = KrylovOptions {
        tolerance: eta,
        max_iterations: budget.cg_iterations,
        restart: budget.restart,
    };
    let cg_failure = match conjugate_gradient(system, rhs, delta, &options) {
        Ok(stats) => return Ok(stats.iterations),
        Err(failure) => failure,
    };
    options.max_iterations = budget.gmres_iterations;
    match gmres(system, rhs, delta, &options) {
        Ok(stats) => Ok(cg_failure.iterations() + stats.iterations),
        Err(failure) if failure.relative_residual() <= ETA_MAX => {
            Ok(cg_failure.iterations() + failure.iterations())
        }
        Err(failure) => {
            let (iterations, residual) = match failure {
                KrylovFailure::Breakdown {
                    iterations,
                    relative_residual,
                }
                | KrylovFailure::MaxIterations {
                    iterations,
                    relative_residual,
                } => (iterations, relative_residual),
            };
            Err(Error::KrylovDidNotConverge {
                at,
                iterations,
                residual,
            })
        }
    }
}

/// Newton–Krylov on the interior nodes of a Gauss-GLEσ boundary value problem, from `guess`
/// (already checked: `N + 1` finite nodes, `N ≥ 2`).
pub(crate) fn solve<L: Lagrangian<D> + ?Sized, const D: usize>(
    problem: &Problem<'_, L, D>,
    scheme: Scheme,
    guess: &[Vector<D>],
    budget: &KrylovBudget,
) -> Result<Solution<D>> {
    let n = problem.grid.n();
    let opts = problem.newton;
    let mut system = FastSystem::<D>::new(problem);
    let mut q = guess.to_vec();
    let mut eval = evaluate(problem, &mut system, &q, 0)?;
    let unknowns = (n - 1) * D;
    let mut rhs = vec![0.0; unknowns];
    let mut delta = vec![0.0; unknowns];
    let mut eta = ETA_MAX;
    let mut previous_norm: Option<f64> = None;
    let mut previous_res = f64::INFINITY;
    for iteration in 0..=opts.max_iterations {
        let at = Location::Newton(iteration);
        let res = max_norm(&eval.r);
        // The same rule as the dense path: tolerance, or stagnation at the round-off floor
        // (with the Jacobian's norm bounded, since it is never assembled here).
        let floor = at_round_off(res, previous_res, system.jacobian_bound(), max_norm(&q));
        previous_res = res;
        if res <= opts.tolerance * eval.scale || floor {
            return Ok(Solution {
                scheme,
                embedding: problem.embedding,
                grid: problem.grid,
                q,
                newton_iterations: iteration,
                explicit_steps: 0,
            });
        }
        if iteration == opts.max_iterations {
            break;
        }
        for (j, r) in eval.r.iter().enumerate() {
            rhs[j * D..(j + 1) * D].copy_from_slice(r.as_slice());
        }
        let norm = rhs.iter().map(|x| x * x).sum::<f64>().sqrt();
        // Eisenstat–Walker choice 2 with its safeguard, capped at ETA_MAX; never asking for
        // more than the Newton tolerance needs (the linear residual then is at most half of it).
        if let Some(previous) = previous_norm {
            let ratio = norm / previous;
            let mut next = 0.9 * ratio * ratio;
            if 0.9 * eta * eta > 0.1 {
                next = next.max(0.9 * eta * eta);
            }
            eta = next.min(ETA_MAX);
        }
        eta = eta.max(0.5 * opts.tolerance * eval.scale / norm).max(1e-13);
        previous_norm = Some(norm);
        system.linearize(problem, &q, &eval.v, at)?;
        solve_newton_system(&mut system, &rhs, &mut delta, eta, budget, at)?;
        let (trial, next, _) = backtrack(&q, &delta, res, |trial| {
            let e = evaluate(problem, &mut system, trial, iteration + 1)?;
            let res = max_norm(&e.r);
            Ok((e, res))
        })?;
        (q, eval) = (trial, next);
    }
    Err(Error::NewtonDidNotConverge {
        at: Location::Newton(opts.max_iterations),
        iterations: opts.max_iterations,
        residual: max_norm(&eval.r),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::embedding::Embedding;
    use crate::grid::Grid;
    use nalgebra::DMatrix;

    use crate::test_models::Mixed;

    /// The fast system at `q`: its residual evaluated and its Jacobian linearised there.
    fn linearized<L: Lagrangian<D>, const D: usize>(
        problem: &Problem<'_, L, D>,
        q: &[Vector<D>],
    ) -> (FastSystem<D>, Evaluation<D>) {
        let mut system = FastSystem::<D>::new(problem);
        let eval = evaluate(problem, &mut system, q, 0).unwrap();
        system
            .linearize(problem, q, &eval.v, Location::Newton(0))
            .unwrap();
        (system, eval)
    }

    fn curve(n: usize) -> Vec<Vector<2>> {
        (0..=n)
            .map(|k| {
                let t = k as f64;
                Vector::<2>::new((0.7 * t).sin(), 0.5 * (1.3 * t).cos())
            })
            .collect()
    }

    /// The matrix-free `J δ` and the residual by FFT equal the assembled dense Jacobian and the
    /// dense residual, for both sides.
    #[test]
    fn matrix_free_jacobian_and_residual_match_the_dense_ones() {
        let n = 13;
        let grid = Grid::new(0.2, 1.5, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::grunwald_letnikov(side, 0.6).unwrap();
            let problem = Problem::new(&Mixed, grid, embedding);
            let q = curve(n);
            let (mut system, eval) = linearized(&problem, &q);
            let dense_r = problem.residual(Scheme::Variational, &q).unwrap();
            for (a, b) in eval.r.iter().zip(&dense_r) {
                assert!((a - b).amax() < 1e-12, "{side:?}: {a} vs {b}");
            }
            let pw = problem.pointwise(&q).unwrap();
            let m = (n - 1) * 2;
            let mut jac = DMatrix::<f64>::zeros(m, m);
            problem.assemble_jacobian(Scheme::Variational, &q, &pw, &mut jac);
            let x: Vec<f64> = (0..m).map(|i| ((3 * i + 1) as f64).sin()).collect();
            let mut y = vec![0.0; m];
            system.apply(&x, &mut y);
            let want = &jac * nalgebra::DVector::from_vec(x.clone());
            for i in 0..m {
                assert!(
                    (y[i] - want[i]).abs() < 1e-11 * want.amax(),
                    "{side:?} row {i}: {} vs {}",
                    y[i],
                    want[i]
                );
            }
        }
    }

    /// The preconditioner's by-product is `D_a z`, and `J z` from it equals `J z` by FFT.
    #[test]
    fn preconditioner_images_are_the_square_block_products() {
        let n = 23;
        let grid = Grid::new(0.2, 1.5, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::grunwald_letnikov(side, 0.55).unwrap();
            let problem = Problem::new(&Mixed, grid, embedding);
            let q = curve(n);
            let (mut system, _) = linearized(&problem, &q);
            let m = (n - 1) * 2;
            let r: Vec<f64> = (0..m).map(|i| ((5 * i + 2) as f64).cos()).collect();
            let (mut z, mut image) = (vec![0.0; m], vec![0.0; m]);
            system.precondition_with_image(&r, &mut z, &mut image);
            // D z on the rows of the interior nodes, D = −σΔ.
            let mut full = vec![Vector::<2>::zeros(); n + 1];
            for j in 1..n {
                full[j] = read(&z, j - 1);
            }
            let dz = problem.velocity.apply(&full).unwrap();
            for j in 1..n {
                let want = dz[j - problem.velocity.first_row()] * -side.sign();
                let got = read::<2>(&image, j - 1);
                assert!(
                    (got - want).amax() < 1e-12 * (1.0 + want.amax()),
                    "{side:?} {j}"
                );
            }
            let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
            system.apply(&z, &mut a);
            system.apply_with_image(&z, &image, &mut b);
            let scale = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
            for i in 0..m {
                assert!(
                    (a[i] - b[i]).abs() < 1e-12 * scale,
                    "{side:?} {i}: {} vs {}",
                    a[i],
                    b[i]
                );
            }
        }
    }

    /// The preconditioner inverts the whole kinetic part `P' = Dᵀ L_vv D` (the square block and
    /// the extra row, `L_vv` varying along the grid): `P'⁻¹ P' x = x`.
    #[test]
    fn preconditioner_inverts_the_whole_kinetic_part() {
        /// `L = (1 + t) v²`.
        struct Free;
        impl Lagrangian<1> for Free {
            fn value(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
                (1.0 + t) * v[0] * v[0]
            }
            fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
                (Vector::<1>::zeros(), *v * (2.0 * (1.0 + t)))
            }
            fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Hessian<1> {
                Hessian {
                    xx: Matrix::<1>::zeros(),
                    xv: Matrix::<1>::zeros(),
                    vv: Matrix::<1>::new(2.0 * (1.0 + t)),
                }
            }
        }
        let n = 17;
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::grunwald_letnikov(side, 0.45).unwrap();
            let problem = Problem::new(&Free, grid, embedding);
            let q: Vec<Vector<1>> = (0..=n).map(|k| Vector::<1>::new(k as f64)).collect();
            let (mut system, _) = linearized(&problem, &q);
            assert!(system.correction.is_some());
            // P' = Σ_k D[k, ·]ᵀ L_vv(t_k) D[k, ·] over every row k of D = −σΔ.
            let m = n - 1;
            let mut p = DMatrix::<f64>::zeros(m, m);
            let sigma = side.sign();
            for a in 1..n {
                for b in 1..n {
                    let mut acc = 0.0;
                    for k in problem.velocity.rows() {
                        let d = |j| {
                            problem
                                .velocity
                                .row_entries(k)
                                .find(|&(jj, _)| jj == j)
                                .map_or(0.0, |(_, c)| -sigma * c)
                        };
                        acc += d(a) * 2.0 * (1.0 + grid.t(k)) * d(b);
                    }
                    p[(a - 1, b - 1)] = acc;
                }
            }
            let x: Vec<f64> = (0..m).map(|i| (i as f64 * 0.37).cos()).collect();
            let px = &p * nalgebra::DVector::from_vec(x.clone());
            let mut z = vec![0.0; m];
            system.precondition(px.as_slice(), &mut z);
            for i in 0..m {
                assert!(
                    (z[i] - x[i]).abs() < 1e-10,
                    "{side:?} {i}: {} vs {}",
                    z[i],
                    x[i]
                );
            }
        }
    }

    /// The same with `d = 2` and full `L_vv` blocks (the Woodbury term is a 2 × 2 system).
    #[test]
    fn preconditioner_inverts_the_kinetic_part_with_blocks() {
        let n = 15;
        let grid = Grid::new(0.2, 1.5, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::grunwald_letnikov(side, 0.6).unwrap();
            let problem = Problem::new(&Mixed, grid, embedding);
            let q = curve(n);
            let (mut system, _) = linearized(&problem, &q);
            assert!(system.correction.is_some());
            let m = n - 1;
            let mut p = DMatrix::<f64>::zeros(2 * m, 2 * m);
            let sigma = side.sign();
            for (i, k) in problem.velocity.rows().enumerate() {
                let vv = system.hessians[i].vv;
                let d = |j| {
                    problem
                        .velocity
                        .row_entries(k)
                        .find(|&(jj, _)| jj == j)
                        .map_or(0.0, |(_, c)| -sigma * c)
                };
                for a in 1..n {
                    for b in 1..n {
                        let block = vv * (d(a) * d(b));
                        for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                            p[(2 * (a - 1) + r, 2 * (b - 1) + c)] += block[(r, c)];
                        }
                    }
                }
            }
            let x: Vec<f64> = (0..2 * m).map(|i| (i as f64 * 0.37).cos()).collect();
            let px = &p * nalgebra::DVector::from_vec(x.clone());
            let mut z = vec![0.0; 2 * m];
            system.precondition(px.as_slice(), &mut z);
            for i in 0..2 * m {
                assert!(
                    (z[i] - x[i]).abs() < 1e-9,
                    "{side:?} {i}: {} vs {}",
                    z[i],
                    x[i]
                );
            }
        }
    }

    /// A Krylov budget too small for the system is a typed error, never a returned curve.
    #[test]
    fn an_exhausted_krylov_budget_is_a_typed_error() {
        let n = 200;
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let embedding = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
        let problem = Problem::new(&Mixed, grid, embedding);
        let guess: Vec<Vector<2>> = (0..=n)
            .map(|k| Vector::<2>::new(k as f64 / n as f64, 0.0))
            .collect();
        let budget = KrylovBudget {
            cg_iterations: 1,
            gmres_iterations: 1,
            restart: 1,
        };
        let err = solve(&problem, Scheme::Variational, &guess, &budget).unwrap_err();
        assert!(
            matches!(
                err,
                Error::KrylovDidNotConverge {
                    at: Location::Newton(0),
                    ..
                }
            ),
            "{err:?}"
        );
    }

    /// `L = ½v² − 72x²`: `J = DᵀD − 144` is indefinite. CG must report the breakdown, and the
    /// Newton system is still solved (by GMRES) to the asked tolerance.
    #[test]
    fn cg_breaks_down_on_an_indefinite_jacobian_and_gmres_takes_over() {
        struct Oscillator;
        impl Lagrangian<1> for Oscillator {
            fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
                0.5 * v[0] * v[0] - 72.0 * x[0] * x[0]
            }
            fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
                (Vector::<1>::new(-144.0 * x[0]), *v)
            }
            fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
                Hessian {
                    xx: Matrix::<1>::new(-144.0),
                    xv: Matrix::<1>::zeros(),
                    vv: Matrix::<1>::identity(),
                }
            }
        }
        let n = 300;
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::grunwald_letnikov(side, 0.7).unwrap();
            let problem = Problem::new(&Oscillator, grid, embedding);
            let q: Vec<Vector<1>> = (0..=n)
                .map(|k| Vector::<1>::new(0.3 - 1.3 * k as f64 / n as f64))
                .collect();
            let (mut system, eval) = linearized(&problem, &q);
            let rhs: Vec<f64> = eval.r.iter().map(|r| r[0]).collect();
            let mut delta = vec![0.0; n - 1];
            let options = KrylovOptions {
                tolerance: 1e-10,
                max_iterations: 300,
                restart: 30,
            };
            let cg = conjugate_gradient(&mut system, &rhs, &mut delta, &options);
            assert!(matches!(cg, Err(KrylovFailure::Breakdown { .. })), "{cg:?}");
            let at = Location::Newton(0);
            solve_newton_system(
                &mut system,
                &rhs,
                &mut delta,
                1e-10,
                &KrylovBudget::default(),
                at,
            )
            .unwrap();
            let mut j_delta = vec![0.0; n - 1];
            system.apply(&delta, &mut j_delta);
            let gap: f64 = rhs
                .iter()
                .zip(&j_delta)
                .map(|(a, b)| (a - b) * (a - b))
                .sum();
            let norm: f64 = rhs.iter().map(|a| a * a).sum();
            assert!(
                (gap / norm).sqrt() <= 1e-10,
                "{side:?}: {:e}",
                (gap / norm).sqrt()
            );
        }
    }
}
