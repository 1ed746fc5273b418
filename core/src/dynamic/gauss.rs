//! The variational Gauss–Legendre integrators on the run-time path: the stage equations of
//! the const-generic path (`solve::gauss`, whose module docs derive them), entry for entry,
//! over slices, with the stage Jacobian stored as a band.
//!
//! # The band of the stage system
//!
//! The unknowns are the `s` stage velocities, `s·d` numbers. Stage by stage (`V_1`, then
//! `V_2`, …) the Jacobian of a chain is `s × s` blocks of tridiagonals: a band of half-width
//! `(s − 1) d + 1`, as wide as the model is long. Component by component instead (the `s`
//! stages of coordinate 0, then those of coordinate 1, …: unknown `(i, c)` at `c s + i`, `c`
//! in the model's band order), an entry `(c, c')` of any Hessian block with `|c − c'| ≤ b`
//! lands at distance at most `s b + s − 1`: the stage Jacobian of a model of half-bandwidth
//! `b` is a band of half-width `s (b + 1) − 1` (3 for a chain at `s = 2`, 7 at `s = 4`), and a
//! step costs `O(s³ d b²)` for the factorisation and `O(s³)` passes over the Hessian's entries
//! for the assembly.

use crate::embedding::Scheme;
use crate::error::{Error, Location, Result};
use crate::gauss_legendre::GaussTableau;
use crate::options::NewtonOptions;
use crate::regularity::{DEGENERACY_THRESHOLD, InitialData};
use crate::solve::gauss::{DEGENERACY_CHECK_INTERVAL, floor_size};
use crate::solve::guard::BlowUpGuard;
use crate::solve::newton::{StepIteration, newton};

use super::DynLagrangian;
use super::band::{BandSystem, OutsideBand};
use super::ivp::{DynIvp, DynRun, node_without_values, vv_factorised};
use super::observer::{DynNode, NodeObserver};
use super::slices::max_norm;
use super::sparse::{SparseForceJacobian, SparseHessian};
use super::stability::resolution_warning;

impl<L: DynLagrangian + ?Sized> DynIvp<'_, L> {
    /// The run of the Gauss–Legendre integrator with `stages` stages from `q(a) = q0`,
    /// `q̇(a) = v0`, each node handed to `observe` with the momentum the scheme carries, and
    /// with its velocity and energy when `values` (as [`DynIvp::run`]).
    pub(crate) fn run_gauss(
        &self,
        (scheme, stages): (Scheme, usize),
        (q0, v0): (&[f64], &[f64]),
        values: bool,
        mut observe: impl FnMut(DynNode<'_>),
    ) -> Result<DynRun> {
        if scheme == Scheme::Direct {
            return Err(Error::Unsupported {
                operation: "the direct scheme (a Gauss–Legendre integrator is variational only)",
                embedding: self.embedding.to_string(),
            });
        }
        let l = self.lagrangian;
        let t0 = self.grid.t(0);
        let (mut vv, hessian) = self.check_initial_data(InitialData::Velocity { q0, v0, t0 })?;
        // The scale the degeneracy checks along the run measure against.
        let reference = vv.pivot_range().1;
        let (grid, h, d) = (self.grid, self.grid.h(), q0.len());
        let warning = self
            .resolution_check
            .then(|| resolution_warning(&hessian, &mut vv, h, stages))
            .flatten();
        drop((vv, hessian));
        let setting = (&self.embedding, scheme, grid);
        let mut values = match values {
            true => Some(NodeObserver::new(l, setting, d)?.primed(q0, v0, grid.t(0))),
            false => None,
        };
        let mut system = StageSystem::new(l, GaussTableau::new(stages), h, v0, self.newton);
        let enabled = self.blow_up_guard && !l.dependence().t && !l.is_forced();
        let mut guard = BlowUpGuard::watching(false, grid.n(), enabled);
        let stride = guard.stride();
        // The nodes Q_{n−2}, Q_{n−1}, Q_n and the momenta p_{n−1}, p_n around step n.
        let (mut a, mut b, mut y) = (q0.to_vec(), q0.to_vec(), vec![0.0; d]);
        let (mut pb, mut py) = (vec![0.0; d], vec![0.0; d]);
        l.momentum(q0, v0, grid.t(0), &mut pb);
        let (mut iterations, mut explicit_steps) = (0, 0);
        for n in 1..=grid.n() {
            let its = system.solve((&b, &pb), grid.t(n - 1), n)?;
            iterations += its;
            explicit_steps += usize::from(its == 0);
            system.advance((&b, &pb), (&mut y, &mut py));
            if !y.iter().chain(&py).all(|c| c.is_finite()) {
                return Err(Error::NotFinite {
                    at: Location::Step(n),
                });
            }
            if guard.is_enabled() && (n - 1) % stride == 0 {
                let (e, vp) = system.first_stage_energy(grid.t(n - 1));
                guard.record(e, vp, e.abs(), n)?;
            }
            if n % DEGENERACY_CHECK_INTERVAL == 0 || n == grid.n() {
                system.check_first_stage_vv(Location::Step(n), reference)?;
            }
            system.extrapolate_guess();
            // Node n − 1 has every node its formulas read (itself and Q_n) and Q_{n−2}.
            let window: (usize, &[&[f64]]) = match n {
                1 => (0, &[&b, &y]),
                _ => (n - 2, &[&a, &b, &y]),
            };
            hand(
                &mut values,
                (n - 1, grid.t(n - 1), &pb),
                window,
                &mut observe,
            )?;
            std::mem::swap(&mut a, &mut b);
            std::mem::swap(&mut b, &mut y);
            std::mem::swap(&mut pb, &mut py);
        }
        let n = grid.n();
        hand(
            &mut values,
            (n, grid.t(n), &pb),
            (n - 1, &[&a, &b]),
            &mut observe,
        )?;
        guard.finish()?;
        let (band, reordered) = system.band();
        Ok(DynRun {
            scheme,
            embedding: self.embedding,
            grid,
            last: b,
            newton_iterations: iterations,
            explicit_steps,
            band,
            reordered,
            warnings: warning.into_iter().collect(),
            linear_solve: None,
        })
    }
}

