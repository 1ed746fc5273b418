//! Initial value problems of the classical embeddings: a three-point recurrence, one
//! `d`-dimensional solve per step.
//!
//! The step math (momentum, step equation, closed-form update) is the crate's step module;
//! this module drives it: the two starts, the loop over the grid, the stability guard and the
//! errors with their step index.

use crate::discretisation::Discretisation;
use crate::embedding::{Embedding, EmbeddingKind, Scheme};
use crate::error::{Error, Location, Result};
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::memory::reserve;
use crate::options::{NewtonOptions, SolverOptions};
use crate::regularity::{InitialData, check_initial_data, check_point, check_vv, pivot_range};
use crate::side::Side;
use crate::solve::gauss::GaussIvp;
use crate::solve::guard::BlowUpGuard;
use crate::solve::newton::newton_step;
use crate::solve::nodes::ConstModel;
use crate::solve::resolution::resolution_warning;
use crate::solve::solution::Solution;
use crate::solve::stability::{Verdict, largest_stable_step, step_map_verdict};
use crate::solve::start::{Start, second_order_start};
use crate::step::{Step, StepKind, StepTimes, Update, momentum_and_energy_terms};

/// The step kind that advances `scheme` under `embedding`, on either path.
///
/// The asymmetric Gauss-FDEσ is coherent: its direct scheme *is* the variational recurrence,
/// so both schemes step with the variational kernel. Gauss-GLEσ has no three-point recurrence
/// (every node talks to every other) and gives [`Error::Unsupported`]: solve it as a boundary
/// value problem. The symmetric embeddings step with kernels of their own.
pub(crate) fn step_kind(embedding: &Embedding, scheme: Scheme) -> Result<StepKind> {
    match (embedding.kind(), scheme, embedding.side()) {
        (EmbeddingKind::Midpoint, Scheme::Variational, _) => Ok(StepKind::MidpointVariational),
        (EmbeddingKind::Midpoint, Scheme::Direct, _) => Ok(StepKind::MidpointDirect),
        (EmbeddingKind::Trapezoidal, Scheme::Variational, _) => {
            Ok(StepKind::TrapezoidalVariational)
        }
        (EmbeddingKind::Trapezoidal, Scheme::Direct, _) => Ok(StepKind::TrapezoidalDirect),
        (
            EmbeddingKind::GrunwaldLetnikov { .. }
            | EmbeddingKind::Caputo { .. }
            | EmbeddingKind::CorrectedGrunwaldLetnikov { .. }
            | EmbeddingKind::CorrectedCaputo { .. },
            _,
            _,
        ) => Err(Error::Unsupported {
            operation: "an initial value problem",
            embedding: embedding.to_string(),
        }),
        // A one-step map of (q, p): its runs start from q(a), q̇(a) (`solve`).
        (EmbeddingKind::GaussLegendre { .. }, _, _) => Err(Error::Unsupported {
            operation: "a three-point recurrence from two nodes or a discrete Legendre start",
            embedding: embedding.to_string(),
        }),
        (EmbeddingKind::FiniteDifference, Scheme::Direct, Side::Backward) => {
            Ok(StepKind::DirectBackward)
        }
        (EmbeddingKind::FiniteDifference, Scheme::Direct, Side::Forward) => {
            Ok(StepKind::DirectForward)
        }
        (_, _, Side::Backward) => Ok(StepKind::VariationalBackward),
        (_, _, Side::Forward) => Ok(StepKind::VariationalForward),
    }
}

/// What an initial value problem is made of: the Lagrangian, the grid, the embedding and the
/// Newton options of its implicit steps.
pub(crate) struct Ivp<'l, L: ?Sized, const D: usize> {
    pub(crate) lagrangian: &'l L,
    pub(crate) grid: Grid,
    pub(crate) embedding: Embedding,
    pub(crate) newton: NewtonOptions,
    /// Whether the run is watched for blow-up (see the guard module).
    pub(crate) blow_up_guard: bool,
    /// Whether the run's step is checked against its fastest motion (see the resolution
    /// module).
    pub(crate) resolution_check: bool,
}

