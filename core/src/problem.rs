//! [`Problem`]: a Lagrangian, a grid and an embedding; the two residual paths, the action, and
//! the Jacobian of the global system.
//!
//! The Grünwald–Letnikov operators are dense: on grids of more than [`FFT_OPERATOR_THRESHOLD`]
//! steps, [`Problem::velocity`], [`Problem::residual`], [`Problem::action`] and
//! [`Problem::energy`] (and so [`compare`](crate::compare) and the dense-LU Newton's residual)
//! apply them by FFT ([`FftOperator`], `O(N log N)`) instead of the `O(N²)` loops of
//! [`Operator`]. The two routes agree to round-off (tested above the threshold).

use crate::embedding::{Embedding, EmbeddingKind, variational_rows};
use crate::error::{Error, Location, Result};
use crate::fft_operator::FftOperator;
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::operator::{Operator, check_len};
use crate::solve::fractional::FractionalSolver;
use crate::solve::newton::NewtonOptions;
use std::ops::RangeInclusive;

/// Grids with more steps than this apply the fractional operators by FFT in [`Problem`]'s
/// residuals, velocity, action and energy (module docs). Below it the dense loops cost less
/// than planning the FFT (at `N = 256` a dense product is about 3·10⁴ multiply–adds).
pub const FFT_OPERATOR_THRESHOLD: usize = 256;

/// A discrete curve from a flat array `[Q_0[0], …, Q_0[D−1], Q_1[0], …]`.
///
/// # Example
///
/// ```
/// let q = varembed::curve_from_flat::<2>(&[0.0, 1.0, 2.0, 3.0])?;
/// assert_eq!(q[1][0], 2.0);
/// assert!(varembed::curve_from_flat::<2>(&[0.0, 1.0, 2.0]).is_err());
/// # Ok::<(), varembed::Error>(())
/// ```
pub fn curve_from_flat<const D: usize>(values: &[f64]) -> Result<Vec<Vector<D>>> {
    if D == 0 || !values.len().is_multiple_of(D) {
        return Err(Error::WrongDimension {
            what: "flat curve",
            dimension: D,
            found: values.len(),
        });
    }
    Ok(values
        .chunks_exact(D)
        .map(Vector::<D>::from_column_slice)
        .collect())
}

/// Which discrete scheme of an embedding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Scheme {
    /// The direct embedding of the Euler–Lagrange equation: the embedding's operators
    /// substituted into `∂_x L − d/dt ∂_v L = 0`.
    Direct,
    /// The variational integrator: the critical points of the discrete action `S_h`.
    Variational,
}

impl std::fmt::Display for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Scheme::Direct => "direct",
            Scheme::Variational => "variational",
        })
    }
}

/// A Lagrangian on a grid under a discrete embedding.
///
/// # Example
///
/// ```
/// use varembed::{Embedding, Grid, Hessian, Lagrangian, Matrix, Problem, Scheme, Side, Vector};
///
/// struct Free; // L = ½v²
/// impl Lagrangian<1> for Free {
///     fn value(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 { 0.5 * v[0] * v[0] }
///     fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
///         (Vector::<1>::zeros(), *v)
///     }
///     fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
///         Hessian { xx: Matrix::<1>::zeros(), xv: Matrix::<1>::zeros(), vv: Matrix::<1>::identity() }
///     }
/// }
///
/// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 4)?, Embedding::finite_difference(Side::Backward));
/// // A straight line is a solution of both schemes.
/// let q: Vec<Vector<1>> = (0..=4).map(|k| Vector::<1>::new(0.25 * k as f64)).collect();
/// assert!(problem.residual(Scheme::Direct, &q)?.iter().all(|r| r[0].abs() < 1e-14));
/// assert!((problem.action(&q)? - 0.5).abs() < 1e-14);
/// # Ok::<(), varembed::Error>(())
/// ```
pub struct Problem<'l, L: ?Sized, const D: usize> {
    pub(crate) lagrangian: &'l L,
    pub(crate) grid: Grid,
    pub(crate) embedding: Embedding,
    /// `Δ_σ` (or `Δ^α_σ`).
    pub(crate) velocity: Operator,
    /// `Δ_{−σ}` (or `Δ^α_{−σ}`).
    pub(crate) adjoint: Operator,
    pub(crate) newton: NewtonOptions,
    pub(crate) fractional_solver: FractionalSolver,
    /// [`FFT_OPERATOR_THRESHOLD`] (tests raise it to force the dense loops).
    pub(crate) fft_threshold: usize,
}

