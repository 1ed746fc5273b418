//! Initial value problems of the variational Gauss–Legendre integrators: a one-step map
//! `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` with `s` internal stages, each step a Newton solve of the
//! `s·d` stage velocities.
//!
//! # The scheme
//!
//! The discrete Lagrangian `L_d(q_k, q_{k+1}) = h Σ_i b_i L(Q_i, V_i, t_k + c_i h)`, taken over
//! the stage values of the collocation polynomial through `q_k` and `q_{k+1}`, gives by its
//! discrete Euler–Lagrange equations the symplectic partitioned Runge–Kutta method
//! (Marsden–West 2001, §2.6.6; Hairer–Lubich–Wanner, *Geometric Numerical Integration*, VI.6.3):
//!
//! ```text
//! Q_i = q_k + h Σ_j a_ij V_j              P_i = ∂L/∂v (Q_i, V_i, t_k + c_i h)
//! P_i = p_k + h Σ_j â_ij Ṗ_j              Ṗ_i = ∂L/∂x (Q_i, V_i, t_k + c_i h)
//! q_{k+1} = q_k + h Σ_i b_i V_i           p_{k+1} = p_k + h Σ_i b_i Ṗ_i
//! ```
//!
//! with the partner coefficients `â_ij = b_j − b_j a_ji / b_i`, which equal `a_ij` for the
//! Gauss tableau (it satisfies `b_i a_ij + b_j a_ji = b_i b_j`). The unknowns are the stage
//! velocities `V_1..V_s`; the equations are
//!
//! ```text
//! R_i(V) = ∂L/∂v (Q_i, V_i) − p_k − h Σ_j a_ij ∂L/∂x (Q_j, V_j) = 0,     i = 1..s,
//! ```
//!
//! in momentum units, with the Jacobian blocks, from the Hessian blocks at the stages,
//!
//! ```text
//! ∂R_i/∂V_m = δ_im L_vv(i) + h a_im L_vx(i) − h a_im L_xv(m) − h² Σ_j a_ij a_jm L_xx(j).
//! ```
//!
//! The run starts from `p_0 = ∂L/∂v(q(a), q̇(a), a)` and the stage guess `V_i = q̇(a)`; each
//! later step starts Newton from the previous step's collocation polynomial extrapolated to its
//! stages.

use crate::embedding::{Embedding, Scheme};
use crate::error::{Error, Location, Result};
use crate::gauss_legendre::GaussTableau;
use crate::grid::Grid;
use crate::lagrangian::{ForceJacobian, Hessian, Lagrangian, Matrix, Vector};
use crate::linalg::solve_dense_in_place;
use crate::memory::reserve;
use crate::options::NewtonOptions;
use crate::regularity::{check_initial_data, check_vv, pivot_range};
use crate::solve::guard::BlowUpGuard;
use crate::solve::newton::{StepIteration, newton};
use crate::solve::resolution::resolution_warning;
use crate::solve::solution::Solution;

/// Steps between two checks of `∂²L/∂v²` along a run (at the first stage of the step).
pub(crate) const DEGENERACY_CHECK_INTERVAL: usize = 1024;