impl<'l, L: Lagrangian<D> + ?Sized, const D: usize> Ivp<'l, L, D> {
    /// The parts of `discretisation` and `options` an initial value problem needs.
    pub(crate) fn new(discretisation: &Discretisation<'l, L, D>, options: &SolverOptions) -> Self {
        Ivp {
            lagrangian: discretisation.lagrangian(),
            grid: *discretisation.grid(),
            embedding: *discretisation.embedding(),
            newton: options.newton,
            blow_up_guard: options.blow_up_guard,
            resolution_check: options.resolution_check,
        }
    }

    /// The step kind that advances `scheme` under this embedding ([`step_kind`]).
    pub(crate) fn step_kind(&self, scheme: Scheme) -> Result<StepKind> {
        step_kind(&self.embedding, scheme)
    }

    /// The discrete Legendre start (see `Problem::legendre_start`).
    pub(crate) fn legendre_start(&self, q0: Vector<D>, v0: Vector<D>) -> Result<Vector<D>> {
        // The variational kind of this embedding, as on the run-time path.
        let kind = self.step_kind(Scheme::Variational)?.legendre_start();
        let (_, pi0, _) = check_initial_data(self.lagrangian, &q0, &v0, self.grid.t(0))?;
        let (grid, h) = (&self.grid, self.grid.h());
        let times = StepTimes::new(h, grid.t(0) - h, grid.t(0), grid.t(1));
        let step = Step {
            kind,
            a: q0 - v0 * h,
            b: q0,
            momentum: pi0,
            times,
        };
        let update = Update::plan(self.lagrangian, kind, &q0, &times);
        self.solve_step(&update, &step, q0 + v0 * h, 1)
            .map(|(q1, _)| q1)
    }

    /// The second-order start (see [`Problem::second_order_start`](crate::Problem::second_order_start)).
    pub(crate) fn second_order_start(&self, q0: Vector<D>, v0: Vector<D>) -> Result<Vector<D>> {
        check_initial_data(self.lagrangian, &q0, &v0, self.grid.t(0))?;
        let model = &mut ConstModel::<L, D>(self.lagrangian);
        let times = (self.grid.t(0), self.grid.h());
        let q1 = second_order_start(model, (q0.as_slice(), v0.as_slice()), times)?;
        Ok(Vector::<D>::from_column_slice(&q1))
    }

    /// The run from `q(a) = q0`, `q̇(a) = v0` with `start` for `Q_1`.
    pub(crate) fn solve(
        &self,
        scheme: Scheme,
        q0: Vector<D>,
        v0: Vector<D>,
        start: Start,
    ) -> Result<Solution<D>> {
        if let EmbeddingKind::GaussLegendre { stages } = self.embedding.kind() {
            let (lagrangian, grid, newton) = (self.lagrangian, self.grid, self.newton);
            let (embedding, blow_up_guard) = (self.embedding, self.blow_up_guard);
            let gauss = GaussIvp {
                lagrangian,
                grid,
                embedding,
                stages,
                newton,
                blow_up_guard,
                resolution_check: self.resolution_check,
            };
            return gauss.solve(scheme, q0, v0);
        }
        // An unsupported embedding is reported before any start is attempted.
        self.step_kind(scheme)?;
        let q1 = match start {
            Start::Legendre => self.legendre_start(q0, v0)?,
            Start::SecondOrder => self.second_order_start(q0, v0)?,
        };
        self.solve_checked(scheme, q0, q1, v0)
    }

    /// The run of `scheme` from given first nodes `Q_0`, `Q_1`.
    pub(crate) fn solve_from_nodes(
        &self,
        scheme: Scheme,
        q0: Vector<D>,
        q1: Vector<D>,
    ) -> Result<Solution<D>> {
        self.solve_checked(scheme, q0, q1, (q1 - q0) / self.grid.h())
    }