/// `V`, `f = ∂L/∂x`, `p = ∂L/∂v` at the quadrature nodes, stored by node index `0..=N` (the one
/// node outside `I_σ` holds zeros and is never read by a valid row).
pub(crate) struct Pointwise<const D: usize> {
    pub v: Vec<Vector<D>>,
    pub f: Vec<Vector<D>>,
    pub p: Vec<Vector<D>>,
}

/// Where the Jacobian blocks of the global system go (banded or dense storage).
pub(crate) trait BlockSink<const D: usize> {
    fn add_block(&mut self, row: usize, col: usize, block: &Matrix<D>);
}

impl<'l, L: Lagrangian<D> + ?Sized, const D: usize> Problem<'l, L, D> {
    /// The problem of `lagrangian` on `grid` under `embedding`, with default Newton options.
    pub fn new(lagrangian: &'l L, grid: Grid, embedding: Embedding) -> Self {
        Problem {
            lagrangian,
            grid,
            embedding,
            velocity: embedding.velocity_operator(&grid),
            adjoint: embedding.adjoint_operator(&grid),
            newton: NewtonOptions::default(),
            fractional_solver: FractionalSolver::default(),
            fft_threshold: FFT_OPERATOR_THRESHOLD,
        }
    }

    /// The same problem with other Newton options.
    pub fn with_newton(mut self, newton: NewtonOptions) -> Self {
        self.newton = newton;
        self
    }