/// Hands node `k` at `t` with the momentum `p` the scheme carries there to `observe`, from the
/// window of consecutive nodes `window` (the first of them node `window.0`): with its velocity
/// and energy when `values` computes them.
fn hand<L: DynLagrangian + ?Sized>(
    values: &mut Option<NodeObserver<'_, L>>,
    (k, t, p): (usize, f64, &[f64]),
    (first, window): (usize, &[&[f64]]),
    observe: &mut impl FnMut(DynNode<'_>),
) -> Result<()> {
    match values {
        Some(values) => values.hand(k, (first, window), Some(p), observe),
        None => {
            node_without_values((k, t, p), (first, window), observe);
            Ok(())
        }
    }
}

/// The stage system of one step and its Newton solve over slices (stage `i` of a flat buffer
/// at `i d..(i + 1) d`), with buffers kept from step to step.
pub(crate) struct StageSystem<'l, L: ?Sized> {
    lagrangian: &'l L,
    tableau: GaussTableau,
    h: f64,
    d: usize,
    newton: NewtonOptions,
    /// The unknowns `V_i`: the guess on entry to a solve, the solution after it.
    v: Vec<f64>,
    /// `Q_i`, `Ṗ_i = ∂L/∂x (+ f)`, `P_i = ∂L/∂v` and the second derivatives at the stages.
    q: Vec<f64>,
    f: Vec<f64>,
    p: Vec<f64>,
    hessian: Vec<SparseHessian>,
    /// The Jacobians of a generalised force at the stages (empty without one).
    force: Vec<SparseForceJacobian>,
    /// The residual, then the Newton update.
    rhs: Vec<f64>,
    /// The stage Jacobian, planned at the first step (again when an entry falls outside its
    /// band), and whether the model's unknowns were reordered to reach it.
    system: Option<(BandSystem, bool)>,
    /// `ℓ_j(1 + c_i)` row by row (see `extrapolate_guess`), and the solved velocities while
    /// the guess is computed from them.
    extrapolation: Vec<f64>,
    solved: Vec<f64>,
}