    /// The run from `Q_0`, `Q_1`, with the initial velocity `v0` its resolution is checked at:
    /// a run that returns has passed the stability checks, so a step too large for the fastest
    /// motion is left only to a scheme without a limit there, and gets
    /// [`Warning::UnderResolved`](crate::Warning::UnderResolved).
    fn solve_checked(
        &self,
        scheme: Scheme,
        q0: Vector<D>,
        q1: Vector<D>,
        v0: Vector<D>,
    ) -> Result<Solution<D>> {
        let mut solution = self.solve_unchecked(scheme, q0, q1)?;
        if self.resolution_check {
            let data = (&q0, &v0, self.grid.t(0));
            solution
                .warnings
                .extend(resolution_warning(self.lagrangian, data, self.grid.h(), 1));
        }
        Ok(solution)
    }

    /// The run of [`solve_from_nodes`](Self::solve_from_nodes) without the resolution check.
    fn solve_unchecked(&self, scheme: Scheme, q0: Vector<D>, q1: Vector<D>) -> Result<Solution<D>> {
        let kind = self.step_kind(scheme)?;
        let reference = self.check_first_nodes(q0, q1)?;
        let solution = self.run(scheme, kind, q0, q1)?;
        let n_steps = self.grid.n();
        if n_steps >= 2 {
            let q = &solution.q;
            self.check_degeneracy(&q[n_steps - 1], &q[n_steps], n_steps, reference)?;
        }
        Ok(solution)
    }

    /// The recurrence of [`solve_from_nodes`](Self::solve_from_nodes) after its checks.
    ///
    /// A function of its own, holding nothing but the loops: with the checks around it in the
    /// same body, the optimiser kept the loop state of an explicit run out of registers (1.5×
    /// slower on the `explicit_step` bench).
    #[inline(never)]
    fn run(
        &self,
        scheme: Scheme,
        kind: StepKind,
        q0: Vector<D>,
        q1: Vector<D>,
    ) -> Result<Solution<D>> {
        let grid = self.grid;
        let n_steps = grid.n();
        let mut q = reserve(n_steps + 1, "the nodes Q_0..=Q_N")?;
        q.push(q0);
        if n_steps >= 1 {
            q.push(q1);
        }
        // One copy of the loop per kind, each with a constant `kind`: the kernels' `match kind`
        // then folds away and the step inlines into a straight-line loop body.
        use StepKind::*;
        let (iterations, explicit_steps) = match kind {
            VariationalBackward => self.recurrence(VariationalBackward, &mut q)?,
            VariationalForward => self.recurrence(VariationalForward, &mut q)?,
            DirectBackward => self.recurrence(DirectBackward, &mut q)?,
            DirectForward => self.recurrence(DirectForward, &mut q)?,
            MidpointVariational => self.recurrence(MidpointVariational, &mut q)?,
            MidpointDirect => self.recurrence(MidpointDirect, &mut q)?,
            TrapezoidalVariational => self.recurrence(TrapezoidalVariational, &mut q)?,
            TrapezoidalDirect => self.recurrence(TrapezoidalDirect, &mut q)?,
        };
        Ok(Solution {
            scheme,
            embedding: self.embedding,
            grid,
            q,
            newton_iterations: iterations,
            explicit_steps,
            momenta: Vec::new(),
            warnings: Vec::new(),
        })
    }

    /// The checks before the first step: finite model constants and first nodes, the first
    /// nodes inside the Lagrangian's domain and `∂²L/∂v²` not degenerate at `Q_1` with the
    /// velocity `(Q_1 − Q_0)/h` (at [`Location::Step`]`(1)`); returns its largest pivot, the
    /// reference scale of the checks along the run.
    ///
    /// The nodes come by value, like the state of `check_stability`: taking the address of the
    /// caller's `Q_0`, `Q_1` kept them out of registers in the stepping loop that follows and
    /// made an explicit run more than 1.5× slower.
    #[cold]
    #[inline(never)]
    fn check_first_nodes(&self, q0: Vector<D>, q1: Vector<D>) -> Result<f64> {
        let (t1, h) = (self.grid.t(1), self.grid.h());
        let (q0, q1) = (q0.as_slice(), q1.as_slice());
        let (_, _, hs) = check_point(self.lagrangian, InitialData::Nodes { q0, q1, t1, h })?;
        Ok(pivot_range(&hs.vv).map_or(0.0, |(_, hi)| hi))
    }