    /// The same problem with another linear solver for the boundary value problems of the
    /// fractional embeddings (default [`FractionalSolver::Auto`]: dense LU for small systems,
    /// the FFT Newton–Krylov fast path above). The classical embeddings ignore it.
    ///
    /// # Example
    ///
    /// ```
    /// use varembed::{Embedding, FractionalSolver, Grid, Problem, Side};
    /// # use varembed::{Hessian, Lagrangian, Matrix, Vector};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     fn value(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 { 0.5 * v[0] * v[0] }
    /// #     fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
    /// #         (Vector::<1>::zeros(), *v)
    /// #     }
    /// #     fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
    /// #         Hessian { xx: Matrix::<1>::zeros(), xv: Matrix::<1>::zeros(), vv: Matrix::<1>::identity() }
    /// #     }
    /// # }
    /// let gle = Embedding::grunwald_letnikov(Side::Backward, 0.7)?;
    /// let problem = Problem::new(&Free, Grid::new(0.0, 1.0, 100)?, gle)
    ///     .with_fractional_solver(FractionalSolver::Fast);
    /// let fast = problem.solve_bvp(varembed::Scheme::Variational, 0.0, 1.0)?;
    /// let dense = problem
    ///     .with_fractional_solver(FractionalSolver::Dense)
    ///     .solve_bvp(varembed::Scheme::Variational, 0.0, 1.0)?;
    /// assert!(fast.max_distance(&dense.q).unwrap() < 1e-10);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn with_fractional_solver(mut self, solver: FractionalSolver) -> Self {
        self.fractional_solver = solver;
        self
    }

    /// The linear solver of the fractional boundary value problems.
    pub fn fractional_solver(&self) -> FractionalSolver {
        self.fractional_solver
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }
    /// The embedding.
    pub fn embedding(&self) -> &Embedding {
        &self.embedding
    }
    /// The Lagrangian.
    pub fn lagrangian(&self) -> &L {
        self.lagrangian
    }
    /// The Newton options.
    pub fn newton_options(&self) -> &NewtonOptions {
        &self.newton
    }

    /// The nodes `k` of the equations of `scheme` (DESIGN.md's table); entry `i` of
    /// [`residual`](Self::residual) is row `rows.start() + i`.
    pub fn residual_rows(&self, scheme: Scheme) -> RangeInclusive<usize> {
        match scheme {
            Scheme::Direct => self.embedding.direct_rows(self.grid.n()),
            Scheme::Variational => variational_rows(self.grid.n()),
        }
    }

    /// The discrete velocity `V = −σ Δ_σ Q` (or `−σ Δ^α_σ Q`) on the quadrature rows `I_σ`.
    pub fn velocity(&self, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        self.check_curve(q)?;
        let sign = -self.embedding.side().sign();
        // By FFT, through the curve's differences: as accurate as the dense loops, where the
        // plain FFT product's error would be amplified into the residual rows (see
        // [`FftOperator`]'s docs, "the difference form").
        let v = if self.by_fft(&self.velocity) {
            FftOperator::new(&self.velocity).apply_by_differences(q)?
        } else {
            self.velocity.apply(q)?
        };
        Ok(v.into_iter().map(|v| v * sign).collect())
    }

    /// Whether `op` is applied by FFT: a fractional (dense) operator on a grid of more than
    /// [`FFT_OPERATOR_THRESHOLD`] steps.
    fn by_fft(&self, op: &Operator) -> bool {
        op.weights().len() > 2 && self.grid.n() > self.fft_threshold
    }

    /// `op Q` ([`Operator::apply`]), by FFT when [`by_fft`](Self::by_fft).
    fn apply_operator(&self, op: &Operator, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        if self.by_fft(op) {
            FftOperator::new(op).apply(q)
        } else {
            op.apply(q)
        }
    }

    /// `opᵀ W` ([`Operator::apply_transpose`]), by FFT when [`by_fft`](Self::by_fft).
    fn apply_operator_transpose(&self, op: &Operator, w: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        if self.by_fft(op) {
            FftOperator::new(op).apply_transpose(w)
        } else {
            op.apply_transpose(w)
        }
    }

    /// The residual of `scheme` at `Q` (`N + 1` nodes), one entry per row of
    /// [`residual_rows`](Self::residual_rows).
    ///
    /// - [`Scheme::Direct`] substitutes the operators into Euler–Lagrange:
    ///   `f_k + σ (Δ_σ p)_k` for Gauss-FDEσ, `f_k − σ (Δ_{−σ} p)_k` for the asymmetric
    ///   Gauss-FDEσ, `f_k − σ (Δ^α_{−σ} p)_k` for Gauss-GLEσ.
    /// - [`Scheme::Variational`] is the gradient of the discrete action,
    ///   `(1/h) ∂S_h/∂Q_j = f_j + (Dᵀ p)_j`, `j = 1..=N−1`, assembled through the transpose of
    ///   the velocity operator `D = −σ Δ_σ`.
    ///
    /// The two are computed by separate code: comparing them is the paper's coherence test.
    pub fn residual(&self, scheme: Scheme, q: &[Vector<D>]) -> Result<Vec<Vector<D>>> {
        let pw = self.pointwise(q)?;
        Ok(self.residual_from(scheme, &pw))
    }

    pub(crate) fn residual_from(&self, scheme: Scheme, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        match scheme {
            Scheme::Direct => self.direct_residual(pw),
            Scheme::Variational => self.variational_residual(pw),
        }
    }

    /// The discrete action `S_h(Q) = h Σ_{k∈I_σ} L(Q_k, V_k, t_k)`.
    pub fn action(&self, q: &[Vector<D>]) -> Result<f64> {
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

    pub(crate) fn check_curve(&self, q: &[Vector<D>]) -> Result<()> {
        check_len("discrete curve Q", self.grid.n() + 1, q.len())?;
        match q.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            Some(k) => Err(Error::NonFiniteInput {
                what: format!("Q_{k} = {:?}", q[k].as_slice()),
            }),
            None => Ok(()),
        }
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

    pub(crate) fn pointwise(&self, q: &[Vector<D>]) -> Result<Pointwise<D>> {
        let v_rows = self.velocity(q)?;
        let n = self.grid.n();
        let mut pw = Pointwise {
            v: vec![Vector::<D>::zeros(); n + 1],
            f: vec![Vector::<D>::zeros(); n + 1],
            p: vec![Vector::<D>::zeros(); n + 1],
        };
        for (k, vk) in self.embedding.quadrature_rows(n).zip(v_rows) {
            let (f, p) = self.lagrangian.gradient(&q[k], &vk, self.grid.t(k));
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

    /// The direct path: the embedding's operators applied to `p` row by row.
    fn direct_residual(&self, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        let sigma = self.embedding.side().sign();
        let rows = self.residual_rows(Scheme::Direct);
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
            EmbeddingKind::GrunwaldLetnikov { .. } => {
                let first = self.adjoint.first_row();
                let adjoint_p = self
                    .apply_operator(&self.adjoint, &pw.p)
                    .expect("p has one value per node");
                rows.map(|k| pw.f[k] - adjoint_p[k - first] * sigma)
                    .collect()
            }
        }
    }

    /// The variational path: `f + Dᵀ p` on the interior nodes, `D = −σ Δ_σ`.
    fn variational_residual(&self, pw: &Pointwise<D>) -> Vec<Vector<D>> {
        let sigma = self.embedding.side().sign();
        let n = self.grid.n();
        let p_rows: Vec<Vector<D>> = self.embedding.quadrature_rows(n).map(|k| pw.p[k]).collect();
        let dt_p = self
            .apply_operator_transpose(&self.velocity, &p_rows)
            .expect("p has one value per quadrature row");
        variational_rows(n)
            .map(|j| pw.f[j] - dt_p[j] * sigma)
            .collect()
    }

    /// The Jacobian of [`residual`](Self::residual) with respect to the interior nodes
    /// `Q_1..Q_{N−1}`: block `(i, j − 1)` is `∂r_{rows[i]}/∂Q_j`.
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
        sink: &mut impl BlockSink<D>,
    ) {
        let n = self.grid.n();
        let sigma = self.embedding.side().sign();
        let hess: Vec<Option<_>> = (0..=n)
            .map(|k| {
                self.embedding
                    .quadrature_rows(n)
                    .contains(&k)
                    .then(|| self.lagrangian.hessian(&q[k], &pw.v[k], self.grid.t(k)))
            })
            .collect();
        let unknown = |j: usize| (1..n).contains(&j);
        // D[m, j] = −σ Δ_σ[m, j].
        let d_row = |m: usize| {
            self.velocity
                .row_entries(m)
                .map(move |(j, c)| (j, -sigma * c))
        };
        for (i, k) in self.residual_rows(scheme).enumerate() {
            let hk = hess[k].as_ref().expect("rows lie in I_σ");
            if unknown(k) {
                sink.add_block(i, k - 1, &hk.xx);
            }
            for (j, c) in d_row(k) {
                if unknown(j) {
                    sink.add_block(i, j - 1, &(hk.xv * c));
                }
            }
            let b_entries: Vec<(usize, f64)> = match (scheme, self.embedding.kind()) {
                (Scheme::Direct, EmbeddingKind::FiniteDifference) => self
                    .velocity
                    .row_entries(k)
                    .map(|(m, c)| (m, sigma * c))
                    .collect(),
                (Scheme::Direct, _) => self
                    .adjoint
                    .row_entries(k)
                    .map(|(m, c)| (m, -sigma * c))
                    .collect(),
                (Scheme::Variational, _) => self
                    .velocity
                    .column_entries(k)
                    .map(|(m, c)| (m, -sigma * c))
                    .collect(),
            };
            for (m, b) in b_entries {
                let hm = hess[m].as_ref().expect("B only reaches nodes of I_σ");
                if unknown(m) {
                    sink.add_block(i, m - 1, &(hm.xv.transpose() * b));
                }
                for (j, c) in d_row(m) {
                    if unknown(j) {
                        sink.add_block(i, j - 1, &(hm.vv * (b * c)));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Side;

    use crate::test_models::Mixed;

    /// Above [`FFT_OPERATOR_THRESHOLD`] the fractional operators go by FFT: velocity, both
    /// residuals, action and energy equal the dense loops' to round-off, for both sides.
    #[test]
    fn fft_route_matches_the_dense_loops_above_the_threshold() {
        let n = 3 * FFT_OPERATOR_THRESHOLD + 7;
        let grid = Grid::new(0.1, 1.3, n).unwrap();
        let q: Vec<Vector<2>> = (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                Vector::<2>::new((5.0 * t).sin(), (3.0 * t).cos() - 0.5)
            })
            .collect();
        let close = |a: &[Vector<2>], b: &[Vector<2>], what: &str| {
            assert_eq!(a.len(), b.len());
            let scale = 1.0 + b.iter().fold(0.0f64, |m, x| m.max(x.amax()));
            for (k, (x, y)) in a.iter().zip(b).enumerate() {
                assert!((x - y).amax() <= 1e-12 * scale, "{what} {k}: {x} vs {y}");
            }
        };
        for side in [Side::Backward, Side::Forward] {
            let embedding = Embedding::grunwald_letnikov(side, 0.65).unwrap();
            let fast = Problem::new(&Mixed, grid, embedding);
            let mut dense = Problem::new(&Mixed, grid, embedding);
            dense.fft_threshold = usize::MAX;
            assert!(fast.by_fft(&fast.velocity) && !dense.by_fft(&dense.velocity));
            close(
                &fast.velocity(&q).unwrap(),
                &dense.velocity(&q).unwrap(),
                "V",
            );
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let (a, b) = (fast.residual(scheme, &q), dense.residual(scheme, &q));
                close(&a.unwrap(), &b.unwrap(), &format!("{side:?} {scheme:?}"));
            }
            let (a, b) = (fast.action(&q).unwrap(), dense.action(&q).unwrap());
            assert!((a - b).abs() <= 1e-13 * (1.0 + b.abs()), "{a} vs {b}");
            let (a, b) = (fast.energy(&q).unwrap(), dense.energy(&q).unwrap());
            for (x, y) in a.iter().zip(&b) {
                assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{x} vs {y}");
            }
        }
    }

    /// The assembled Jacobian equals central differences of the residual, for every scheme of
    /// every embedding (so Newton's quadratic convergence rests on the right matrix).
    #[test]
    fn jacobian_matches_finite_differences_of_the_residual() {
        let n = 9;
        let grid = Grid::new(0.1, 1.0, n).unwrap();
        let mut embeddings = Vec::new();
        for side in [Side::Backward, Side::Forward] {
            embeddings.push(Embedding::finite_difference(side));
            embeddings.push(Embedding::asymmetric(side));
            embeddings.push(Embedding::grunwald_letnikov(side, 0.6).unwrap());
        }
        let q: Vec<Vector<2>> = (0..=n)
            .map(|k| Vector::<2>::new((k as f64 * 0.7).sin(), (k as f64 * 0.3).cos() - 0.5))
            .collect();
        for embedding in embeddings {
            let problem = Problem::new(&Mixed, grid, embedding);
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let pw = problem.pointwise(&q).unwrap();
                let size = (n - 1) * 2;
                let mut jac = nalgebra::DMatrix::<f64>::zeros(size, size);
                problem.assemble_jacobian(scheme, &q, &pw, &mut jac);
                let eps = 1e-6;
                for j in 1..n {
                    for c in 0..2 {
                        let (mut plus, mut minus) = (q.clone(), q.clone());
                        plus[j][c] += eps;
                        minus[j][c] -= eps;
                        let rp = problem.residual(scheme, &plus).unwrap();
                        let rm = problem.residual(scheme, &minus).unwrap();
                        for i in 0..n - 1 {
                            for a in 0..2 {
                                let fd = (rp[i][a] - rm[i][a]) / (2.0 * eps);
                                let exact = jac[(i * 2 + a, (j - 1) * 2 + c)];
                                assert!(
                                    (fd - exact).abs() <= 1e-6 * (1.0 + fd.abs()),
                                    "{embedding} {scheme}: d r_{i}[{a}] / d Q_{j}[{c}] = {exact} vs {fd}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