/// What a Gauss–Legendre initial value problem is made of.
pub(crate) struct GaussIvp<'l, L: ?Sized, const D: usize> {
    pub(crate) lagrangian: &'l L,
    pub(crate) grid: Grid,
    pub(crate) embedding: Embedding,
    pub(crate) stages: usize,
    pub(crate) newton: NewtonOptions,
    pub(crate) blow_up_guard: bool,
    /// Whether the run's step is checked against its fastest motion.
    pub(crate) resolution_check: bool,
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> GaussIvp<'_, L, D> {
    /// The run from `q(a) = q0`, `q̇(a) = v0`: the nodes `q_k` and the momenta `p_k`.
    pub(crate) fn solve(
        &self,
        scheme: Scheme,
        q0: Vector<D>,
        v0: Vector<D>,
    ) -> Result<Solution<D>> {
        if scheme == Scheme::Direct {
            return Err(Error::Unsupported {
                operation: "the direct scheme (a Gauss–Legendre integrator is variational only)",
                embedding: self.embedding.to_string(),
            });
        }
        let (l, grid) = (self.lagrangian, self.grid);
        let t0 = grid.t(0);
        let (_, p0, hs) = check_initial_data(l, &q0, &v0, t0)?;
        let reference = pivot_range(&hs.vv).map_or(0.0, |(_, hi)| hi);
        let n_steps = grid.n();
        let mut stages = StageSystem::new(GaussTableau::new(self.stages), grid.h(), v0);
        let mut guard = BlowUpGuard::new(l, false, n_steps, self.blow_up_guard);
        let stride = guard.stride();
        let (mut q, mut p) = (
            reserve(n_steps + 1, "the nodes q_0..=q_N")?,
            reserve(n_steps + 1, "the momenta p_0..=p_N")?,
        );
        q.push(q0);
        p.push(p0);
        let (mut qk, mut pk) = (q0, p0);
        let (mut iterations, mut explicit_steps) = (0, 0);
        for n in 1..=n_steps {
            let its = stages.solve(l, (&qk, &pk), grid.t(n - 1), n, &self.newton)?;
            iterations += its;
            explicit_steps += usize::from(its == 0);
            (qk, pk) = stages.advance(&qk, &pk);
            if !qk.iter().chain(pk.iter()).all(|c| c.is_finite()) {
                return Err(Error::NotFinite {
                    at: Location::Step(n),
                });
            }
            q.push(qk);
            p.push(pk);
            let t1 = grid.t(n - 1) + stages.tableau.c[0] * grid.h();
            if (n - 1) % stride == 0 {
                guard.sample_state(l, &stages.q[0], &stages.v[0], t1, n)?;
            }
            if n % DEGENERACY_CHECK_INTERVAL == 0 || n == n_steps {
                check_vv(&stages.hessian[0].vv, reference, Location::Step(n))?;
            }
            stages.extrapolate_guess();
        }
        guard.finish()?;
        let warnings = match self.resolution_check {
            true => resolution_warning(l, (&q0, &v0, t0), grid.h(), self.stages),
            false => None,
        };
        Ok(Solution {
            scheme,
            embedding: self.embedding,
            grid,
            q,
            momenta: p,
            newton_iterations: iterations,
            explicit_steps,
            warnings: warnings.into_iter().collect(),
        })
    }
}

/// The stage system of one step and its Newton solve, with buffers kept from step to step.
pub(crate) struct StageSystem<const D: usize> {
    pub(crate) tableau: GaussTableau,
    pub(crate) h: f64,
    /// The unknowns `V_i`: the initial guess on entry to a solve, the solution after it.
    pub(crate) v: Vec<Vector<D>>,
    /// `Q_i`, `Ṗ_i = ∂L/∂x`, `P_i = ∂L/∂v` and the Hessian blocks at the current `V`.
    q: Vec<Vector<D>>,
    pub(crate) f: Vec<Vector<D>>,
    pub(crate) p: Vec<Vector<D>>,
    hessian: Vec<Hessian<D>>,
    /// The Jacobian of a generalised force at every stage (empty without one): its blocks join
    /// `L_xx` and `L_xv` where the stage equations differentiate `Ṗ_i`.
    force: Vec<ForceJacobian<D>>,
    /// The `s·d × s·d` Jacobian row by row, and the residual (then the Newton update).
    pub(crate) jacobian: Vec<f64>,
    pub(crate) rhs: Vec<f64>,
    /// `ℓ_j(1 + c_i)` row by row: the Lagrange basis of the nodes at the next step's nodes,
    /// which carries the stage velocities of one step to the guess of the next.
    extrapolation: Vec<f64>,
    /// The solved stage velocities while the guess is computed from them.
    solved: Vec<Vector<D>>,
}