    /// The largest pivot of `∂²L/∂v²` at `Q_1` with the velocity `(Q_1 − Q_0)/h`: the scale the
    /// checks along the run measure against. Recomputed by each (rare) check rather than
    /// carried through the stepping loop, whose registers it would take.
    fn vv_reference(&self, q0: &Vector<D>, q1: &Vector<D>) -> f64 {
        let v = (q1 - q0) / self.grid.h();
        let hs = self.lagrangian.hessian(q1, &v, self.grid.t(1));
        pivot_range(&hs.vv).map_or(0.0, |(_, hi)| hi)
    }

    /// `∂²L/∂v²` at node `Q_k = b` with the velocity `(b − a)/h`, against the run's reference
    /// scale: [`Error::DegenerateLagrangian`] at step `k` when degenerate.
    #[cold]
    #[inline(never)]
    fn check_degeneracy(
        &self,
        a: &Vector<D>,
        b: &Vector<D>,
        k: usize,
        reference: f64,
    ) -> Result<()> {
        let v = (b - a) / self.grid.h();
        let hs = self.lagrangian.hessian(b, &v, self.grid.t(k));
        check_vv(&hs.vv, reference, Location::Step(k)).map(|_| ())
    }

    /// Appends `Q_2..=Q_N` to `q = [Q_0, Q_1]`; returns the Newton iterations and the steps
    /// that took none.
    ///
    /// The two previous nodes live in locals rather than being read back from `q` (a load
    /// right after the store of the same node would put store forwarding on the critical path
    /// of every step), `1/h` is computed once, and so is the [`Update`] (with its `J⁻¹` when
    /// the step Jacobian is constant).
    #[inline(always)]
    fn recurrence(&self, kind: StepKind, q: &mut Vec<Vector<D>>) -> Result<(usize, usize)> {
        let grid = self.grid;
        let n_steps = grid.n();
        if n_steps < 2 {
            return Ok((0, 0));
        }
        let first = StepTimes::new(grid.h(), grid.t(0), grid.t(1), grid.t(2));
        let update = Update::plan(self.lagrangian, kind, &q[1], &first);
        // One copy of the loop per kind of update as well, each with the update's variant a
        // constant: a loop-invariant `match` left in the loop costs an indirect jump per step
        // and keeps the zero velocity of the closed form in memory.
        let l = self.lagrangian;
        match update {
            Update::Newton => self.steps(kind, &update, q, |_| None),
            Update::ConstantDiagonalInverse(d) => self.steps(kind, &update, q, |s| {
                Update::ConstantDiagonalInverse(d).explicit(l, s)
            }),
            Update::ConstantInverse(m) => self.steps(kind, &update, q, |s| {
                Update::ConstantInverse(m).explicit(l, s)
            }),
            Update::SolvePerStep => {
                self.steps(kind, &update, q, |s| Update::SolvePerStep.explicit(l, s))
            }
        }
    }

    /// The loop of [`recurrence`](Self::recurrence), with the closed form of `update` as
    /// `closed_form`.
    #[inline(always)]
    fn steps(
        &self,
        kind: StepKind,
        update: &Update<D>,
        q: &mut Vec<Vector<D>>,
        closed_form: impl Fn(&Step<D>) -> Option<Vector<D>>,
    ) -> Result<(usize, usize)> {
        let grid = self.grid;
        let n_steps = grid.n();
        let (h, inv_h) = (grid.h(), 1.0 / grid.h());
        let (mut a, mut b) = (q[0], q[1]);
        let drifts = matches!(kind, StepKind::DirectBackward | StepKind::DirectForward);
        let mut guard = BlowUpGuard::new(self.lagrangian, drifts, n_steps, self.blow_up_guard);
        let stride = guard.stride();
        let l = self.lagrangian;
        let mut counts = (0, 0);
        let mut start = 2;
        while start <= n_steps {
            // The first step of the stretch: the guard's energy comes from the same evaluation
            // of `∂L/∂v` as the step's momentum (with `L`, which only the guard reads).
            let times = StepTimes::new(h, grid.t(start - 2), grid.t(start - 1), grid.t(start));
            let step = if guard.is_enabled() {
                let (momentum, energy_terms) = momentum_and_energy_terms(l, kind, &a, &b, &times);
                guard.sample(energy_terms, &a, &b, inv_h, start)?;
                Step {
                    kind,
                    a,
                    b,
                    momentum,
                    times,
                }
            } else {
                Step::new(l, kind, &a, &b, &times)
            };
            if (start - 2) % STABILITY_CHECK_INTERVAL == 0 {
                self.check_along_the_run(update, a, step, start, [q[0], q[1]])?;
            }
            let y = self.advance(step, start, &closed_form, &mut counts)?;
            q.push(y);
            (a, b) = (b, y);
            let end = (start + stride - 1).min(n_steps);
            for n in start + 1..=end {
                let times = StepTimes {
                    h,
                    inv_h,
                    t_a: grid.t(n - 2),
                    t_b: grid.t(n - 1),
                    t_y: grid.t(n),
                };
                let step = Step::new(l, kind, &a, &b, &times);
                let y = self.advance(step, n, &closed_form, &mut counts)?;
                q.push(y);
                (a, b) = (b, y);
            }
            start = end + 1;
        }
        guard.finish()?;
        Ok(counts)
    }