impl<'l, L: DynLagrangian + ?Sized> StageSystem<'l, L> {
    pub(crate) fn new(
        lagrangian: &'l L,
        tableau: GaussTableau,
        h: f64,
        v0: &[f64],
        newton: NewtonOptions,
    ) -> Self {
        let (s, d) = (tableau.stages(), v0.len());
        let extrapolation = tableau.extrapolation();
        let forced = lagrangian.is_forced();
        StageSystem {
            lagrangian,
            h,
            d,
            newton,
            v: v0.repeat(s),
            q: vec![0.0; s * d],
            f: vec![0.0; s * d],
            p: vec![0.0; s * d],
            hessian: (0..s).map(|_| SparseHessian::new(d)).collect(),
            force: match forced {
                true => (0..s).map(|_| SparseForceJacobian::new(d)).collect(),
                false => Vec::new(),
            },
            rhs: vec![0.0; s * d],
            system: None,
            extrapolation,
            solved: vec![0.0; s * d],
            tableau,
        }
    }

    fn stages(&self) -> usize {
        self.tableau.stages()
    }

    /// `Q_i = q_k + h Σ_j a_ij V_j`, then `Ṗ`, `P` and the second derivatives at every
    /// stage; whether all are finite.
    fn evaluate(&mut self, qk: &[f64], tk: f64) -> bool {
        let (s, d, h, l) = (self.stages(), self.d, self.h, self.lagrangian);
        let mut finite = true;
        for i in 0..s {
            let qi = &mut self.q[i * d..(i + 1) * d];
            qi.copy_from_slice(qk);
            for j in 0..s {
                let w = h * self.tableau.a(i, j);
                for (x, v) in qi.iter_mut().zip(&self.v[j * d..(j + 1) * d]) {
                    *x += v * w;
                }
            }
            let (qi, vi) = (&self.q[i * d..(i + 1) * d], &self.v[i * d..(i + 1) * d]);
            let ti = tk + self.tableau.c[i] * h;
            l.force(qi, vi, ti, &mut self.f[i * d..(i + 1) * d]);
            l.momentum(qi, vi, ti, &mut self.p[i * d..(i + 1) * d]);
            self.hessian[i].clear();
            l.hessian(qi, vi, ti, &mut self.hessian[i]);
            finite &= self.hessian[i].is_finite();
            if let Some(force) = self.force.get_mut(i) {
                force.clear();
                l.force_jacobian(qi, vi, ti, force);
                finite &= [&force.x, &force.v]
                    .iter()
                    .all(|b| b.entries().iter().all(|e| e.2.is_finite()));
            }
        }
        finite && self.f.iter().chain(&self.p).all(|c| c.is_finite())
    }

    /// The residual `R_i = P_i − p_k − h Σ_j a_ij Ṗ_j` into `rhs`; its max-norm.
    fn residual(&mut self, pk: &[f64]) -> f64 {
        let (s, d, h) = (self.stages(), self.d, self.h);
        for i in 0..s {
            let r = &mut self.rhs[i * d..(i + 1) * d];
            for ((r, p), pk) in r.iter_mut().zip(&self.p[i * d..(i + 1) * d]).zip(pk) {
                *r = p - pk;
            }
            for j in 0..s {
                let w = h * self.tableau.a(i, j);
                for (r, f) in r.iter_mut().zip(&self.f[j * d..(j + 1) * d]) {
                    *r -= f * w;
                }
            }
        }
        max_norm(&self.rhs)
    }

    /// The stage Jacobian assembled and factorised: its `‖J‖∞` and whether it is regular.
    /// The first call plans the band from every stage's pattern, so the entries of this
    /// step always fit a plan made from them.
    fn factorize_jacobian(&mut self) -> (f64, bool) {
        let (s, d) = (self.stages(), self.d);
        let claimed = self.lagrangian.hessian_bandwidth();
        // A plan made from this step's own pattern always fits it: at most one re-plan.
        for _ in 0..2 {
            let (system, _) = self.system.get_or_insert_with(|| {
                let blocks: Vec<_> = self
                    .hessian
                    .iter()
                    .flat_map(|h| [&h.xx, &h.xv, &h.vv])
                    .chain(self.force.iter().flat_map(|f| [&f.x, &f.v]))
                    .collect();
                BandSystem::interleaved(d, s, claimed, &blocks)
            });
            system.clear();
            let parts = (&self.tableau, self.h, d);
            if add_jacobian(system, parts, &self.hessian, &self.force).is_ok() {
                let (norms, regular) = system.factorize_measured();
                return (norms.inf, regular);
            }
            // An entry outside the planned band: plan again from this step's pattern.
            self.system = None;
        }
        (0.0, false)
    }