impl<const D: usize> StageSystem<D> {
    pub(crate) fn new(tableau: GaussTableau, h: f64, v0: Vector<D>) -> Self {
        let s = tableau.stages();
        let zero = Vector::<D>::zeros();
        let no_hessian = Hessian {
            xx: Matrix::<D>::zeros(),
            xv: Matrix::<D>::zeros(),
            vv: Matrix::<D>::zeros(),
        };
        let extrapolation = tableau.extrapolation();
        StageSystem {
            extrapolation,
            solved: vec![zero; s],
            tableau,
            h,
            v: vec![v0; s],
            q: vec![zero; s],
            f: vec![zero; s],
            p: vec![zero; s],
            hessian: vec![no_hessian; s],
            force: Vec::new(),
            jacobian: vec![0.0; s * s * D * D],
            rhs: vec![0.0; s * D],
        }
    }

    /// `Q_i`, then `f`, `p` and the Hessian at every stage; whether all are finite.
    pub(crate) fn evaluate<L: Lagrangian<D> + ?Sized>(
        &mut self,
        l: &L,
        qk: &Vector<D>,
        tk: f64,
    ) -> bool {
        let (s, h) = (self.tableau.stages(), self.h);
        let mut finite = true;
        for i in 0..s {
            let mut qi = *qk;
            for j in 0..s {
                qi += self.v[j] * (h * self.tableau.a(i, j));
            }
            let ti = tk + self.tableau.c[i] * h;
            let (f, p, hs) = l.gradient_and_hessian(&qi, &self.v[i], ti);
            if let Some(force) = l.force_jacobian(&qi, &self.v[i], ti) {
                self.force.resize(s, force);
                self.force[i] = force;
                finite &= force.x.iter().chain(force.v.iter()).all(|c| c.is_finite());
            }
            finite &= f.iter().chain(p.iter()).all(|c| c.is_finite())
                && [hs.xx, hs.xv, hs.vv]
                    .iter()
                    .all(|m| m.iter().all(|c| c.is_finite()));
            (self.q[i], self.f[i], self.p[i], self.hessian[i]) = (qi, f, p, hs);
        }
        finite
    }

    /// The residual `R_i = P_i − p_k − h Σ_j a_ij Ṗ_j` into `rhs`; its max-norm.
    pub(crate) fn residual(&mut self, pk: &Vector<D>) -> f64 {
        let (s, h) = (self.tableau.stages(), self.h);
        let mut norm = 0.0f64;
        for i in 0..s {
            let mut r = self.p[i] - pk;
            for j in 0..s {
                r -= self.f[j] * (h * self.tableau.a(i, j));
            }
            self.rhs[i * D..(i + 1) * D].copy_from_slice(r.as_slice());
            norm = norm.max(r.amax());
        }
        norm
    }

    /// The Jacobian `∂R_i/∂V_m` into `jacobian` (see the module docs); its max-norm (largest
    /// absolute row sum).
    pub(crate) fn assemble_jacobian(&mut self) -> f64 {
        let (s, h) = (self.tableau.stages(), self.h);
        let width = s * D;
        for i in 0..s {
            for m in 0..s {
                let a_im = self.tableau.a(i, m);
                // ∂Ṗ/∂x and ∂Ṗ/∂v at a stage: L_xx, L_xv and a force's blocks.
                let f_x = |j: usize| match self.force.get(j) {
                    Some(force) => self.hessian[j].xx + force.x,
                    None => self.hessian[j].xx,
                };
                let f_v = match self.force.get(m) {
                    Some(force) => self.hessian[m].xv + force.v,
                    None => self.hessian[m].xv,
                };
                let mut block = (self.hessian[i].xv.transpose() - f_v) * (h * a_im);
                if i == m {
                    block += self.hessian[i].vv;
                }
                for j in 0..s {
                    let weight = h * h * self.tableau.a(i, j) * self.tableau.a(j, m);
                    block -= f_x(j) * weight;
                }
                for r in 0..D {
                    for c in 0..D {
                        self.jacobian[(i * D + r) * width + m * D + c] = block[(r, c)];
                    }
                }
            }
        }
        self.jacobian
            .chunks_exact(width)
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }

    /// Newton's method on the stage equations of the step from `(q_k, p_k)` at `t_k` (step `n`,
    /// for the errors), from the stage velocities in `v`: the shared iteration
    /// ([`newton`]) with its stopping rule and errors; returns the iterations (0 when the guess
    /// already solves them). The residual is measured against `‖p_k‖∞ + max ‖P_i‖∞ + h max
    /// ‖Ṗ_i‖∞` (no absolute part: `c L` stops where `L` does), and the round-off floor is
    /// `64 ε` times that plus `‖J‖∞ max ‖V_i‖∞` ([`StageIteration::size`]).
    fn solve<L: Lagrangian<D> + ?Sized>(
        &mut self,
        l: &L,
        (qk, pk): (&Vector<D>, &Vector<D>),
        tk: f64,
        n: usize,
        options: &NewtonOptions,
    ) -> Result<usize> {
        let mut iteration = StageIteration {
            stages: self,
            lagrangian: l,
            step: (qk, pk, tk),
            rows: 0.0,
            j_norm: 0.0,
        };
        newton(&mut iteration, options, Location::Step(n))
    }

    /// Replaces the solved stage velocities by the guess for the next step: the velocity of
    /// this step's collocation polynomial (degree `s − 1` in `V`, through `(c_j, V_j)`)
    /// extrapolated to the next step's stages, `V_i ← Σ_j ℓ_j(1 + c_i) V_j`, an `O(hˢ)` guess
    /// (for s = 1, the previous velocity).
    pub(crate) fn extrapolate_guess(&mut self) {
        let s = self.tableau.stages();
        self.solved.copy_from_slice(&self.v);
        for (i, v) in self.v.iter_mut().enumerate() {
            *v = (0..s).fold(Vector::<D>::zeros(), |sum, j| {
                sum + self.solved[j] * self.extrapolation[i * s + j]
            });
        }
    }

    /// `(q_{k+1}, p_{k+1}) = (q_k + h Σ b_i V_i, p_k + h Σ b_i Ṗ_i)` from the solved stages.
    pub(crate) fn advance(&self, qk: &Vector<D>, pk: &Vector<D>) -> (Vector<D>, Vector<D>) {
        let (mut q, mut p) = (*qk, *pk);
        for (i, b) in self.tableau.b.iter().enumerate() {
            q += self.v[i] * (self.h * b);
            p += self.f[i] * (self.h * b);
        }
        (q, p)
    }
}

/// The stage equations of one step at the current stage velocities, as Newton's method sees
/// them.
struct StageIteration<'a, L: ?Sized, const D: usize> {
    stages: &'a mut StageSystem<D>,
    lagrangian: &'a L,
    /// `(q_k, p_k, t_k)`.
    step: (&'a Vector<D>, &'a Vector<D>, f64),
    /// The scale of the rows' terms and `‖J‖∞`, at the last evaluation and linearisation.
    rows: f64,
    j_norm: f64,
}