    /// The node of `step` (index `n`): its closed form when that is finite, otherwise Newton.
    /// One finiteness test per step, on the closed form; Newton's nodes are finite by
    /// construction (it checks every iterate and errs otherwise). `counts` gathers the
    /// Newton iterations and the steps taken without any.
    #[inline(always)]
    fn advance(
        &self,
        step: Step<D>,
        n: usize,
        closed_form: &impl Fn(&Step<D>) -> Option<Vector<D>>,
        (iterations, explicit_steps): &mut (usize, usize),
    ) -> Result<Vector<D>> {
        match closed_form(&step) {
            Some(y) if y.iter().all(|c| c.is_finite()) => {
                *explicit_steps += 1;
                Ok(y)
            }
            _ => {
                let (y, its) = self.implicit_step(step.kind, step.b, step.momentum, step.a, n)?;
                *explicit_steps += usize::from(its == 0);
                *iterations += its;
                Ok(y)
            }
        }
    }

    /// Newton's method on step `n` (from `a = Q_{n−2}`, `b = Q_{n−1}`, with its momentum
    /// already computed), from the guess `2b − a`: the stepping loop's way out when there is no
    /// finite closed form.
    ///
    /// Out of line, taking plain values and recomputing the node times: the loop's hot path
    /// (the closed form) then keeps its step in registers instead of laying it out in memory
    /// for this call, and, for an autonomous Lagrangian, computes no times at all.
    #[inline(never)]
    fn implicit_step(
        &self,
        kind: StepKind,
        b: Vector<D>,
        momentum: Vector<D>,
        a: Vector<D>,
        n: usize,
    ) -> Result<(Vector<D>, usize)> {
        let grid = self.grid;
        let times = StepTimes::new(grid.h(), grid.t(n - 2), grid.t(n - 1), grid.t(n));
        let step = Step {
            kind,
            a,
            b,
            momentum,
            times,
        };
        newton_step(self.lagrangian, &step, b * 2.0 - a, n, &self.newton)
    }

    /// The newest node of `step` (index `n`, for the errors) and the Newton iterations it
    /// took: the closed form of `update` when it has one and it is finite, otherwise Newton
    /// from `guess`, which reports a singular Jacobian or a non-finite value at step `n`.
    fn solve_step(
        &self,
        update: &Update<D>,
        step: &Step<D>,
        guess: Vector<D>,
        n: usize,
    ) -> Result<(Vector<D>, usize)> {
        match update.explicit(self.lagrangian, step) {
            Some(y) if y.iter().all(|c| c.is_finite()) => Ok((y, 0)),
            _ => newton_step(self.lagrangian, step, guess, n, &self.newton),
        }
    }