    /// Newton's method on the stage equations of the step from `(q_k, p_k)` at `t_k` (step
    /// `n`, for the errors), from the stage velocities in `v`: the shared iteration
    /// ([`newton`]) with the const-generic path's scale and round-off floor; returns the
    /// iterations (0 when the guess already solves them).
    pub(crate) fn solve(&mut self, (qk, pk): (&[f64], &[f64]), tk: f64, n: usize) -> Result<usize> {
        let options = self.newton;
        let mut iteration = StageIteration {
            stages: self,
            step: (qk, pk, tk),
            rows: 0.0,
            j_norm: 0.0,
        };
        newton(&mut iteration, &options, Location::Step(n))
    }

    /// `(q_{k+1}, p_{k+1}) = (q_k + h Σ b_i V_i, p_k + h Σ b_i Ṗ_i)` from the solved stages.
    pub(crate) fn advance(&self, (qk, pk): (&[f64], &[f64]), (q, p): (&mut [f64], &mut [f64])) {
        let d = self.d;
        q.copy_from_slice(qk);
        p.copy_from_slice(pk);
        for (i, b) in self.tableau.b.iter().enumerate() {
            let w = self.h * b;
            for (q, v) in q.iter_mut().zip(&self.v[i * d..(i + 1) * d]) {
                *q += v * w;
            }
            for (p, f) in p.iter_mut().zip(&self.f[i * d..(i + 1) * d]) {
                *p += f * w;
            }
        }
    }

    /// Replaces the solved stage velocities by the guess for the next step,
    /// `V_i ← Σ_j ℓ_j(1 + c_i) V_j` (the const-generic path's extrapolation).
    pub(crate) fn extrapolate_guess(&mut self) {
        let (s, d) = (self.stages(), self.d);
        self.solved.copy_from_slice(&self.v);
        for i in 0..s {
            let vi = &mut self.v[i * d..(i + 1) * d];
            vi.fill(0.0);
            for j in 0..s {
                let w = self.extrapolation[i * s + j];
                for (v, solved) in vi.iter_mut().zip(&self.solved[j * d..(j + 1) * d]) {
                    *v += solved * w;
                }
            }
        }
    }

    /// The energy `V_1·P_1 − L(Q_1, V_1)` at the first stage of the solved step from `t_k`,
    /// and `V_1·P_1`: the blow-up guard's sample (a stage velocity is no difference quotient,
    /// so the round-off floor is that of the energy alone).
    fn first_stage_energy(&self, tk: f64) -> (f64, f64) {
        let d = self.d;
        let (q, v, p) = (&self.q[..d], &self.v[..d], &self.p[..d]);
        let vp: f64 = v.iter().zip(p).map(|(v, p)| v * p).sum();
        let t = tk + self.tableau.c[0] * self.h;
        (vp - self.lagrangian.value(q, v, t), vp)
    }

    /// [`Error::DegenerateLagrangian`] at `at` when `∂²L/∂v²` at the first stage of the
    /// solved step is degenerate: the const-generic path's measure, its smallest pivot over
    /// the larger of its largest and `reference` (the largest pivot at the initial data), so
    /// that an `∂²L/∂v²` shrinking as a whole along the run is caught too.
    fn check_first_stage_vv(&self, at: Location, reference: f64) -> Result<()> {
        let hessian = &self.hessian[0];
        let claimed = self.lagrangian.hessian_bandwidth();
        let measure = match vv_factorised(self.d, claimed, hessian) {
            (Some(system), _) => {
                let (lo, hi) = system.pivot_range();
                let scale = hi.max(reference);
                if scale > 0.0 { lo / scale } else { 0.0 }
            }
            (None, _) => 0.0,
        };
        if measure >= DEGENERACY_THRESHOLD {
            return Ok(());
        }
        Err(Error::DegenerateLagrangian {
            at,
            measure,
            directions: hessian.vv.degenerate_directions(),
        })
    }

