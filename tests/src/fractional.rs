//! Exact solutions of fractional boundary value problems on `[0, 1]`, and the forced model
//! they solve.
//!
//! Choose the momentum `p(t)` a polynomial; `q = q_a + I^α_− p` (left Riemann–Liouville
//! integral, `I^α tᵏ = k!/Γ(k + 1 + α) t^{k+α}`) has `D^α_− (q − q_a) = p`, and it solves the
//! Euler–Lagrange equation `∂_x L + D^α_+ (∂_v L) = 0` of `L = ½v² + c cos x − F(t) x` with
//! `F = D^α_+ p − c sin q`, where `D^α_+ p` is in closed form once `p` is written in powers of
//! `u = 1 − t`: `D^α_+ uʲ = j!/Γ(j + 1 − α) u^{j−α}`. When `p(1) ≠ 0` the forcing is singular
//! like `(1 − t)^{−α}` at `b` (infinite there). With `q_a = 0` the curve solves Gauss-GLE−'s
//! problem, with `q_a ≠ 0` the Caputo form's. σ = + is the mirror image: `q(1 − t)` solves
//! the problem of `F(1 − t)`.

use crate::curve::v1;
use crate::special::gamma;
use varembed::{
    Embedding, FractionalSolver, Grid, Hessian, Lagrangian, Matrix, Problem, Scheme, Side,
    Solution, Vector,
};

/// An exact solution `q = q_a + I^α p`, `p = Σ_k p[k] tᵏ`.
#[derive(Clone, Debug)]
pub struct ExactSolution {
    /// The order α.
    pub alpha: f64,
    /// `q(0)`.
    pub qa: f64,
    /// `p` in powers of `t`.
    pub p: Vec<f64>,
    /// The weight `c` of `c cos x` in `L`.
    pub c: f64,
}

impl ExactSolution {
    /// `q(t)` on the σ = − problem.
    pub fn q(&self, t: f64) -> f64 {
        let a = self.alpha;
        self.qa
            + self
                .p
                .iter()
                .enumerate()
                .map(|(k, pk)| {
                    pk * gamma(k as f64 + 1.0) / gamma(k as f64 + 1.0 + a) * t.powf(k as f64 + a)
                })
                .sum::<f64>()
    }

    /// `D^α_+ p(t)`: `p = Σ_j ρ_j uʲ`, `ρ_j = (−1)ʲ Σ_k p_k C(k, j)` (terms with a zero
    /// coefficient skipped, so that a momentum vanishing at `b` gives a finite value there).
    pub fn right_derivative_of_p(&self, t: f64) -> f64 {
        let (a, u) = (self.alpha, 1.0 - t);
        let mut total = 0.0;
        for j in 0..self.p.len() {
            let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
            let rho: f64 = self
                .p
                .iter()
                .enumerate()
                .skip(j)
                .map(|(k, pk)| pk * binomial(k, j))
                .sum::<f64>()
                * sign;
            // Zero at a pole of Γ(j + 1 − α) (α = 1, j = 0): the term is absent, not 0 · ∞ at b.
            let coefficient = rho * gamma(j as f64 + 1.0) / gamma(j as f64 + 1.0 - a);
            if coefficient != 0.0 {
                total += coefficient * u.powf(j as f64 - a);
            }
        }
        total
    }

    /// `q(t)` on the problem of `side`: the σ = − curve, read at `1 − t` for σ = + (the mirror
    /// image).
    pub fn q_on(&self, side: Side, t: f64) -> f64 {
        self.q(if side == Side::Forward { 1.0 - t } else { t })
    }

    /// The boundary value problem of this solution on `n` steps of `[0, 1]` (the mirror image
    /// for an `embedding` of side σ = +), solved by `scheme` with `solver`: the solution, and
    /// its max nodal error against [`q_on`](Self::q_on).
    ///
    /// # Panics
    ///
    /// When the solve fails.
    pub fn solve(
        &self,
        (embedding, scheme): (Embedding, Scheme),
        solver: FractionalSolver,
        n: usize,
    ) -> (Solution<1>, f64) {
        let side = embedding.side();
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let model = ForcedByExact {
            exact: self,
            mirrored: side == Side::Forward,
        };
        let solution = Problem::new(&model, grid, embedding)
            .with_fractional_solver(solver)
            .solve_bvp(scheme, self.q_on(side, 0.0), self.q_on(side, 1.0))
            .unwrap_or_else(|e| panic!("{embedding} {scheme}, N = {n}: {e}"));
        let error = solution
            .q
            .iter()
            .zip(grid.nodes())
            .fold(0.0f64, |m, (x, t)| m.max((x[0] - self.q_on(side, t)).abs()));
        (solution, error)
    }

    /// The forcing `F = D^α_+ p − c sin q` of the σ = − problem.
    pub fn forcing(&self, t: f64) -> f64 {
        self.right_derivative_of_p(t) - self.c * self.q(t).sin()
    }
}

/// `C(k, j)`.
fn binomial(k: usize, j: usize) -> f64 {
    (0..j).fold(1.0, |c, i| c * (k - i) as f64 / (i + 1) as f64)
}

/// `L = ½v² + c cos x − F(t) x`, `F` from an [`ExactSolution`] (mirrored for σ = +).
pub struct ForcedByExact<'e> {
    /// The solution whose forcing `L` carries.
    pub exact: &'e ExactSolution,
    /// Whether `F` is read at `1 − t` (the σ = + problem).
    pub mirrored: bool,
}

impl ForcedByExact<'_> {
    fn forcing(&self, t: f64) -> f64 {
        self.exact.forcing(if self.mirrored { 1.0 - t } else { t })
    }
}

impl Lagrangian<1> for ForcedByExact<'_> {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        0.5 * v[0] * v[0] + self.exact.c * x[0].cos() - self.forcing(t) * x[0]
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        (v1(-self.exact.c * x[0].sin() - self.forcing(t)), *v)
    }
    fn hessian(&self, x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-self.exact.c * x[0].cos()),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}