/// The size Newton's round-off floor `64 ε ‖J‖∞ size` reads for a stage system, both paths:
/// `max ‖V_i‖∞ + rows / ‖J‖∞` (`max ‖V_i‖∞` alone when `‖J‖∞ = 0`), so that the floor is
/// `64 ε (rows + ‖J‖∞ max ‖V_i‖∞)`.
pub(crate) fn floor_size(largest_v: f64, rows: f64, j_norm: f64) -> f64 {
    match j_norm > 0.0 {
        true => largest_v + rows / j_norm,
        false => largest_v,
    }
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> StepIteration for StageIteration<'_, L, D> {
    fn residual(&mut self) -> (f64, f64) {
        let (qk, pk, tk) = self.step;
        let stages = &mut *self.stages;
        let finite = stages.evaluate(self.lagrangian, qk, tk);
        let residual = stages.residual(pk);
        let largest = |x: &[Vector<D>]| x.iter().fold(0.0f64, |m, y| m.max(y.amax()));
        self.rows = pk.amax() + largest(&stages.p) + stages.h * largest(&stages.f);
        (if finite { residual } else { f64::NAN }, self.rows)
    }

    fn solve(&mut self) -> (f64, bool) {
        let stages = &mut *self.stages;
        self.j_norm = stages.assemble_jacobian();
        let regular = solve_dense_in_place(&mut stages.jacobian, &mut stages.rhs);
        (self.j_norm, regular)
    }

    /// `max ‖V_i‖∞ + rows / ‖J‖∞`: the floor `64 ε ‖J‖∞ size` is then `64 ε (rows + ‖J‖∞ max
    /// ‖V_i‖∞)`, the sizes of the terms the residual sums (a large momentum `p_k` beside small
    /// velocities rounds at its own scale).
    fn size(&self) -> f64 {
        let v = self.stages.v.iter().fold(0.0f64, |m, y| m.max(y.amax()));
        floor_size(v, self.rows, self.j_norm)
    }

    fn update(&mut self) -> bool {
        let stages = &mut *self.stages;
        for (i, v) in stages.v.iter_mut().enumerate() {
            *v -= Vector::<D>::from_column_slice(&stages.rhs[i * D..(i + 1) * D]);
        }
        stages.v.iter().all(|v| v.iter().all(|c| c.is_finite()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::Mixed;

    /// The assembled stage Jacobian equals central differences of the stage residual, for
    /// every s, on a Lagrangian whose every Hessian block is non-zero and depends on x, v, t,
    /// alone and under a force whose blocks are not symmetric either.
    #[test]
    fn stage_jacobian_matches_finite_differences() {
        stage_jacobian_matches(&Mixed);
        stage_jacobian_matches(&crate::test_models::FORCED_MIXED);
    }

    fn stage_jacobian_matches<L: Lagrangian<2>>(lagrangian: &L) {
        let (qk, pk) = (Vector::<2>::new(0.3, -0.7), Vector::<2>::new(0.4, 1.1));
        let (tk, h) = (0.2, 0.15);
        for s in 1..=4 {
            let mut system = StageSystem::new(GaussTableau::new(s), h, Vector::<2>::zeros());
            for i in 0..s {
                system.v[i] = Vector::<2>::new(0.5 + 0.1 * i as f64, -0.3 * i as f64 + 0.2);
            }
            assert!(system.evaluate(lagrangian, &qk, tk));
            system.residual(&pk);
            system.assemble_jacobian();
            let jacobian = system.jacobian.clone();
            let width = 2 * s;
            let eps = 1e-6;
            for col in 0..width {
                let shifted = |delta: f64| {
                    let mut other = StageSystem::new(GaussTableau::new(s), h, Vector::<2>::zeros());
                    other.v = system.v.clone();
                    other.v[col / 2][col % 2] += delta;
                    assert!(other.evaluate(lagrangian, &qk, tk));
                    other.residual(&pk);
                    other.rhs
                };
                let (plus, minus) = (shifted(eps), shifted(-eps));
                for row in 0..width {
                    let fd = (plus[row] - minus[row]) / (2.0 * eps);
                    let exact = jacobian[row * width + col];
                    assert!(
                        (fd - exact).abs() <= 1e-7 * (1.0 + fd.abs()),
                        "s = {s} ({row}, {col}): {exact} vs {fd}"
                    );
                }
            }
        }
    }
}