    /// The checks that run every [`STABILITY_CHECK_INTERVAL`] steps, before step `n`: `∂²L/∂v²`
    /// at node `Q_{n−1}` not degenerate, then the stability of the step map.
    #[cold]
    #[inline(never)]
    fn check_along_the_run(
        &self,
        update: &Update<D>,
        a: Vector<D>,
        step: Step<D>,
        n: usize,
        first: [Vector<D>; 2],
    ) -> Result<()> {
        let reference = self.vv_reference(&first[0], &first[1]);
        self.check_degeneracy(&a, &step.b, n - 1, reference)?;
        self.check_stability(update, a, step, n)
    }

    /// Linear stability of the step map `(Q_{n−2}, Q_{n−1}) ↦ (Q_{n−1}, Q_n)` at the state
    /// `(a, step.b)`, from its `2d × 2d` Jacobian by central differences.
    ///
    /// A resolved step has its eigenvalues near the unit circle: physical instabilities (an
    /// inverted pendulum, chaos) show as real eigenvalues `≈ e^{μh} > 0`. A step too large for
    /// the scheme shows as a real eigenvalue below `−1` (for Störmer–Verlet, trace
    /// `2 − h²U″ < −2`, i.e. `ωh > 2`) or as an eigenvalue of modulus ≥ 2 (perturbations
    /// doubling every step): both are reported as [`Error::Unstable`].
    ///
    /// The state comes by value: the stepping loop keeps its nodes in registers, which taking
    /// their address for this (rare) call would prevent.
    #[cold]
    #[inline(never)]
    fn check_stability(
        &self,
        update: &Update<D>,
        a: Vector<D>,
        step: Step<D>,
        n: usize,
    ) -> Result<()> {
        let Step { kind, b, times, .. } = step;
        let map = |a: &Vector<D>, b: &Vector<D>| -> Result<Vector<D>> {
            let step = Step::new(self.lagrangian, kind, a, b, &times);
            self.solve_step(update, &step, b * 2.0 - a, n)
                .map(|(y, _)| y)
        };
        // The Jacobian is [[0, I], [∂y/∂a, ∂y/∂b]]: the two lower blocks, column by column.
        let mut lower = [Matrix::<D>::zeros(); 2];
        for c in 0..2 * D {
            // Perturb coordinate c of the stacked state (a, b).
            let mut plus = [a, b];
            let mut minus = [a, b];
            let (which, i) = (c / D, c % D);
            // The map depends on (b − a)/h: perturb by 1e-5·h so that the velocity moves by
            // 1e-5 (central-difference error ≈ ε/(1e-5 h) relative, ≈ 1e-7 at h = 1e-4).
            let delta = 1e-5 * times.h * (1.0 + plus[which][i].abs());
            plus[which][i] += delta;
            minus[which][i] -= delta;
            // A probe that leaves the Lagrangian's domain gives no verdict; the run goes on.
            let (Ok(yp), Ok(ym)) = (map(&plus[0], &plus[1]), map(&minus[0], &minus[1])) else {
                return Ok(());
            };
            lower[which].set_column(i, &((yp - ym) / (2.0 * delta)));
        }
        if !lower.iter().all(|m| m.iter().all(|x| x.is_finite())) {
            return Ok(());
        }
        let verdict = step_map_verdict(&lower[0], &lower[1], times.h);
        match verdict {
            // The QR iteration did not converge; an overflow is still caught as NotFinite.
            Verdict::Undecided | Verdict::Stable => Ok(()),
            Verdict::Unstable(lambda) => Err(Error::Unstable {
                at: Location::Step(n),
                re: lambda.re,
                im: lambda.im,
                largest_stable_step: largest_stable_step(
                    self.lagrangian,
                    kind,
                    &b,
                    &((b - a) * times.inv_h),
                    times.t_b,
                ),
            }),
        }
    }
}

/// Steps between two stability checks (the first runs at step 2). A check costs `4d` step
/// solves, plus a `2d × 2d` Schur form when the step is not plainly resolved (see
/// `near_identity`): on the explicit runs of the `explicit_step` bench at most 0.3 µs per
/// check against about 20 µs for the 1024 steps in between, an overhead below 1.5 %. An
/// instability that develops between two checks overflows to [`Error::NotFinite`] within a
/// few hundred steps anyway.
const STABILITY_CHECK_INTERVAL: usize = 1024;