    /// The half-bandwidth of the stage Jacobian and whether the model's unknowns were
    /// reordered to reach it.
    fn band(&self) -> (usize, bool) {
        self.system
            .as_ref()
            .map_or((0, false), |(system, reordered)| {
                (system.band(), *reordered)
            })
    }
}

/// The stage equations of one step at the current stage velocities, as Newton's method sees
/// them (the const-generic path's `StageIteration` over slices).
struct StageIteration<'a, 'l, L: ?Sized> {
    stages: &'a mut StageSystem<'l, L>,
    /// `(q_k, p_k, t_k)`.
    step: (&'a [f64], &'a [f64], f64),
    /// The scale of the rows' terms and `‖J‖∞`, at the last evaluation and linearisation.
    rows: f64,
    j_norm: f64,
}

impl<L: DynLagrangian + ?Sized> StepIteration for StageIteration<'_, '_, L> {
    fn residual(&mut self) -> (f64, f64) {
        let (qk, pk, tk) = self.step;
        let stages = &mut *self.stages;
        let finite = stages.evaluate(qk, tk);
        let residual = stages.residual(pk);
        self.rows = max_norm(pk) + max_norm(&stages.p) + stages.h * max_norm(&stages.f);
        (if finite { residual } else { f64::NAN }, self.rows)
    }

    fn solve(&mut self) -> (f64, bool) {
        let stages = &mut *self.stages;
        let (j_norm, regular) = stages.factorize_jacobian();
        if regular {
            let (system, _) = stages.system.as_mut().expect("factorised above");
            system.solve_in_place(&mut stages.rhs);
        }
        self.j_norm = j_norm;
        (j_norm, regular)
    }

    /// As on the const-generic path: `max ‖V_i‖∞ + rows / ‖J‖∞`, so that the floor is
    /// `64 ε (rows + ‖J‖∞ max ‖V_i‖∞)`.
    fn size(&self) -> f64 {
        floor_size(max_norm(&self.stages.v), self.rows, self.j_norm)
    }

    fn update(&mut self) -> bool {
        let stages = &mut *self.stages;
        for (v, delta) in stages.v.iter_mut().zip(&stages.rhs) {
            *v -= delta;
        }
        stages.v.iter().all(|c| c.is_finite())
    }
}

/// `∂R_i/∂V_m = δ_im L_vv(i) + h a_im L_vx(i) − h a_im ∂Ṗ/∂v(m) − h² Σ_j a_ij a_jm ∂Ṗ/∂x(j)`
/// added entry by entry (`L_vx = L_xvᵀ`; `∂Ṗ/∂x = L_xx + ∂f/∂x`, `∂Ṗ/∂v = L_xv + ∂f/∂v`),
/// unknown `(m, c)` at `m d + c` in the model's order.
fn add_jacobian(
    system: &mut BandSystem,
    (tableau, h, d): (&GaussTableau, f64, usize),
    hessian: &[SparseHessian],
    force: &[SparseForceJacobian],
) -> std::result::Result<(), OutsideBand> {
    let s = tableau.stages();
    for i in 0..s {
        for &(r, c, value) in hessian[i].vv.entries() {
            system.add(i * d + r, i * d + c, value)?;
        }
        for m in 0..s {
            let w = h * tableau.a(i, m);
            // L_vx(i)(r, c) = L_xv(i)(c, r).
            for &(c, r, value) in hessian[i].xv.entries() {
                system.add(i * d + r, m * d + c, w * value)?;
            }
            let f_v = force.get(m).map_or(&[][..], |f| f.v.entries());
            for &(r, c, value) in hessian[m].xv.entries().iter().chain(f_v) {
                system.add(i * d + r, m * d + c, -w * value)?;
            }
            for j in 0..s {
                let w = h * h * tableau.a(i, j) * tableau.a(j, m);
                let f_x = force.get(j).map_or(&[][..], |f| f.x.entries());
                for &(r, c, value) in hessian[j].xx.entries().iter().chain(f_x) {
                    system.add(i * d + r, m * d + c, -w * value)?;
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
